"""scipy ``solve_ivp`` peers on the same model: the paper's nested approach.

The DAE F(t, y, y') = M y' - f(t, y) = 0 (diagonal M, zero on the algebraic rows) is reduced
to an ODE in the differential unknowns y_d alone: for each right-hand-side call the algebraic
unknowns z (radial_position, tilt, ring_*) are solved from F_a(t, y_d, z) = 0 by an inner
Newton, warm-started from the previous call's z, and then

    y_d' = -F_d(t, y_d, z, 0) / M_d.

The inner Newton reuses the DAE kernel (system/residual.py) and is a chord iteration: the
inverse of dF_a/dz is kept between calls and refreshed (from the DAE Jacobian, analytic as for
IDA, or structured FD) only when the residual stops shrinking fast; each call starts from the
linear prediction z_ref + dz/dy_d (y_d - y_d,ref) of the last converged call. ``project_algebraic`` (the static solver's numpy
Newton) does the same job but costs ~0.8 ms per call against ~35 µs per kernel evaluation.

The Jacobian handed to BDF / Radau / LSODA (``jac="schur"``, the default) is the exact
derivative of the reduced right-hand side, the Schur complement

    d y_d'/d y_d = -M_d^-1 (J_dd - J_da J_aa^-1 J_ad),   J = dF/dy at y' = 0,

from the same DAE Jacobian IDA uses; ``jac="fd"`` leaves it to scipy's dense finite
differences (one right-hand side, i.e. one inner Newton, per column). A ``jac_sparsity`` does
not help: the reduced Jacobian is structurally dense (the cage-speed row and the cage columns
are full, and through the ring every loaded roller's rows depend on every roller's azimuth),
so scipy's column grouping needs 102 groups for the 102 columns of the baseline (measured).

Stepping is done with the ``OdeSolver`` classes directly (what ``solve_ivp`` does inside) so a
failure or a wall-time limit keeps every output computed before it.
"""

from __future__ import annotations

import time
import warnings

import numpy as np
from numba import njit
from numba.extending import overload

from ..system.jacobian import fill_jacobian
from ..system.jacobian_analytic import fill_jacobian_analytic
from ..system.model import Model
from ..system.residual import residual
from .base import IntegrationResult, Solution, Solver  # noqa: F401  (IntegrationResult: old name)
from .common import JACOBIANS as DAE_JACOBIANS
from .common import check_choice, jacobian_filler
from .native_call import entry, native_call, residual_entry

#: the name of these kernels in the first-compile notice (util/kernel_cache.py)
KERNEL_GROUP = "scipy peers"

METHODS = ("BDF", "Radau", "LSODA")
JACOBIANS = ("schur", "fd")
#: inner solve: "chord" (numba, the default) or "static" (project_algebraic: the straightforward
#: nested implementation, ~0.8 ms per call; kept to measure what the lean inner Newton buys)
INNER = ("chord", "static")
# Chord iteration: refresh dF_a/dz when the residual shrinks by less than this factor ...
CHORD_RATE = 0.3
# ... and give up after this many iterations in one call.
INNER_MAX_ITERATIONS = 30
# Inner tolerance on the scaled algebraic rows (forces by F_ref: the scaled dF_a/dz is O(1-10),
# so this is also the error of z in units of its scale): a factor below rtol, so the inner
# solve does not pollute the outer error test, floored near round-off of the contact sums.
INNER_TOL_FACTOR = 1e-3
INNER_TOL_MIN = 1e-13
INNER_TOL_MAX = 1e-9


class InnerNewtonError(RuntimeError):
    """The algebraic part could not be solved at some right-hand-side call."""


def inner_tolerance(rtol: float) -> float:
    """Tolerance of the inner Newton (max |F_a| in scaled rows) for an outer ``rtol``."""
    return min(max(INNER_TOL_FACTOR * rtol, INNER_TOL_MIN), INNER_TOL_MAX)


def _fill(t, y, yp, d, jd, at):
    """The DAE Jacobian's filler of the work tuple ``jd`` (compiled code only) with c_j = 0,
    through its address ``at`` (:func:`kernel_entries`): analytic
    (system/jacobian_analytic.analytic_work, 8 arrays) or structured FD (9 arrays), chosen
    when the caller compiles. Not the filler as an argument: numba cannot cache a kernel that
    takes a function (every process would compile these kernels again, ~26 s of CPU)."""


@overload(_fill)
def _fill_of(t, y, yp, d, jd, at):
    kernel = {8: fill_jacobian_analytic, 9: fill_jacobian}[len(jd)]

    def impl(t, y, yp, d, jd, at):
        native_call(kernel, at, (t, y, yp, 0.0, d, jd))
    return impl


def kernel_entries(d, jd) -> np.ndarray:
    """The ``calls`` of the kernels below: the (address, key) of the residual and of the
    Jacobian's filler for the work tuples ``d``, ``jd`` (solvers/native_call.py), compiled or
    loaded from numba's cache. Called through their addresses, they are not optimised again
    in these kernels' compile (a first LSODA run compiled for 3.4 s of CPU instead of 5.2 s
    on a 2-CPU Xeon; the same machine code of the callees, the same numbers)."""
    v = np.empty(1)
    filler = {8: fill_jacobian_analytic, 9: fill_jacobian}[len(jd)]
    return np.array(residual_entry(d) + entry(filler, 0.0, v, v, 0.0, d, jd), np.int64)


@njit(cache=True, no_cfunc_wrapper=True)
def _refresh(t, y, yp0, d, jd, diff, alg, Jinv, S, calls):
    """DAE Jacobian J = dF/dy at (t, y, y' = 0) into jd[0] by :func:`_fill` (analytic or
    structured FD, as ``jd`` is); Jinv <- (dF_a/dz)^-1 and the sensitivity S = dz/dy_d =
    -J_aa^-1 J_ad (the predictor of the next call's z)."""
    _fill(t, y, yp0, d, jd, (calls[2], calls[3]))
    J = jd[0]
    na, nd = alg.shape[0], diff.shape[0]
    Jaa = np.empty((na, na))
    Jad = np.empty((na, nd))
    for a in range(na):
        for b in range(na):
            Jaa[a, b] = J[alg[a], alg[b]]
        for b in range(nd):
            Jad[a, b] = J[alg[a], diff[b]]
    # element loops, not ``Jinv[:, :] = ...``: a slice assignment checks the shapes and
    # compiles numba's error-message formatting (~3 s of a first run), for the same copy
    inv = np.linalg.inv(Jaa)
    for a in range(na):
        for b in range(na):
            Jinv[a, b] = inv[a, b]
    JinvJad = Jinv @ Jad
    for a in range(na):
        for b in range(nd):
            S[a, b] = -JinvJad[a, b]


@njit(cache=True, no_cfunc_wrapper=True)
def algebraic_newton(t, yd, y, yp0, res, d, jd, diff, alg, Jinv, S, ref, tol, counts, calls):
    """Solve F_a(t, y_d, z) = 0 for z = y[alg] (chord Newton), with y[diff] <- yd.

    Start: the linear prediction z_ref + S (yd - yd_ref) from the last converged call
    (``ref`` = [yd_ref, z_ref]). On return ``res`` holds F(t, y, 0) at the converged y.
    Returns the iterations used, or -1. counts: [rhs calls, kernel evaluations, Jacobian
    refreshes, inner iterations]; ``calls``: :func:`kernel_entries`.
    """
    na, nd = alg.shape[0], diff.shape[0]
    if not np.isfinite(Jinv[0, 0]):  # first call: ref holds the initial state
        for i in range(nd):
            y[diff[i]] = yd[i]
        _refresh(t, y, yp0, d, jd, diff, alg, Jinv, S, calls)
        counts[2] += 1
    for a in range(na):
        s = ref[nd + a]
        for b in range(nd):
            s += S[a, b] * (yd[b] - ref[b])
        y[alg[a]] = s
    for i in range(nd):
        y[diff[i]] = yd[i]
    r_prev = np.inf
    for it in range(INNER_MAX_ITERATIONS):
        native_call(residual, (calls[0], calls[1]), (t, y, yp0, res, d))
        counts[1] += 1
        r = 0.0
        for a in range(na):
            v = abs(res[alg[a]])
            if not v <= r:  # also catches NaN
                r = v
        if r <= tol:
            counts[3] += it
            for i in range(nd):
                ref[i] = yd[i]
            for a in range(na):
                ref[nd + a] = y[alg[a]]
            return it
        if not np.isfinite(r):
            return -1
        if r > CHORD_RATE * r_prev:
            _refresh(t, y, yp0, d, jd, diff, alg, Jinv, S, calls)
            counts[2] += 1
        for a in range(na):
            s = 0.0
            for b in range(na):
                s += Jinv[a, b] * res[alg[b]]
            y[alg[a]] -= s
        r_prev = r
    return -1


@njit(cache=True, no_cfunc_wrapper=True)
def reduced_rhs(t, yd, y, yp0, res, d, jd, diff, alg, mass_d, Jinv, S, ref, tol, counts,
                calls, out):
    """out <- y_d' of the reduced ODE at (t, yd)."""
    counts[0] += 1
    it = algebraic_newton(t, yd, y, yp0, res, d, jd, diff, alg, Jinv, S, ref, tol, counts,
                          calls)
    for i in range(diff.shape[0]):
        out[i] = -res[diff[i]] / mass_d[i]
    return it


@njit(cache=True, no_cfunc_wrapper=True)
def reduced_jacobian(t, yd, y, yp0, res, d, jd, diff, alg, mass_d, Jinv, S, ref, tol,
                     counts, calls, Jr):
    """Jr <- d y_d'/d y_d = -M_d^-1 (J_dd + J_da S), S = -J_aa^-1 J_ad (Schur complement)."""
    it = algebraic_newton(t, yd, y, yp0, res, d, jd, diff, alg, Jinv, S, ref, tol, counts,
                          calls)
    if it < 0:
        return it
    _refresh(t, y, yp0, d, jd, diff, alg, Jinv, S, calls)
    counts[2] += 1
    J = jd[0]
    nd, na = diff.shape[0], alg.shape[0]
    for a in range(nd):
        for b in range(nd):
            s = J[diff[a], diff[b]]
            for c in range(na):
                s += J[diff[a], alg[c]] * S[c, b]
            Jr[a, b] = -s / mass_d[a]
    return it


class ReducedODE:
    """The reduced ODE y_d' = g(t, y_d) of a model, with its Jacobian and call counters."""

    def __init__(self, model: Model, y0: np.ndarray, rtol: float,
                 dae_jacobian: str = "analytic", inner: str = "chord"):
        if inner not in INNER:
            raise ValueError(f"inner = {inner!r}: allowed are {', '.join(INNER)}")
        n = model.size
        self.model = model
        self.inner = inner
        self.alg = np.flatnonzero(model.layout.algebraic).astype(np.int64)
        self.diff = np.flatnonzero(~model.layout.algebraic).astype(np.int64)
        self.mass_d = model.mass[self.diff].copy()
        self.y = np.array(y0, dtype=float)
        self.yp0 = np.zeros(n)
        self.res = np.zeros(n)
        # the kernels pick the filler by the work tuple's layout (_fill): only jd is kept
        self.jd, _, self.evals_per_jacobian = jacobian_filler(
            model, dae_jacobian, key="dae_jacobian")
        na, nd = self.alg.size, self.diff.size
        self.Jinv = np.full((na, na), np.nan)
        self.S = np.zeros((na, nd))
        self.ref = np.concatenate([self.y[self.diff], self.y[self.alg]])
        self.tol = inner_tolerance(rtol)
        self.counts = np.zeros(4, dtype=np.int64)
        self._args = (self.y, self.yp0, self.res, model.data, self.jd, self.diff, self.alg,
                      self.mass_d, self.Jinv, self.S, self.ref, self.tol, self.counts,
                      kernel_entries(model.data, self.jd))

    def fun(self, t, yd):
        if self.inner == "static":
            return self._fun_static(t, yd)
        out = np.empty(self.diff.size)
        # scipy's finite differences pass column views: one array layout, one compilation.
        yd = np.ascontiguousarray(yd, dtype=float)
        if reduced_rhs(t, yd, *self._args, out) < 0:
            raise InnerNewtonError(f"inner Newton on the algebraic unknowns failed at "
                                   f"t = {t:.6g} s")
        return out

    def _fun_static(self, t, yd):
        """The straightforward nested right-hand side: the static solver's Newton
        (``project_algebraic``, numpy, analytic Jacobian) warm-started from the last z."""
        from .algebraic import project_algebraic
        from .static import StaticConvergenceError

        self.counts[0] += 1
        self.y[self.diff] = yd
        try:
            y, it = project_algebraic(self.model, t, self.y)
        except StaticConvergenceError as exc:
            raise InnerNewtonError(f"static Newton failed at t = {t:.6g} s: {exc}") from None
        self.y[:] = y
        self.counts[3] += it
        residual(t, self.y, self.yp0, self.res, self.model.data)
        self.counts[1] += 1
        return -self.res[self.diff] / self.mass_d

    def jac(self, t, yd):
        Jr = np.empty((self.diff.size, self.diff.size))
        yd = np.ascontiguousarray(yd, dtype=float)
        if reduced_jacobian(t, yd, *self._args, Jr) < 0:
            raise InnerNewtonError(f"inner Newton on the algebraic unknowns failed at "
                                   f"t = {t:.6g} s (Jacobian)")
        return Jr

    def full_state(self, t, yd) -> tuple[np.ndarray, np.ndarray]:
        """(y, y') of the DAE at (t, y_d): algebraic part solved, y'_a = 0 (not tracked)."""
        ydot = self.fun(t, yd)
        y = self.y.copy()
        yp = np.zeros_like(y)
        yp[self.diff] = ydot
        return y, yp


class ScipyPeer(Solver):
    """A scipy ``OdeSolver`` (BDF, Radau, LSODA) on the reduced ODE: the paper's nested approach.

    ``method``: one of :data:`METHODS`; ``jac``: ``"schur"`` (the exact reduced Jacobian, the
    default) or ``"fd"`` (scipy's dense differences); ``dae_jacobian``: how dF/dy is formed for
    the inner Newton and the Schur complement, ``"analytic"`` (as IDA) or ``"fd"``;
    ``inner``: see :data:`INNER` (``"static"`` with ``jac="fd"`` is the naive nested approach);
    ``time_limit_s``: wall time after which the run stops (a failure that keeps its samples).
    Tolerances: the scene's rtol, and its atol on every differential unknown (scaled units, as
    for IDA). ``yp0`` is not used (scipy needs no initial derivative).
    """

    def __init__(self, method: str = "BDF", jac: str = "schur",
                 time_limit_s: float | None = None, dae_jacobian: str = "analytic",
                 inner: str = "chord"):
        check_choice(method, METHODS, "method")
        check_choice(jac, JACOBIANS, "jac")
        check_choice(dae_jacobian, DAE_JACOBIANS, "dae_jacobian")
        check_choice(inner, INNER, "inner")
        if time_limit_s is not None and (isinstance(time_limit_s, bool) or not isinstance(
                time_limit_s, (int, float, np.floating, np.integer))):
            raise TypeError(f"time_limit_s = {time_limit_s!r:.100}: expected a positive number "
                            f"of seconds or None, got {type(time_limit_s).__name__}")
        try:
            limit = None if time_limit_s is None else float(time_limit_s)
        except OverflowError:
            limit = float("inf")
        if limit is not None and not (0 < limit < float("inf")):
            raise ValueError(f"time_limit_s = {time_limit_s!r:.100}: expected a positive number "
                             "of seconds or None")
        self.method, self.jac, self.dae_jacobian, self.inner = method, jac, dae_jacobian, inner
        self.time_limit_s = limit
        self._extra: dict = {}

    @property
    def name(self) -> str:  # type: ignore[override]
        return f"scipy-{self.method}"

    def describe(self) -> dict:
        opts = {"method": self.method, "jac": self.jac, "dae_jacobian": self.dae_jacobian,
                "inner": self.inner}
        if self.time_limit_s is not None:
            opts["time_limit_s"] = self.time_limit_s
        return {"solver": self.name,
                "solver_description": (f"scipy {self.method} (solve_ivp OdeSolver) on the "
                                       f"reduced ODE, algebraic unknowns by an inner chord Newton "
                                       f"per right-hand side ({self.inner}), Jacobian: "
                                       f"{self.jac} ({self.dae_jacobian} dF/dy)"),
                "options": opts}

    def dataset_attrs(self, model, solution) -> dict:
        return {"sundials_version": f"not used (solver = {self.name})",
                "scikit_sundae_version": f"not used (solver = {self.name})",
                "atol_algebraic": inner_tolerance(model.scene.dynamics.rtol),
                "atol_units": "atol is in units of each differential unknown's scale "
                              "(unknown_scales); the algebraic unknowns are solved by the inner "
                              "Newton to atol_algebraic (max scaled residual)",
                "options": {"atol_algebraic": inner_tolerance(model.scene.dynamics.rtol)}}

    def extra_stats(self) -> dict:
        return dict(self._extra)

    def _run(self, model, y0, yp0, t_out, t_start, emit):
        from scipy import integrate as si

        dyn = model.scene.dynamics
        wall0 = time.perf_counter()
        ode = ReducedODE(model, y0, dyn.rtol, self.dae_jacobian, self.inner)
        solver, n_steps, k = None, 0, 0
        last_t = [t_start]
        opts = dict(rtol=dyn.rtol, atol=np.full(ode.diff.size, dyn.atol))
        if self.jac == "schur":
            opts["jac"] = ode.jac
        self._extra = {"method": self.method, "jacobian": self.jac, "inner": self.inner,
                       "dae_jacobian": self.dae_jacobian, "inner_tolerance": ode.tol}
        if self.time_limit_s is not None:
            self._extra["time_limit_s"] = self.time_limit_s

        def sample(tk, yd):
            y, yp = ode.full_state(tk, yd)
            last_t[0] = tk
            emit(tk, y, yp)

        try:
            if t_out[0] == t_start:
                sample(t_start, y0[ode.diff])
                k = 1
            solver = getattr(si, self.method)(ode.fun, t_start, np.array(y0[ode.diff]),
                                              float(t_out[-1]), **opts)
            while k < t_out.size:
                t_prev = solver.t
                message = solver.step()
                n_steps += 1
                if solver.status == "failed":
                    return (False, f"scipy {self.method} failed at t = {solver.t:.6g} s: "
                            f"{message}", float(solver.t))
                if t_out[k] <= solver.t:
                    dense = solver.dense_output()
                    while k < t_out.size and t_out[k] <= solver.t:
                        tk = float(t_out[k])
                        sample(tk, solver.y if tk == solver.t else dense(tk))
                        k += 1
                if (self.time_limit_s is not None and k < t_out.size
                        and time.perf_counter() - wall0 > self.time_limit_s):
                    return (False, f"time limit of {self.time_limit_s:.4g} s wall exceeded at "
                            f"t = {solver.t:.6g} s (from {t_prev:.6g} s)", float(solver.t))
                if solver.status == "finished" and k < t_out.size:
                    return (False, f"scipy {self.method} finished at t = {solver.t:.6g} s "
                            "before the last output", float(solver.t))
        except InnerNewtonError as exc:
            return False, str(exc), last_t[0]
        finally:  # also on Ctrl-C: the counters stay right
            c = ode.counts
            cnt = self.counters
            cnt.steps = int(n_steps)
            cnt.residual_calls = int(c[1])
            cnt.jacobian_calls = int(c[2])
            cnt.residual_calls_in_jacobian = int(c[2]) * ode.evals_per_jacobian
            self._extra.update({"rhs_calls": int(c[0]), "inner_jacobian_refreshes": int(c[2]),
                                "inner_iterations": int(c[3])})
            if solver is not None:
                self._extra.update({"nfev": int(solver.nfev), "njev": int(solver.njev),
                                    "nlu": int(solver.nlu)})
        return True, "completed", None


def integrate(model: Model, y0: np.ndarray, yp0: np.ndarray, t_out: np.ndarray,
              method: str = "BDF", jac: str = "schur", time_limit_s: float | None = None,
              progress=None, dae_jacobian: str = "analytic",
              inner: str = "chord") -> Solution:
    """Deprecated: ``ScipyPeer(method, jac, time_limit_s, dae_jacobian, inner).integrate(model,
    y0, yp0, t_out, progress=progress)`` (the contract of solvers/base.py)."""
    warnings.warn("bearingdae.solvers.scipy_peers.integrate is deprecated; use "
                  "ScipyPeer(method, ...).integrate(model, y0, yp0, t_out)",
                  DeprecationWarning, stacklevel=2)
    return ScipyPeer(method, jac, time_limit_s, dae_jacobian, inner).integrate(
        model, y0, yp0, t_out, progress=progress)
