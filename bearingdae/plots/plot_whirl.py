"""Cage whirl figure (theory.md §17): the cage centre's orbit in its guidance clearance, and the
orbit radius and land force over time. ``bearingdae plot RUN.nc`` draws it when the run has
``cage_center``.

Stage: plots (reads a run's Dataset, writes a PNG).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from .figure_common import closed_on_failure, _plt, save_figure, wrap_title


@closed_on_failure
def orbit_figure(ds: xr.Dataset, path: str | Path) -> Path:
    """Two panels: the orbit of the cage centre [µm] with the guidance clearance circle, coloured
    by time; its radius over the clearance and the land force against time."""
    if "cage_center" not in ds:
        raise ValueError("the run has no cage_center (run with physics.cage_whirl = true)")
    plt = _plt()
    c = np.asarray(ds.cage_center.values) * 1e6
    t_ms = np.asarray(ds.time.values) * 1e3
    clearance = float(ds.attrs.get("cage_guidance_clearance_m", np.nan)) * 1e6
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 5.2), layout="constrained")
    sc = a.scatter(c[:, 0], c[:, 1], c=t_ms, s=2, cmap="viridis")
    a.plot(c[:, 0], c[:, 1], color="0.6", lw=0.4, zorder=0)
    if np.isfinite(clearance):
        th = np.linspace(0.0, 2.0 * np.pi, 361)
        a.plot(clearance * np.cos(th), clearance * np.sin(th), "r--", lw=1,
               label=f"guidance clearance ({ds.attrs.get('cage_guidance', '')})")
        a.legend(loc="upper right", fontsize=8)
    a.set_aspect("equal")
    a.set(xlabel="radial (load line) [µm]", ylabel="tangential [µm]", title="cage centre orbit")
    fig.colorbar(sc, ax=a, label="time [ms]")
    r = np.hypot(c[:, 0], c[:, 1])
    b.plot(t_ms, r / clearance if np.isfinite(clearance) else r, "k", lw=0.8,
           label="orbit radius / clearance")
    b.set(xlabel="time [ms]", ylabel="orbit radius / guidance clearance [1]")
    if "cage_land_force" in ds and float(np.nanmax(ds.cage_land_force.values)) > 0:
        b2 = b.twinx()
        b2.plot(t_ms, ds.cage_land_force.values, color="tab:orange", lw=0.6)
        b2.set_ylabel("land force [N]", color="tab:orange")
    ratio = ds.attrs.get("cage_whirl_ratio")
    b.set_title("orbit radius" + (f" (whirl ratio {float(ratio):.3g})" if ratio is not None
                                  else ""))
    fig.suptitle(wrap_title(str(ds.attrs.get("title", "bearingdae")), fig, 10), fontsize=10)
    return save_figure(fig, path)
