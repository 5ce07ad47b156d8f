"""Steady-state summaries computed from a result Dataset only."""

from __future__ import annotations

import numpy as np
import xarray as xr


def summary(ds: xr.Dataset) -> dict[str, float]:
    """Mean cage speed vs epicyclic, cage slip ratio, max |skew|, max |slip|, peak loads."""
    out: dict[str, float] = {}
    epi = float(ds.attrs.get("epicyclic_cage_speed_rad_s", np.nan))
    out["epicyclic_cage_speed_rad_s"] = epi
    if "cage_speed" in ds and ds.sizes["time"]:
        mean = float(ds.cage_speed.mean())
        out["mean_cage_speed_rad_s"] = mean
        out["cage_slip_ratio"] = (epi - mean) / epi if epi > 0 else np.nan
    if "skew_angle" in ds and ds.sizes["time"]:
        out["max_abs_skew_rad"] = float(np.abs(ds.skew_angle).max())
    if "slip_velocity" in ds and ds.sizes["time"]:
        out["max_abs_slip_m_s"] = float(np.abs(ds.slip_velocity).max())
    if "cage_force" in ds and ds.sizes["time"]:
        out["peak_cage_force_N"] = float(np.abs(ds.cage_force).max())
    if "contact_force" in ds and ds.sizes["time"]:
        out["peak_slice_load_N"] = float(ds.contact_force.max())
    return out
