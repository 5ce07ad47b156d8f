"""The flat public entry points: each takes a :class:`~bearingdae.scene.Scene`, returns a Dataset."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from .analysis.guards import check_plausibility
from .analysis.result_variables import with_result_variables
from .physics.geometry import make_geometry
from .results import static_dataset
from .scene import Scene
from .solvers import SCIPY_PEERS, static  # noqa: F401  (SCIPY_PEERS: kept importable here)
# the integration every dynamic run shares; output_times and the warm-up rate importable here
from .run.integrate import (WARMUP_SAMPLES_PER_CAGE_REVOLUTION, _UNSET,  # noqa: F401
                            check_scene as _check_scene, integrate_scene as _integrate,
                            output_times)


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
    bearingdae.analysis.guards.PlausibilityWarning
        A result outside the model's range of validity (e.g. Hertz pressure above 4 GPa).

    Examples
    --------
    >>> from bearingdae import load_scene, solve_static
    >>> ds = solve_static(load_scene("yang20_baseline"))
    >>> load = ds.contact_force.sum("slice").sel(race="inner")   # per roller [N]
    """
    from .analysis.engineering import add_static
    from .analysis.static_state import scene_static

    _check_scene(scene, "solve_static")
    from .system.thermal_network import start_scene

    scene = start_scene(scene)  # physics.thermal = "steady": the oil at its inlet temperature
    geometry = make_geometry(scene)
    if z0 is not None:
        z0 = _check_start(z0, 2 * geometry.rollers + 4)
    sol, flange_vars = scene_static(scene, geometry, z0=z0)  # loads, support, flanges (§5, §16)
    ds = add_static(static_dataset(scene, geometry, sol), scene, geometry)  # life, film
    if flange_vars is not None:
        ds = ds.assign(flange_vars)
    return with_result_variables(check_plausibility(ds, scene))


def stiffness(scene: Scene) -> xr.Dataset:
    """Quasi-static stiffness matrix of the bearing at the scene's equilibrium
    (docs/theory.md §18).

    The tangent of the rollers' reaction on the inner ring with respect to the ring's
    displacement and tilt, K = d(reaction)/d(motion), taken from the static Newton's analytic
    Jacobian by the implicit-function theorem: the rollers re-find their equilibrium as the
    ring moves (Schur complement), they are not frozen. Centrifugal force (the scene's speed),
    clearance, profile and flanges (their contacts and friction, from the compiled DAE's
    algebraic Jacobian) enter through the equilibrium; a dynamic ring's support is not part
    of the bearing's K.

    Parameters
    ----------
    scene : Scene
        The bearing and its operating point (:func:`load_scene`).

    Returns
    -------
    xarray.Dataset
        ``stiffness`` on (``dof``, ``dof_2``): rows the reaction (force F_r, F_t [N], moments
        M, M_t [N m]), columns the motion (δ_r, δ_t [m], γ_r, γ_t [rad]), dofs ``radial``
        (the load line), ``tangential``, ``tilt_radial``, ``tilt_tangential``; with flanges
        also ``axial`` (F_a [N], axial displacement [m]), after ``tangential``;
        ``entry_units`` gives each entry's unit (N/m, N/rad, N m/m, N m/rad);
        ``stiffness_slice_error``: the change of each entry with ``numerics.slices`` doubled
        (its discretisation error).

    Warns
    -----
    bearingdae.analysis.stiffness.StiffnessResolutionWarning
        A diagonal entry changes by more than 1 % with the slices doubled (the line names
        ``numerics.slices``).

    Examples
    --------
    >>> from bearingdae import load_scene, stiffness
    >>> K = stiffness(load_scene("yang20_baseline")).stiffness
    >>> k_rr = float(K.sel(dof="radial", dof_2="radial"))   # [N/m]
    """
    from .analysis.stiffness import scene_stiffness

    _check_scene(scene, "stiffness")
    return scene_stiffness(scene)


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


def simulate(scene: Scene, solver="ida", progress: bool | None = None,
             linsolver=_UNSET, jacobian=_UNSET, solver_options: dict | None = None,
             checkpoint=None, output=None) -> xr.Dataset:
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
    output : str or path-like, optional
        Stream the record to this NetCDF file as the run goes, a block of samples at a time
        (memory independent of the record's length; ``bearingdae run`` does this), and return
        the Dataset opened from it, lazily (``ds.close()`` when done). The file appears at the
        path only when complete; a failed run leaves ``<stem>_partial.nc`` beside it, which a
        later complete run of the same target (a resume) removes.
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
    bearingdae.analysis.guards.PlausibilityWarning
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
    >>> slip = 1 - ds.cage_speed.mean() / ds.epicyclic_cage_speed_rad_s
    >>> ds_newmark = simulate(scene, solver=Newmark())   # the independent cross-check
    """
    if output is not None:
        return simulate_to_file(scene, output, solver, progress, checkpoint,
                                _options=(linsolver, jacobian, solver_options)).open()
    from .results import ProjectionError, from_solution

    model, res, start, extra_attrs, solver = _integrate(
        scene, solver, progress, checkpoint, (linsolver, jacobian, solver_options))
    projection_error = None
    try:
        ds = from_solution(model, res, solver, record_start_s=start)
    except ProjectionError as exc:
        ds, projection_error = exc.dataset, str(exc)
    ds.attrs.update(extra_attrs)
    if model.thermal is not None:  # temperatures and viscosity (results/thermal_variables.py)
        from .results.thermal_variables import thermal_variables

        speed = None  # the life's speed, the record's mean (analysis/rating_life.py): one κ
        if "inner_ring_speed" in ds and ds.sizes.get("time", 0):
            from .analysis.rating_life import mean_speed_rpm

            speed = mean_speed_rpm(float(np.sum(ds.inner_ring_speed.values)), ds.sizes["time"])
        ds = ds.assign(thermal_variables(model, scene.output_variables, speed))
    if ds.sizes.get("time", 0) > 0:  # error bars of the run's statistics
        from .analysis.statistics import statistics_attrs

        ds.attrs.update(statistics_attrs(ds))
    # PlausibilityWarning + attrs (bearingdae/analysis/guards.py), of the oil the model read
    ds = check_plausibility(ds, model.scene)
    ds = with_result_variables(ds)  # the numbers as variables (analysis/result_variables.py)
    if not res.success:
        raise SimulationError(res.message, ds)
    if projection_error is not None:
        raise SimulationError(projection_error, ds)
    return ds


# ---------------------------------------------------------------------------------------------
# A run streamed to its file (bearingdae run; simulate(..., output=path))
# ---------------------------------------------------------------------------------------------
def partial_target(target: str | Path) -> Path:
    """``TARGET_partial.nc``: where the samples of a failed or interrupted run go."""
    from .results.partial_files import partial_path

    return partial_path(target)


def simulate_to_file(scene, target, solver="ida", progress=None, checkpoint=None, *,
                     fallback=None, complevel: int = 4, _options=None):
    """Run ``scene`` and stream its record to ``target`` (NetCDF): what ``bearingdae run``
    and ``simulate(scene, output=path)`` do. The surroundings are :func:`simulate`'s
    (run/integrate.py); the record goes to a
    :class:`~bearingdae.results.streamed_record.StreamedRecord` instead of the Solution (``keep_samples=False``), so memory does not grow with the
    recorded length. The target appears only complete; a failed or interrupted run leaves
    ``<stem>_partial.nc`` with every sample computed (the warm-up's first), which a later
    complete run of the same target removes (``result.superseded``); the checkpoint holds
    every sample until the file is written (a run killed even by SIGKILL loses nothing).
 Returns a
    :class:`~bearingdae.results.streamed_record.StreamedResult` (the path written, summary,
    attributes) whether the run completed or not; raises :class:`bearingdae.api.SimulationError` (with the
    partial file's Dataset) when the run failed and was not asked to return (``simulate``).

    ``fallback(path)``: where a file goes when the target's folder cannot take it (a full
    disk); None: the write error is raised.
    """
    import os

    from .results.streamed_record import StreamedRecord
    from .util.atomic import check_writable

    if not isinstance(target, (str, os.PathLike)):
        raise TypeError(f"simulate: output: expected a file path (str or os.PathLike), got "
                        f"{type(target).__name__}")
    target = check_writable(target)
    sink = StreamedRecord(target, partial_target(target), fallback, complevel)
    options = _options if _options is not None else _no_deprecated()
    model, res, start, extra_attrs, solver = _integrate(
        scene, solver, progress, checkpoint, options, on_sample=_Begun(sink, checkpoint),
        keep_samples=False)
    result = sink.finish(res, extra_attrs, start)
    if result.success and result.path == target:  # an earlier failed run's samples: stale
        from .results.partial_files import remove_superseded

        result.superseded = remove_superseded(target, (".nc",))
    if _options is not None and not result.success:  # simulate(..., output=): raise as it does
        ds = result.open() if result.path is not None else None
        raise SimulationError(result.message, ds)
    return result


class _Begun:
    """The sink as ``on_sample``, told the model, record start and solver by ``_integrate``."""

    def __init__(self, sink, checkpoint):
        self.sink, self.checkpoint = sink, checkpoint

    def begin(self, model, start, solver):
        self.sink.begin(model, start, solver, self.checkpoint,
                        model.scene.dynamics.until_steady or model.thermal is not None)

    def __call__(self, t, y, yp):
        self.sink(t, y, yp)


def _no_deprecated():
    return (_UNSET, _UNSET, None)
