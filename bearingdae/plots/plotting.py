"""Figures from a result Dataset only (never from solver internals): the overview of a run, the
skid map; the paper's figures are in :mod:`.paper_figures` (re-exported here).

Pipeline place: plots. Every figure is written by :func:`save_figure` (atomic).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from ..analysis.result_variables import value as result_value
from .figure_common import (END_LABELS, POCKET_SIGN, RAD_S_TO_RPM, SKEW_SCALE, SKEW_UNIT,
                            closed_on_failure, fixed_panels, room_for_titles,
                            _plt, envelope, outside_legend, save_figure, slice_colours, slice_key,
                            time_axis, wrap_title)
from .paper_figures import (  # noqa: F401  (the command line and the paper set find them here)
    PAPER_CAPTIONS,
    STEADY_DRIFT,
    available_figures,
    figure,
    is_sweep,
    orbit_view,
    selected_point,
    sweep_dims,
)


#: Samples read at a time from a file when a figure takes a series out of a variable: each
#: read of a lazily opened file allocates a multiple of what it reads (netCDF4 and HDF5
#: buffers), so a long record is read in pieces (the figure's memory stays bounded).
READ_SAMPLES = 8192
#: height [in] of a panel of the overview (its width is 6 in)
PANEL_IN = 3.75


def _read(da: xr.DataArray) -> np.ndarray:
    """The values of a time series (a selection of a lazily opened file, or in memory),
    read :data:`READ_SAMPLES` samples at a time."""
    n = da.sizes.get("time", 0)
    if n <= READ_SAMPLES:
        return np.asarray(da.values)
    return np.concatenate([np.asarray(da.isel(time=slice(a, a + READ_SAMPLES)).values)
                           for a in range(0, n, READ_SAMPLES)], axis=da.dims.index("time"))


@closed_on_failure
def overview(ds: xr.Dataset, path: str | Path) -> Path:
    """Four-panel overview PNG of a dynamic run: cage and roller-1 orbit speed [r/min], skew of
    every fourth roller [mrad], the slice loads of roller 1 on the inner race (keyed by a
    colour bar of the slices, ends named) and roller 1's pocket forces (sign stated); with a
    dynamic ring two more: its displacement [µm] and its displacement spectrum with the
    characteristic frequencies (analysis/spectrum.py); with flanges two more: roller 1's
    end-flange forces and the flanges' friction power."""
    plt = _plt()
    # a dynamic ring (its acceleration is kept) with its motion kept: motion, spectrum below
    ring = "ring_acceleration" in ds and "ring_displacement" in ds
    flange = "flange_force" in ds and "flange_friction_power" in ds  # flanges: a row below
    rows = 2 + ring + flange
    # a subfigure per panel, each with room for its own legend or colour bar
    fig, panels, ax = fixed_panels(plt, rows, 2, 6.0, PANEL_IN,
                                   ds.attrs.get("title", "bearingdae"))
    t_ms, t_label, record_ms = time_axis(ds)
    r1 = "roller 1"
    if "start_azimuth" in ds.coords:
        deg = np.degrees(float(ds.start_azimuth.sel(roller=1)))
        r1 += f" (θ = {deg:.0f}° at the first sample)"
    a = ax[0, 0]
    if "cage_speed" in ds:
        a.plot(*envelope(t_ms, _read(ds.cage_speed) * RAD_S_TO_RPM), "k", lw=1.5,
               label="cage")
    if "orbit_speed" in ds:
        a.plot(*envelope(t_ms, _read(ds.orbit_speed.sel(roller=1)) * RAD_S_TO_RPM), lw=0.8,
               label="roller 1 orbit")
    epi = result_value(ds, "epicyclic_cage_speed_rad_s", None)
    if epi:
        a.axhline(epi * RAD_S_TO_RPM, color="r", ls="--", lw=0.8, label="epicyclic")
    a.set(ylabel="speed [r/min]", title="cage and orbit speed")
    outside_legend(a)
    a = ax[0, 1]
    if "skew_angle" in ds:
        for j in ds.roller.values[:: max(1, ds.sizes["roller"] // 5)]:
            a.plot(*envelope(t_ms, _read(ds.skew_angle.sel(roller=j)) * SKEW_SCALE), lw=0.8,
                   label=f"roller {j}")
        a.set(ylabel=f"skew angle [{SKEW_UNIT}]", title="roller skew")
        outside_legend(a)
    else:
        a.text(0.5, 0.5, "skew switched off", ha="center", transform=a.transAxes)
    a = ax[1, 0]
    if "contact_force" in ds:
        q = ds.contact_force.sel(roller=1, race="inner")
        q = q.copy(data=_read(q))  # one read of a file
        for s, colour in zip(q.slice.values, slice_colours(q.sizes["slice"])):
            a.plot(*envelope(t_ms, q.sel(slice=s).values), lw=0.8, color=colour)
        a.set(ylabel="slice contact force [N]", title=f"{r1}, inner race: slice loads")
        slice_key(panels[1, 0], a, q.sizes["slice"])
    a = ax[1, 1]
    if "cage_force" in ds:
        for end in ("a", "b"):
            a.plot(*envelope(t_ms, _read(ds.cage_force.sel(roller=1, end=end))), lw=0.8,
                   label=END_LABELS[end])
        a.set(ylabel=f"pocket force [N]\n({POCKET_SIGN})", title=f"{r1}: cage pocket forces")
        outside_legend(a)
    else:
        a.text(0.5, 0.5, "cage switched off", ha="center", transform=a.transAxes)
    if ring:
        from .plot_spectrum import draw_spectrum

        a = ax[2, 0]
        for d in ("radial", "tangential"):
            a.plot(*envelope(t_ms, _read(ds.ring_displacement.sel(direction=d)) * 1e6),
                   lw=0.8, label=d)
        a.set(ylabel="ring displacement [µm]", title="inner ring (dynamic)")
        outside_legend(a)
        try:
            draw_spectrum(ax[2, 1], ds, "ring_displacement", log=True)
        except ValueError as exc:  # too short a record for a spectrum: say so in the panel
            ax[2, 1].text(0.5, 0.5, str(exc), ha="center", wrap=True, fontsize=8,
                          transform=ax[2, 1].transAxes)
    if flange:  # roller end-flange contacts (docs/theory.md §16)
        a, b = ax[rows - 1]
        for end in ("a", "b"):
            a.plot(t_ms, ds.flange_force.sel(roller=1, end=end), lw=0.8, label=END_LABELS[end])
        a.set(ylabel="flange force [N]", title=f"{r1}: end-flange contact forces")
        outside_legend(a)
        b.plot(t_ms, ds.flange_friction_power, "k", lw=0.8)
        b.set(ylabel="power [W]", title="friction power of the end-flange contacts")
    room_for_titles(panels, ax, PANEL_IN)
    for a in (ax[:2].ravel().tolist() + ([ax[2, 0]] if ring else [])
              + (ax[rows - 1].tolist() if flange else [])):
        a.set_xlabel(t_label, fontsize=9)
        if record_ms is not None:
            a.axvline(record_ms, color="0.5", ls=":", lw=0.8)
    return save_figure(fig, path)


@closed_on_failure
def skidmap_figure(ds: xr.Dataset, path: str | Path) -> Path:
    """Skid map PNG (bearingdae/studies/skidmap.py): filled contours of the steady cage slip
    [%] over radial load (x) and speed (y), the skid boundary (cage slip =
    ``skid_boundary_cage_slip``) as a thick line, and the computed points, each with its slip:
    filled = steady, open = hit the warm-up cap, x = failed or missing (keyed below the map)."""
    from matplotlib.ticker import MaxNLocator

    plt = _plt()
    slip = ds.cage_slip_ratio.transpose("speed_rpm", "radial_load_N").values * 100.0
    loads, speeds = ds.radial_load_N.values, ds.speed_rpm.values
    bound = float(ds.attrs.get("skid_boundary_cage_slip", 0.01)) * 100.0
    fig, ax = plt.subplots(figsize=(6.8, 4.8), constrained_layout=True)
    masked = np.ma.masked_invalid(slip)
    note = ""
    if masked.count() >= 4 and np.ptp(masked.compressed()) > 0:
        # the colour scale spans the data (and the boundary where the data crosses it)
        low, top = min(float(masked.min()), 0.0), float(masked.max())
        crosses = masked.min() < bound < masked.max()
        levels = MaxNLocator(12).tick_values(low, top)
        if crosses:
            levels = np.unique(np.concatenate([levels, [bound]]))
        cs = ax.contourf(loads, speeds, masked, levels=levels, cmap="viridis_r")
        fig.colorbar(cs, ax=ax, label="cage slip [%]")
        if crosses:
            ax.contour(loads, speeds, masked, levels=[bound], colors="r", linewidths=2.0)
            ax.plot([], [], "r-", lw=2, label=f"skid boundary: cage slip = {bound:g} %")
        else:  # say so: a map without the line is an answer too
            side = "below" if masked.max() <= bound else "above"
            note = f"\ncage slip {side} {bound:g} % at every point: no skid boundary here"
    # room around the grid for the points and their values (contourf fills the grid only)
    for lim, v in ((ax.set_xlim, loads), (ax.set_ylim, speeds)):
        pad = 0.06 * float(np.ptp(v)) or 1.0
        lim(float(v.min()) - pad, float(v.max()) + pad)
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
    ax.set(xlabel="radial load [N]", ylabel="inner-ring speed [r/min]")
    title = str(ds.attrs.get("title", "skid map")).removeprefix("bearingdae ") + note
    ax.set_title(wrap_title(title, fig, 10), fontsize=10)
    fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncol=4, fontsize=7,
               title="cage slip [%] printed at each point", title_fontsize=7)
    return save_figure(fig, path)

