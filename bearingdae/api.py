"""The flat public entry points: each takes a :class:`~bearingdae.scene.Scene`, returns a Dataset."""

from __future__ import annotations

import numpy as np
import xarray as xr

from .guards import check_plausibility
from .physics.geometry import make_geometry
from .results import contact_regularisation, dynamic_dataset, static_dataset
from .system.residual import PARAM_NAMES
from .scene import Scene
from .solvers import static


def solve_static(scene: Scene, z0=None) -> xr.Dataset:
    """Quasi-static equilibrium of inner ring and rollers (MODEL §5) as a Dataset.

    Rollers at their initial azimuths (roller 1 on the load line, equally spaced), orbiting at
    the epicyclic speed of ``operating.speed_rpm`` (at t = 0 for a ramp), so the centrifugal
    force is included; ``speed_rpm = 0`` is the plain static case.
    """
    geometry = make_geometry(scene)
    o = scene.operating
    prob = static.make_problem(
        geometry,
        o.loads,
        o.speed_at(0.0),
        scene.numerics.contact_smoothing_m,
    )
    sol = static.solve(prob, z0, tol=scene.numerics.static_tolerance,
                       max_iter=scene.numerics.static_max_iterations)
    return check_plausibility(static_dataset(scene, geometry, sol), scene)


class SimulationError(RuntimeError):
    """The solver failed or was interrupted. ``.dataset`` holds every sample computed before."""

    def __init__(self, message: str, dataset: xr.Dataset | None):
        super().__init__(message)
        self.dataset = dataset


def output_times(model) -> tuple[np.ndarray, float]:
    """Sample times from t = 0 to the end of the recorded window, and the window start [s].

    One cage revolution T = 2π / Ω_epicyclic at the final inner-ring speed (a scene whose final
    speed is 0 uses 0.01 s). Recording starts after the speed ramp plus
    ``warmup_cage_revolutions`` and lasts ``cage_revolutions``.
    """
    from .system.model import STATIC_REFERENCE_PERIOD_S

    dyn = model.scene.dynamics
    om = model.final_cage_speed()
    period = 2.0 * np.pi / om if om > 0 else STATIC_REFERENCE_PERIOD_S
    start = float(model.ramp_t[-1]) + dyn.warmup_cage_revolutions * period
    dt = period / dyn.samples_per_cage_revolution
    n_rec = int(round(dyn.cage_revolutions * dyn.samples_per_cage_revolution))
    n_warm = int(np.ceil(start / dt))
    warm = np.linspace(0.0, start, n_warm + 1)[:-1] if n_warm > 0 else np.empty(0)
    rec = start + dt * np.arange(n_rec + 1)
    return np.concatenate([warm, rec]), start


#: solver name -> scipy method of the nested peers (solvers/scipy_peers.py)
SCIPY_PEERS = {"scipy-BDF": "BDF", "scipy-Radau": "Radau", "scipy-LSODA": "LSODA"}


def simulate(scene: Scene, solver: str = "ida", progress: bool = False,
             linsolver: str = "sparse", jacobian: str = "analytic",
             solver_options: dict | None = None, checkpoint=None) -> xr.Dataset:
    """Dynamic simulation of a scene (MODEL §6-11) as a labelled Dataset.

    ``solver``: ``"ida"`` (SUNDIALS IDA, the default), ``"newmark"`` (fixed-step Newmark-β /
    HHT-α over the same residual, MODEL §12; settings ``numerics.newmark_*``, ``hht_alpha``) or
    a nested scipy peer ``"scipy-BDF"``, ``"scipy-Radau"``, ``"scipy-LSODA"``
    (solvers/scipy_peers.py; ``solver_options`` go to its ``integrate``, e.g. ``time_limit_s``).
    ``jacobian``: IDA's iteration matrix, ``"analytic"`` (default) or ``"fd"`` (structured
    finite differences, a cross-check). All give the same Dataset. It holds the recorded window
    (after the warm-up); its attributes carry the solver statistics, tolerances, unknown scales
    and regularisation lengths. On solver failure or Ctrl-C raises :class:`SimulationError`
    whose ``.dataset`` holds every sample computed before the failure. ``checkpoint``: a
    :class:`bearingdae.checkpoint.Checkpoint` that saves the run as it goes (and resumes it).
    """
    from .solvers import ida, newmark
    from .system.model import build_model, initial_state, project_algebraic

    if solver not in ("ida", "newmark") and solver not in SCIPY_PEERS:
        raise ValueError(f"solver = {solver!r}: allowed are 'ida', 'newmark', "
                         f"{', '.join(repr(k) for k in SCIPY_PEERS)}")
    if checkpoint is not None and solver != "ida":
        raise ValueError(f"checkpoint/resume is implemented for solver = 'ida' only, "
                         f"not {solver!r}")
    model = build_model(scene)
    y0, yp0 = initial_state(model)
    t_out, start = output_times(model)
    extra_attrs = {}  # issue 14: skid start and until_steady (bearingdae/steady.py)
    if scene.dynamics.initial_speeds == "torque_balance":
        from .system.torque_balance import torque_balance_state

        y0, yp0, extra_attrs = torque_balance_state(model, y0)

    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=float(t_out[-1]), unit="s", desc="simulated time",
                   bar_format="{l_bar}{bar}| {n:.4f}/{total:.4f} s [{elapsed}<{remaining}]")

    def tick(t):
        if bar is not None:
            bar.n = t
            bar.refresh()

    if scene.dynamics.until_steady:
        from .steady import integrate_until_steady, warmup_path

        if solver != "ida":
            raise ValueError(f"numerics.until_steady is implemented for solver = 'ida' only, "
                             f"not {solver!r}")
        res, start, steady_attrs = integrate_until_steady(
            ida.IDA(linsolver, jacobian), model, y0, yp0, progress=tick,
            warmup_path=warmup_path(checkpoint), resume=getattr(checkpoint, "resume", False))
        extra_attrs.update(steady_attrs)
    elif solver in SCIPY_PEERS:
        from .solvers import scipy_peers

        res = scipy_peers.integrate(model, y0, yp0, t_out, method=SCIPY_PEERS[solver],
                                    progress=tick, **(solver_options or {}))
    elif solver == "ida":
        run = ida.integrate if checkpoint is None else checkpoint.integrate  # checkpoint.py
        res = run(model, y0, yp0, t_out, linsolver=linsolver, progress=tick, jacobian=jacobian)
    else:
        res = newmark.integrate(model, y0, yp0, t_out, progress=tick, jacobian=jacobian)
    if bar is not None:
        bar.close()
    keep = res.t >= start - 1e-12 if res.success else np.ones(res.t.size, bool)
    t, Ys = res.t[keep], res.y[keep]
    iters = 0
    full_l, full_g, diags = [], [], []
    projection_error = None
    for tk, y in zip(t, Ys):
        try:
            y, it = project_algebraic(model, tk, y)
        except static.StaticConvergenceError as exc:
            # keep every sample projected so far (the failure contract of SimulationError)
            projection_error = (f"projection onto the algebraic equations failed at "
                                f"t = {tk:.6g} s: {exc}")
            break
        iters += it
        fl, fg = model.layout.unpack(y * model.scale)
        full_l.append(fl), full_g.append(fg)
        diags.append(model.diagnostics(tk, y))
    names = ("contact_force", "contact_pressure", "slip_velocity", "traction_force", "cage_force")
    Z, k = model.geometry.rollers, model.geometry.slices
    diag = {n: (np.array([d[n] for d in diags]) if diags else
                np.empty((0, Z, 2) if n == "cage_force" else (0, Z, k, 2))) for n in names}
    t = t[:len(full_l)]
    Y = (np.array(full_l).reshape(-1, Z, 7), np.array(full_g).reshape(-1, 6))
    info = _solver_info(model, res, start, iters)
    info.update(extra_attrs)
    if solver == "newmark":
        info.update(newmark.solver_info(model, res))
    ds = dynamic_dataset(model, t, Y, diag, info)
    if getattr(res, "error_estimate", None) is not None:
        ds = ds.assign(newmark.error_estimate_variables(model, res.error_estimate[keep]))
    ds = check_plausibility(ds, scene)  # PlausibilityWarning + attrs (bearingdae/guards.py)
    if not res.success:
        raise SimulationError(res.message, ds)
    if projection_error is not None:
        raise SimulationError(projection_error, ds)
    return ds


def _unknown_scales(model) -> dict[str, float]:
    """Scale of each kind of unknown (the same for every roller): roller 1's and the globals'."""
    lay = model.layout
    names = list(lay.local_names) + list(lay.global_names)
    idx = list(range(lay.n_local)) + list(range(lay.size - lay.n_global, lay.size))
    return {name: float(model.scale[i]) for name, i in zip(names, idx)}


def _solver_info(model, res, start: float, projection_iterations: int) -> dict:
    import json

    import sksundae

    from .solvers.ida import algebraic_atol

    sc, dyn = model.scene, model.scene.dynamics
    stats = dict(res.stats)
    solver = stats.pop("solver_description", None)  # set by the scipy peers
    stats["projection_newton_iterations"] = int(projection_iterations)
    P = dict(zip(PARAM_NAMES, model.params))
    return {
        "solver": solver or (f"SUNDIALS IDA via scikit-sundae (BDF, {res.stats.get('linsolver', 'sparse')} "
                             f"linear solver, {res.stats.get('jacobian', 'analytic')} Jacobian)"),
        "sundials_version": str(getattr(sksundae, "SUNDIALS_VERSION", "unknown")),
        "scikit_sundae_version": str(sksundae.__version__),
        "solver_status": "completed" if res.success else "failed",
        "solver_message": res.message,
        "solver_statistics": json.dumps(stats),
        "wall_time_s": float(stats["wall_time_s"]),
        "rtol": dyn.rtol,
        "atol": dyn.atol,
        "atol_algebraic": algebraic_atol(dyn.atol),
        "atol_units": "atol is in units of each unknown's scale (unknown_scales)",
        "solver_options": json.dumps({"solver": "ida", "rtol": dyn.rtol, "atol": dyn.atol,
                                      "atol_algebraic": algebraic_atol(dyn.atol),
                                      "linsolver": stats.get("linsolver", "sparse")}),
        "unknown_scales": json.dumps(_unknown_scales(model)),
        "record_start_s": float(start),
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
