"""Every slice contact's load, traction and their slopes: the analytic Jacobian's first pass
(system/jacobian_analytic.py), the derivative of system/residual.contact_pass line by line.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..physics.contact import hertz_pressure, palmgren_load, smooth_positive
from ..physics.elementary import log_
from ..physics.traction import (_mu_paper, _mu_slide_roll, _traction_force_paper,
                                _traction_force_slide_roll)
from .arrayview import c_view
from .optional import mixed_slope_rows
from .param_vector import (P_ETA, P_EPS, P_KW, P_MX, P_RPI, P_RPO, P_SRA, P_SRB, P_SRC, P_SRD,
                           P_SRU0, P_TA, P_TALT, P_TB, P_TC, P_TD, P_TLAW, P_TV, P_W)

# Within |V| < ZERO_SLIP_BAND · v₀ the regularised traction μ(|V|) q sg(V) has a slope that dips
# to 0 at V = 0 (μ ∝ |V| there, so F ∝ V|V|/v₀ over a band of width v₀ = 1e-12 m/s by default).
# That exact slope is useless to Newton, whose iterates move by far more than v₀: there we use
# the slope of the exact-sign law, q dμ/d|V| at |V| = 0, which the regularised slope meets
# outside the band (they differ by O(v₀²/V²)).
ZERO_SLIP_BAND = 1e3


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def contact_slopes(P, q, pr, v, f, out, marker):
    """Every slice contact in two flat loops (as system/residual.contact_pass; race = index
    parity), with slopes. In: approaches in q, slips in v, rolling speeds in f (slide-to-roll law), as
    residual.kinematics_pass leaves them. Out: q <- load, pr <- dq/dδ, out[0] <- traction F,
    out[1] <- dF/dV, out[2] <- dF/dq including the Hertz pressure's dp/dq, out[3] <- dF/du.
    Branch-free (selects), every law inlined: the loops vectorise. ``marker``: the work
    tuple's (system/optional.py; None: mixed lubrication not compiled)."""
    n = q.size
    qf, pf, vf, ff = c_view(q, (n,)), c_view(pr, (n,)), c_view(v, (n,)), c_view(f, (n,))
    o = c_view(out, (4, n))
    Kw, eps, w, Rpi, Rpo, eta = P[P_KW], P[P_EPS], P[P_W], P[P_RPI], P[P_RPO], P[P_ETA]
    tv = P[P_TV]
    band = ZERO_SLIP_BAND * tv
    # The laws in stages, each a loop over all contacts (as residual.contact_pass: fused, the
    # loop body ran at about half the speed): smoothed approach and its slope, ln s (in out[0]
    # until the tractions), load and its slope, pressure (in out[3] until the tractions).
    for i in range(n):
        qf[i], pf[i] = smooth_positive(qf[i], eps)
    for i in range(n):
        o[0, i] = log_(qf[i])
    for i in range(n):
        load, slope = palmgren_load(qf[i], o[0, i], pf[i], Kw)
        qf[i] = load
        pf[i] = slope
        o[3, i] = hertz_pressure(load, w, Rpo if i & 1 else Rpi, eta)
    if P[P_TLAW] < 0.5:
        tA, tB, tC, tD, alt = P[P_TA], P[P_TB], P[P_TC], P[P_TD], P[P_TALT] > 0.5
        for i in range(n):
            load = qf[i]
            p = o[3, i]
            V = vf[i]
            F, FV, Fq, Fp = _traction_force_paper(load, V, p, tv, tA, tB, tC, tD, alt)
            # p = C sqrt(q): dp/dq = p / (2 q) (0 where q underflows to 0)
            Fq_p = Fp * 0.5 * p / load
            FV0 = load * _mu_paper(0.0, p * 1e-9, tA, tB, tC, tD, alt)[1]
            o[0, i] = F
            o[1, i] = FV0 if abs(V) < band else FV
            o[2, i] = Fq + Fq_p if load > 0.0 else Fq
            o[3, i] = 0.0
    else:
        sA, sB, sC, sD, su0 = P[P_SRA], P[P_SRB], P[P_SRC], P[P_SRD], P[P_SRU0]
        mu0_slope = _mu_slide_roll(0.0, sA, sB, sC, sD)[1]
        for i in range(n):
            load = qf[i]
            V = vf[i]
            roll = ff[i]
            F, FV, Fq, Fu = _traction_force_slide_roll(load, V, roll, tv, sA, sB, sC, sD, su0)
            FV0 = load * mu0_slope / np.sqrt(roll * roll + su0 * su0)
            o[0, i] = F
            o[1, i] = FV0 if abs(V) < band else FV
            o[2, i] = Fq
            o[3, i] = Fu
    if P[P_MX] > 0.5:  # mixed lubrication (system/mixed.py): the asperities' share
        mixed_slope_rows(marker, P[P_MX:], P[P_TLAW:P_SRU0 + 1], qf, vf, ff, o, w, Rpi, Rpo)
