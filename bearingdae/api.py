"""The flat public entry points: each takes a :class:`~bearingdae.scene.Scene`, returns a Dataset."""

from __future__ import annotations

import os

import numpy as np
import xarray as xr

from .results.guards import check_plausibility
from .physics.geometry import make_geometry
from .results import static_dataset
from .scene import Scene
from .solvers import SCIPY_PEERS, static  # noqa: F401  (SCIPY_PEERS: kept importable here)


def solve_static(scene: Scene, z0=None) -> xr.Dataset:
    """Quasi-static equilibrium of inner ring and rollers (docs/theory.md §5) as a Dataset.

    Rollers at their initial azimuths (roller 1 on the load line, equally spaced), orbiting at
    the epicyclic speed of ``operating.speed_rpm`` (at t = 0 for a ramp), so the centrifugal
    force is included; ``speed_rpm = 0`` is the plain static case.

    Parameters
    ----------
    scene : Scene
        The bearing and its operating point (:func:`load_scene`).
    z0 : numpy.ndarray, optional
        Start of the Newton iteration in its scaled unknowns (default: the rigid-ring guess,
        with ε-continuation when plain Newton fails).

    Returns
    -------
    xarray.Dataset
        ``contact_force``, ``contact_pressure``, ``approach`` on (roller, slice, race); roller
        radial positions and tilts; ring displacement and tilt; the scene as TOML, the Newton
        iterations and the residual reached in the attributes (user guide, "Quasi-static
        equilibrium").

    Raises
    ------
    bearingdae.solvers.static.StaticConvergenceError
        Newton did not reach ``numerics.static_tolerance`` (the message names the residual).

    Warns
    -----
    bearingdae.results.guards.PlausibilityWarning
        A result outside the model's range of validity (e.g. Hertz pressure above 4 GPa).

    Examples
    --------
    >>> from bearingdae import load_scene, solve_static
    >>> ds = solve_static(load_scene("yang20_baseline"))
    >>> load = ds.contact_force.sum("slice").sel(race="inner")   # per roller [N]
    """
    from .physics.loads import applied_loads
    from .solvers.algebraic import support_stiffness
    from .system.model import _speed_ramp, load_table

    _check_scene(scene, "solve_static")
    geometry = make_geometry(scene)
    o = scene.operating
    ramp_t, ramp_w = _speed_ramp(scene)
    prob = static.make_problem(
        geometry,
        applied_loads(0.0, load_table(o), ramp_t, ramp_w, o.unbalance_N,
                      o.unbalance_phase_rad)[:4],  # the slice contacts' loads (F_a: flanges)
        o.speed_rad_s_at(0.0),
        scene.numerics.contact_smoothing_m,
        support_N_m=support_stiffness(scene),
    )
    if z0 is not None:
        z0 = _check_start(z0, static.default_start(prob).size)
    sol = static.solve(prob, z0, tol=scene.numerics.static_tolerance,
                       max_iter=scene.numerics.static_max_iterations)
    from .results.engineering import add_static

    if scene.bearing.flanges is not None:  # the flange contacts and the axial unknowns (§16)
        from .results.flange import static_with_flanges

        sol, flange_vars = static_with_flanges(scene, sol)
    ds = add_static(static_dataset(scene, geometry, sol), scene, geometry)  # life, film
    if scene.bearing.flanges is not None:
        ds = ds.assign(flange_vars)
    return check_plausibility(ds, scene)


def _check_scene(scene, where: str) -> None:
    """The ``scene`` argument of the entry points: a :class:`Scene` (TypeError otherwise)."""
    if not isinstance(scene, Scene):
        hint = (f"; load it first: {where}(load_scene({str(scene)[:100]!r}))"
                if isinstance(scene, (str, os.PathLike)) else "")
        raise TypeError(f"{where}: scene: expected a Scene (from load_scene or scene_from_dict),"
                        f" got {type(scene).__name__}{hint}")


def _check_start(z0, size: int) -> np.ndarray:
    """``solve_static``'s ``z0``: a start of the static unknowns (the ``z`` of a static
    solution: radial positions, tilts, ring displacement and tilt), ``size`` finite numbers."""
    try:
        z = np.array(z0, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise TypeError(f"solve_static: z0: expected None or {size} numbers, got "
                        f"{type(z0).__name__}") from None
    if z.shape != (size,):
        raise ValueError(f"solve_static: z0: expected {size} numbers (2 Z + 4 static unknowns "
                         f"of this scene), got shape {z.shape}")
    if not np.all(np.isfinite(z)):
        raise ValueError("solve_static: z0: every value must be finite, got NaN or inf")
    return z


class SimulationError(RuntimeError):
    """The solver failed, or the run was interrupted (Ctrl-C).

    Attributes
    ----------
    dataset : xarray.Dataset or None
        Every sample computed before the failure, as :func:`simulate` would have returned them
        (save it with :func:`save`); None if none was computed.
    """

    def __init__(self, message: str, dataset: xr.Dataset | None):
        super().__init__(message)
        self.dataset = dataset


#: the densest sampling of the warm-up (samples per cage revolution), whatever
#: ``numerics.samples_per_cage_revolution`` asks for the record
WARMUP_SAMPLES_PER_CAGE_REVOLUTION = 200


def output_times(model) -> tuple[np.ndarray, float]:
    """Sample times from t = 0 to the end of the recorded window, and the window start [s].

    One cage revolution T = 2π / Ω_epicyclic at the final inner-ring speed (a scene whose final
    speed is 0 uses 0.01 s). Recording starts after the speed ramp plus
    ``warmup_cage_revolutions`` and lasts ``cage_revolutions``, sampled at
    ``samples_per_cage_revolution``; the warm-up at that rate or
    :data:`WARMUP_SAMPLES_PER_CAGE_REVOLUTION`, whichever is sparser.
    """
    from .system.model import STATIC_REFERENCE_PERIOD_S

    dyn = model.scene.dynamics
    om = model.final_cage_speed()
    period = 2.0 * np.pi / om if om > 0 else STATIC_REFERENCE_PERIOD_S
    start = float(model.ramp_t[-1]) + dyn.warmup_cage_revolutions * period
    dt = period / dyn.samples_per_cage_revolution
    n_rec = int(round(dyn.cage_revolutions * dyn.samples_per_cage_revolution))
    # the warm-up is sampled no denser than WARMUP_SAMPLES_PER_CAGE_REVOLUTION: its samples
    # are dropped (they serve progress, Ctrl-C and checkpoints), and at dense output they
    # were half of the samples' cost
    dt_warm = period / min(dyn.samples_per_cage_revolution, WARMUP_SAMPLES_PER_CAGE_REVOLUTION)
    n_warm = int(np.ceil(start / dt_warm))
    warm = np.linspace(0.0, start, n_warm + 1)[:-1] if n_warm > 0 else np.empty(0)
    rec = start + dt * np.arange(n_rec + 1)
    return np.concatenate([warm, rec]), start



def _check_load_file_span(scene, model, end_s: float) -> None:
    """A load file must cover the run (its history is data, not to be extrapolated): the end of
    the record, or with until_steady the end of the longest warm-up plus the record."""
    o = scene.operating
    if o.load_file is None:
        return
    from .scene import SceneError

    if scene.dynamics.until_steady:
        from .run.steady import horizon_s

        end_s = max(end_s, horizon_s(model))
    last = o.load_history[-1][0]
    if last < end_s:
        raise SceneError(f"'operating.load_file': load file '{o.load_file}': variable 'time': "
                         f"ends at {last:.9g} s; "
                         f"expected to cover the run to {end_s:.9g} s (warm-up and record)")


class _Unset:
    """Default of the deprecated keywords of :func:`simulate` (given or not)."""

    def __repr__(self) -> str:
        return "<deprecated>"


_UNSET = _Unset()


def simulate(scene: Scene, solver="ida", progress: bool | None = None,
             linsolver=_UNSET, jacobian=_UNSET, solver_options: dict | None = None,
             checkpoint=None) -> xr.Dataset:
    """Dynamic simulation of a scene (docs/theory.md §6-11) as a labelled Dataset.

    The run starts from the quasi-static equilibrium with every roller at pure-rolling speeds
    (or the torque-balance skid speeds, ``numerics.initial_speeds``), runs
    ``numerics.warmup_cage_revolutions`` (or until steady, ``numerics.until_steady``) and
    records ``numerics.cage_revolutions`` at ``numerics.samples_per_cage_revolution``.

    Parameters
    ----------
    scene : Scene
        The bearing and its operating point (:func:`load_scene`).
    solver : Solver or str, default "ida"
        A solver object of the contract in ``bearingdae/solvers/base.py`` —
        :class:`IDA` (SUNDIALS IDA, the default), :class:`Newmark` (fixed-step Newmark-β /
        HHT-α over the same residual, docs/theory.md §12; settings ``numerics.newmark_*``,
        ``hht_alpha``) or :class:`ScipyPeer` (``"BDF"``, ``"Radau"``, ``"LSODA"``) — or its
        name: ``"ida"``, ``"newmark"``, ``"scipy-BDF"``, ``"scipy-Radau"``, ``"scipy-LSODA"``.
        All give the same Dataset.
    progress : bool or None, default None
        Show the progress on stderr: a line saying that the numba kernels are being compiled
        (the first run after installing: 15 s and more; later runs load them from numba's
        cache), then a bar in simulated time. ``None`` shows it where a person watches, i.e.
        stderr is a terminal or the code runs in a Jupyter notebook, and is quiet elsewhere
        (a script writing to a log, a test, a sweep worker). ``True`` always shows it (where
        stderr is not a terminal: one line per 10 % of the simulated time instead of a bar),
        ``False`` never.
    checkpoint : Checkpoint, optional
        Save the run as it goes, and resume it (``Checkpoint(path, resume=True)``); any solver.
    linsolver, jacobian, solver_options
        Deprecated: give the options to the solver object instead, e.g.
        ``IDA(linsolver="dense")``, ``ScipyPeer("BDF", time_limit_s=60)``.

    Returns
    -------
    xarray.Dataset
        The recorded window (after the speed ramp and the warm-up; ``time`` counts from the
        start of the simulation, the record starts at the attribute ``record_start_s``). Its
        attributes carry the solver's name and settings (``solver_options``), statistics,
        tolerances, unknown scales, regularisation lengths and the operating point. Every variable
        (cage and roller speeds, skew, tilt, slice contact forces, pressures, slip velocities
        and traction forces, pocket forces, ring motion) has ``units`` and ``long_name``.

    Raises
    ------
    SimulationError
        The solver failed or the run was interrupted; its ``.dataset`` holds every sample
        computed before.

    Warns
    -----
    bearingdae.results.guards.PlausibilityWarning
        The run left the model's range of validity (pressure, edge loading, skew against the
        pocket, cage slip); the findings are also in the attribute ``plausibility_warnings``.

    See Also
    --------
    solve_static : the quasi-static equilibrium alone.
    save : write the Dataset to NetCDF.

    Examples
    --------
    >>> from bearingdae import Newmark, load_scene, simulate
    >>> scene = load_scene("yang20_baseline", {"numerics.cage_revolutions": 0.5})
    >>> ds = simulate(scene, progress=False)
    >>> slip = 1 - ds.cage_speed.mean() / ds.attrs["epicyclic_cage_speed_rad_s"]
    >>> ds_newmark = simulate(scene, solver=Newmark())   # the independent cross-check
    """
    if not (progress is None or progress is True or progress is False
            or isinstance(progress, np.bool_)):
        raise TypeError(f"simulate: progress = {str(progress)[:100]!r}: expected True, False "
                        "or None (shown where a person watches: a terminal or a notebook)")
    from .run.checkpoint import Checkpointed
    from .run.progress import interactive
    from .results import ProjectionError, from_solution
    from .solvers import from_name
    from .solvers.algebraic import initial_state
    from .solvers.base import Solver
    from .system.model import build_model

    _check_scene(scene, "simulate")
    if progress is not None and not isinstance(progress, (bool, np.bool_)):
        raise TypeError(f"simulate: progress: expected True, False or None, got "
                        f"{type(progress).__name__}")
    if solver_options is not None and not isinstance(solver_options, dict):
        raise TypeError(f"simulate: solver_options: expected a dict or None, got "
                        f"{type(solver_options).__name__}")
    if checkpoint is not None:
        from .run.checkpoint import Checkpoint

        if not isinstance(checkpoint, Checkpoint):
            raise TypeError(f"simulate: checkpoint: expected a Checkpoint or None, got "
                            f"{type(checkpoint).__name__}")
    if progress is None:
        progress = interactive()
    if progress:  # before anything compiles (initial_state's residual is a kernel)
        from .run.progress import announce_compiling

        announce_compiling()
    solver = _solver_object(solver, linsolver, jacobian, solver_options, Solver, from_name)
    plain = solver  # until_steady checkpoints per block itself (bearingdae/run/steady.py)
    if checkpoint is not None:
        solver = Checkpointed(solver, checkpoint)
    model = build_model(scene)
    t_out, start = output_times(model)
    _check_load_file_span(scene, model, float(t_out[-1]))
    y0, yp0 = initial_state(model)
    extra_attrs = {}  # skid start and until_steady
    if scene.dynamics.initial_speeds == "torque_balance":
        from .solvers.torque_balance import torque_balance_state

        y0, yp0, extra_attrs = torque_balance_state(model, y0)

    bar = None
    if progress:  # a bar where a person watches, a line per 10 % otherwise (progress.py)
        from .run.progress import SimulationProgress

        total = t_out[-1]
        if scene.dynamics.until_steady:  # the cap: an upper bound (bearingdae/run/steady.py)
            from .run.steady import horizon_s

            total = horizon_s(model)
        bar = SimulationProgress(float(total))

    def tick(t):
        if bar is not None:
            bar.update(t)

    if scene.dynamics.until_steady:
        from .run.steady import integrate_until_steady, warmup_path

        solver = plain
        res, start, steady_attrs = integrate_until_steady(
            solver, model, y0, yp0, progress=tick, warmup_path=warmup_path(checkpoint),
            resume=getattr(checkpoint, "resume", False),
            expected_end=bar.set_total if bar is not None else None)
        extra_attrs.update(steady_attrs)
    else:
        from .system.extremes import requested

        res = solver.integrate(model, y0, yp0, t_out, progress=tick,
                               extremes_from=start if requested(scene) else None)
    if bar is not None:
        bar.close()
    projection_error = None
    try:
        ds = from_solution(model, res, solver, record_start_s=start)
    except ProjectionError as exc:
        ds, projection_error = exc.dataset, str(exc)
    ds.attrs.update(extra_attrs)
    if ds.sizes.get("time", 0) > 0:  # error bars of the run's statistics
        from .results.statistics import statistics_attrs

        ds.attrs.update(statistics_attrs(ds))
    ds = check_plausibility(ds, scene)  # PlausibilityWarning + attrs (bearingdae/results/guards.py)
    if not res.success:
        raise SimulationError(res.message, ds)
    if projection_error is not None:
        raise SimulationError(projection_error, ds)
    return ds


def _solver_object(solver, linsolver, jacobian, solver_options, Solver, from_name):
    """``simulate``'s solver argument as a solver object; the old keywords with a
    DeprecationWarning (each becomes an option of the named solver)."""
    import warnings

    old, given = {}, []
    for key, value in (("linsolver", linsolver), ("jacobian", jacobian)):
        if value is not _UNSET:
            old[key] = value
            given.append(key)
    if solver_options:
        old.update(solver_options)
        given.append("solver_options")
    if given:
        warnings.warn(f"simulate(..., {'=, '.join(given)}=) is deprecated: pass a solver object "
                      "with its options, e.g. simulate(scene, solver=IDA(linsolver='dense', "
                      "jacobian='fd')) or ScipyPeer('BDF', time_limit_s=60)",
                      DeprecationWarning, stacklevel=3)
    if isinstance(solver, Solver):
        if old:
            raise ValueError(f"simulate: options {sorted(old)} given beside the solver object "
                             f"{type(solver).__name__}; set them on the solver object instead")
        return solver
    if not isinstance(solver, str):
        raise TypeError(f"simulate: solver: expected a Solver object (IDA(), Newmark(), "
                        f"ScipyPeer(...)) or a name, got {type(solver).__name__}")
    if solver != "ida":
        old.pop("linsolver", None)  # IDA's linear solver: ignored by the others, as before
    return from_name(solver, **old)
