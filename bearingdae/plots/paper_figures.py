"""The paper's figures (Yang et al. 2024, Figs 11-24) and the sweep trends, from result files.

Pipeline place: plots; a run or sweep Dataset -> PNG (``bearingdae plot``, ``paper``).
Labels, units and colour keys from :mod:`.figure_common`; saved by
:func:`.figure_common.save_figure`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from .figure_common import (END_LABELS, POCKET_SIGN, RAD_S_TO_RPM, SKEW_SCALE, SKEW_UNIT,
                            closed_on_failure,
                            _plt, outside_legend, save_figure, slice_colours, slice_key,
                            wrap_title)

#: figure number -> caption (the paper's, shortened)
PAPER_CAPTIONS = {
    11: "Fig. 11: steady cage speed against radial load",
    12: "Fig. 12: slice contact force, (a) inner and (b) outer raceway",
    13: "Fig. 13: roller (a) spin and (b) orbit speed",
    14: "Fig. 14: roller skew angle",
    15: "Fig. 15: slice slip velocity, (a) inner and (b) outer raceway",
    16: "Fig. 16: slice traction (drag) force, (a) inner and (b) outer raceway",
    17: "Fig. 17: cage (pocket) force on the roller, ends a and b",
    18: "Fig. 18: roller skew angle at different speeds",
    19: "Fig. 19: cage force on roller end (a) a and (b) b at different speeds",
    20: "Fig. 20: inner-race slice slip velocity at different speeds",
    21: "Fig. 21: roller (a) spin and (b) orbit speed under different moments",
    22: "Fig. 22: roller skew angle under different moments",
    23: "Fig. 23: cage force on roller end (a) a and (b) b under different moments",
    24: "Fig. 24: inner-race slice slip velocity under different moments",
}
#: a run whose cage speed changes by more than this fraction of the epicyclic speed across the
#: recorded window is drawn as "not steady" (open marker) in the cage-speed figure
STEADY_DRIFT = 0.002


def is_sweep(ds: xr.Dataset) -> bool:
    """A sweep Dataset (bearingdae.studies.sweep) rather than a single run."""
    return "sweep_axes" in ds.attrs


def sweep_dims(ds: xr.Dataset) -> list[str]:
    import json

    return [a["dim"] for a in json.loads(ds.attrs.get("sweep_axes", "[]")) if a["dim"] in ds.dims]


def orbit_view(ds: xr.Dataset) -> xr.Dataset:
    """Quantities against the azimuth of one roller over one orbit: a dynamic run is
    phase-folded (:func:`bearingdae.analysis.summary.one_orbit`); a sweep file already holds
    them."""
    from ..analysis.summary import one_orbit

    if "azimuth" in ds.dims:
        return ds
    if "time" in ds.dims:
        return one_orbit(ds)
    if is_sweep(ds):
        raise ValueError(f"needs the one-orbit curves of a run, {_no_orbits(ds)}")
    what = ("a quasi-static solution (bearingdae static), which has no orbit"
            if "newton_iterations" in ds.attrs else "no dynamic run (no time dimension)")
    raise ValueError(f"the file holds {what}; the orbit figures need `bearingdae run` or "
                     "`bearingdae sweep` output")


def available_figures(ds: xr.Dataset) -> list:
    """Default figures for a file: a sweep's ``figures`` attribute (+ 'trends' for a one-axis
    sweep), the single-orbit Figs 12-17 for a run (and the cage orbit with cage whirl)."""
    import json

    if is_sweep(ds):
        figs = list(json.loads(ds.attrs.get("figures", "[]")))
        if len(sweep_dims(ds)) == 1:
            figs.append("trends")
        return figs
    return [12, 13, 14, 15, 16, 17] + (["orbit"] if "cage_center" in ds else [])


def _axis_label(ds: xr.Dataset, dim: str) -> str:
    shown = ds[dim].attrs.get("display_units", "")
    return f"{dim} [{shown}]" if shown else dim


def _value_label(ds: xr.Dataset, dim: str, value) -> str:
    shown = ds[dim].attrs.get("display_units", "")
    v = f"{value:g}" if isinstance(value, (float, np.floating, int, np.integer)) else str(value)
    return f"{v} {shown}".strip()


def _one_axis(ds: xr.Dataset, number) -> str:
    dims = sweep_dims(ds)
    if len(dims) == 1:
        return dims[0]
    what = f"figure {number} draws the runs of a sweep against one axis"
    if not is_sweep(ds):
        raise ValueError(f"{what}; this file holds a single run")
    if dims:
        raise ValueError(f"{what}; this sweep has axes {dims}: fix all but one with "
                         f"--select, e.g. --select {dims[0]}={ds[dims[0]].values[0]}")
    chosen = selected_point(ds)
    raise ValueError(f"{what}; " + (f"--select {chosen} left one run (drop it)" if chosen
                                     else "this sweep has no axis (a single run)"))


def _single(ds: xr.Dataset, number) -> xr.Dataset:
    o = orbit_view(ds)
    dims = sweep_dims(ds) if is_sweep(ds) else []
    if dims:
        raise ValueError(f"figure {number} shows one run; this sweep has axes {dims}: pick a run "
                         f"with --select, e.g. --select {dims[0]}={ds[dims[0]].values[0]}")
    return o


def _slices(ax, da: xr.DataArray, scale: float = 1.0) -> None:
    """One line per slice, coloured as :func:`slice_key` keys them."""
    for s, colour in zip(da.slice.values, slice_colours(da.sizes["slice"])):
        ax.plot(da.azimuth, da.sel(slice=s) * scale, lw=0.9, color=colour)


def _orbit_axes(ax, ylabel: str) -> None:
    ax.set(xlabel="roller azimuth θX [deg]", ylabel=ylabel, xlim=(0, 360),
           xticks=np.arange(0, 361, 90))
    ax.grid(alpha=0.3)


def _fig_single(o: xr.Dataset, number: int, fig) -> None:
    if number in (12, 15, 16):
        name, label, scale = {12: ("contact_force", "slice contact force [N]", 1.0),
                              15: ("slip_velocity", "slip velocity [m/s]", 1.0),
                              16: ("traction_force", "traction force [N]", 1.0)}[number]
        axs = fig.subplots(1, 2)
        for ax, race, tag in zip(axs, ("inner", "outer"), "ab"):
            _slices(ax, o[name].sel(race=race), scale)
            _orbit_axes(ax, label)
            ax.set_title(f"({tag}) {race} raceway", fontsize=9)
        slice_key(fig, list(axs), o.sizes["slice"])
    elif number == 13:
        axs = fig.subplots(1, 2)
        for ax, name, tag in zip(axs, ("spin_speed", "orbit_speed"), ("(a) spin", "(b) orbit")):
            ax.plot(o.azimuth, o[name] * RAD_S_TO_RPM, "k", lw=0.9)
            _orbit_axes(ax, f"{tag} speed [r/min]")
    elif number == 14:
        ax = fig.subplots()
        ax.plot(o.azimuth, o.skew_angle * SKEW_SCALE, "k", lw=0.9)
        _orbit_axes(ax, f"skew angle θz [{SKEW_UNIT}]")
    elif number == 17:
        ax = fig.subplots()
        for end in ("a", "b"):
            ax.plot(o.azimuth, o.cage_force.sel(end=end), lw=0.9, label=END_LABELS[end])
        _orbit_axes(ax, f"pocket force on roller [N]\n({POCKET_SIGN})")
        outside_legend(ax)


def _need_orbits(ds: xr.Dataset, names) -> None:
    """Overlay figures draw the one-orbit curves a sweep stores per run; a sweep whose runs
    are shorter than one orbit of a roller has none (summaries only)."""
    if not any(n in ds for n in names):
        raise ValueError(f"needs the one-orbit curves ({', '.join(names)}), {_no_orbits(ds)}")


def _no_orbits(ds: xr.Dataset) -> str:
    """Why a sweep file holds no one-orbit curves: no run completed, or the runs are shorter
    than one orbit of a roller (sweep/assemble.py stores none then)."""
    done = int((ds.status == "completed").sum()) if "status" in ds else 0
    if done == 0:
        return ("which this sweep file does not hold: none of its runs completed (see its "
                "status and error variables)")
    return ("which this sweep file does not hold: its runs are shorter than one orbit of a "
            "roller (numerics.cage_revolutions >= 1.25 gives one)")


def _fig_overlay(ds: xr.Dataset, number: int, fig) -> None:
    dim = _one_axis(ds, number)
    _need_orbits(ds, {18: ["skew_angle"], 22: ["skew_angle"], 19: ["cage_force"],
                      23: ["cage_force"]}.get(number, ["spin_speed", "orbit_speed"]))
    cmap = _plt().cm.plasma
    n = ds.sizes[dim]
    colours = [cmap(0.85 * i / max(1, n - 1)) for i in range(n)]
    if number in (18, 22):
        axs = [fig.subplots()]
        panels = [("skew_angle", None, f"skew angle θz [{SKEW_UNIT}]",
                   lambda v: v * SKEW_SCALE)]
    elif number in (19, 23):
        axs = fig.subplots(1, 2)
        panels = [("cage_force", "a", f"(a) pocket force, {END_LABELS['a']} [N]\n"
                   f"({POCKET_SIGN})", None),
                  ("cage_force", "b", f"(b) pocket force, {END_LABELS['b']} [N]\n"
                   f"({POCKET_SIGN})", None)]
    else:  # 21
        axs = fig.subplots(1, 2)
        panels = [("spin_speed", None, "(a) spin speed [r/min]", lambda v: v * RAD_S_TO_RPM),
                  ("orbit_speed", None, "(b) orbit speed [r/min]", lambda v: v * RAD_S_TO_RPM)]
    for ax, (name, end, label, f) in zip(axs, panels):
        if name not in ds:
            ax.text(0.5, 0.5, f"{name} not in file", ha="center", transform=ax.transAxes)
            continue
        for i, value in enumerate(ds[dim].values):
            da = ds[name].isel({dim: i})
            if end is not None:
                da = da.sel(end=end)
            y = f(da) if f is not None else da
            ax.plot(ds.azimuth, y, lw=0.9, color=colours[i], label=_value_label(ds, dim, value))
        _orbit_axes(ax, label)
    if len(axs) == 1:
        outside_legend(axs[0], title=_axis_label(ds, dim), title_fontsize=7)
    else:  # beside the figure: the panels keep one width
        fig.legend(*axs[-1].get_legend_handles_labels(), loc="outside right center",
                   fontsize=7, title=_axis_label(ds, dim), title_fontsize=7)


def _fig_panels(ds: xr.Dataset, number: int, fig) -> None:
    dim = _one_axis(ds, number)
    _need_orbits(ds, ["slip_velocity"])
    n = ds.sizes[dim]
    cols = min(n, 2)
    axs = np.atleast_1d(fig.subplots((n + cols - 1) // cols, cols, squeeze=False).ravel())
    for i, value in enumerate(ds[dim].values):
        ax = axs[i]
        _slices(ax, ds.slip_velocity.isel({dim: i}).sel(race="inner"))
        _orbit_axes(ax, "inner slip velocity [m/s]")
        ax.set_title(f"({'abcdefghijklmnop'[i % 16]}) {dim} = {_value_label(ds, dim, value)}",
                     fontsize=9)
    for ax in axs[n:]:
        ax.set_visible(False)
    slice_key(fig, list(axs[:n]), ds.sizes["slice"])


def _fig_cage_speed(ds: xr.Dataset, number: int, fig) -> None:
    dim = _one_axis(ds, number)
    ax = fig.subplots()
    x = ds[dim].values
    cage = ds.mean_cage_speed_rad_s.values * RAD_S_TO_RPM
    epi = ds.epicyclic_cage_speed_rad_s.values * RAD_S_TO_RPM
    drift = ds.cage_speed_drift.values
    steady = np.abs(drift) <= STEADY_DRIFT
    if "steady_state_reached" in ds:  # until_steady runs: the criterion of bearingdae/run/steady.py
        steady = np.where(np.isfinite(ds.steady_state_reached.values),
                          ds.steady_state_reached.values == 1, steady)
    ax.plot(x, cage, "k-", lw=1.0)
    ax.plot(x[steady], cage[steady], "ko", ms=5, label="bearingdae: mean over window")
    if (~steady & np.isfinite(cage)).any():
        ax.plot(x[~steady], cage[~steady], "o", mfc="white", mec="k", ms=5,
                label="not steady (until_steady reached its cap)" if "steady_state_reached"
                in ds else f"not steady (|drift| > {STEADY_DRIFT:g} of epicyclic)")
    ax.plot(x, epi, "r--", lw=1.0, label="epicyclic n/2 (1 − D_w/d_m)")
    failed = ds.status.values != "completed"
    for xi in x[failed]:
        ax.axvline(xi, color="0.7", ls=":", lw=0.8)
    ax.set(xlabel=_axis_label(ds, dim), ylabel="cage speed [r/min]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")


def _fig_trends(ds: xr.Dataset, number, fig) -> None:
    dim = _one_axis(ds, "trends")
    panels = [("cage_slip_ratio", 100.0, "cage slip [%]"),
              ("skew_amplitude_rad", SKEW_SCALE, f"skew amplitude [{SKEW_UNIT}]"),
              ("load_weighted_slip_m_s", 1.0, "load-weighted slip [m/s]"),
              ("max_abs_slip_m_s", 1.0, "max |slip| [m/s]"),
              ("slice_slip_spread_m_s", 1.0, "slice slip spread [m/s]"),
              ("peak_cage_force_N", 1.0, "peak cage force [N]"),
              ("rms_cage_force_N", 1.0, "rms cage force [N]"),
              ("peak_slice_load_N", 1.0, "peak slice load [N]")]
    axs = fig.subplots(2, 4).ravel()
    x = ds[dim].values
    for ax, (name, scale, label) in zip(axs, panels):
        ax.plot(x, ds[name].values * scale, "ko-", ms=4, lw=1.0)
        ax.set(xlabel=_axis_label(ds, dim), ylabel=label)
        ax.grid(alpha=0.3)


@closed_on_failure
def figure(ds: xr.Dataset, number, path: str | Path) -> Path:
    """Draw paper figure ``number`` (11-24) or ``"trends"`` (sweep summaries against the
    axis) from a run or sweep Dataset into the PNG ``path``."""
    if number == "orbit":  # cage whirl (plots/plot_whirl.py)
        from .plot_whirl import orbit_figure

        return orbit_figure(ds, path)
    plt = _plt()
    if number == "trends":
        fig = plt.figure(figsize=(14, 6), constrained_layout=True)
        _fig_trends(ds, number, fig)
        caption = "steady-state summaries against the sweep axis"
    elif number in PAPER_CAPTIONS:
        wide = number in (12, 13, 15, 16, 19, 21, 23) or number in (20, 24)
        size = (11, 7) if number in (20, 24) else ((11, 4.2) if wide else (6.5, 4.2))
        fig = plt.figure(figsize=size, constrained_layout=True)
        try:
            if number == 11:
                _fig_cage_speed(ds, number, fig)
            elif 12 <= number <= 17:
                _fig_single(_single(ds, number), number, fig)
            elif number in (20, 24):
                _fig_panels(ds, number, fig)
            else:
                _fig_overlay(ds, number, fig)
        except BaseException:
            plt.close(fig)
            raise
        caption = PAPER_CAPTIONS[number]
    else:
        raise ValueError(f"figure {number!r}: allowed are 11-24 and 'trends'")
    title = str(ds.attrs.get("title", "")).removeprefix("bearingdae ")
    chosen = selected_point(ds)
    if chosen:
        caption += f"; selected: {chosen}"
    fig.suptitle(wrap_title(f"{caption}\n{title}", fig, 9), fontsize=9)
    return save_figure(fig, path)


def selected_point(ds: xr.Dataset) -> str:
    """The sweep point a figure shows when ``plot --select`` fixed axes of a sweep (they are
    scalar coordinates then): "speed_rpm = 6000 r/min"; "" otherwise."""
    import json

    if not is_sweep(ds):
        return ""
    dims = [a["dim"] for a in json.loads(ds.attrs.get("sweep_axes", "[]"))]
    return ", ".join(f"{d} = {_value_label(ds, d, ds[d].item())}" for d in dims
                     if d in ds.coords and ds[d].ndim == 0)
