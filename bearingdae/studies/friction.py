"""Friction maps: the steady total friction torque over speed x radial load.

Pipeline place: a scene -> **a speed x load sweep** (bearingdae/studies/sweep: one task per
point, each run kept as it completes, resumable) with ``numerics.until_steady`` and the
torque-balance start (as the skid maps, studies/skidmap.py) -> the mean, over the recorded
window, of each run's power loss by source (results/engineering.py, physics/power.py) ->
one Dataset on (speed_rpm, radial_load_N).

The friction torque referred to the inner ring is T = Σ_s P_s / ω_i (physics/power.py); the
map holds its window mean, the mean drive torque beside it (they differ by the kinetic energy
the window stores, ≈ 0 when steady), the mean per source, and the share of the lubricant's
drag (orbit drag and churning of the oil-air mixture, :data:`DRAG_SOURCES`). A catalogue model
gives one number per (speed, load): the torque to hold against it (docs/user-guide.md,
"Friction, power loss and temperature against the catalogue"), with or without the drag,
which catalogues give only for an oil bath.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from ..analysis.result_variables import cf_attrs, run_variable

#: every friction-map run (the caller's overrides win): a pure radial load, steady warm-up in
#: half-revolution blocks from the torque-balance start (capped at 20 revolutions), one cage
#: revolution recorded
DEFAULT_OVERRIDES = {"operating.moment_Nm": 0.0,
                     "numerics.until_steady": True, "numerics.initial_speeds": "torque_balance",
                     "numerics.warmup_cage_revolutions": 0.0,
                     "numerics.steady_block_cage_revolutions": 0.5,
                     "numerics.max_warmup_cage_revolutions": 20.0,
                     "numerics.cage_revolutions": 1.0,
                     "numerics.samples_per_cage_revolution": 200}

#: the power-loss sources of the lubricant's drag (physics/lubricant.py, theory.md §9)
DRAG_SOURCES = ("orbit_drag", "roller_churning", "cage_churning")

#: map variable -> (units, long_name)
MAP_VARIABLES = {
    "friction_torque_N_m": ("N m", "mean total friction torque referred to the inner ring "
                            "(sum of the power-loss sources / inner-ring speed)"),
    "drag_torque_N_m": ("N m", "mean friction torque of the lubricant's drag (orbit drag "
                        "and churning), part of friction_torque_N_m"),
    "drive_torque_N_m": ("N m", "mean drive torque of the inner ring"),
    "power_loss_W": ("W", "mean total power loss"),
    "cage_slip_ratio": run_variable("cage_slip_ratio"),
    "steady_state_reached": run_variable("steady_state_reached"),
    "run_cpu_time_s": ("s", "CPU time of the worker for the run"),
}


def make_sweep(case: str, speeds_rpm, loads_N, overrides: dict | None = None,
               name: str | None = None):
    """The :class:`bearingdae.studies.sweep.Sweep` of the map (validates every point's scene)."""
    from ..scene import resolve_case
    from .sweep import sweep_from_dict

    path = resolve_case(case)
    data = {"title": f"friction map: {path.stem}", "base": str(path.resolve()),
            "overrides": {**DEFAULT_OVERRIDES, **(overrides or {})},
            "axes": {"operating.speed_rpm": [float(s) for s in speeds_rpm],
                     "operating.radial_load_N": [float(f) for f in loads_N]}}
    return sweep_from_dict(data, origin=f"friction map {case}",
                           name=name or f"{path.stem}_friction")


def _source_dim(ds: xr.Dataset) -> str:
    return next(d for d in ds.power_loss_W.dims if d != "time")


def run_means(path: Path) -> dict[str, float | dict[str, float]]:
    """Window means of one run file: total friction and drive torque [N m], total power
    loss [W] and the power by source (trapezoids over the recorded times)."""
    with xr.open_dataset(path) as ds:
        t = ds.time.values
        span = t[-1] - t[0]

        def mean(v):
            return np.trapezoid(np.asarray(v), t, axis=0) / span

        dim = _source_dim(ds)
        by_source = mean(ds.power_loss_W.transpose("time", dim).values)
        ring = mean(ds.inner_ring_speed.values) if "inner_ring_speed" in ds else np.nan
        drag = [s for s in DRAG_SOURCES if s in ds[dim].values]
        return {"friction_torque_N_m": float(mean(ds.friction_torque_N_m.sum(dim).values)),
                "drag_torque_N_m": float(mean(ds.friction_torque_N_m.sel({dim: drag})
                                              .sum(dim).values)),
                "drive_torque_N_m": float(mean(ds.drive_torque_N_m.values)),
                "power_loss_W": float(by_source.sum()),
                "inner_ring_speed_rad_s": float(ring),
                "by_source_W": dict(zip(map(str, ds[dim].values), map(float, by_source)))}


def map_dataset(sweep_ds: xr.Dataset, folder: Path) -> xr.Dataset:
    """The friction map from a finished sweep Dataset (``folder``: where its run_file paths
    start); points that did not complete are nan."""
    dims = ("speed_rpm", "radial_load_N")
    sw = sweep_ds.transpose(*dims)
    shape = sw.status.shape
    values = {k: np.full(shape, np.nan) for k in MAP_VARIABLES}
    sources: dict[str, np.ndarray] = {}
    for i in np.ndindex(shape):
        f = str(sw.run_file.values[i])
        if sw.status.values[i] != "completed" or not f:
            continue
        means = run_means(folder / f)
        for k in ("friction_torque_N_m", "drag_torque_N_m", "drive_torque_N_m", "power_loss_W"):
            values[k][i] = means[k]
        for s, p in means["by_source_W"].items():
            sources.setdefault(s, np.full(shape, np.nan))[i] = p
    values["cage_slip_ratio"] = sw.cage_slip_ratio.values
    values["run_cpu_time_s"] = sw.run_cpu_time_s.values
    if "steady_state_reached" in sw:
        values["steady_state_reached"] = sw.steady_state_reached.values
    data = {k: xr.Variable(dims, np.asarray(v, float), cf_attrs(k, *MAP_VARIABLES[k]))
            for k, v in values.items()}
    names = sorted(sources)
    data["power_loss_by_source_W"] = xr.Variable(
        dims + ("loss_source",), np.stack([sources[s] for s in names], axis=-1)
        if names else np.full(shape + (0,), np.nan),
        {"units": "W", "long_name": "mean power loss by source"})
    coords = {d: sw[d].variable for d in dims}
    coords["loss_source"] = xr.Variable("loss_source", np.array(names, dtype=str),
                                        {"long_name": "power loss source"})
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update({"title": f"bearingdae friction map: {sweep_ds.attrs.get('sweep_name', '')}",
                     "scene_toml": sweep_ds.attrs.get("scene_toml", ""),
                     "sweep_toml": sweep_ds.attrs.get("sweep_toml", "")})
    return ds


def run_friction_map(case: str, speeds_rpm, loads_N, output: str | Path,
                     overrides: dict | None = None, **sweep_options) -> xr.Dataset:
    """Run (or resume) the map's sweep, written to ``output`` with its runs in
    ``<output stem>_runs/``; returns the map Dataset (:func:`map_dataset`).
    ``sweep_options`` go to :func:`bearingdae.studies.sweep.run_sweep`."""
    from .sweep import run_sweep

    output = Path(output)
    sweep = make_sweep(case, speeds_rpm, loads_N, overrides, name=output.stem)
    sweep_ds = run_sweep(sweep, output, **sweep_options)
    return map_dataset(sweep_ds, output.parent)
