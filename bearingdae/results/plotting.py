"""Figures from a result Dataset only (never from solver internals)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr


def overview(ds: xr.Dataset, path: str | Path) -> Path:
    """Four-panel overview PNG of a dynamic run: cage and roller speeds, skew, slice loads of
    roller 1, pocket forces."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 2, figsize=(11, 7), constrained_layout=True)
    t_ms = ds.time.values * 1e3
    a = ax[0, 0]
    if "cage_speed" in ds:
        a.plot(t_ms, ds.cage_speed, "k", lw=1.5, label="cage")
    if "orbit_speed" in ds:
        a.plot(t_ms, ds.orbit_speed.sel(roller=1), lw=0.8, label="roller 1 orbit")
    epi = ds.attrs.get("epicyclic_cage_speed_rad_s")
    if epi:
        a.axhline(epi, color="r", ls="--", lw=0.8, label="epicyclic")
    a.set(xlabel="time [ms]", ylabel="speed [rad/s]", title="cage and orbit speed")
    a.legend(fontsize=8)
    a = ax[0, 1]
    if "skew_angle" in ds:
        for j in ds.roller.values[:: max(1, ds.sizes["roller"] // 5)]:
            a.plot(t_ms, np.degrees(ds.skew_angle.sel(roller=j)), lw=0.8, label=f"roller {j}")
        a.set(ylabel="skew angle [deg]", title="roller skew")
        a.legend(fontsize=7)
    else:
        a.text(0.5, 0.5, "skew switched off", ha="center", transform=a.transAxes)
    a.set(xlabel="time [ms]")
    a = ax[1, 0]
    if "contact_force" in ds:
        q = ds.contact_force.sel(roller=1, race="inner")
        for s in q.slice.values:
            a.plot(t_ms, q.sel(slice=s), lw=0.8, color=matplotlib.cm.viridis(
                (s - 1) / max(1, q.sizes["slice"] - 1)))
        a.set(ylabel="slice force [N]", title="roller 1, inner race: slice loads (1 → k)")
    a.set(xlabel="time [ms]")
    a = ax[1, 1]
    if "cage_force" in ds:
        a.plot(t_ms, ds.cage_force.sel(roller=1, end="a"), lw=0.8, label="end a")
        a.plot(t_ms, ds.cage_force.sel(roller=1, end="b"), lw=0.8, label="end b")
        a.set(ylabel="pocket force [N]", title="roller 1: cage pocket forces")
        a.legend(fontsize=8)
    else:
        a.text(0.5, 0.5, "cage switched off", ha="center", transform=a.transAxes)
    a.set(xlabel="time [ms]")
    fig.suptitle(ds.attrs.get("title", "bearingdae"), fontsize=10)
    return save_figure(fig, path)


def save_figure(fig, path: str | Path) -> Path:
    """Write ``fig`` atomically (bearingdae.util.atomic: a temporary beside ``path``, then rename),
    so that an error or a kill while saving never leaves a partial image at ``path``; the
    format follows the suffix as in ``savefig`` (PNG without one); the figure is closed."""
    import matplotlib
    import matplotlib.pyplot as plt

    from ..util.atomic import atomic_write

    path = Path(path)
    fmt = path.suffix.lstrip(".").lower() or matplotlib.rcParams["savefig.format"]
    try:
        with atomic_write(path) as tmp:  # the temporary's name ends in .part: give the format
            fig.savefig(tmp, format=fmt, dpi=110)
    finally:
        plt.close(fig)
    return path


# ---------------------------------------------------------------------------------------------
# The paper's figures (Yang et al. 2024, Figs 11-24) from result files
# ---------------------------------------------------------------------------------------------
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
RAD_S_TO_RPM = 60.0 / (2.0 * np.pi)
#: a run whose cage speed changes by more than this fraction of the epicyclic speed across the
#: recorded window is drawn as "not steady" (open marker) in the cage-speed figure
STEADY_DRIFT = 0.002


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def is_sweep(ds: xr.Dataset) -> bool:
    """A sweep Dataset (bearingdae.studies.sweep) rather than a single run."""
    return "sweep_axes" in ds.attrs


def sweep_dims(ds: xr.Dataset) -> list[str]:
    import json

    return [a["dim"] for a in json.loads(ds.attrs.get("sweep_axes", "[]")) if a["dim"] in ds.dims]


def orbit_view(ds: xr.Dataset) -> xr.Dataset:
    """Quantities against the azimuth of one roller over one orbit: a dynamic run is
    phase-folded (:func:`bearingdae.results.analysis.one_orbit`); a sweep file already holds them."""
    from .analysis import one_orbit

    if "azimuth" in ds.dims:
        return ds
    if "time" in ds.dims:
        return one_orbit(ds)
    raise ValueError("the file holds no dynamic run (no time or azimuth dimension); the orbit "
                     "figures need `bearingdae run` or `bearingdae sweep` output")


def available_figures(ds: xr.Dataset) -> list:
    """Default figures for a file: a sweep's ``figures`` attribute (+ 'trends' for a one-axis
    sweep), the single-orbit Figs 12-17 for a run."""
    import json

    if is_sweep(ds):
        figs = list(json.loads(ds.attrs.get("figures", "[]")))
        if len(sweep_dims(ds)) == 1:
            figs.append("trends")
        return figs
    return [12, 13, 14, 15, 16, 17]


def _axis_label(ds: xr.Dataset, dim: str) -> str:
    shown = ds[dim].attrs.get("display_units", "")
    return f"{dim} [{shown}]" if shown else dim


def _value_label(ds: xr.Dataset, dim: str, value) -> str:
    shown = ds[dim].attrs.get("display_units", "")
    v = f"{value:g}" if isinstance(value, (float, np.floating, int, np.integer)) else str(value)
    return f"{v} {shown}".strip()


def _one_axis(ds: xr.Dataset, number) -> str:
    dims = sweep_dims(ds)
    if len(dims) != 1:
        raise ValueError(f"figure {number} overlays the runs of a one-axis sweep; this file has "
                         f"axes {dims or 'none'} (use --select KEY=VALUE to fix the others)")
    return dims[0]


def _single(ds: xr.Dataset, number) -> xr.Dataset:
    o = orbit_view(ds)
    dims = sweep_dims(ds) if is_sweep(ds) else []
    if dims:
        raise ValueError(f"figure {number} shows one run; this sweep has axes {dims}: pick a run "
                         f"with --select, e.g. --select {dims[0]}={ds[dims[0]].values[0]}")
    return o


def _slices(ax, da: xr.DataArray, scale: float = 1.0) -> None:
    cmap = _plt().cm.viridis
    k = da.sizes["slice"]
    for i, s in enumerate(da.slice.values):
        ax.plot(da.azimuth, da.sel(slice=s) * scale, lw=0.9,
                color=cmap(i / max(1, k - 1)), label=f"λ = {s}")


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
        axs[1].legend(fontsize=6, ncol=2)
    elif number == 13:
        axs = fig.subplots(1, 2)
        for ax, name, tag in zip(axs, ("spin_speed", "orbit_speed"), ("(a) spin", "(b) orbit")):
            ax.plot(o.azimuth, o[name] * RAD_S_TO_RPM, "k", lw=0.9)
            _orbit_axes(ax, f"{tag} speed [r/min]")
    elif number == 14:
        ax = fig.subplots()
        ax.plot(o.azimuth, np.degrees(o.skew_angle), "k", lw=0.9)
        _orbit_axes(ax, "skew angle θz [deg]")
    elif number == 17:
        ax = fig.subplots()
        for end in ("a", "b"):
            ax.plot(o.azimuth, o.cage_force.sel(end=end), lw=0.9, label=f"end {end}")
        _orbit_axes(ax, "pocket force on roller [N]")
        ax.legend(fontsize=8)


def _need_orbits(ds: xr.Dataset, names) -> None:
    """Overlay figures draw the one-orbit curves a sweep stores per run; a sweep whose runs
    are shorter than one orbit of a roller has none (summaries only)."""
    if not any(n in ds for n in names):
        raise ValueError(f"needs the one-orbit curves ({', '.join(names)}), "
                         "which this file does not hold: its runs are shorter than one orbit "
                         "of a roller (numerics.cage_revolutions >= 1.25 gives one)")


def _fig_overlay(ds: xr.Dataset, number: int, fig) -> None:
    dim = _one_axis(ds, number)
    _need_orbits(ds, {18: ["skew_angle"], 22: ["skew_angle"], 19: ["cage_force"],
                      23: ["cage_force"]}.get(number, ["spin_speed", "orbit_speed"]))
    cmap = _plt().cm.plasma
    n = ds.sizes[dim]
    colours = [cmap(0.85 * i / max(1, n - 1)) for i in range(n)]
    if number in (18, 22):
        axs = [fig.subplots()]
        panels = [("skew_angle", None, "skew angle θz [deg]", np.degrees)]
    elif number in (19, 23):
        axs = fig.subplots(1, 2)
        panels = [("cage_force", "a", "(a) pocket force, end a [N]", None),
                  ("cage_force", "b", "(b) pocket force, end b [N]", None)]
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
    axs[-1].legend(fontsize=7, title=dim, title_fontsize=7)


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
    axs[0].legend(fontsize=6, ncol=2)


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
    ax.legend(fontsize=8, loc="lower right")


def _fig_trends(ds: xr.Dataset, number, fig) -> None:
    dim = _one_axis(ds, "trends")
    panels = [("cage_slip_ratio", 100.0, "cage slip [%]"),
              ("skew_amplitude_rad", 180 / np.pi, "skew amplitude [deg]"),
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


def figure(ds: xr.Dataset, number, path: str | Path) -> Path:
    """Draw paper figure ``number`` (11-24) or ``"trends"`` (sweep summaries against the
    axis) from a run or sweep Dataset into the PNG ``path``."""
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
    fig.suptitle(f"{caption}\n{title}", fontsize=9)
    return save_figure(fig, path)


def skidmap_figure(ds: xr.Dataset, path: str | Path) -> Path:
    """Skid map PNG (bearingdae/studies/skidmap.py): filled contours of the steady cage slip [%] over
    radial load (x) and speed (y), the skid boundary (cage slip = ``skid_boundary_cage_slip``)
    as a thick line, and the computed points: filled = steady, open = hit the warm-up cap,
    x = failed or missing."""
    plt = _plt()
    slip = ds.cage_slip_ratio.transpose("speed_rpm", "radial_load_N").values * 100.0
    loads, speeds = ds.radial_load_N.values, ds.speed_rpm.values
    bound = float(ds.attrs.get("skid_boundary_cage_slip", 0.01)) * 100.0
    fig, ax = plt.subplots(figsize=(6.8, 4.8), constrained_layout=True)
    masked = np.ma.masked_invalid(slip)
    note = ""
    if masked.count() >= 4 and np.ptp(masked.compressed()) > 0:
        top = max(float(masked.max()), bound * 1.01)
        low = min(float(masked.min()), 0.0)
        levels = np.unique(np.concatenate([np.linspace(low, top, 12), [bound]]))
        cs = ax.contourf(loads, speeds, masked, levels=levels, cmap="viridis_r")
        fig.colorbar(cs, ax=ax, label="cage slip [%]")
        if masked.min() < bound < masked.max():
            ax.contour(loads, speeds, masked, levels=[bound], colors="r", linewidths=2.0)
            ax.plot([], [], "r-", lw=2, label=f"skid boundary: cage slip = {bound:g} %")
        else:  # say so: a map without the line is an answer too
            side = "below" if masked.max() <= bound else "above"
            note = f"\ncage slip {side} {bound:g} % at every point: no skid boundary here"
    L, S = np.meshgrid(loads, speeds)
    steady = ds.steady_state_reached.transpose("speed_rpm", "radial_load_N").values
    done = ds.status.transpose("speed_rpm", "radial_load_N").values == "completed"
    ok = done & (steady == 1)
    ax.plot(L[ok], S[ok], "ko", ms=4, label="steady", clip_on=False)
    if (done & ~ok).any():
        ax.plot(L[done & ~ok], S[done & ~ok], "o", mfc="white", mec="k", ms=5,
                label="not steady (cap reached)", clip_on=False)
    if (~done).any():
        ax.plot(L[~done], S[~done], "kx", ms=6, label="failed / missing", clip_on=False)
    for i, j in zip(*np.nonzero(done)):
        if np.isfinite(slip[i, j]):
            ax.annotate(f"{slip[i, j]:.2f}", (L[i, j], S[i, j]), fontsize=6,
                        xytext=(3, 3), textcoords="offset points", annotation_clip=False)
    ax.set(xlabel="radial load [N]", ylabel="inner-ring speed [r/min]",
           title=str(ds.attrs.get("title", "skid map")).removeprefix("bearingdae ") + note)
    ax.legend(fontsize=7, loc="upper right")
    return save_figure(fig, path)
