"""scikit-sundae IDA adapter: integrate the DAE model to the output times (MODEL §11).

Facts this relies on (SOLVER-NOTES.md, measured): ``calc_initcond='yp0'`` computes the algebraic
y and the differential y' (IDA_YA_YDP_INIT); ``linsolver='sparse'`` is SuperLU_MT and with a
``jacfn`` its ``JJ`` is the CSC data array of the ``sparsity`` pattern; IDA's own ``nfev`` does
not count residual calls inside our Jacobian, so we count them ourselves.

The integration advances output time by output time (``step(t_k)``), so a failure keeps every
sample computed before it and the caller can report the time it happened.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..system.jacobian import jacobian_dense, jacobian_sparse
from ..system.jacobian_analytic import (analytic_work, jacobian_analytic_dense,
                                        jacobian_analytic_sparse)
from ..system.model import Model
from ..system.residual import residual_flat
from .base import IntegrationResult, Solution, Solver  # noqa: F401  (IntegrationResult: old name)
# The pieces every solver of the DAE shares (algebraic tolerance, sparsity, Jacobian fillers)
# live in solvers/common.py; re-exported here for the code that imported them from ida.
from .common import (ALG_ATOL_FACTOR, ALG_ATOL_MAX, JACOBIANS,  # noqa: F401
                     _jacobian_work, algebraic_atol, jacobian_filler, sparsity_pattern)


MIN_STEP_S = 1e-15


def make_solver(model: Model, linsolver: str = "sparse", atol=None, jacobian: str = "analytic"):
    """An ``sksundae.ida.IDA`` for the model, plus call counters [res, jac, res-in-jac].

    ``jacobian``: ``"analytic"`` (system/jacobian_analytic.py, the default: about one residual
    evaluation each) or ``"fd"`` (structured finite differences, n_local + n_global + 1
    evaluations; kept as an independent cross-check). ``atol``: per-component absolute
    tolerances (scaled units) replacing the default ones.

    The residual callback is the compiled kernel itself (``residual_flat`` with
    ``userdata = model.work``): no Python frame per call. IDA counts those calls itself, so
    ``counts[0]`` is filled from its ``nfev`` (``integrate``); the Jacobian callback is a Python
    closure that counts (it runs ~0.07 times per step).
    """
    from sksundae.ida import IDA

    d = model.data
    jd, pattern = _jacobian_work(model, sparsity_pattern(model))
    counts = np.zeros(3, dtype=np.int64)
    if jacobian not in JACOBIANS:
        raise ValueError(f"jacobian = {jacobian!r}: allowed are {', '.join(map(repr, JACOBIANS))}")
    if linsolver not in ("sparse", "dense"):
        raise ValueError(f"linsolver = {linsolver!r}: allowed are 'sparse' and 'dense'")
    if jacobian == "analytic":
        jd = analytic_work(model, jd[1], jd[2])
        evals_per_jac = 0
        kernel = jacobian_analytic_sparse if linsolver == "sparse" else jacobian_analytic_dense
    else:
        evals_per_jac = model.layout.n_local + model.layout.n_global + 1
        kernel = jacobian_sparse if linsolver == "sparse" else jacobian_dense

    def jacfn(t, y, yp, res, cj, JJ, userdata):
        counts[1] += 1
        counts[2] += evals_per_jac
        kernel(t, y, yp, res, cj, JJ, d, jd)

    dyn = model.scene.dynamics
    opts = dict(
        rtol=dyn.rtol,
        atol=(np.where(model.layout.algebraic, algebraic_atol(dyn.atol), dyn.atol)
              if atol is None else np.asarray(atol, float)),
        algebraic_idx=np.flatnonzero(model.layout.algebraic).tolist(),
        calc_initcond="yp0",
        calc_init_dt=1e-7,
        linsolver=linsolver,
        jacfn=jacfn,
        max_num_steps=dyn.max_steps,
        # A NaN in the residual makes IDA retry forever at one t with status 0 (measured);
        # a minimum step turns that into a clean failure (status -4). 1e-13 s was too large
        # for the start of a 30 000 r/min scene (its first steps go below it); 1e-15 s works.
        min_step=MIN_STEP_S,
        max_step=1.0,
    )
    if linsolver == "sparse":
        opts["sparsity"] = pattern
    with warnings.catch_warnings():
        # sksundae warns that its own sparse FD Jacobian is not used when jacfn is given.
        warnings.simplefilter("ignore", UserWarning)
        solver = IDA(residual_flat, userdata=model.work, **opts)
    return solver, counts


class IDA(Solver):
    """SUNDIALS IDA (variable-order BDF) through scikit-sundae: the reference integrator.

    ``linsolver``: ``"sparse"`` (SuperLU_MT on the block-arrow pattern, the default) or
    ``"dense"``; ``jacobian``: ``"analytic"`` (default) or ``"fd"`` (structured differences, a
    cross-check). Tolerances come from the scene (``numerics.rtol``, ``atol``).
    """

    name = "ida"

    def __init__(self, linsolver: str = "sparse", jacobian: str = "analytic"):
        if linsolver not in ("sparse", "dense"):
            raise ValueError(f"linsolver = {linsolver!r}: allowed are 'sparse' and 'dense'")
        if jacobian not in JACOBIANS:
            raise ValueError(f"jacobian = {jacobian!r}: allowed are "
                             f"{', '.join(map(repr, JACOBIANS))}")
        self.linsolver, self.jacobian = linsolver, jacobian
        self._extra: dict = {}

    def describe(self) -> dict:
        return {"solver": self.name,
                "solver_description": (f"SUNDIALS IDA via scikit-sundae (BDF, {self.linsolver} "
                                       f"linear solver, {self.jacobian} Jacobian)"),
                "options": {"linsolver": self.linsolver, "jacobian": self.jacobian}}

    def extra_stats(self) -> dict:
        return dict(self._extra)

    def _run(self, model, y0, yp0, t_out, t_start, emit):
        solver, counts = make_solver(model, self.linsolver, jacobian=self.jacobian)
        self._extra = {"linsolver": self.linsolver, "jacobian": self.jacobian}
        try:
            r = solver.init_step(t_start, y0, yp0)
        except Exception as exc:  # sksundae raises RuntimeError when IDACalcIC fails
            return False, f"consistent initialisation failed: {exc}", t_start
        ok, msg, fail_t = True, "completed", None
        try:
            if t_out[0] == t_start:
                emit(t_start, r.y, r.yp)
                t_iter = t_out[1:]
            else:
                t_iter = t_out
            for tk in t_iter:
                r = solver.step(float(tk))
                if r.status < 0 or not np.all(np.isfinite(r.y)):
                    ok, fail_t = False, float(r.t)
                    msg = f"IDA failed at t = {r.t:.6g} s: {r.message}"
                    break
                emit(float(r.t), r.y, r.yp)
        finally:  # also on Ctrl-C: the base reports the interruption, the counts stay right
            c = self.counters
            c.residual_calls = int(r.nfev)
            c.jacobian_calls, c.residual_calls_in_jacobian = int(counts[1]), int(counts[2])
            try:
                s = solver.get_stats() if hasattr(solver, "get_stats") else {}
                self._extra.update({k: (int(v) if isinstance(v, (int, np.integer)) else v)
                                    for k, v in dict(s).items()})
                c.steps = int(self._extra.get("nst", self._extra.get("steps", 0)) or 0)
            except Exception:  # statistics are informative only
                pass
        return ok, msg, fail_t


def integrate(model: Model, y0: np.ndarray, yp0: np.ndarray, t_out: np.ndarray,
              linsolver: str = "sparse", progress=None,
              jacobian: str = "analytic", t_start: float = 0.0,
              on_sample=None) -> Solution:
    """``IDA(linsolver, jacobian).integrate(...)`` (the function form of earlier versions)."""
    return IDA(linsolver, jacobian).integrate(model, y0, yp0, t_out, t_start=t_start,
                                              progress=progress, on_sample=on_sample)


def check_jacobian(model: Model, y: np.ndarray, yp: np.ndarray, cj: float = 1e3,
                   jacobian: str = "fd", rel_step: float = 1e-6) -> float:
    """Max difference between a Jacobian of ours (``"fd"``: structured finite differences,
    ``"analytic"``) and central differences of the residual, relative to each column's largest
    entry (a diagnostic and a test hook). ``rel_step`` must resolve the shortest regularisation
    length in play (a roller pressed into a pocket bar bends its force over 0.1 µm)."""
    n = model.size
    jd, fill, _ = jacobian_filler(model, jacobian)
    fill(0.0, y, yp, cj, model.data, jd)
    J = jd[0]
    ref = np.zeros((n, n))
    for j in range(n):
        h = rel_step * max(abs(y[j]), 1.0)
        e = np.zeros(n)
        e[j] = h
        ref[:, j] = (model.residual(0.0, y + e, yp + cj * e)
                     - model.residual(0.0, y - e, yp - cj * e)) / (2 * h)
    # Forward differences carry round-off of order sqrt(eps) times the column's magnitude, so
    # the error is measured against the largest entry of each column.
    scale = np.abs(ref).max(axis=0) + 1e-300
    return float(np.max(np.abs(J - ref) / scale[None, :]))
