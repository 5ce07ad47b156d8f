"""What every dynamic run of a scene does before its results: the output times, the solver,
the start state, progress and until-steady (``bearingdae.simulate`` in memory, and streamed to
a file by ``bearingdae.api.simulate_to_file``).

Stage: run (what surrounds one dynamic run), over solvers and system; the results stage then
makes the Dataset (in memory) or the streamed file.
"""

from __future__ import annotations

import os

import numpy as np

from ..scene import Scene


def check_scene(scene, where: str) -> None:
    """The ``scene`` argument of the entry points: a :class:`Scene` (TypeError otherwise)."""
    if not isinstance(scene, Scene):
        hint = (f"; load it first: {where}(load_scene({str(scene)[:100]!r}))"
                if isinstance(scene, (str, os.PathLike)) else "")
        raise TypeError(f"{where}: scene: expected a Scene (from load_scene or scene_from_dict),"
                        f" got {type(scene).__name__}{hint}")


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
    from ..system.model import STATIC_REFERENCE_PERIOD_S

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



def check_load_file_span(scene, model, end_s: float) -> None:
    """A load file must cover the run (its history is data, not to be extrapolated): the end of
    the record, or with until_steady the end of the longest warm-up plus the record."""
    o = scene.operating
    if o.load_file is None:
        return
    from ..scene import SceneError

    if scene.dynamics.until_steady or scene.thermal is not None:  # in blocks, up to the cap
        from .steady import horizon_s

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


def compile_aside(solver, scene, busy_ok: bool = False) -> None:
    """Cold start of an IDA run: its Jacobian callback, then the projection of its samples,
    compile in a second process while this one compiles the residual and the residual
    callback (solvers/sundials/precompile.py, callbacks.py), when they are not cached and a
    CPU is idle; nothing otherwise. ``bearingdae run`` calls it as early as its imports allow,
    :func:`integrate_scene` for a run from Python (a second call does nothing). Not for a
    scene with extensions: their passes live in the user's module, which the second process
    does not import (their callbacks compile in this process). ``busy_ok``: whatever the
    machine's load (a sweep's client, before its workers take every CPU)."""
    from ..solvers.ida import IDA

    if isinstance(solver, IDA) and not scene.extensions:
        from ..solvers.sundials import callbacks
        from ..system.effects import scene_marker

        callbacks.compile_aside(solver.jacobian, busy_ok, optional=scene_marker(scene),
                                scene=scene)


def integrate_scene(scene, solver, progress, checkpoint, deprecated, on_sample=None,
               keep_samples: bool = True):
    """:func:`bearingdae.simulate`'s integration: the arguments checked, solver and model built,
    start state, progress, until steady. Returns ``(model, solution, record_start_s, extra
    attributes, solver)``. ``on_sample`` (with ``begin(model, record_start_s, solver)``) sees
    every sample; ``keep_samples=False``: the solution keeps the last one only (a streamed
    run, :func:`bearingdae.api.simulate_to_file`). A scene with ``physics.thermal = "steady"``
    runs in blocks (run/thermal_coupling.py; the coupling is ``model.thermal``)."""
    if not (progress is None or progress is True or progress is False
            or isinstance(progress, np.bool_)):
        raise TypeError(f"simulate: progress = {str(progress)[:100]!r}: expected True, False "
                        "or None (shown where a person watches: a terminal or a notebook)")
    from .checkpoint import Checkpointed
    from .progress import interactive
    from ..solvers import from_name
    from ..solvers.algebraic import initial_state
    from ..solvers.base import Solver
    from ..system.model import build_model

    linsolver, jacobian, solver_options = deprecated
    check_scene(scene, "simulate")
    if progress is not None and not isinstance(progress, (bool, np.bool_)):
        raise TypeError(f"simulate: progress: expected True, False or None, got "
                        f"{type(progress).__name__}")
    if solver_options is not None and not isinstance(solver_options, dict):
        raise TypeError(f"simulate: solver_options: expected a dict or None, got "
                        f"{type(solver_options).__name__}")
    if checkpoint is not None:
        from .checkpoint import Checkpoint

        if not isinstance(checkpoint, Checkpoint):
            raise TypeError(f"simulate: checkpoint: expected a Checkpoint or None, got "
                            f"{type(checkpoint).__name__}")
    if progress is None:
        progress = interactive()
    from ..util.kernel_cache import notices

    notices(bool(progress))  # the first-compile notices where the progress is shown
    if progress:  # before anything compiles (initial_state's residual is a kernel)
        from .progress import announce_compiling

        announce_compiling()
    solver = solver_object(solver, linsolver, jacobian, solver_options, Solver, from_name)
    compile_aside(solver, scene)  # (before the initial state: its residual compiles here)
    plain = solver  # until_steady checkpoints per block itself (bearingdae/run/steady.py)
    if checkpoint is not None:
        solver = Checkpointed(solver, checkpoint)
    model = build_model(scene)
    coupling = None
    if scene.thermal is not None:  # the oil at its inlet temperature from the start
        from .thermal_coupling import ThermalCoupling

        coupling = model.thermal = ThermalCoupling(model)
    blocks = scene.dynamics.until_steady or coupling is not None
    t_out, start = output_times(model)
    check_load_file_span(scene, model, float(t_out[-1]))
    y0, yp0 = initial_state(model)
    if coupling is not None and coupling.start_from(float(t_out[0]), y0):
        y0, yp0 = initial_state(model)  # (the first block's viscosities: a consistent start)
    extra_attrs = {}  # skid start and until_steady
    if scene.dynamics.initial_speeds == "torque_balance":
        from ..solvers.torque_balance import torque_balance_state

        y0, yp0, extra_attrs = torque_balance_state(model, y0)

    bar = None
    if progress:  # a bar where a person watches, a line per 10 % otherwise (progress.py)
        from .progress import SimulationProgress

        total = t_out[-1]
        if blocks:  # the cap: an upper bound (bearingdae/run/steady.py)
            from .steady import horizon_s

            total = horizon_s(model)
        bar = SimulationProgress(float(total))

    from .progress import mark_first_sample

    def tick(t):
        mark_first_sample()
        if bar is not None:
            bar.update(t)

    if blocks:
        from .steady import integrate_until_steady
        from .warmup_checkpoint import warmup_path

        solver = plain
    if on_sample is not None:
        on_sample.begin(model, start, solver)
    if blocks:
        res, start, steady_attrs = integrate_until_steady(
            solver, model, y0, yp0, progress=tick, warmup_path=warmup_path(checkpoint),
            resume=getattr(checkpoint, "resume", False),
            expected_end=bar.set_total if bar is not None else None,
            on_sample=on_sample, keep_samples=keep_samples, coupling=coupling)
        extra_attrs.update(steady_attrs)
    else:
        from ..system.extremes import requested

        res = solver.integrate(model, y0, yp0, t_out, progress=tick,
                               extremes_from=start if requested(scene) else None,
                               on_sample=on_sample, keep_samples=keep_samples)
    if bar is not None:
        bar.close()
    return model, res, start, extra_attrs, solver


def solver_object(solver, linsolver, jacobian, solver_options, Solver, from_name):
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
