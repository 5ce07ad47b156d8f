"""Solver output -> labelled :class:`xarray.Dataset` -> NetCDF (last pipeline stage).

Every variable carries CF ``units`` and ``long_name``; global attributes record the package,
the scene as TOML text and the regularisation scales. :func:`save` writes NetCDF4 with
compression **atomically** (:func:`bearingdae.atomic.atomic_write`: a temporary file beside the
target, then ``os.replace``), so an interrupted write never leaves a partial file at the target
path.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import json
import signal
import threading
from pathlib import Path

import numpy as np
import xarray as xr

from . import __version__
from .atomic import atomic_write  # noqa: F401  (re-exported: results.atomic_write)
from .physics.contact import hertz_pressure

RACES = ("inner", "outer")
DIRECTIONS = ("radial", "tangential")


def _var(dims, data, units: str, long_name: str, **extra) -> xr.Variable:
    attrs = {"units": units, "long_name": long_name}
    attrs.update(extra)
    return xr.Variable(dims, np.asarray(data), attrs)


def contact_regularisation(scene) -> dict:
    """The contact-onset regularisation of a scene, as recorded in every output file."""
    return {
        "contact_onset": "s(d) = (d + sqrt(d^2 + eps^2))/2 replaces max(d, 0)",
        "contact_smoothing_m": scene.numerics.contact_smoothing_m,
    }


def base_attrs(scene, kind: str) -> dict:
    """Global attributes shared by every result file."""
    now = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")
    attrs = {
        "Conventions": "CF-1.10",
        "title": f"bearingdae {kind}: {scene.title}",
        "institution": "bearingdae (open source)",
        "source": f"bearingdae {__version__}",
        "history": f"{now} created by bearingdae {__version__} ({kind})",
        "references": "Yang, Wang, Wang & Wen, Lubricants 2024, 12(9), 317; project MODEL.md",
        "bearingdae_version": __version__,
        "scene_toml": scene.to_toml(),
        "contact_smoothing_m": scene.numerics.contact_smoothing_m,
        "regularisation": json.dumps(contact_regularisation(scene)),
        "output_precision": getattr(scene, "output_precision", "float64"),
    }
    if scene.preset_citation:
        attrs["preset_citation"] = scene.preset_citation
    return attrs


def static_dataset(scene, geometry, solution) -> xr.Dataset:
    """Dataset of a quasi-static solution (dims roller, slice, race, direction)."""
    from .system.layout import split_static

    g = geometry
    Z, k = g.rollers, g.slices
    u, beta, ring = split_static(solution.z, Z)
    cs = solution.contact
    force = np.stack([cs.load_inner_N, cs.load_outer_N], axis=-1)
    approach = np.stack([cs.approach_inner_m, cs.approach_outer_m], axis=-1)
    pressure = np.stack(
        [
            hertz_pressure(cs.load_inner_N, g.slice_width_m, g.reduced_radius_inner_m,
                           g.compliance_m2_N),
            hertz_pressure(cs.load_outer_N, g.slice_width_m, g.reduced_radius_outer_m,
                           g.compliance_m2_N),
        ],
        axis=-1,
    )
    prob = solution.problem
    coords = {
        "roller": _var("roller", np.arange(1, Z + 1), "1", "roller number"),
        "slice": _var("slice", np.arange(1, k + 1), "1", "slice number"),
        "race": _var("race", np.array(RACES), "", "raceway"),
        "direction": _var("direction", np.array(DIRECTIONS), "", "load direction"),
        "x": _var("slice", g.x_m, "m", "axial position of slice centre from roller centre"),
        "azimuth": _var("roller", prob.azimuth_rad, "rad",
                        "roller azimuth from the radial-load line, in the direction of rotation"),
    }
    data = {
        "contact_force": _var(("roller", "slice", "race"), force, "N", "slice contact force"),
        "contact_pressure": _var(("roller", "slice", "race"), pressure, "Pa",
                                 "maximum Hertz pressure of the slice"),
        "approach": _var(("roller", "slice", "race"), approach, "m",
                         "slice contact approach (positive = overlap)"),
        "roller_radial_position": _var("roller", u, "m",
                                       "roller radial position u (outward; 0 = touching the "
                                       "outer race)"),
        "roller_tilt": _var("roller", beta, "rad",
                            "roller tilt beta (positive moves the +x end outward)"),
        "ring_displacement": _var("direction", ring[:2], "m", "inner ring displacement"),
        "ring_tilt": _var("direction", ring[2:], "rad", "inner ring tilt"),
        "centrifugal_force": _var("roller", prob.centrifugal_N, "N", "roller centrifugal force"),
    }
    attrs = base_attrs(scene, "quasi-static equilibrium")
    attrs.update(
        {
            "solver": "bearingdae damped Newton (analytic Jacobian)",
            "newton_iterations": int(solution.iterations),
            "residual_max_relative": float(solution.relative_residual),
            "radial_load_N": float(prob.loads[0]),
            "tangential_load_N": float(prob.loads[1]),
            "moment_Nm": float(prob.loads[2]),
            "tangential_moment_Nm": float(prob.loads[3]),
            "speed_rpm": float(scene.operating.speed_at(0.0)),
        }
    )
    return xr.Dataset(data, coords=coords, attrs=attrs)


#: NetCDF types a result's data variables may be written as (``[output] precision``)
PRECISIONS = ("float64", "float32")


def save(ds: xr.Dataset, path: str | Path, complevel: int = 4,
         precision: str | None = None) -> Path:
    """Write ``ds`` to NetCDF4 (zlib-compressed) atomically; returns the final path.

    ``precision``: ``"float64"`` or ``"float32"`` for the floating-point *data* variables
    (default: the Dataset's ``output_precision`` attribute, set from the scene's
    ``[output] precision``, else float64). Coordinates (time, azimuth, x) stay float64: a
    float32 time would round sample times of a long run to ~1e-7 of the run's length.
    """
    path = Path(path)
    precision = precision or str(ds.attrs.get("output_precision", "float64"))
    if precision not in PRECISIONS:
        raise ValueError(f"precision = {precision!r}: allowed are {', '.join(PRECISIONS)}")
    path.parent.mkdir(parents=True, exist_ok=True)
    labels = [n for n, v in ds.variables.items()
              if v.dtype.kind in "OUS" and "units" not in v.attrs]
    if labels:  # text has no unit; say so, so that every variable lists units (ncdump -h)
        ds = ds.copy(deep=False)
        for name in labels:
            ds[name].attrs["units"] = ""
    encoding = {}
    for name, var in ds.variables.items():
        enc = encoding.setdefault(name, {})
        if var.dtype.kind in "fiu" and var.ndim > 0:
            enc.update(zlib=True, complevel=complevel)
        if var.dtype.kind == "f" and precision != "float64" and name not in ds.coords:
            enc["dtype"] = precision
        if name in ds.coords:
            enc["_FillValue"] = None  # CF 2.5.1: coordinate variables have no missing values
        if var.dtype.kind in "OUS":
            # Labels (race = inner/outer) as char arrays: CF coordinate variables are numeric
            # (CF 1.3, 6.1); xarray reads them back as the same string coordinate.
            enc["dtype"] = "S1"
    ds = _name_labels_in_coordinates(ds)
    with atomic_write(path) as tmp, _ctrl_c_deferred():
        ds.to_netcdf(tmp, format="NETCDF4", engine="netcdf4", encoding=encoding)
    return path


def _name_labels_in_coordinates(ds: xr.Dataset) -> xr.Dataset:
    """CF 6.1: a label variable (``race`` = inner/outer, written as a char array) is an
    auxiliary coordinate, tied to the data it labels by their ``coordinates`` attribute. xarray
    lists only non-index coordinates there; add the label dimensions (the NCAS cf-checker warns
    "possible incorrect declaration of a coordinate variable" otherwise). xarray reads the
    attribute back into ``encoding``: the round trip stays identical. Returns a shallow copy."""
    ds = ds.copy(deep=False)
    labels = {d for d in ds.dims if d in ds.variables and ds[d].dtype.kind in "OUS"}
    aux = [c for c in ds.coords if c not in ds.dims]
    for name, var in ds.data_vars.items():
        if not labels & set(var.dims) or "coordinates" in var.attrs:
            continue
        # xarray's own choice (non-index coordinates on a subset of the dims) plus the labels
        refs = {c for c in aux if set(ds[c].dims) <= set(var.dims)} | (labels & set(var.dims))
        ds[name].encoding = {**var.encoding, "coordinates": " ".join(sorted(map(str, refs)))}
    return ds


@contextlib.contextmanager
def _ctrl_c_deferred():
    """Hold Ctrl-C (SIGINT) until the block is done, then raise KeyboardInterrupt.

    A KeyboardInterrupt inside xarray's NetCDF write can leave its file lock held; the write's
    own clean-up then waits for that lock forever (measured: 1 of 20 SIGINTs during `bearingdae
    run` hung the process). Only the main thread receives signals, so elsewhere this is a no-op.
    """
    previous = signal.getsignal(signal.SIGINT)
    if threading.current_thread() is not threading.main_thread() or previous in (
            None, signal.SIG_IGN):  # no Python handler to defer (or Ctrl-C ignored anyway)
        yield
        return
    caught = []
    signal.signal(signal.SIGINT, lambda signum, frame: caught.append(signum))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
    if caught:
        raise KeyboardInterrupt


# ---------------------------------------------------------------------------------------------
# Dynamic results
# ---------------------------------------------------------------------------------------------
ENDS = ("a", "b")

#: name -> (dims after time, units, long_name)
DYNAMIC_VARIABLES = {
    "cage_angle": ((), "rad", "cage angle (unwrapped)"),
    "cage_speed": ((), "rad s-1", "cage angular speed"),
    "inner_ring_speed": ((), "rad s-1", "inner ring angular speed"),
    "roller_azimuth": (("roller",), "rad", "roller azimuth from the load line (unwrapped)"),
    "orbit_speed": (("roller",), "rad s-1", "roller orbit (revolution) speed"),
    "spin_speed": (("roller",), "rad s-1",
                   "roller spin speed (positive when rolling forward on the inner race)"),
    "skew_angle": (("roller",), "rad", "roller skew angle about the radial axis"),
    "skew_rate": (("roller",), "rad s-1", "roller skew rate"),
    "roller_tilt": (("roller",), "rad", "roller tilt (positive moves the +x end outward)"),
    "roller_radial_position": (("roller",), "m",
                               "roller radial position (outward; 0 = touching the outer race)"),
    "contact_force": (("roller", "slice", "race"), "N", "slice contact force"),
    "contact_pressure": (("roller", "slice", "race"), "Pa", "maximum Hertz pressure of slice"),
    "slip_velocity": (("roller", "slice", "race"), "m s-1",
                      "tangential slip velocity, race surface minus roller surface"),
    "traction_force": (("roller", "slice", "race"), "N", "slice traction force on the roller"),
    "cage_force": (("roller", "end"), "N", "pocket force on the roller end, along the "
                   "direction of rotation"),
    "ring_displacement": (("direction",), "m", "inner ring displacement"),
    "ring_tilt": (("direction",), "rad", "inner ring tilt"),
}


def dynamic_dataset(model, t, Y, diag, info: dict) -> xr.Dataset:
    """Dataset of a dynamic run. ``Y``: unscaled full states as (full_l (n, Z, 7),
    full_g (n, 6)); ``diag``: stacked kernel diagnostics; ``info``: solver attributes."""
    from .scene import OUTPUT_VARIABLES
    from .system.layout import GLOBAL, LOCAL

    scene, g = model.scene, model.geometry
    full_l, full_g = Y
    Z, k = g.rollers, g.slices
    L = {n: full_l[..., LOCAL.index(n)] for n in LOCAL}
    G = {n: full_g[..., GLOBAL.index(n)] for n in GLOBAL}
    values = {
        "cage_angle": G["cage_angle"], "cage_speed": G["cage_speed"],
        "inner_ring_speed": np.array([model.ring_speed(tt) for tt in t]),
        "roller_azimuth": L["azimuth"], "orbit_speed": L["orbit_speed"],
        "spin_speed": L["spin_speed"], "skew_angle": L["skew_angle"], "skew_rate": L["skew_rate"],
        "roller_tilt": L["tilt"], "roller_radial_position": L["radial_position"],
        "contact_force": diag["contact_force"], "contact_pressure": diag["contact_pressure"],
        "slip_velocity": diag["slip_velocity"], "traction_force": diag["traction_force"],
        "cage_force": diag["cage_force"],
        "ring_displacement": np.stack([G["ring_dr"], G["ring_dt"]], axis=-1),
        "ring_tilt": np.stack([G["ring_gr"], G["ring_gt"]], axis=-1),
    }
    wanted = scene.output_variables or tuple(OUTPUT_VARIABLES)
    # What the assembled model actually has (tilt is also dropped with a single slice).
    present = {"cage": model.layout.cage, "skew": model.layout.skew, "tilt": model.layout.tilt}
    data = {}
    for name in wanted:
        switch = OUTPUT_VARIABLES[name]
        if switch is not None and not present[switch]:
            continue
        dims, units, long_name = DYNAMIC_VARIABLES[name]
        data[name] = _var(("time",) + dims, values[name], units, long_name)
    coords = {
        "time": _var("time", t, "s", "time"),
        "roller": _var("roller", np.arange(1, Z + 1), "1", "roller number"),
        "slice": _var("slice", np.arange(1, k + 1), "1", "slice number"),
        "race": _var("race", np.array(RACES), "", "raceway"),
        "end": _var("end", np.array(ENDS), "", "roller end (a: x = +L/2, b: x = -L/2)"),
        "direction": _var("direction", np.array(DIRECTIONS), "", "load direction"),
        "x": _var("slice", g.x_m, "m", "axial position of slice centre from roller centre"),
    }
    ds = xr.Dataset(data, coords=coords)
    used = set()
    for v in ds.data_vars.values():
        used |= set(v.dims)
    ds = ds.drop_vars([c for c in ("roller", "slice", "race", "end", "direction", "x")
                       if c in ds.coords and not (set(ds[c].dims) & used)])
    attrs = base_attrs(scene, "dynamic simulation")
    attrs.update(info)
    ds.attrs.update(attrs)
    return ds


# ---------------------------------------------------------------------------------------------
# Solution -> Dataset
# ---------------------------------------------------------------------------------------------
#: Newmark's error-estimate outputs: name -> (state unknown, units, long name)
ERROR_ESTIMATES = {
    "cage_speed_error_estimate": ("cage_speed", "rad s-1", "cage speed"),
    "orbit_speed_error_estimate": ("orbit_speed", "rad s-1", "orbit speed (max over rollers)"),
    "spin_speed_error_estimate": ("spin_speed", "rad s-1", "spin speed (max over rollers)"),
    "skew_angle_error_estimate": ("skew_angle", "rad", "skew angle (max over rollers)"),
}


def error_estimate_variables(model, E: np.ndarray) -> dict:
    """Global-error estimates (n_t, N scaled; Newmark's Richardson estimate) -> Dataset
    variables in SI units, one per kind of unknown (largest magnitude over the rollers)."""
    lay = model.layout
    out = {}
    for name, (unknown, units, long_name) in ERROR_ESTIMATES.items():
        if unknown in lay.local_names:
            idx = [lay.index(unknown, j) for j in range(lay.rollers)]
        elif unknown in lay.global_names:
            idx = [lay.index(unknown)]
        else:
            continue
        val = np.abs(E[:, idx] * model.scale[idx]).max(axis=1)
        out[name] = _var("time", val, units, f"Newmark step-doubling (Richardson) estimate of "
                         f"the global error of the {long_name}",
                         comment="4/3 |y_h - y_h/2| from a second solution at half the step")
    return out


class ProjectionError(RuntimeError):
    """A sample could not be projected onto the algebraic equations; ``.dataset`` holds every
    sample projected before it."""

    def __init__(self, message: str, dataset: xr.Dataset):
        super().__init__(message)
        self.dataset = dataset


def from_solution(model, solution, solver, record_start_s: float = 0.0) -> xr.Dataset:
    """Dataset of a dynamic run: the samples of ``solution`` from ``record_start_s`` on (all of
    them when the run failed), each projected onto the algebraic equations (MODEL §5; the
    static Newton, solvers/algebraic.py) and with the kernel's diagnostics (contact forces,
    pressures, slip, traction, pocket forces); attributes from ``solver.describe()`` and
    ``solver.dataset_attrs(model, solution)``.

    A projection that fails keeps every sample projected before it: :class:`ProjectionError`
    carries that Dataset.
    """
    from .solvers.algebraic import project_algebraic
    from .solvers.static import StaticConvergenceError

    res = solution
    keep = res.t >= record_start_s - 1e-12 if res.success else np.ones(res.t.size, bool)
    t, Ys = res.t[keep], res.y[keep]
    iters = 0
    projected = []
    projection_error = None
    for tk, y in zip(t, Ys):
        try:
            y, it = project_algebraic(model, tk, y)
        except StaticConvergenceError as exc:
            projection_error = (f"projection onto the algebraic equations failed at "
                                f"t = {tk:.6g} s: {exc}")
            break
        iters += it
        projected.append(y)
    t = t[:len(projected)]
    Yp = np.array(projected).reshape(-1, model.size)
    Z = model.geometry.rollers
    full = [model.layout.unpack(y * model.scale) for y in Yp]
    Y = (np.array([f[0] for f in full]).reshape(-1, Z, 7),
         np.array([f[1] for f in full]).reshape(-1, 6))
    diag = model.diagnostics_series(t, Yp)
    info = solver_attrs(model, res, solver, record_start_s, iters)
    ds = dynamic_dataset(model, t, Y, diag, info)
    if res.error_estimate is not None:
        ds = ds.assign(error_estimate_variables(model, res.error_estimate[keep][:t.size]))
    if projection_error is not None:
        raise ProjectionError(projection_error, ds)
    return ds


def _unknown_scales(model) -> dict[str, float]:
    """Scale of each kind of unknown (the same for every roller): roller 1's and the globals'."""
    lay = model.layout
    names = list(lay.local_names) + list(lay.global_names)
    idx = list(range(lay.n_local)) + list(range(lay.size - lay.n_global, lay.size))
    return {name: float(model.scale[i]) for name, i in zip(names, idx)}


def solver_attrs(model, solution, solver, record_start_s: float,
                 projection_iterations: int) -> dict:
    """The solver's Dataset attributes: ``solver`` (one human line), ``solver_options`` (JSON,
    ``"solver"`` is the solver's own short name, contract item 5), statistics, tolerances,
    unknown scales and regularisation lengths."""
    import sksundae

    from .solvers.common import algebraic_atol
    from .system.residual import PARAM_NAMES

    sc, dyn = model.scene, model.scene.dynamics
    d = solver.describe()
    stats = dict(solution.stats)
    stats["projection_newton_iterations"] = int(projection_iterations)
    P = dict(zip(PARAM_NAMES, model.params))
    options = {"solver": d["solver"], "rtol": dyn.rtol, "atol": dyn.atol,
               "atol_algebraic": algebraic_atol(dyn.atol), **d["options"]}
    attrs = {
        "solver": d["solver_description"],
        "sundials_version": str(getattr(sksundae, "SUNDIALS_VERSION", "unknown")),
        "scikit_sundae_version": str(sksundae.__version__),
        "solver_status": "completed" if solution.success else "failed",
        "solver_message": solution.message,
        "solver_statistics": json.dumps(stats, default=_json_default),
        "wall_time_s": float(stats.get("wall_time_s", 0.0)),
        "rtol": dyn.rtol,
        "atol": dyn.atol,
        "atol_algebraic": algebraic_atol(dyn.atol),
        "atol_units": "atol is in units of each unknown's scale (unknown_scales)",
        "unknown_scales": json.dumps(_unknown_scales(model)),
        "record_start_s": float(record_start_s),
        "epicyclic_cage_speed_rad_s": float(model.final_cage_speed()),
        "physics": json.dumps(vars(sc.physics)),
        "regularisation": json.dumps({
            **contact_regularisation(sc),
            "traction_sign": "V / sqrt(V^2 + v^2)",
            "traction_velocity_scale_m_s": sc.traction.velocity_scale_m_s,
            "pocket_smoothing_m": sc.cage.smoothing_m,
            "pocket_force_scale_N": float(P["f_p"]),
            "cage_friction_spin_scale_rad_s": float(P["spin_scale"]),
            "algebraic_outputs": "projected onto the algebraic equations (static Newton) at "
                                 "every output time",
        }),
    }
    extra = dict(solver.dataset_attrs(model, solution))
    options.update(extra.pop("options", {}))
    attrs.update(extra)
    options["solver"] = d["solver"]  # the solver's own name, whatever the extras say
    attrs["solver_options"] = json.dumps(options, default=_json_default)
    return attrs


def _json_default(value):
    """numpy scalars and other leftovers in statistics -> JSON."""
    if isinstance(value, np.generic):
        return value.item()
    return str(value)
