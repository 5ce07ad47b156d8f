"""The algebraic block of the analytic iteration matrix: what projecting a sample needs.

Stage: system (DAE model) -> solvers (the projection of output samples onto the algebraic
equations, solvers/projection_kernel.py). The projection's Newton reads only dF_a/dy_a: the
rows and columns of the roller radial positions and tilts and of the ring displacement and
tilt (theory.md §5), and with flanges the rollers' and the ring's axial positions
(theory.md §16, system/flange.py). They depend on the slice loads only — not on traction, the pocket, drag
or the speeds — so this fills them from the kinematics and the load slopes, skipping the
traction laws and the other rows: ~4x cheaper than ``fill_jacobian_analytic``.

Every entry is computed by the very expressions of system/jacobian_analytic.py
(``contact_slopes``' first three loops, ``roller_blocks``' slice sums dF rows 0-3, the rows
A_U and A_B of JR, the ring rows of JC, the scatter and the summed ring block), in the same
order: the block is equal bit for bit to the full matrix's (tests/system/
test_jacobian_algebraic.py checks it), so the projected samples do not change.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..physics.compiled import helper

from ..physics.contact import palmgren_load, smooth_positive
from ..physics.elementary import log_
from .arrayview import c_view
from .layout import LOCAL
from .defects import defect_rows
from .optional import flange_jacobian_block, flange_marker
from .residual import (A_B, A_U, G_DR, G_DT, G_GR, G_GT, P_EPS, P_KW, P_W, kinematics_pass,
                       ring_speed_at, unpack)

NL = len(LOCAL)
#: the full-order columns of the block: A_U, A_B, then the ring's (NL + G_*)
_COLS = (A_U, A_B, NL + G_DR, NL + G_DT, NL + G_GR, NL + G_GT)


@helper
def _ring(g):
    return g == G_DR or g == G_DT or g == G_GR or g == G_GT


@helper
def _local(a):
    return a == A_U or a == A_B


def algebraic_work(d: tuple) -> tuple:
    """The work tuple ``d`` (a model's ``data``) as the projection hands it to
    :func:`fill_jacobian_algebraic`: the same arrays, the marker narrowed to the flanges and
    the defects (system/optional.flange_marker), the only effects compiled apart whose passes
    the block runs. One specialisation of the block then serves every pattern without flanges
    (a cold compile of the whirl, rolling-resistance or mixed-lubrication pattern reuses the
    default scene's: ~1.5 s of CPU each), with the same code. projection_kernel.project_batch
    builds the same tuple in compiled code (its entry's key checks that the types agree)."""
    return d[:-1] + (flange_marker(d[-1]),)


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def fill_jacobian_algebraic(t, y, d, Jd, mass):
    """The entries of the scaled iteration matrix at c_j = 0 in the algebraic rows and
    columns, into Jd (others untouched): those of ``fill_jacobian_analytic``."""
    P, x, c, S, RS, lmap, gmap = d[0], d[1], d[2], d[3], d[4], d[5], d[6]
    ramp_t, ramp_w, yl, yg = d[7], d[8], d[9], d[11]
    q, pr, v, f, contrib = d[16], d[17], d[18], d[19], d[15]
    unpack(y, S, lmap, gmap, yl, yg)
    w_ring = ring_speed_at(t, ramp_t, ramp_w)
    kinematics_pass(yl, yg, w_ring, P, x, c, q, v, f, contrib)
    defect_rows(d[23], t, yl, x, P[P_W], ramp_t, ramp_w, q)  # (system/defects.py)
    # loads and their slopes (contact_slopes, physics/contact.py)
    n = q.size
    qf, pf = c_view(q, (n,)), c_view(pr, (n,))
    Kw, eps = P[P_KW], P[P_EPS]
    lg = np.empty(n)
    for i in range(n):
        qf[i], pf[i] = smooth_positive(qf[i], eps)
    for i in range(n):
        lg[i] = log_(qf[i])
    for i in range(n):
        load, slope = palmgren_load(qf[i], lg[i], pf[i], Kw)
        qf[i] = load
        pf[i] = slope
    Z, k = yl.shape[0], x.shape[0]
    nl, ng = lmap.shape[0], gmap.shape[0]
    base = Z * nl
    # np.empty and zeroing loops, not np.zeros: each np.zeros shape is two more numba
    # specialisations to compile at a cold start (np.zeros' own and np.empty's with a dtype)
    dF = np.empty((4, NL + 6))
    JR = np.empty((NL, NL + 6))
    JC = np.empty((6, NL + 6))
    CG = np.empty((6, 6))
    for b in range(NL + 6):
        for a in range(NL):
            JR[a, b] = 0.0
        for a in range(6):
            JC[a, b] = 0.0
    for a in range(6):
        for b in range(6):
            CG[a, b] = 0.0
    for j in range(Z):
        cphi, sphi = contrib[j, G_DR], contrib[j, G_DT]
        for a in range(4):
            for b in range(NL + 6):
                dF[a, b] = 0.0
        for lam in range(k):
            xl = x[lam]
            kqi, kqo = pr[j, lam, 0], pr[j, lam, 1]
            gi_dr = kqi * cphi
            gi_dt = kqi * sphi
            dF[0, A_U] -= kqi
            dF[0, A_B] -= kqi * xl
            dF[0, NL + G_DR] += gi_dr
            dF[0, NL + G_DT] += gi_dt
            dF[0, NL + G_GR] += gi_dr * xl
            dF[0, NL + G_GT] += gi_dt * xl
            dF[1, A_U] += kqo
            dF[1, A_B] += kqo * xl
            dF[2, A_U] -= xl * kqi
            dF[2, A_B] -= xl * xl * kqi
            dF[2, NL + G_DR] += xl * gi_dr
            dF[2, NL + G_DT] += xl * gi_dt
            dF[2, NL + G_GR] += xl * xl * gi_dr
            dF[2, NL + G_GT] += xl * xl * gi_dt
            dF[3, A_U] += xl * kqo
            dF[3, A_B] += xl * xl * kqo
        for b in _COLS:
            JR[A_U, b] = dF[0, b] - dF[1, b]
            JR[A_B, b] = dF[2, b] - dF[3, b]
            JC[G_DR, b] = dF[0, b] * cphi
            JC[G_DT, b] = dF[0, b] * sphi
            JC[G_GR, b] = dF[2, b] * cphi
            JC[G_GT, b] = dF[2, b] * sphi
        for a in range(nl):
            fa = lmap[a]
            if not _local(fa):
                continue
            row = j * nl + a
            for b in range(nl):
                if _local(lmap[b]):
                    col = j * nl + b
                    Jd[row, col] = JR[fa, lmap[b]] * S[col] / RS[row]
            for gb in range(ng):
                if _ring(gmap[gb]):
                    col = base + gb
                    Jd[row, col] = JR[fa, NL + gmap[gb]] * S[col] / RS[row]
        for ga in range(ng):
            g = gmap[ga]
            if not _ring(g):
                continue
            row = base + ga
            for b in range(nl):
                if _local(lmap[b]):
                    col = j * nl + b
                    Jd[row, col] = -JC[g, lmap[b]] * S[col] / RS[row]
            for h in range(6):
                if _ring(h):
                    CG[g, h] += JC[g, NL + h]
    for ga in range(ng):
        g = gmap[ga]
        if not _ring(g):
            continue
        row = base + ga
        for gb in range(ng):
            h = gmap[gb]
            if _ring(h):
                col = base + gb
                Jd[row, col] = -CG[g, h] * S[col] / RS[row]
    # roller end-flange contacts (system/flange.py): the same entries, where there are any
    flange_jacobian_block(d[23], yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd)
    for i in range(Jd.shape[0]):  # as the full fill's Jd[i, i] += c_j·mass, c_j = 0
        Jd[i, i] += 0.0 * mass[i]
