"""Skid maps: steady cage slip (and roller slip, skew, pocket force) over speed x radial load.

Pipeline place: a scene -> **a speed x load sweep** (bearingdae/studies/sweep/__init__.py: one dask task per
point, each run kept as it completes, resumable) with ``numerics.until_steady`` and the
torque-balance start (bearingdae/run/steady.py, solvers/torque_balance.py) -> one map Dataset on
(speed_rpm, radial_load_N) -> NetCDF + a contour PNG with the skid boundary.

The map answers "at which load does my bearing skid at this speed": the cage slip ratio
1 − Ω̄_c / Ω_e (bearingdae/analysis/summary.py) of the steady state at each point, and the boundary
where it equals ``boundary`` (default 1 %). Quantities per point (recorded window after the
steady warm-up): cage slip ratio, largest slice slip velocity, skew RMS over rollers and time,
peak pocket force, and whether the point met the steady criterion (points that hit the cap
are drawn with an open marker and kept in the file, never silently reported as steady).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from ..analysis.result_variables import cf_attrs, run_variable

#: defaults of every skid-map run (the user's --set wins)
DEFAULT_OVERRIDES = {"numerics.until_steady": True, "numerics.initial_speeds": "torque_balance",
                     "numerics.warmup_cage_revolutions": 0.0,
                     "numerics.cage_revolutions": 1.0}
DEFAULT_BOUNDARY = 0.01

#: map variable -> (units, long_name)
MAP_VARIABLES = {
    "cage_slip_ratio": run_variable("cage_slip_ratio"),
    "max_roller_slip_m_s": ("m s-1", "largest |slip velocity| of any slice, roller and race "
                            "in the recorded window"),
    "skew_rms_rad": ("rad", "root mean square of the roller skew angle over rollers and time"),
    "peak_pocket_force_N": ("N", "largest |pocket force| on any roller end, at every solver "
                            "step of the recorded window (cage_force_max)"),
    "steady_state_reached": run_variable("steady_state_reached"),
    "warmup_cage_revolutions_used": ("1", "warm-up cage revolutions before recording"),
    "run_wall_time_s": ("s", "IDA wall time of the run"),
}


def make_sweep(case: str, speeds_rpm, loads_N, overrides: dict | None = None):
    """The :class:`bearingdae.studies.sweep.Sweep` of the map (validates every point's scene)."""
    from ..scene import SceneError, resolve_case
    from .sweep import sweep_from_dict

    speeds, loads = [float(s) for s in speeds_rpm], [float(f) for f in loads_N]
    for name, values in (("--speeds", speeds), ("--loads", loads)):
        if len(values) < 2:
            raise SceneError(f"skidmap {name}: give at least 2 values for a map, got {values}")
    path = resolve_case(case)
    data = {"title": f"skid map: {path.stem}", "base": str(path.resolve()),
            "overrides": {**DEFAULT_OVERRIDES, **(overrides or {})},
            "axes": {"operating.speed_rpm": speeds, "operating.radial_load_N": loads}}
    return sweep_from_dict(data, origin=f"skidmap {case}", name=f"{path.stem}_skidmap")


def _skew_rms(path: Path) -> float:
    with xr.open_dataset(path) as ds:
        if "skew_angle" not in ds or ds.sizes.get("time", 0) == 0:
            return np.nan
        return float(np.sqrt((ds.skew_angle.values ** 2).mean()))


def map_dataset(sweep_ds: xr.Dataset, folder: Path, boundary: float) -> xr.Dataset:
    """The map Dataset from the sweep Dataset (``folder``: where its run_file paths start)."""
    dims = ("speed_rpm", "radial_load_N")
    sw = sweep_ds.transpose(*dims, ...)
    shape = sw.status.shape
    skew = np.full(shape, np.nan)
    for i in np.ndindex(shape):
        f = str(sw.run_file.values[i])
        if sw.status.values[i] == "completed" and f:
            skew[i] = _skew_rms(folder / f)
    values = {
        "cage_slip_ratio": sw.cage_slip_ratio.values,
        "max_roller_slip_m_s": sw.max_abs_slip_m_s.values,
        "skew_rms_rad": skew,
        "peak_pocket_force_N": (sw.peak_cage_force_N.values if "peak_cage_force_N" in sw
                                else np.full(shape, np.nan)),
        "steady_state_reached": (sw.steady_state_reached.values if "steady_state_reached" in sw
                                 else np.full(shape, np.nan)),
        "warmup_cage_revolutions_used": (sw.warmup_cage_revolutions_used.values
                                         if "warmup_cage_revolutions_used" in sw
                                         else np.full(shape, np.nan)),
        "run_wall_time_s": sw.run_wall_time_s.values,
    }
    data = {k: xr.Variable(dims, np.asarray(v, float), cf_attrs(k, *MAP_VARIABLES[k]))
            for k, v in values.items()}
    data["status"] = xr.Variable(dims, sw.status.values.astype(str), {
        "long_name": "run status: completed, failed or missing"})
    # the operating point the map does not vary: the runs' variables (result_variables.py)
    for name in ("tangential_load_N", "moment_Nm", "tangential_moment_Nm"):
        if name in sw:
            data[name] = sw[name].variable
    coords = {d: sw[d].variable for d in dims}
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update({k: v for k, v in sweep_ds.attrs.items()
                     if k in ("Conventions", "institution", "source", "references",
                              "bearingdae_version", "scene_toml", "sweep_toml",
                              "run_directory")})
    ds.attrs.update({
        "title": f"bearingdae skid map: {sweep_ds.attrs.get('sweep_name', '')}",
        "history": sweep_ds.attrs.get("history", ""),
        "skid_boundary_cage_slip": float(boundary),
        "runs_total": int(sweep_ds.attrs.get("runs_total", 0)),
        "runs_completed": int(sweep_ds.attrs.get("runs_completed", 0)),
        "runs_not_steady": int(np.sum(values["steady_state_reached"] == 0)),
    })
    return ds


def run_skidmap(case: str, speeds_rpm, loads_N, output: str | Path,
                overrides: dict | None = None, boundary: float = DEFAULT_BOUNDARY,
                scheduler: str | None = None, workers: int | None = None,
                progress: bool = True, figure: bool = True,
                **sweep_options) -> tuple[xr.Dataset, list[Path]]:
    """Run (or resume) the map; write ``output`` (NetCDF), ``output`` .png and the sweep file
    ``<output stem>_sweep.nc`` (every point's summaries beyond the map's — mean cage speed,
    skew amplitude, slip, loads — and one-orbit curves; ``bearingdae plot`` draws its trends
    at a fixed speed or load). Returns the map Dataset and the paths written (map, sweep
    file, PNG). The runs are kept in ``<output stem>_sweep_runs/``;
    ``sweep_options`` go to :func:`bearingdae.studies.sweep.run_sweep` (``retry_failed``,
    ``scheduler_timeout_s``)."""
    from ..results import save
    from .sweep import SweepIncomplete, run_sweep

    if not 0.0 < boundary < 1.0:
        raise ValueError(f"skidmap --boundary {boundary!r}: the cage slip of the skid boundary "
                         "must lie in (0, 1), e.g. 0.01 for 1 %")
    output = Path(output)
    sweep = make_sweep(case, speeds_rpm, loads_N, overrides)
    sweep_file = output.with_name(output.stem + "_sweep.nc")
    incomplete = None
    try:
        sweep_ds = run_sweep(sweep, sweep_file, scheduler=scheduler, workers=workers,
                             progress=progress, **sweep_options)
    except SweepIncomplete as exc:  # write what finished, then report
        sweep_ds, incomplete = exc.datasets[0], exc
    ds = map_dataset(sweep_ds, sweep_file.parent, boundary)
    paths = [save(ds, output), sweep_file]
    if figure:
        from ..plots.plotting import skidmap_figure

        paths.append(skidmap_figure(ds, output.with_suffix(".png")))
    if incomplete is not None:
        raise incomplete
    return ds, paths
