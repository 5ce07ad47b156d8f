"""SUNDIALS IDA: integrate the DAE model to the output times (theory.md §11).

Stage: system (DAE model) -> **solver** -> results. :class:`IDA` (the default) drives the
SUNDIALS 7 libraries scikit-sundae ships with compiled callbacks and no Python in the step loop
(solvers/sundials/); :class:`IDAScikitSundae` (solvers/ida_scikit_sundae.py, re-exported here)
runs the same IDA through scikit-sundae's Python callback wrappers and is kept as a tested
cross-check. Both share the options below (tolerances, algebraic atol, minimum step,
consistent initialisation at t_start + CALC_INIT_DT_S).

Both advance output time by output time (one ``IDASolve(IDA_NORMAL)`` each), so a failure keeps
every sample computed before it and the caller can report the time it happened. IDA's counters
over a run, across projected restarts, are solvers/ida_statistics.py's.
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np

from ..system.defect_sides import has_sharp
from ..system.jacobian_analytic import analytic_work
from ..system.model import Model
from ..util.warning_lines import BearingdaeWarning
from .base import IntegrationResult, Solution, Solver  # noqa: F401  (IntegrationResult: old name)
from .ida_base import CALC_INIT_DT_S, MIN_STEP_S, _IDABase  # noqa: F401
# The pieces every solver of the DAE shares (algebraic tolerance, sparsity, Jacobian fillers)
# live in solvers/common.py; re-exported here for the code that imported them from ida.
from .common import (ALG_ATOL_FACTOR, ALG_ATOL_MAX, JACOBIANS,  # noqa: F401
                     _jacobian_work, algebraic_atol, check_flag, check_jacobian,
                     jacobian_filler, sparsity_pattern)
from .ida_statistics import StatsTracker


class SolverFallbackWarning(BearingdaeWarning):
    """IDA went on past a corrector failure with the algebraic unknowns out of its error test
    (:class:`IDA`, "fallback")."""


#: IDASolve's flag for repeated corrector (Newton) convergence failures
IDA_CONV_FAIL = -4
#: A projected restart (``IDA(suppress_alg=True)``) needs this many accepted steps since the
#: previous one: a failure that recurs at once is not the drift a restart repairs.
RESTART_MIN_STEPS = 10


#: ``IDASetDeltaCjLSetup`` of :class:`IDA`. A Jacobian refreshed when c_j has moved by 15 %
#: instead of SUNDIALS' 25 % costs 1.6x the refreshes but saves 2/3 of the Newton convergence
#: failures (each a step cut by 4 and ~10 steps to regrow): on the default run ~13 % fewer
#: steps, ~20 % fewer residual calls and ~15 % less CPU; 0.12-0.2 cost the same within 0.3 %.
DELTA_CJ_LSETUP = 0.15


#: the range of a factor of ``IDA(atol_factors=...)``
ATOL_FACTOR_RANGE = (1e-3, 1e3)


def check_atol_factors(factors) -> dict:
    """``IDA(atol_factors=...)`` checked: {unknown name: factor}, the names those of
    system/layout.py (LOCAL: per roller, GLOBAL), each factor a number in
    :data:`ATOL_FACTOR_RANGE`."""
    from ..system.layout import GLOBAL, LOCAL

    if factors is None:
        return {}
    if not isinstance(factors, dict):
        raise ValueError(f"atol_factors = {factors!r:.100}: expected a dict of unknown name -> "
                         "factor, e.g. {'skew_rate': 10.0}")
    lo, hi = ATOL_FACTOR_RANGE
    out = {}
    for name, f in factors.items():
        if name not in LOCAL + GLOBAL:
            raise ValueError(f"atol_factors: unknown {name!r:.60}; allowed are "
                             f"{', '.join(LOCAL + GLOBAL)}")
        if isinstance(f, bool) or not isinstance(f, (int, float, np.floating)) \
                or not lo <= f <= hi:
            raise ValueError(f"atol_factors[{name!r}] = {f!r:.60}: allowed is a number in "
                             f"[{lo:g}, {hi:g}]")
        out[name] = float(f)
    return out


#: ``IDA(max_order=..., nonlin_conv_coef=..., max_nonlin_iters=...)``: (kind, least, most)
STEP_CONTROLS = {"max_order": (int, 1, 5), "nonlin_conv_coef": (float, 1e-3, 1.0),
                 "max_nonlin_iters": (int, 1, 20),
                 # the step ratios (SUNDIALS takes a value outside these as its default)
                 "eta_max_fx": (float, 1.0, 10.0), "eta_max": (float, 1.01, 100.0),
                 "eta_conv_fail": (float, 0.01, 0.99)}


def check_step_controls(**given) -> dict:
    """The IDA step controls given (not None), checked against :data:`STEP_CONTROLS`."""
    out = {}
    for name, value in given.items():
        if value is None:
            continue
        kind, lo, hi = STEP_CONTROLS[name]
        ok = not isinstance(value, bool) and isinstance(
            value, (int, np.integer) if kind is int else (int, float, np.floating))
        if not ok or not lo <= value <= hi:
            what = "an integer" if kind is int else "a number"
            raise ValueError(f"{name} = {value!r:.60}: allowed is {what} in [{lo:g}, {hi:g}] "
                             "(None: SUNDIALS' default)")
        out[name] = kind(value)
    return out


def atol_vector(layout, atol: float, factors: dict | None = None) -> np.ndarray:
    """IDA's absolute tolerances (scaled units): ``atol``, the algebraic unknowns'
    (solvers/common.py ``algebraic_atol``), each named unknown's times its factor (every
    roller's for a per-roller name; a name the scene does not assemble changes nothing)."""
    v = np.where(layout.algebraic, algebraic_atol(atol), atol)
    if factors:
        names = np.array(list(layout.local_names) * layout.rollers + list(layout.global_names))
        for name, f in factors.items():
            v = np.where(names == name, v * f, v)
    return v


class IDA(_IDABase):
    """SUNDIALS IDA (variable-order BDF) driven with no Python in the step loop: the default.

    The residual and the Jacobian are compiled C callbacks (solvers/sundials/callbacks.py) that
    IDA calls directly; Python calls ``IDASolve`` once per output time (progress, checkpoints,
    Ctrl-C are handled there). SUNDIALS is the 7.x build scikit-sundae ships
    (solvers/sundials/library.py). ``linsolver``: ``"blockarrow"`` (the default: per-roller
    blocks and a Schur complement on the global unknowns, compiled, solvers/blockarrow.py and
    solvers/sundials/linsol.py), ``"sparse"`` (SuperLU_MT on the block-arrow pattern) or
    ``"dense"`` (SUNDIALS dense LU); ``jacobian``: ``"analytic"``
    (default) or ``"fd"`` (structured differences, a cross-check). Tolerances come from the
    scene (``numerics.rtol``, ``atol``). ``delta_cj_lsetup``: refresh the Jacobian and its
    factorisation when c_j = α/h has moved by more than this fraction since the last refresh
    (``IDASetDeltaCjLSetup``; default :data:`DELTA_CJ_LSETUP`, SUNDIALS' own is 0.25).
    ``max_order``, ``nonlin_conv_coef``, ``max_nonlin_iters``: ``IDASetMaxOrd``,
    ``IDASetNonlinConvCoef``, ``IDASetMaxNonlinIters`` (None, the default: SUNDIALS' 5, 0.33,
    4); ``eta_max_fx``, ``eta_max``, ``eta_conv_fail``: the step ratio below which IDA keeps
    its step (``IDASetEtaFixedStepBounds``' upper bound, 2), the largest growth of a step
    (``IDASetEtaMax``, 2) and the cut after a Newton failure (``IDASetEtaConvFail``, 0.25);
    all measured at equal error in docs/performance.md, "IDA's settings at equal error".
    ``atol_factors``: {unknown name: factor} multiplying those unknowns' absolute tolerance
    (e.g. ``{"skew_rate": 10.0}``; :func:`atol_vector`), for tuning the error weights of fast
    variables; none by default (docs/performance.md, "IDA's settings at equal error").

    ``suppress_alg`` (default False): leave the algebraic unknowns (theory.md §5: roller radial
    position and tilt, ring displacement and tilt) out of IDA's local error test
    (``IDASetSuppressAlg``); the Newton iteration still solves their equations at every step,
    and their quasi-static error no longer sets the step. What it buys depends on the scene:
    −35 … −70 % residual calls on harris36 at 6000 N and heavier, high speed at light load and
    rigid pockets, −2 % and no CPU on the default run, −13 … +5 % on harris36 at 500 N
    (docs/performance.md, "Cost of each switch").
    With larger steps IDA's Newton iteration can accept a step with a roller's contact rows off
    their manifold (a stale Jacobian across slice onsets) and then fail at every step size;
    such a corrector failure is recovered by a **projected restart**: IDA's last accepted
    state, its algebraic unknowns solved again by the static Newton (solvers/algebraic.py) and
    y' from the equations of motion, as at the start of a run, then ``IDAReInit`` (order 1).
    Allowed when IDA accepted at least :data:`RESTART_MIN_STEPS` steps since the previous one
    and at most ``max_restarts`` times (None: no cap); otherwise, and for every other failure,
    the run fails as it would without. With ``suppress_alg=False`` there are no restarts,
    except in a scene with flanges (theory.md §16): there an unloaded roller pinched
    diagonally between two flanges has a soft tilt (its algebraic block's smallest singular
    value ~1/300 of a loaded roller's), in which IDA's Newton iteration can accept a step off
    the manifold and then fail at every step size (measured: an NUP under -300 N with a
    dynamic ring, at 15.7 ms; one restart and the revolution runs). A restart only replaces
    such a failure, so a run that succeeds is the same with or without.

    **Fallback** (``suppress_alg=False``): the first corrector failure of a run switches the
    error test to ``suppress_alg``'s (``IDASetSuppressAlg`` from there on) and makes a projected
    restart; restarts are then allowed as with ``suppress_alg=True``. A failure that only the
    algebraic unknowns' error test provokes (IDA cutting the step to the minimum on their
    quasi-static error) then goes on; measured: yang20 at 500 r/min and 8000 N (the paper's
    model, and with the friction switches) failed at t ≈ 0.06-0.26 s and run with it.
    The statistics count it (``algebraic_error_test_fallbacks``; its time is the first of
    ``restart_times_s``) and the run warns. A run that does not fail is unchanged, bit for bit.

    Statistics (``Solution.stats``) come from IDA itself: steps, residual and Jacobian
    evaluations, error-test and convergence failures, Newton iterations, linear-solver set-ups,
    projected restarts (count and times), the last step and order, and — sampled once per
    output time, so approximate — the smallest last step and a histogram of the order in use at
    the output times. ``record_steps=True`` (benchmarks: a Python round trip per step) records
    every step instead (``last_step_record``: sizes and times) and names each step's limiter,
    the unknown of largest weighted local error (``step_limiters``: steps per unknown name).
    """

    name = "ida"
    locates_edges = True
    #: a dynamic ring's displacement at sub-sample times for the record's anti-alias filter
    #: (system/taps.py); IDA interpolates there without extra steps
    ring_taps = True
    LINSOLVERS = ("sparse", "dense", "blockarrow")

    def __init__(self, linsolver: str = "blockarrow", jacobian: str = "analytic",
                 suppress_alg: bool = False, record_steps: bool = False,
                 delta_cj_lsetup: float = None, max_restarts: int | None = None,
                 atol_factors: dict | None = None, max_order: int | None = None,
                 nonlin_conv_coef: float | None = None, max_nonlin_iters: int | None = None,
                 eta_max_fx: float | None = None, eta_max: float | None = None,
                 eta_conv_fail: float | None = None):
        super().__init__(linsolver, jacobian)
        self.atol_factors = check_atol_factors(atol_factors)
        self.step_controls = check_step_controls(max_order=max_order,
                                                 nonlin_conv_coef=nonlin_conv_coef,
                                                 max_nonlin_iters=max_nonlin_iters,
                                                 eta_max_fx=eta_max_fx, eta_max=eta_max,
                                                 eta_conv_fail=eta_conv_fail)
        dcj = DELTA_CJ_LSETUP if delta_cj_lsetup is None else delta_cj_lsetup
        if isinstance(dcj, bool) or not (isinstance(dcj, (int, float, np.floating))
                                         and 0.0 < dcj < 1.0):
            raise ValueError(f"delta_cj_lsetup = {delta_cj_lsetup!r}: allowed is a number "
                             "in (0, 1)")
        self.delta_cj_lsetup = float(dcj)
        if max_restarts is not None and (isinstance(max_restarts, bool)
                                         or not isinstance(max_restarts, (int, np.integer))
                                         or max_restarts < 0):
            raise ValueError(f"max_restarts = {max_restarts!r}: allowed are None (no cap) or "
                             "an integer >= 0")
        self.suppress_alg = check_flag(suppress_alg, "suppress_alg")
        self._restarts_on = self.suppress_alg  # and a scene with flanges (``_run``)
        self.max_restarts = None if max_restarts is None else int(max_restarts)
        self.record_steps = check_flag(record_steps, "record_steps")
        self.last_step_record: tuple | None = None  # (step sizes [s], times [s]); record_steps
        self._edges = None  # the root finding of a run with located defect edges
        #: that run's crossings (t, roller, defect-table entry, contact, ±1, ...: ida_edges.py)
        self.last_edge_crossings: list | None = None

    def describe(self) -> dict:
        opts = {"linsolver": self.linsolver, "jacobian": self.jacobian,
                "delta_cj_lsetup": self.delta_cj_lsetup, "suppress_alg": self.suppress_alg}
        if self.suppress_alg:
            opts["max_restarts"] = self.max_restarts
        if self.atol_factors:  # (absent by default: the default run's attributes unchanged)
            opts["atol_factors"] = dict(self.atol_factors)
        opts.update(self.step_controls)  # (likewise: only those given)
        alg = ("algebraic unknowns out of the error test, projected restart on corrector "
               "failure" if self.suppress_alg else "every unknown in the error test")
        return {"solver": self.name,
                "solver_description": (f"SUNDIALS IDA (BDF, {self.linsolver} linear solver, "
                                       f"{self.jacobian} Jacobian, {alg}), compiled callbacks"),
                "options": opts}

    def _run(self, model, y0, yp0, t_out, t_start, emit):
        from .sundials.session import Session

        dyn = model.scene.dynamics
        n = model.size
        # projected restarts on a corrector failure: with suppress_alg, or flanges (docstring)
        self._restarts_on = self.suppress_alg or model.layout.flange
        pattern = sparsity_pattern(model)
        pat = pattern.tocoo()
        if self.jacobian == "analytic":
            def jac_work(rows, cols):
                return analytic_work(model, rows, cols)
        else:
            def jac_work(rows, cols):
                jd, _ = _jacobian_work(model, pattern)
                return (jd[0], rows, cols) + tuple(jd[3:])
        self._extra = {"linsolver": self.linsolver, "jacobian": self.jacobian}
        setup_t0 = time.perf_counter()
        with Session(n, y0, yp0, t_start, model.work + model.data[-1:], jac_work, self.jacobian,
                     pat.row.astype(np.int64), pat.col.astype(np.int64), self.linsolver,
                     dyn.rtol, atol_vector(model.layout, dyn.atol, self.atol_factors),
                     model.layout.algebraic, dyn.max_steps, MIN_STEP_S, 1.0,
                     self.suppress_alg,
                     blocks=(model.layout.rollers, model.layout.n_local,
                             model.layout.n_global)) as ses:
            # Set-up: the compiled callbacks and linear-solver operations loaded from numba's
            # cache, or compiled on a cold start (several seconds, counted in wall_time_s)
            self._extra["setup_wall_s"] = time.perf_counter() - setup_t0
            ses.set_delta_cj_lsetup(self.delta_cj_lsetup)
            ses.set_step_controls(**self.step_controls)
            ext = None
            if self._extremes_from is not None:
                from ..system.extremes import Extremes

                ext = self._extremes = Extremes(model.layout.rollers, model.geometry.slices,
                                                self._extremes_from)
                ses.track_extremes(ext.buffer, dyn.rtol)
            tracker = StatsTracker(ses)
            self._edges = None
            if has_sharp(model.defect_table):  # numerics.defect_edges = "locate" (ida_edges.py)
                from .ida_edges import EdgeRoots

                self._edges = EdgeRoots(model, ses, t_start, y0, _restart)
            try:
                flag = ses.calc_ic(t_start + CALC_INIT_DT_S)
                if flag < 0:
                    return (False, f"consistent initialisation failed at t = {t_start:.6g} s: "
                            f"{_cause(flag, ses)}", t_start)
                if ext is not None:
                    ses.arm_extremes()
                taps, carried = None, False
                if model.layout.ring_dynamic and self.ring_taps:
                    from ..system.taps import RingTaps

                    carried = getattr(model, "ring_taps_carried", None) is not None
                    taps = model.ring_taps = RingTaps.for_run(model)
                t_iter = self._emit_start(t_out, t_start, emit, ses.y, ses.yp)
                # the first interval is not tapped (IDA's first step as without taps), but
                # for a resumed run, whose taps before it the replay restored
                t_prev = float(t_start) if carried else None
                for tk in t_iter:
                    if t_prev is not None and taps is not None:
                        for tau in taps.between(t_prev, float(tk)):
                            flag, t_reached = self._reach(model, ses, tracker, float(tau))
                            if _failed(flag, ses):
                                return (False, f"IDA failed at t = {t_reached:.6g} s: "
                                        f"{_failure_cause(flag, ses)}", t_reached)
                            taps.add(t_reached, ses.y)
                    flag, t_reached = self._reach(model, ses, tracker, float(tk))
                    tracker.sample()
                    if _failed(flag, ses):
                        return (False, f"IDA failed at t = {t_reached:.6g} s: "
                                f"{_failure_cause(flag, ses)}", t_reached)
                    if taps is not None:
                        taps.add(t_reached, ses.y)
                    emit(t_reached, ses.y, ses.yp)
                    t_prev = float(tk)
                if taps is not None and t_prev is not None and len(t_out) > 1:
                    self._tail(model, ses, tracker, taps, t_prev, float(t_out[-1] - t_out[-2]))
                return True, "completed", None
            finally:  # also on Ctrl-C: the base reports the interruption, counts stay right
                tracker.finish(self.counters, self._extra, self.jacobian, model)
                if self._edges is not None:
                    self._edges.finish(self._extra)
                    self.last_edge_crossings = self._edges.crossings
                if tracker.suppressed_from_s is not None:
                    warnings.warn(
                        "IDA: a corrector failure; from there on the algebraic unknowns were "
                        "left out of the error test (as IDA(suppress_alg=True)) and IDA "
                        "restarted, their error then the Newton tolerance's (solver statistics "
                        "algebraic_error_test_fallbacks, restart_times_s)",
                        SolverFallbackWarning, stacklevel=2)
                if self.record_steps:
                    self.last_step_record = (np.array(tracker.steps_s),
                                             np.array(tracker.times_s))

    def _reach(self, model, ses, tracker, tk: float) -> tuple[int, float]:
        """IDASolve to ``tk``, restarting on a corrector failure where allowed; the first
        corrector failure of a run whose error test still sees the algebraic unknowns
        suppresses them and restarts (class docstring, "fallback")."""
        flag, t_reached = self._advance(ses, tracker, tk)
        while flag == IDA_CONV_FAIL:
            fallback = tracker.suppressed_from_s is None and not self.suppress_alg
            if not (fallback or self._may_restart(tracker)):
                break
            if fallback:
                ses.suppress_algebraic()
                tracker.suppressed_from_s = float(t_reached)
                self._restarts_on = True
            if not _restart(model, ses, tracker, t_reached):
                break
            flag, t_reached = self._advance(ses, tracker, tk)
        return flag, t_reached

    def _tail(self, model, ses, tracker, taps, t_last: float, dt: float) -> None:
        """The taps past the last sample (system/taps.py): the record's filter is centred on
        each sample. Its steps are outside the record: the extremes stop folding them. A
        failure there ends the taps, not the run (the record is complete)."""
        from ..system.extremes import H_ARMED
        from ..system.taps import TAIL_INTERVALS, TAPS_PER_INTERVAL

        if self._extremes is not None:
            self._extremes.buffer[H_ARMED] = 0.0
        n = TAIL_INTERVALS * TAPS_PER_INTERVAL
        for j in range(1, n + 1):
            flag, t_reached = self._reach(model, ses, tracker, t_last + dt * j / TAPS_PER_INTERVAL)
            if _failed(flag, ses):
                return
            taps.add(t_reached, ses.y)

    def _advance(self, ses, tracker, tk: float) -> tuple[int, float]:
        """IDASolve to ``tk`` (one internal step per call with ``record_steps``), restarted
        at each sharp defect edge on the way (solvers/ida_edges.py)."""
        if self._edges is not None:
            return self._edges.advance(lambda t: self._solve(ses, tracker, t), tracker, tk)
        return self._solve(ses, tracker, tk)

    def _solve(self, ses, tracker, tk: float) -> tuple[int, float]:
        if not self.record_steps:
            return ses.solve(tk)
        n0 = len(tracker.steps_s)
        out = ses.solve_recording(tk, tracker.steps_s, tracker.times_s, tracker.limiters)
        tracker.most_per_output = max(tracker.most_per_output, len(tracker.steps_s) - n0)
        return out

    def _may_restart(self, tracker) -> bool:
        return (self._restarts_on
                and (self.max_restarts is None or tracker.restarts < self.max_restarts)
                and tracker.steps_since_restart() >= RESTART_MIN_STEPS)


def _restart(model, ses, tracker, t: float) -> bool:
    """Restart IDA at its last accepted state (``ses.y``, ``ses.yp`` at ``t`` after a failed
    IDASolve) with the algebraic unknowns projected onto theory.md §5 and the differential y' of
    the equations of motion (F linear in y' with the diagonal ``model.mass``, as
    ``initial_state``). False (nothing changed) if the projection fails: the caller then
    reports IDA's failure."""
    from .algebraic import project_algebraic

    try:
        y, _ = project_algebraic(model, t, ses.y.copy())
        res = model.residual(t, y, np.zeros_like(y))
    except Exception:  # noqa: BLE001 - any failure here leaves IDA's own failure to report
        return False
    yp = ses.yp.copy()
    diff = model.mass > 0
    yp[diff] = -res[diff] / model.mass[diff]
    if not (np.all(np.isfinite(y)) and np.all(np.isfinite(yp))):
        return False
    tracker.bank()
    tracker.restart_times.append(float(t))
    ses.restart(t, y, yp)
    return True


def _failed(flag: int, ses) -> bool:
    """IDA failed, or its state is not finite: one sum per call (a NaN or inf anywhere makes
    it non-finite), the element-wise test only when it is."""
    return flag < 0 or not (math.isfinite(ses.y.sum() + ses.yp.sum())
                            or (np.all(np.isfinite(ses.y)) and np.all(np.isfinite(ses.yp))))


def _failure_cause(flag: int, ses) -> str:
    return _cause(flag, ses) if flag < 0 else "the solution became non-finite"


def _cause(flag: int, ses) -> str:
    from .sundials.prototypes import flag_message

    said = ses.last_error()
    return flag_message(flag) + (f"; SUNDIALS: {said}" if said else "")


def integrate(model: Model, y0: np.ndarray, yp0: np.ndarray, t_out: np.ndarray,
              linsolver: str = "blockarrow", progress=None,
              jacobian: str = "analytic", t_start: float = 0.0,
              on_sample=None) -> Solution:
    """``IDA(linsolver, jacobian).integrate(...)`` (the function form of earlier versions)."""
    return IDA(linsolver, jacobian).integrate(model, y0, yp0, t_out, t_start=t_start,
                                              progress=progress, on_sample=on_sample)


# The scikit-sundae cross-check lives in its own module; importable from here as before.
from .ida_scikit_sundae import IDAScikitSundae, make_solver  # noqa: E402,F401
