"""The projection of a run's samples onto the algebraic equations, compiled and batched.

Stage: solvers (after the integration) -> results. :class:`~.algebraic.AlgebraicProjector`
projects one sample per Python call; :func:`project_batch` does what it does for every sample
of a run in one compiled call — the same Newton on the algebraic rows of the residual with the
algebraic block of the analytic Jacobian (filled alone, the same numbers:
system/jacobian_algebraic.py), the same tests, the same linear solve (:func:`arrow_solve`) —
and keeps each projected sample's diagnostics (the kernel's work arrays after the residual at
the projected state with y' = 0, as ``Model.diagnostics``), so that an output sample costs no
Python. Why: per sample, the Python route cost ~0.3 ms (a projection, a diagnostics call,
their arrays), more than the integration between two samples at 4 000 samples per cage
revolution. A sample the compiled Newton does not settle is marked, and
the caller hands it to the static Newton as before.
"""

from __future__ import annotations

import numpy as np
from numba import njit, types

from ..physics.compiled import copy1, helper

from ..system.arrayview import c_view
from ..system.jacobian_algebraic import algebraic_work, fill_jacobian_algebraic
from ..system.optional import flange_marker
from ..system.residual import residual
from .native_call import entry, native_call, residual_entry

# status of a sample
SETTLED, UNSETTLED = 0, 1


def arrow_shape(alg: np.ndarray, rollers: int, n_local: int) -> int:
    """b, the algebraic unknowns per roller, of the compact positions ``alg`` (sorted): each
    roller's b in its own block, then the global ones (system/layout.py). The Jacobian block
    dF_a/dy_a then has the block-arrow pattern of the layout (a roller's rows see only its own
    and the global unknowns), which :func:`arrow_solve` uses. Raises if ``alg`` is not so."""
    local = alg[alg < rollers * n_local]
    b, rest = divmod(local.size, rollers)
    owner = local // n_local
    if rest or not np.array_equal(owner, np.repeat(np.arange(rollers), b)):
        raise AssertionError("algebraic unknowns not in equal blocks per roller")
    return b


@helper
def _gauss(M, R, m, r):
    """Solve M[:m, :m] X = R[:m, :r] in place (X into R), Gaussian elimination with partial
    pivoting; False if a pivot is 0 or not finite (M, R destroyed)."""
    for col in range(m):
        p = col
        big = abs(M[col, col])
        for i in range(col + 1, m):
            if abs(M[i, col]) > big:
                big = abs(M[i, col])
                p = i
        if not (big > 0.0) or not np.isfinite(big):
            return False
        if p != col:
            for k in range(m):
                M[col, k], M[p, k] = M[p, k], M[col, k]
            for k in range(r):
                R[col, k], R[p, k] = R[p, k], R[col, k]
        for i in range(col + 1, m):
            f = M[i, col] / M[col, col]
            if f != 0.0:
                for k in range(col + 1, m):
                    M[i, k] -= f * M[col, k]
                for k in range(r):
                    R[i, k] -= f * R[col, k]
    for i in range(m - 1, -1, -1):
        for k in range(r):
            acc = R[i, k]
            for c in range(i + 1, m):
                acc -= M[i, c] * R[c, k]
            R[i, k] = acc / M[i, i]
    return True


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def arrow_solve(J, alg, b, F, x, Mw, Rw, S, g):
    """x = -A⁻¹ F for A = J[alg, alg] with Z blocks of b roller unknowns and c = len(alg) - Z b
    global ones (:func:`arrow_shape`), by the Schur complement on the globals: per roller
    D_j [X_j | x_j] = [A_jG | -F_j] (b × b, pivoted elimination), S = A_GG - Σ_j A_Gj X_j,
    g = -F_G - Σ_j A_Gj x_j, S x_G = g, x_j -= X_j x_G. ~1 µs for the default scene against
    ~10 µs for LAPACK's dense 44 × 44 solve. Work arrays (:func:`arrow_work`): Mw (b, b),
    Rw (Z, b, c + 1), S (c, c), g (c, 1). False if a pivot vanished or is not finite (the
    caller treats the sample as not settled)."""
    na = alg.shape[0]
    Z = Rw.shape[0]
    c = na - Z * b
    base = Z * b
    for i in range(c):
        for k in range(c):
            S[i, k] = J[alg[base + i], alg[base + k]]
        g[i, 0] = -F[base + i]
    for j in range(Z):
        o = j * b
        for i in range(b):
            row = alg[o + i]
            for k in range(b):
                Mw[i, k] = J[row, alg[o + k]]
            for k in range(c):
                Rw[j, i, k] = J[row, alg[base + k]]
            Rw[j, i, c] = -F[o + i]
        if not _gauss(Mw, Rw[j], b, c + 1):
            return False
        for i in range(c):
            row = alg[base + i]
            for q in range(b):
                a_gq = J[row, alg[o + q]]
                if a_gq != 0.0:
                    for k in range(c):
                        S[i, k] -= a_gq * Rw[j, q, k]
                    g[i, 0] -= a_gq * Rw[j, q, c]
    if c > 0 and not _gauss(S, g, c, 1):
        return False
    for j in range(Z):
        o = j * b
        for i in range(b):
            acc = Rw[j, i, c]
            for k in range(c):
                acc -= Rw[j, i, k] * g[k, 0]
            x[o + i] = acc
    for i in range(c):
        x[base + i] = g[i, 0]
    return True


def compile_arrow_solve() -> None:
    """Compile (or load from numba's cache) :func:`arrow_solve` for the argument types
    :func:`project_batch` and ``AlgebraicProjector`` call it with (contiguous float64 arrays,
    int64 positions and block size): a cold start compiles it in the second process
    (sundials/precompile.py) while this one compiles the residual."""
    f1, f2, f3 = (types.Array(types.float64, k, "C") for k in (1, 2, 3))
    arrow_solve.compile((f2, types.Array(types.int64, 1, "C"), types.int64, f1, f1, f2, f3,
                         f2, f2))


def arrow_work(alg: np.ndarray, rollers: int, b: int) -> tuple:
    """The work arrays of :func:`arrow_solve` (Mw, Rw, S, g)."""
    c = alg.size - rollers * b
    return (np.empty((max(b, 1), max(b, 1))), np.empty((rollers, max(b, 1), c + 1)),
            np.empty((max(c, 1), max(c, 1))), np.empty((max(c, 1), 1)))


# (no Python wrapper: compiled code calls it, never Python; sundials/callbacks.py)
@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True, no_cpython_wrapper=True)
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


def kernel_entries(d, jd, alg, b, aw) -> np.ndarray:
    """The ``calls`` of :func:`project_batch`: the (address, key) of the residual, the
    algebraic Jacobian block and :func:`arrow_solve` for these arguments (solvers/
    native_call.py), compiled or loaded from numba's cache."""
    v, M = np.empty(1), jd[0]
    return np.array(residual_entry(d) + entry(fill_jacobian_algebraic, 0.0, v,
                                              algebraic_work(d), M, jd[3])
                    + entry(arrow_solve, M, alg, b, v, v, *aw), np.int64)


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def project_batch(t, Y, d, jd, alg, b, aw, tol, max_iterations, out_y, out_it, status, diag,
                  calls):
    """Project every sample (t[i], Y[i]) (scaled states) onto the algebraic rows: Newton as
    ``AlgebraicProjector.__call__`` (algebraic.py), into ``out_y``, iterations into
    ``out_it``, SETTLED / UNSETTLED into ``status``; ``diag``: (contact_force,
    contact_pressure, slip_velocity, traction_force, cage_force) arrays with a leading sample
    axis, filled for the settled samples; ``b``, ``aw``: the block shape and work arrays of
    :func:`arrow_solve`; ``calls``: :func:`kernel_entries` (the three kernels are called
    through their addresses: this kernel's compile does not optimise them again)."""
    n = Y.shape[1]
    na = alg.shape[0]
    yp = np.empty(n)  # (zeros: np.zeros would be two more specialisations to compile)
    for i in range(n):
        yp[i] = 0.0
    res = np.empty(n)
    F = np.empty(na)
    step = np.empty(na)
    Mw, Rw, S, g = aw
    y = np.empty(n)
    # the diagnostics and their per-sample rows as flat C views, copied by one 1-D loop
    # (copy1): one copy specialisation for all five instead of one per block shape, in a
    # kernel compiled once per switch pattern (~0.25 s of its ~1.6 s)
    q, pr, v = c_view(d[16], (d[16].size,)), c_view(d[17], (d[17].size,)), \
        c_view(d[18], (d[18].size,))
    f, fp = c_view(d[19], (d[19].size,)), c_view(d[20], (d[20].size,))
    da = d[:-1] + (flange_marker(d[-1]),)  # system/jacobian_algebraic.algebraic_work(d)
    ns = t.shape[0]
    dq, dpr, dv = c_view(diag[0], (ns, q.size)), c_view(diag[1], (ns, pr.size)), \
        c_view(diag[2], (ns, v.size))
    df, dfp = c_view(diag[3], (ns, f.size)), c_view(diag[4], (ns, fp.size))
    res_at, block_at, solve_at = (calls[0], calls[1]), (calls[2], calls[3]), (calls[4], calls[5])
    for s in range(t.shape[0]):
        tk = t[s]
        for i in range(n):
            y[i] = Y[s, i]
        native_call(residual, res_at, (tk, y, yp, res, d))
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
            # the block, bit for bit
            native_call(fill_jacobian_algebraic, block_at, (tk, y, da, jd[0], jd[3]))
            if not native_call(arrow_solve, solve_at, (jd[0], alg, b, F, step, Mw, Rw, S, g)):
                break
            moved = 0.0
            for a in range(na):
                y[alg[a]] += step[a]
                if abs(step[a]) > moved:
                    moved = abs(step[a])
            native_call(residual, res_at, (tk, y, yp, res, d))
            for a in range(na):
                F[a] = res[alg[a]]
        if status[s] == SETTLED:
            for i in range(n):
                out_y[s, i] = y[i]
            # loops, not dq[s] = q (physics/compiled.copy1: no error path to compile)
            copy1(dq[s], q)
            copy1(dpr[s], pr)
            copy1(dv[s], v)
            copy1(df[s], f)
            copy1(dfp[s], fp)
