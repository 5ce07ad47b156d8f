"""The projection of a run's samples onto the algebraic equations, compiled and batched.

Stage: solvers (after the integration) -> results. :class:`~.algebraic.AlgebraicProjector`
projects one sample per Python call; :func:`project_batch` does what it does for every sample
of a run in one compiled call — the same Newton on the algebraic rows of the residual with the
algebraic block of the analytic Jacobian (filled alone, the same numbers:
system/jacobian_algebraic.py), the same tests, the same LAPACK solve (``dgesv``) —
and keeps each projected sample's diagnostics (the kernel's work arrays after the residual at
the projected state with y' = 0, as ``Model.diagnostics``), so that an output sample costs no
Python. Why: per sample, the Python route cost ~0.3 ms (a projection, a diagnostics call,
their arrays), more than the integration between two samples at 4 000 samples per cage
revolution (CHANGELOG.md). A sample the compiled Newton does not settle is marked, and
the caller hands it to the static Newton as before.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..system.jacobian_algebraic import fill_jacobian_algebraic
from ..system.residual import residual

# status of a sample
SETTLED, UNSETTLED = 0, 1


@njit(cache=True)
def _max_abs_finite(F):
    """max |F|, or -1 when an entry is not finite."""
    m = 0.0
    for i in range(F.shape[0]):
        if not np.isfinite(F[i]):
            return -1.0
        a = abs(F[i])
        if a > m:
            m = a
    return m


@njit(cache=True)
def project_batch(t, Y, d, jd, alg, tol, max_iterations, out_y, out_it, status, diag):
    """Project every sample (t[i], Y[i]) (scaled states) onto the algebraic rows: Newton as
    ``AlgebraicProjector.__call__`` (algebraic.py), into ``out_y``, iterations into
    ``out_it``, SETTLED / UNSETTLED into ``status``; ``diag``: (contact_force,
    contact_pressure, slip_velocity, traction_force, cage_force) arrays with a leading sample
    axis, filled for the settled samples."""
    n = Y.shape[1]
    na = alg.shape[0]
    yp = np.zeros(n)
    res = np.empty(n)
    F = np.empty(na)
    A = np.empty((na, na))
    y = np.empty(n)
    q, pr, v, f, fp = d[16], d[17], d[18], d[19], d[20]
    dq, dpr, dv, df, dfp = diag
    for s in range(t.shape[0]):
        tk = t[s]
        for i in range(n):
            y[i] = Y[s, i]
        residual(tk, y, yp, res, d)
        for a in range(na):
            F[a] = res[alg[a]]
        moved = np.inf
        status[s] = UNSETTLED
        for it in range(max_iterations + 1):
            m = _max_abs_finite(F)
            if m < 0.0:
                break
            if m <= tol and moved <= 1e-6:
                status[s] = SETTLED
                out_it[s] = it
                break
            if it == max_iterations:
                break
            fill_jacobian_algebraic(tk, y, d, jd[0], jd[3])  # the block, bit for bit
            J = jd[0]
            for a in range(na):
                for b in range(na):
                    A[a, b] = J[alg[a], alg[b]]
            step = np.linalg.solve(A, -F)
            moved = 0.0
            for a in range(na):
                y[alg[a]] += step[a]
                if abs(step[a]) > moved:
                    moved = abs(step[a])
            residual(tk, y, yp, res, d)
            for a in range(na):
                F[a] = res[alg[a]]
        if status[s] == SETTLED:
            out_y[s, :] = y
            dq[s] = q
            dpr[s] = pr
            dv[s] = v
            df[s] = f
            dfp[s] = fp
