"""SUNDIALS IDA through scikit-sundae's Python callbacks: the cross-check of the compiled core.

Stage: system (DAE model) -> **solver** -> results. :class:`IDAScikitSundae` runs the same IDA
7.x as :class:`bearingdae.solvers.ida.IDA`, with the same tolerances, algebraic atol, minimum
step and consistent initialisation, but through scikit-sundae's own Python callback wrappers
(one Python frame and fresh numpy views per residual call). It is kept as a tested cross-check
(tests/solvers/test_ida_compiled.py: the same samples and work counts, to the last bit, at
SUNDIALS' own Jacobian-refresh threshold and with SuperLU_MT, which is all scikit-sundae can
set), not as a second product.

Facts this path relies on (SOLVER-NOTES.md, measured): ``calc_initcond='yp0'`` computes the
algebraic y and the differential y' (IDA_YA_YDP_INIT); ``linsolver='sparse'`` is SuperLU_MT and
with a ``jacfn`` its ``JJ`` is the CSC data array of the ``sparsity`` pattern; IDA's own
``nfev`` does not count residual calls inside our Jacobian, so we count them.
"""

from __future__ import annotations

import warnings

import numpy as np
from numba import njit

from ..physics.compiled import copy1
from ..system.jacobian import jacobian_dense, jacobian_sparse
from ..system.jacobian_analytic import (analytic_work, jacobian_analytic_dense,
                                        jacobian_analytic_sparse)
from ..system.model import Model
from ..system.residual import residual
from ..system.work import work_views
from .common import JACOBIANS, _jacobian_work, algebraic_atol, sparsity_pattern
from .ida_base import CALC_INIT_DT_S, MIN_STEP_S, _IDABase


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def residual_flat(t, y, yp, res, work):
    """``residual`` with the work arrays as ``work = (W, I, marker, scratch)`` (system/work.py's
    ``flat_work``, the optional passes' marker and a (2, n) array): the residual callback
    passed to scikit-sundae directly (``userdata = work``), no Python frame in between.
    scikit-sundae hands y and y' over read-only: copied into ``scratch`` (~0.1 µs), the
    residual is called with the writable arrays of every other caller, the specialisation
    already compiled, instead of compiling another one for read-only arrays (~2 s of CPU)."""
    scratch = work[3]
    ys, yps = scratch[0], scratch[1]
    copy1(ys, y)
    copy1(yps, yp)
    residual(t, ys, yps, res, work_views(work[0], work[1]) + (work[2],))


def make_solver(model: Model, linsolver: str = "sparse", atol=None, jacobian: str = "analytic"):
    """An ``sksundae.ida.IDA`` for the model, plus call counters [res, jac, res-in-jac].

    ``jacobian``: ``"analytic"`` (system/jacobian_analytic.py, the default: about one residual
    evaluation each) or ``"fd"`` (structured finite differences, n_local + n_global + 1
    evaluations; kept as an independent cross-check). ``atol``: per-component absolute
    tolerances (scaled units) replacing the default ones.

    The residual callback is the compiled kernel itself (``residual_flat`` with
    ``userdata = model.work``, the optional passes' marker and a scratch array): no Python
    frame per call. IDA counts those calls itself, so
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
        # writable copies: scikit-sundae hands read-only views, and a read-only array is
        # another numba type, for which the whole Jacobian kernel would compile again
        # (~2.5 s of a first run; the copies cost ~1 µs at ~0.07 Jacobians a step)
        kernel(t, np.array(y), np.array(yp), res, cj, JJ, d, jd)

    dyn = model.scene.dynamics
    opts = dict(
        rtol=dyn.rtol,
        atol=(np.where(model.layout.algebraic, algebraic_atol(dyn.atol), dyn.atol)
              if atol is None else np.asarray(atol, float)),
        algebraic_idx=np.flatnonzero(model.layout.algebraic).tolist(),
        calc_initcond="yp0",
        calc_init_dt=CALC_INIT_DT_S,
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
        solver = IDA(residual_flat, userdata=model.work + model.data[-1:]
                     + (np.empty((2, model.size)),), **opts)
    return solver, counts



class IDAScikitSundae(_IDABase):
    """The same IDA through scikit-sundae's Python callbacks: a tested cross-check of
    :class:`IDA` (same options, same SUNDIALS), not a second product. About twice the CPU of
    :class:`IDA` on the default scene (docs/performance.md, "Cost of each switch": 2.11x):
    Python glue at every callback, and no Jacobian refresh threshold."""

    name = "ida-scikit-sundae"

    def describe(self) -> dict:
        return {"solver": self.name,
                "solver_description": (f"SUNDIALS IDA via scikit-sundae (BDF, {self.linsolver} "
                                       f"linear solver, {self.jacobian} Jacobian)"),
                "options": {"linsolver": self.linsolver, "jacobian": self.jacobian}}

    def _run(self, model, y0, yp0, t_out, t_start, emit):
        solver, counts = make_solver(model, self.linsolver, jacobian=self.jacobian)
        self._extra = {"linsolver": self.linsolver, "jacobian": self.jacobian}
        try:
            r = solver.init_step(t_start, y0, yp0)
        except Exception as exc:  # sksundae raises RuntimeError when IDACalcIC fails
            return False, f"consistent initialisation failed: {exc}", t_start
        ok, msg, fail_t = True, "completed", None
        try:
            t_iter = self._emit_start(t_out, t_start, emit, r.y, r.yp)
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
        return ok, msg, fail_t
