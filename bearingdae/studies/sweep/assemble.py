"""Assembling the sweep Dataset from the run store: axes as dimensions, per-run summaries.

Pipeline place: studies -> results; steady-state summaries (analysis), status/error and one
orbit per run, with CF units for the axes.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import xarray as xr

from ...scene.overrides import field_of
from .parse import Axis, Sweep
from .signals import record_signals, stack_signals
from .store import RunStore


# ---------------------------------------------------------------------------------------------
# Assembling the sweep Dataset
# ---------------------------------------------------------------------------------------------
#: attributes of an until_steady run (bearingdae/run/steady.py) stored per sweep point
STEADY_VARIABLES = {
    "steady_state_reached": ("1", "1 if the warm-up met the steady-state criterion "
                             "(numerics.until_steady), 0 if it hit the cap; NaN: not asked"),
    "warmup_cage_revolutions_used": ("1", "warm-up cage revolutions run before recording"),
    "steady_last_change": ("1", "change of the block-mean cage speed over the last warm-up "
                           "block / epicyclic speed"),
    "steady_remaining_estimate": ("1", "extrapolated remaining change of the cage speed / "
                                  "epicyclic speed (0: fluctuating, no drift)"),
}
_AXIS_UNITS = {"_rpm": ("min-1", "r/min"), "_Nm": ("N m", "N·m"), "_N": ("N", "N"),
               "_mm": ("mm", "mm"), "_um": ("um", "µm"), "_nm": ("nm", "nm"),
               "_GPa": ("GPa", "GPa"), "_kg_m3": ("kg m-3", "kg/m³"), "_Pa_s": ("Pa s", "Pa·s"),
               "_N_m": ("N m-1", "N/m"), "_s_m": ("s m-1", "s/m"), "_m_s": ("m s-1", "m/s")}


def axis_units(key: str) -> tuple[str, str]:
    """(CF units, display units) of a scene key from its unit suffix ('1' if none)."""
    for suffix, units in sorted(_AXIS_UNITS.items(), key=lambda kv: -len(kv[0])):
        if key.endswith(suffix):
            return units
    return "1", ""


def _coord(axis: Axis) -> xr.Variable:
    units, shown = axis_units(axis.key)
    field = field_of(axis.key)
    desc = (field.description if field is not None else None) or axis.key
    return xr.Variable(axis.dim, np.asarray(axis.values), {
        "units": units, "long_name": desc, "scene_key": axis.key, "display_units": shown})


def assemble(sweep: Sweep, store: RunStore, relative_to: Path | None = None) -> xr.Dataset:
    """The sweep Dataset from the run store: summaries, status/error, one orbit per run."""
    from ...analysis.summary import SUMMARY_VARIABLES, one_orbit, summary
    from ...analysis.guards import findings
    from ...results import base_attrs
    from ...analysis.result_variables import cf_attrs, results_of, upgrade, value as run_value

    shape = sweep.shape
    dims = tuple(a.dim for a in sweep.axes)
    status = np.full(shape, "missing", dtype=object)
    error = np.full(shape, "", dtype=object)
    files = np.full(shape, "", dtype=object)
    keys = np.full(shape, "", dtype=object)
    roller = np.zeros(shape, dtype=np.int64)
    wall = np.full(shape, np.nan)
    cpu = np.full(shape, np.nan)
    plausible = np.full(shape, "", dtype=object)
    summ = {n: np.full(shape, np.nan) for n in SUMMARY_VARIABLES}
    steady = {n: np.full(shape, np.nan) for n in STEADY_VARIABLES}  # until_steady runs only
    results: dict[str, np.ndarray] = {}  # each run's 0-d result variables, along the axes
    templates: dict[str, xr.DataArray] = {}  # (their attributes)
    orbits: dict[tuple, xr.Dataset] = {}
    signals: dict[tuple, dict] = {}  # [sweep] signals: each run's recorded series
    for pt in sweep.points:
        i = pt.index
        keys[i] = pt.key
        st = store.status(pt.key)
        if st == "completed":
            path = store.result(pt.key)
            files[i] = os.path.relpath(path, relative_to) if relative_to else str(path)
            with xr.open_dataset(path) as ds:
                ds = upgrade(ds.load())  # (a run file of the older format: attributes)
            status[i] = "completed"
            for name, value in summary(ds).items():
                summ[name][i] = value
            for name in STEADY_VARIABLES:
                steady[name][i] = float(run_value(ds, name))
            wall[i] = float(json.loads(ds.attrs.get("solver_statistics", "{}")).get(
                "wall_time_s", np.nan))  # (provenance: the solver's statistics)
            cpu[i] = float(run_value(ds, "run_cpu_time_s"))
            for name, number in results_of(ds).items():
                results.setdefault(name, np.full(shape, np.nan))[i] = number
                templates.setdefault(name, ds[name])
            plausible[i] = ", ".join(sorted({f["check"] for f in findings(ds)}))
            if sweep.settings.signals:
                signals[i] = record_signals(ds, sweep.settings.signals)
            try:
                orbit = one_orbit(ds, sweep.settings.orbit_points, sweep.settings.orbit_roller)
                orbits[i] = orbit
                roller[i] = orbit.attrs["roller"]
            except ValueError:  # window shorter than an orbit: summaries only (orbit_roller 0)
                pass
        elif st == "failed":
            status[i] = "failed"
            error[i] = str(store.read_failure(pt.key).get("error", "unknown error"))
    coords = {a.dim: _coord(a) for a in sweep.axes}
    data = {
        # labels: text, no units (as the other char variables: race, end)
        "status": xr.Variable(dims, status.astype(str), {
            "long_name": "run status: completed, failed or missing (not run yet)"}),
        "error": xr.Variable(dims, error.astype(str), {
            "long_name": "error of a failed run"}),
        "run_key": xr.Variable(dims, keys.astype(str), {
            "long_name": "SHA-256 (16 hex) of the run's scene TOML without title"}),
        "run_file": xr.Variable(dims, files.astype(str), {
            "long_name": "NetCDF file of the run's full time series (relative to "
            "this file)"}),
        "plausibility_warnings": xr.Variable(dims, plausible.astype(str), {
            "long_name": "plausibility checks the run tripped (bearingdae.analysis.guards; "
            "details in the run file's plausibility_warnings attribute)"}),
        "run_wall_time_s": xr.Variable(dims, wall, {"units": "s",
                                                    "long_name": "IDA wall time of the run"}),
        "run_cpu_time_s": xr.Variable(dims, cpu, {"units": "s", "long_name":
                                                  "CPU time of the worker for the whole run"}),
        "orbit_roller": xr.Variable(dims, roller, {
            "units": "1", "long_name": "roller whose orbit is stored (0: none)"}),
    }
    for name, (units, long_name) in SUMMARY_VARIABLES.items():
        data[name] = xr.Variable(dims, summ[name], {"units": units, "long_name": long_name})
    for name, (units, long_name) in STEADY_VARIABLES.items():
        if np.isfinite(steady[name]).any():
            data[name] = xr.Variable(dims, steady[name], cf_attrs(name, units, long_name))
    # the runs' result variables along the axes (the same names, units and error links as in a
    # run file: analysis/result_variables.py); where a summary above has the same name, the
    # run's own value
    for name, values in results.items():
        if name in dims:  # a swept operating point: the axis holds it
            continue
        attrs = dict(templates[name].attrs)
        if attrs.get("ancillary_variables") not in results:
            attrs.pop("ancillary_variables", None)
        if "flag_values" in attrs:  # a flag's values in the stacked type (NaN: no run)
            attrs["flag_values"] = np.asarray(attrs["flag_values"]).astype(values.dtype)
        data[name] = xr.Variable(dims, values, attrs)
    if orbits:
        template = next(iter(orbits.values()))
        for name, var in template.data_vars.items():
            arr = np.full(shape + var.shape, np.nan)
            for i, orbit in orbits.items():
                if name in orbit:
                    arr[i] = orbit[name].values
            attrs = dict(var.attrs)
            attrs["long_name"] = f"{attrs.get('long_name', name)}, one roller over one orbit"
            data[name] = xr.Variable(dims + var.dims, arr, attrs)
        for c in ("azimuth", "slice", "race", "end", "slice_position", "slice_position_bounds"):
            if c in template.coords:
                coords[c] = template[c].variable
    series, series_coords = stack_signals(shape, dims, signals)
    data.update(series)
    coords.update({k: v for k, v in series_coords.items() if k not in coords})
    ds = xr.Dataset(data, coords=coords)
    attrs = base_attrs(sweep.base_scene, "parameter sweep")
    # (the operating point is in each run's variables, along the axes, and in sweep_toml)
    attrs.update({
        "title": f"bearingdae sweep: {sweep.title}",
        "sweep_name": sweep.name,
        "sweep_toml": sweep.text,
        "sweep_axes": json.dumps([{"key": a.key, "dim": a.dim, "values": list(a.values)}
                                  for a in sweep.axes]),
        "figures": json.dumps(list(sweep.settings.figures)),
        "runs_total": len(sweep.points),
        "runs_completed": int((status == "completed").sum()),
        "runs_failed": int((status == "failed").sum()),
        "run_directory": (os.path.relpath(store.folder, relative_to) if relative_to
                          else str(store.folder)),
        "summary_window": "recorded window of each run (after numerics."
                          "warmup_cage_revolutions); formulas in bearingdae.analysis.summary",
    })
    ds.attrs.update(attrs)
    return ds
