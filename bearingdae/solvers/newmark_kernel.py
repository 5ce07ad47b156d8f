"""Compiled inner loop of the Newmark-β / HHT-α integrator (solvers/newmark.py): steps,
predictor, modified Newton and the triangular solves with SuperLU's factors (numba).

Why compiled: one step is ~2 Newton iterations of one residual call (~35 µs) and one solve
with the factors (a few µs); driving them from Python cost ~10 µs per numpy operation and
~20 operations per iteration, more than the residual itself (measured with cProfile on the
baseline). The matrix is built and factorised in Python (solvers/newmark.py) only when this
loop asks for it.

Notation (newmark.py docstring): y, y' the scaled model state; x the Newton unknowns
(accelerations and first-order rates on ``dUx``, algebraic unknowns on ``aUx``), U[k] the
state index of unknown k; y_i = base_i + coef_i x[src_i] during a step.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..system.extremes import update_extremes
from ..system.residual import residual
from .native_call import native_call

#: the name of these kernels in the first-compile notice (util/kernel_cache.py)
KERNEL_GROUP = "Newmark"

# Return codes of ``advance``
DONE = 0  #: all steps taken
NEED_MATRIX = 1  #: a (new) factorisation is needed before the next step
FAILED = 2  #: Newton failed with a matrix built for this very step: halve the step


@njit(cache=True, no_cfunc_wrapper=True)
def lu_solve(Ld, Li, Lp, Ud, Ui, Up, perm_r, perm_c, b, work, out):
    """Solve A out = b with SuperLU's Pr A Pc = L U (CSC factors, any index order)."""
    n = b.shape[0]
    for i in range(n):
        work[perm_r[i]] = b[i]
    for j in range(n):  # L z = Pr b (forward, column-oriented)
        diag = 1.0
        for k in range(Lp[j], Lp[j + 1]):
            if Li[k] == j:
                diag = Ld[k]
        work[j] /= diag
        xj = work[j]
        for k in range(Lp[j], Lp[j + 1]):
            if Li[k] > j:
                work[Li[k]] -= Ld[k] * xj
    for j in range(n - 1, -1, -1):  # U w = z (backward)
        diag = 1.0
        for k in range(Up[j], Up[j + 1]):
            if Ui[k] == j:
                diag = Ud[k]
        work[j] /= diag
        xj = work[j]
        for k in range(Up[j], Up[j + 1]):
            if Ui[k] < j:
                work[Ui[k]] -= Ud[k] * xj
    for i in range(n):
        out[i] = work[perm_c[i]]


@njit(cache=True, no_cfunc_wrapper=True)
def predict(h, y, yp, x_hist, h_hist, order, U, dUx, aUx, x):
    """Newton start for a step of size h: the unknowns at t_n (accelerations, algebraic
    values) extrapolated by the polynomial through the starts of the last ``order`` steps
    (``x_hist[0]`` at t_n - h_hist[0], ``x_hist[1]`` one step earlier; fewer when the history
    is shorter). Measured on the baseline (see docs/theory.md): holding the unknowns made the
    first correction ~1e3 x larger than linear extrapolation."""
    for k in dUx:
        x[k] = yp[U[k]]
    for k in aUx:
        x[k] = y[U[k]]
    if order >= 2 and h_hist[0] > 0.0 and h_hist[1] > 0.0:
        t1, t2 = -h_hist[0], -h_hist[0] - h_hist[1]  # Lagrange nodes 0, t1, t2 -> h
        l0 = (h - t1) * (h - t2) / (t1 * t2)
        l1 = h * (h - t2) / (t1 * (t1 - t2))
        l2 = h * (h - t1) / (t2 * (t2 - t1))
        for k in range(x.shape[0]):
            x[k] = l0 * x[k] + l1 * x_hist[0, k] + l2 * x_hist[1, k]
    elif order >= 1 and h_hist[0] > 0.0:
        r = h / h_hist[0]
        for k in range(x.shape[0]):
            x[k] += r * (x[k] - x_hist[0, k])


@njit(cache=True, no_cfunc_wrapper=True)
def setup(h, y, yp, beta, gamma, pos, vel, c, U, dUx, aUx, base, coef):
    """y_{n+1} = base + coef * x[src]: the Newmark / γ-rule update as an affine map."""
    # element loops, not ``base[:] = y``: a slice assignment checks the shapes and compiles
    # numba's error-message formatting (~4 s of a first Newmark run), for the same copy
    for i in range(y.shape[0]):
        base[i] = y[i]
        coef[i] = 1.0
    for k in dUx:
        i = U[k]
        base[i] = y[i] + h * (1.0 - gamma) * yp[i]
        coef[i] = h * gamma
    for k in aUx:
        base[U[k]] = 0.0
    for m in range(pos.shape[0]):
        q, v = pos[m], vel[m]
        base[q] = y[q] + c[m] * (h * y[v] + h * h * (0.5 - beta) * yp[v])
        coef[q] = c[m] * h * h * beta


@njit(cache=True, no_cfunc_wrapper=True)
def state(x, base, coef, src, pos, vel, c, U, dUx, y1, yp1):
    """(y_{n+1}, y'_{n+1}) for unknowns x; y' of the positions is their pair's velocity."""
    n = y1.shape[0]
    for i in range(n):
        y1[i] = base[i] + coef[i] * x[src[i]]
        yp1[i] = 0.0
    for k in dUx:
        yp1[U[k]] = x[k]
    for m in range(pos.shape[0]):
        yp1[pos[m]] = c[m] * y1[vel[m]]


@njit(cache=True, no_cfunc_wrapper=True)
def advance(t, h, nsteps, fresh, y, yp, f, x_hist, h_hist, wt, d, P, LU, opts, counts, w, E,
            calls):
    """Take up to ``nsteps`` steps of size h from (t, y, y') in place.

    ``P`` = (pos, vel, c, U, dUx, aUx, src, mass); ``LU`` = SuperLU factors (L data, indices,
    indptr, U data, indices, indptr, perm_r, perm_c); ``opts`` = [β, γ, α, rtol, atol,
    maxiter, slow, predictor order] (opts[4] unused); ``counts`` += [steps, Newton
    iterations, residual calls];
    ``w`` work arrays. ``fresh``: the factorisation was built at this state for this h.
    ``E``: running-extremes buffer (system/extremes.py) each accepted step is folded into (a
    buffer whose window starts at +inf when none is kept).
    ``wt``: absolute tolerance of each state component (the relative one is ``opts[3]``).
    ``calls``: the residual's (address, key) (solvers/native_call.residual_entry: the
    residual is called through its address, so this kernel's compile, once per switch
    pattern, does not optimise the residual again).
    Returns (code, steps taken, time reached); ``f`` and the predictor history ``x_hist``,
    ``h_hist`` are updated in place.

    Convergence (as in IDA and scipy's BDF): with r the measured contraction rate, the error
    left after a correction of weighted max-norm δ is about r/(1 - r) δ; the step converges
    when that is ≤ 1.
    """
    pos, vel, c, U, dUx, aUx, src, mass = P
    Ld, Li, Lp, Ud, Ui, Up, perm_r, perm_c = LU
    beta, gamma, alpha = opts[0], opts[1], opts[2]
    rtol, maxiter, slow = opts[3], int(opts[5]), int(opts[6])
    order = int(opts[7])
    base, coef, y1, yp1, res, x, x0, x_start, G, dx, lu_work = w
    nU = U.shape[0]
    res_at = (calls[0], calls[1])
    for s in range(nsteps):
        t1 = t + h
        setup(h, y, yp, beta, gamma, pos, vel, c, U, dUx, aUx, base, coef)
        predict(h, y, yp, x_hist, h_hist, order, U, dUx, aUx, x)
        for k in dUx:
            x_start[k] = yp[U[k]]
        for k in aUx:
            x_start[k] = y[U[k]]
        converged = False
        norm_old = -1.0
        its = 0
        for it in range(maxiter):
            its = it + 1
            state(x, base, coef, src, pos, vel, c, U, dUx, y1, yp1)
            native_call(residual, res_at, (t1, y1, yp1, res, d))
            counts[1] += 1
            counts[2] += 1
            finite = True
            for k in range(nU):
                G[k] = res[U[k]]
            if alpha != 0.0:
                for k in dUx:
                    i = U[k]
                    G[k] = (1.0 + alpha) * G[k] - alpha * mass[i] * x[k] + alpha * f[i]
            for k in range(nU):
                if not np.isfinite(G[k]):
                    finite = False
            if not finite:
                break
            lu_solve(Ld, Li, Lp, Ud, Ui, Up, perm_r, perm_c, G, lu_work, dx)
            norm = 0.0
            for k in range(nU):
                x[k] -= dx[k]
            for i in range(y1.shape[0]):
                dyi = abs(coef[i] * dx[src[i]])
                yi = abs(base[i] + coef[i] * x[src[i]])
                e = dyi / (rtol * yi + wt[i])
                if not e <= norm:  # also catches NaN
                    norm = e
            if not np.isfinite(norm):
                break
            if norm_old < 0.0:
                # No rate measured yet: accept only a first correction that is itself within
                # the tolerance (the error left is then below it for any rate <= 1/2). A rate
                # remembered from earlier steps (IDA's way) once accepted corrections of 1e6
                # tolerances on a floating roller's tilt, whose iteration contracts at only
                # ~0.4 per iteration, and the run failed a few steps later (baseline, 15.7 ms).
                if norm <= 1.0:
                    converged = True
                    break
            else:
                r = norm / norm_old
                if r >= 1.0:
                    break
                if r / (1.0 - r) * norm <= 1.0:
                    converged = True
                    break
            norm_old = norm
        if not converged:
            return (FAILED if fresh else NEED_MATRIX), s, t
        # accept: new state, HHT's f_{n+1} from the converged equation, predictor memory
        state(x, base, coef, src, pos, vel, c, U, dUx, y1, yp1)
        if alpha != 0.0:
            for k in dUx:
                i = U[k]
                f[i] = (mass[i] * x[k] + alpha * f[i]) / (1.0 + alpha)
        for i in range(y.shape[0]):  # loops: see setup()
            y[i] = y1[i]
            yp[i] = yp1[i]
        for k in range(x_hist.shape[1]):
            x_hist[1, k] = x_hist[0, k]
            x_hist[0, k] = x_start[k]
        h_hist[1] = h_hist[0]
        h_hist[0] = h
        t = t1
        counts[0] += 1
        # the last residual evaluation (d's diagnostics) was the last Newton iterate's
        update_extremes(t, y, d[3], d[5], d[16], d[18], d[20], E)
        fresh = False
        if its > slow:
            return NEED_MATRIX, s + 1, t
    return DONE, nsteps, t
