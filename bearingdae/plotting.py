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
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
