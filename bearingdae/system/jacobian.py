"""Iteration matrix dF/dy + c_j dF/dy' by *structured* finite differences (numba).

Why not plain coloured FD: the ring and cage rows touch every roller, so column colouring of the
block-arrow pattern needs ~N/3 colours (63 residual calls for N = 204, SOLVER-NOTES). But each
roller's equations depend only on its own unknowns and the global ones, and the global rows are
``own terms - Σ_j contribution_j`` (system/residual.py). Perturbing local unknown a of *every*
roller at once therefore still separates exactly: roller j's rows and its contribution to the
global rows change only through roller j's own perturbation. The full Jacobian costs
n_local + n_global residual evaluations (≤ 13), independent of the number of rollers.

dF/dy' is the constant diagonal "mass" of each row (the residual is linear in y').
Forward differences with h_i = sqrt(machine eps) · max(|y_i|, 1) on the scaled unknowns.

Each evaluation is a call of the residual kernel (system/residual.py ``residual``, which leaves
the full rows and the rollers' contributions in the work arrays as well): its machine code is
the residual callback's, from numba's cache. Inlining its body (``full_evaluate``) at the three
call sites, and array assignments (numba's error path for mismatched shapes), made this kernel
compile for 11 s of CPU cold on a 2-CPU Xeon, for the same numbers.
"""

from __future__ import annotations

from numba import njit

from ..physics.compiled import copy1, copy2
from .residual import residual

SQRT_EPS = 1.4901161193847656e-08


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def fill_jacobian(t, y, yp, cj, d, jd):
    """Dense iteration matrix (pattern entries only) into jd[0]."""
    (Jd, rows, cols, mass, res0, res1, resl0, contrib0, y2) = jd
    RS, lmap, gmap = d[4], d[5], d[6]
    resl, resg, contrib = d[13], d[14], d[15]
    Z = resl.shape[0]
    nl = lmap.shape[0]
    ng = gmap.shape[0]
    base = Z * nl
    n = y.shape[0]

    residual(t, y, yp, res0, d)
    copy2(resl0, resl)  # (loops: physics/compiled.copy2)
    copy2(contrib0, contrib)

    for a in range(nl):
        copy1(y2, y)
        for j in range(Z):
            i = j * nl + a
            y2[i] += SQRT_EPS * max(abs(y[i]), 1.0)
        residual(t, y2, yp, res1, d)  # (res1: scratch here; the rows read are resl, contrib)
        for j in range(Z):
            col = j * nl + a
            h = y2[col] - y[col]
            for b in range(nl):
                row = j * nl + b
                Jd[row, col] = (resl[j, lmap[b]] - resl0[j, lmap[b]]) / (RS[row] * h)
            for gb in range(ng):
                row = base + gb
                g = gmap[gb]
                Jd[row, col] = -(contrib[j, g] - contrib0[j, g]) / (RS[row] * h)

    for gb in range(ng):
        col = base + gb
        copy1(y2, y)
        y2[col] += SQRT_EPS * max(abs(y[col]), 1.0)
        h = y2[col] - y[col]
        residual(t, y2, yp, res1, d)
        for j in range(Z):
            for b in range(nl):
                row = j * nl + b
                Jd[row, col] = (res1[row] - res0[row]) / h
        for gb2 in range(ng):
            row = base + gb2
            Jd[row, col] = (res1[row] - res0[row]) / h

    for i in range(n):
        Jd[i, i] += cj * mass[i]


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def jacobian_sparse(t, y, yp, res, cj, JJ, d, jd):
    """IDA ``jacfn`` for linsolver='sparse': JJ is the CSC data array of the pattern."""
    fill_jacobian(t, y, yp, cj, d, jd)
    gather_csc(jd[0], jd[1], jd[2], JJ)


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def gather_csc(Jd, rows, cols, JJ):
    """Pattern entries of the dense matrix Jd into IDA's CSC data array JJ (column-major)."""
    for k in range(rows.shape[0]):
        JJ[k] = Jd[rows[k], cols[k]]


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def jacobian_dense(t, y, yp, res, cj, JJ, d, jd):
    """IDA ``jacfn`` for linsolver='dense': JJ is the (N, N) matrix."""
    fill_jacobian(t, y, yp, cj, d, jd)
    copy2(JJ, jd[0])  # (a loop: physics/compiled.copy2)
