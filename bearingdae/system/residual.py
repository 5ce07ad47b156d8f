"""The DAE residual F(t, y, y') = 0 of theory.md §6-11: the compiled hot kernel (numba).

Per roller j (``LOCAL`` order of system/layout.py), with V, q, F per slice λ and race:

    θX' - Ω                                                          = 0   (kinematics)
    m R_m Ω' - [Σ(F_i + F_o) + F_cr - F_D]                            = 0   (orbit, Newton)
    I_x ω' - [r Σ(F_i - F_o) + M_spin - M_lr]                          = 0   (spin)
    θz' - ζ                                                          = 0
    I_t ζ' - [-Σ x(F_i + F_o) + M_cz - (I_x - I_t) Ω(ω + Ω cos θz) sin θz] = 0   (skew)
    Σ q_i - Σ q_o + m R_m Ω²                                         = 0   (radial, algebraic)
    Σ x (q_i - q_o)                                                  = 0   (tilt, algebraic)

and globally: θc' - ω_c = 0; I_c ω_c' - [Σ_j(-R_m F_cr,j + M_spin,j) - M_lc] = 0; the inner-ring
balance (F_r, F_t, M, M_t) - Σ_jλ q_i P_jλ = 0 (theory.md §5). The formulas live in physics/*; this
module only wires them together per roller and slice, without Python loops per call.

The residual is linear in y' with a constant diagonal coefficient (the "mass" of each row), so
dF/dy' is that diagonal and IDA's iteration matrix is dF/dy + c_j diag(mass).

Each roller's equations depend on its own unknowns and the global ones only; the global rows are
``own terms - Σ_j contribution_j``. That is what makes the structured finite-difference Jacobian
of system/jacobian.py exact with n_local + n_global evaluations.

Speed: the kernels use numba's ``error_model="numpy"``, i.e. no ZeroDivisionError check
(and raise path) after each of the ~20 divisions per slice; every denominator here is bounded
away from 0 by a regularisation length, a floor or a positive scene parameter, and NaN / inf
propagate as before. The traction law is called through its value-only entry points
(physics/traction.py).

Three passes per call: per roller, the kinematics of physics/kinematics.py (approaches, slips,
rolling speeds); one flat, branch-free loop over all Z k 2 slice contacts (load, Hertz
pressure, traction), which LLVM vectorises because every law in it is inlined plain arithmetic
(physics/elementary.py); per roller again, the slice sums, pocket and drag loads and the equations.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..physics.compiled import helper

from ..physics.cage import _pocket_force, _pocket_loads
from ..physics.contact import hertz_pressure, palmgren_load, smooth_positive
from ..physics.elementary import log_
from ..physics.kinematics import (centrifugal_force, effective_radius, end_positions,
                                  pocket_lead, pocket_lead_rate, race_approaches, ring_approach,
                                  ring_load_share, roller_balance, rolling_sums, slip_velocities)
from ..physics.loads import applied_loads
from ..physics.ring import support_force
from ..physics.lubricant import (cage_side_churning, drag_coefficient_at_log, drag_log_reynolds,
                                 orbit_drag_at, orbit_drag_reynolds, roller_end_churning)
from ..physics.traction import _traction_value_paper, _traction_value_slide_roll
from ..physics.cage_guidance import _pocket_displacement
from .arrayview import c_view
from .defects import defect_rows, spin_angle_rows
from .optional import (extension_rows, flange_rows, mixed_marker, mixed_traction_rows,
                       rolling_resistance_rows, whirl_rows)
from .param_vector import (  # the parameter vector's layout, read by the kernels below
    PARAM_NAMES, P_Z, P_RM, P_RI, P_RO, P_R, P_L, P_MASS, P_IX, P_IT, P_IC, P_CL, P_KW, P_EPS,
    P_W, P_RPI, P_RPO, P_ETA, P_TLAW, P_TA, P_TB, P_TC, P_TD, P_TALT, P_TV, P_SRA, P_SRB,
    P_SRC, P_SRD, P_SRU0, P_SLIP, P_ORBIT, P_GYRO, P_CAGE, P_DRAG, P_CP, P_KP, P_CD, P_MUC,
    P_EPSP, P_FP, P_SPIN, P_SPINF, P_RHO, P_MUO, P_CRI, P_CRO, P_UNB, P_UNBPH, P_RDYN, P_RMASS,
    P_RINER, P_SUPK, P_SUPC, P_FL, P_WH, P_RR, P_MX,
)

# ---- full per-roller unknowns (system/layout.py LOCAL) ----
A_TH, A_OM, A_W, A_SK, A_SR, A_U, A_B = 0, 1, 2, 3, 4, 5, 6
# ---- full global unknowns (layout GLOBAL) ----
G_TC, G_WC, G_DR, G_DT, G_GR, G_GT, G_VR, G_VT, G_WR, G_WT = range(10)
G_CX, G_CY, G_CVX, G_CVY = range(11, 15)  # the cage centre and its velocity (cage whirl)


# Small steps: ring speed and unpacking (the Jacobians call them too) are helpers (physics/
# compiled.py: compiled once, inlined by LLVM); the global rows, packing and ``full_evaluate``
# (one caller each) are inlined as numba IR. As kernels each was typing, wrappers, machine code
# and a cache file at a cold start (~0.1 s each). The passes stay kernels: the Jacobian calls them.
@helper
def ring_speed_at(t, ramp_t, ramp_w):
    """Inner-ring speed [rad/s] at t: piecewise linear through (ramp_t, ramp_w), held after."""
    n = ramp_t.shape[0]
    if n == 1 or t <= ramp_t[0]:
        return ramp_w[0]
    for i in range(1, n):
        if t <= ramp_t[i]:
            a = (t - ramp_t[i - 1]) / (ramp_t[i] - ramp_t[i - 1])
            return ramp_w[i - 1] + a * (ramp_w[i] - ramp_w[i - 1])
    return ramp_w[n - 1]


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def kinematics_pass(yl, yg, w_ring, P, x, c, q, v, f, contrib):
    """Pass 1, every roller (physics/kinematics.py): slice approaches into q (replaced by the
    loads in pass 2), slip velocities into v and, for the slide-to-roll law, rolling speeds into
    f (replaced by the tractions in pass 2); (cos φ, sin φ) into contrib[:, G_DR:G_GR] for
    pass 3, which overwrites them. One call for the bearing, the roller loop inside (a call per
    roller passed every array argument, field by field, ~40 ns each)."""
    Ri, Ro, r = P[P_RI], P[P_RO], P[P_R]
    dr, dt, gr, gt = yg[G_DR], yg[G_DT], yg[G_GR], yg[G_GT]
    half_cl = 0.5 * P[P_CL]
    paper_slip = P[P_SLIP] > 0.5
    slide_roll = P[P_TLAW] > 0.5 or P[P_MX] > 0.5  # (mixed lubrication: the film's u too)
    for j in range(yl.shape[0]):
        th, Om, om = yl[j, A_TH], yl[j, A_OM], yl[j, A_W]
        sk, sr, u, be = yl[j, A_SK], yl[j, A_SR], yl[j, A_U], yl[j, A_B]
        cphi, sphi = np.cos(th), np.sin(th)
        contrib[j, G_DR] = cphi
        contrib[j, G_DT] = sphi
        tan_sk = np.tan(sk) if paper_slip else 0.0
        for lam in range(x.shape[0]):
            xl = x[lam]
            rho = ring_approach(dr, dt, gr, gt, xl, cphi, sphi)[0]
            q[j, lam, 0], q[j, lam, 1] = race_approaches(rho, u, be, xl, half_cl, c[lam])
            r_l = effective_radius(r, xl, tan_sk)
            v[j, lam, 0], v[j, lam, 1] = slip_velocities(w_ring, Om, om, sr, r_l, xl, Ri, Ro)
            if slide_roll:
                s_i, s_o = rolling_sums(w_ring, Om, om, r_l, Ri, Ro)
                f[j, lam, 0] = 0.5 * abs(s_i)
                f[j, lam, 1] = 0.5 * abs(s_o)


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def contact_pass(P, q, pr, v, f, marker):
    """Pass 2, every slice contact of the bearing in one loop (Z k 2 of them, race = index
    parity): load from approach (physics/contact.py), Hertz pressure, traction
    (physics/traction.py). No branch and no call inside the loops (every law is inlined and
    written in plain arithmetic, physics/elementary.py), so that they vectorise. ``marker``:
    the work tuple's (system/optional.py; None: mixed lubrication not compiled)."""
    n = q.size
    qf, pf, vf, ff = c_view(q, (n,)), c_view(pr, (n,)), c_view(v, (n,)), c_view(f, (n,))
    Kw, eps, w, Rpi, Rpo, eta = P[P_KW], P[P_EPS], P[P_W], P[P_RPI], P[P_RPO], P[P_ETA]
    tv = P[P_TV]
    # The laws in stages, each a loop over all contacts: smoothed approach, its logarithm,
    # load and pressure (physics/contact.py's slice_load, stage by stage), then tractions.
    # Fused into one loop body (four exponentials, a logarithm, six divisions; the log -> exp
    # chain of the load) the vectorised loop ran at half the speed. pf holds ln s first.
    for i in range(n):
        qf[i] = smooth_positive(qf[i], eps)[0]
    for i in range(n):
        pf[i] = log_(qf[i])
    for i in range(n):
        load = palmgren_load(qf[i], pf[i], 0.0, Kw)[0]
        qf[i] = load
        pf[i] = hertz_pressure(load, w, Rpo if i & 1 else Rpi, eta)
    if P[P_MX] > 0.5:  # mixed lubrication (system/mixed.py): film and asperity shares
        mixed_traction_rows(marker, P[P_MX:], P[P_TLAW:P_SRU0 + 1], qf, pf, vf, ff, w, Rpi,
                            Rpo)
    elif P[P_TLAW] < 0.5:
        tA, tB, tC, tD, alt = P[P_TA], P[P_TB], P[P_TC], P[P_TD], P[P_TALT] > 0.5
        for i in range(n):
            ff[i] = _traction_value_paper(qf[i], vf[i], pf[i], tv, tA, tB, tC, tD, alt)
    else:
        sA, sB, sC, sD, su0 = P[P_SRA], P[P_SRB], P[P_SRC], P[P_SRD], P[P_SRU0]
        for i in range(n):
            ff[i] = _traction_value_slide_roll(qf[i], vf[i], ff[i], tv, sA, sB, sC, sD, su0)


@njit(error_model="numpy", no_cfunc_wrapper=True)
def pocket_shift(yg, j, Z):
    """(Δs, Δv): the change of roller j's pocket lead and lead rate by a displaced cage
    (physics/cage_guidance.py, theory.md §17)."""
    ds, dv, _, _, _, _, _ = _pocket_displacement(
        yg[G_CX], yg[G_CY], yg[G_CVX], yg[G_CVY], yg[G_TC], yg[G_WC], j, Z)
    return ds, dv


@njit(inline="always", error_model="numpy")
def cage_pocket_lead(th, Om, yg, j, Z, Rm, whirl):
    """(lead, rate) of roller j in its pocket (physics/kinematics.py), with a displaced cage's
    share (:func:`pocket_shift`) when the cage whirls; as ``roller_pass`` adds them."""
    lead = pocket_lead(th, yg[G_TC], j, Z, Rm)
    rate = pocket_lead_rate(Om, yg[G_WC], Rm)
    if whirl:
        ds, dv = pocket_shift(yg, j, Z)
        lead += ds
        rate += dv
    return lead, rate


# Rows of the roller pass's scratch array T (the work tuple's last entry, (SCRATCH_ROWS, Z)):
# one contiguous row per quantity and roller, so that the pass runs as loops over the rollers
# that LLVM vectorises (see roller_pass).
(T_QI, T_QO, T_MI, T_MO, T_SFI, T_SFO, T_SXF, T_FCR, T_MCZ, T_MSPIN, T_MCAGE, T_FD, T_MLR,
 T_GYRO, T_LEAD, T_RATE, T_SK, T_SR, T_OMW, T_OMO, T_FA, T_FB, T_LGRE) = range(23)
SCRATCH_ROWS = 23


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def roller_pass(yl, ypl, yg, P, x, res, contrib, q, f, fp, T):
    """Pass 3, every roller: slice sums, pocket and drag loads, the roller's equations into
    res[j], its contributions to the global rows into contrib[j], pocket end forces into
    fp[j]. One call for the bearing.

    Written as stages, each a loop over the rollers through the rows of the scratch T: the
    stages of plain arithmetic (pocket forces with their square roots and divisions, the drag
    table, the equations) vectorise; the libm calls (log10 of the drag, the churning law's
    branch, sincos of the gyroscopic term) stay in loops of their own. The same operations in
    the same order per roller as one loop over the rollers with everything inside, so the same
    bits (vector square roots and divisions round as the scalar ones; no fast-math)."""
    Z = int(P[P_Z])
    n = yl.shape[0]
    k = x.shape[0]
    Rm, Ri, Ro, r, L = P[P_RM], P[P_RI], P[P_RO], P[P_R], P[P_L]
    whirl = P[P_WH] > 0.5
    if whirl and P[P_CAGE] > 0.5:
        # a displaced cage's share of each pocket's lead, parked in fp until the pocket stage
        # writes the pocket forces there: computed in the pocket stage (trigonometry, never
        # run without whirl) it would keep that stage of every other scene from vectorising
        for j in range(n):
            fp[j, 0], fp[j, 1] = pocket_shift(yg, j, Z)
    for j in range(n):
        Qi = 0.0
        Qo = 0.0
        Mi = 0.0
        Mo = 0.0
        SFi = 0.0
        SFo = 0.0
        SxF = 0.0
        for lam in range(k):
            xl = x[lam]
            Qi += q[j, lam, 0]
            Qo += q[j, lam, 1]
            Mi += xl * q[j, lam, 0]
            Mo += xl * q[j, lam, 1]
            SFi += f[j, lam, 0]
            SFo += f[j, lam, 1]
            SxF += xl * (f[j, lam, 0] + f[j, lam, 1])
        T[T_QI, j], T[T_QO, j], T[T_MI, j], T[T_MO, j] = Qi, Qo, Mi, Mo
        T[T_SFI, j], T[T_SFO, j], T[T_SXF, j] = SFi, SFo, SxF
        T[T_SK, j] = yl[j, A_SK]
        T[T_SR, j] = yl[j, A_SR]
        T[T_OMW, j] = yl[j, A_W]
        T[T_OMO, j] = yl[j, A_OM]

    # roller-cage pocket (theory.md §8)
    if P[P_CAGE] > 0.5:
        tc, wc = yg[G_TC], yg[G_WC]
        cp, Kp, cd, epsp, fsc = P[P_CP], P[P_KP], P[P_CD], P[P_EPSP], P[P_FP]
        muc, spin, spinf = P[P_MUC], P[P_SPIN], P[P_SPINF]
        for j in range(n):
            T[T_LEAD, j] = pocket_lead(yl[j, A_TH], tc, j, Z, Rm)
            T[T_RATE, j] = pocket_lead_rate(T[T_OMO, j], wc, Rm)
        if whirl:
            for j in range(n):
                T[T_LEAD, j] += fp[j, 0]
                T[T_RATE, j] += fp[j, 1]
        for j in range(n):
            s_a, s_b = end_positions(T[T_LEAD, j], T[T_SK, j], L)
            v_a, v_b = end_positions(T[T_RATE, j], T[T_SR, j], L)
            Fa = _pocket_force(s_a, v_a, cp, Kp, cd, epsp, fsc)[0]
            Fb = _pocket_force(s_b, v_b, cp, Kp, cd, epsp, fsc)[0]
            T[T_FCR, j], T[T_MCZ, j], T[T_MSPIN, j], T[T_MCAGE, j] = _pocket_loads(
                Fa, Fb, T[T_OMW, j], L, r, Rm, muc, spin, spinf)
            T[T_FA, j] = Fa
            T[T_FB, j] = Fb
        for j in range(n):
            fp[j, 0] = T[T_FA, j]
            fp[j, 1] = T[T_FB, j]
    else:
        for j in range(n):
            T[T_FCR, j], T[T_MCZ, j], T[T_MSPIN, j], T[T_MCAGE, j] = 0.0, 0.0, 0.0, 0.0
            fp[j, 0] = 0.0
            fp[j, 1] = 0.0

    # lubricant drag and churning (theory.md §9)
    if P[P_DRAG] > 0.5:
        rho, muo, D = P[P_RHO], P[P_MUO], 2.0 * r
        for j in range(n):
            T[T_LGRE, j] = drag_log_reynolds(orbit_drag_reynolds(T[T_OMO, j], Rm, D, rho, muo))
        for j in range(n):
            T[T_FD, j] = orbit_drag_at(drag_coefficient_at_log(T[T_LGRE, j]), T[T_OMO, j], Rm,
                                       D, L, rho)
        for j in range(n):
            T[T_MLR, j] = roller_end_churning(T[T_OMW, j], r, rho, muo)
    else:
        for j in range(n):
            T[T_FD, j] = 0.0
            T[T_MLR, j] = 0.0

    mass = P[P_MASS]
    Ix, It = P[P_IX], P[P_IT]
    if P[P_GYRO] > 0.5:
        for j in range(n):
            Om, om, sk = T[T_OMO, j], T[T_OMW, j], T[T_SK, j]
            T[T_GYRO, j] = (Ix - It) * Om * (om + Om * np.cos(sk)) * np.sin(sk)
    else:
        for j in range(n):
            T[T_GYRO, j] = 0.0

    orbit_paper = P[P_ORBIT] > 0.5
    for j in range(n):
        Om = T[T_OMO, j]
        SFi, SFo, F_cr, F_D = T[T_SFI, j], T[T_SFO, j], T[T_FCR, j], T[T_FD, j]
        res[j, A_TH] = ypl[j, A_TH] - Om
        if not orbit_paper:
            res[j, A_OM] = mass * Rm * ypl[j, A_OM] - (SFi + SFo + F_cr - F_D)
        else:  # [reading] the paper's moment form about the bearing axis, I_X = m R_m² + I_x
            res[j, A_OM] = (mass * Rm * Rm + Ix) * ypl[j, A_OM] - (
                Ri * SFi + Ro * SFo + Rm * (F_cr - F_D))
        res[j, A_W] = Ix * ypl[j, A_W] - (r * (SFi - SFo) + T[T_MSPIN, j] - T[T_MLR, j])
        res[j, A_SK] = ypl[j, A_SK] - T[T_SR, j]
        res[j, A_SR] = It * ypl[j, A_SR] - (-T[T_SXF, j] + T[T_MCZ, j] - T[T_GYRO, j])
        res[j, A_U], res[j, A_B] = roller_balance(T[T_QI, j], T[T_QO, j], T[T_MI, j],
                                                  T[T_MO, j], centrifugal_force(mass, Rm, Om))

    if P[P_RDYN] < 0.5:
        for j in range(n):
            cphi, sphi = contrib[j, G_DR], contrib[j, G_DT]  # left by kinematics_pass
            contrib[j, G_TC] = 0.0
            contrib[j, G_WC] = T[T_MCAGE, j]
            contrib[j, G_DR], contrib[j, G_DT], contrib[j, G_GR], contrib[j, G_GT] = (
                ring_load_share(T[T_QI, j], T[T_MI, j], cphi, sphi))
    else:  # a dynamic ring (theory.md §15): the shares enter its momentum rows
        for j in range(n):
            cphi, sphi = contrib[j, G_DR], contrib[j, G_DT]
            contrib[j, G_TC] = 0.0
            contrib[j, G_WC] = T[T_MCAGE, j]
            s_r, s_t, s_gr, s_gt = ring_load_share(T[T_QI, j], T[T_MI, j], cphi, sphi)
            contrib[j, G_VR], contrib[j, G_VT], contrib[j, G_WR], contrib[j, G_WT] = (
                -s_r, -s_t, -s_gr, -s_gt)
            contrib[j, G_DR], contrib[j, G_DT], contrib[j, G_GR], contrib[j, G_GT] = (
                0.0, 0.0, 0.0, 0.0)


@njit(inline="always", error_model="numpy")
def global_rows(yg, ypg, P, contrib, resg, loads):
    """Global rows: cage kinematics and dynamics, inner-ring balance (own terms - Σ_j contrib)
    with the applied loads ``loads`` = (F_r, F_t, M, M_t) at this time (physics/loads.py)."""
    Z = contrib.shape[0]
    # the sums over rollers in scalars: a ``np.zeros(6)`` here was a heap allocation per call
    t_wc = 0.0
    t_dr = 0.0
    t_dt = 0.0
    t_gr = 0.0
    t_gt = 0.0
    for j in range(Z):
        t_wc += contrib[j, G_WC]
        t_dr += contrib[j, G_DR]
        t_dt += contrib[j, G_DT]
        t_gr += contrib[j, G_GR]
        t_gt += contrib[j, G_GT]
    wc = yg[G_WC]
    M_lc = 0.0
    if P[P_DRAG] > 0.5:
        M_lc = cage_side_churning(wc, P[P_CRI], P[P_CRO], P[P_RHO], P[P_MUO])
    resg[G_TC] = ypg[G_TC] - wc
    resg[G_WC] = P[P_IC] * ypg[G_WC] - (t_wc - M_lc)
    if P[P_RDYN] < 0.5:
        resg[G_DR] = loads[0] - t_dr
        resg[G_DT] = loads[1] - t_dt
        resg[G_GR] = loads[2] - t_gr
        resg[G_GT] = loads[3] - t_gt
    else:
        dynamic_ring_rows(yg, ypg, P, contrib, resg, loads)


@njit(inline="always", error_model="numpy")
def dynamic_ring_rows(yg, ypg, P, contrib, resg, loads):
    """The ring as a body (theory.md §15): δ' - v = 0 and m v' - (F + F_s - Σ_j share_j) = 0
    for both directions (F_s the support, physics/ring.py), I_d ω' - (M - Σ_j share_j) = 0 for
    both tilts. The shares are in contrib[:, G_VR:] already negated (own - Σ contrib)."""
    t_vr = 0.0
    t_vt = 0.0
    t_wr = 0.0
    t_wt = 0.0
    for j in range(contrib.shape[0]):
        t_vr += contrib[j, G_VR]
        t_vt += contrib[j, G_VT]
        t_wr += contrib[j, G_WR]
        t_wt += contrib[j, G_WT]
    m, I, k, c = P[P_RMASS], P[P_RINER], P[P_SUPK], P[P_SUPC]
    resg[G_DR] = ypg[G_DR] - yg[G_VR]
    resg[G_DT] = ypg[G_DT] - yg[G_VT]
    resg[G_GR] = ypg[G_GR] - yg[G_WR]
    resg[G_GT] = ypg[G_GT] - yg[G_WT]
    resg[G_VR] = m * ypg[G_VR] - (loads[0] + support_force(k, c, yg[G_DR], yg[G_VR])) - t_vr
    resg[G_VT] = m * ypg[G_VT] - (loads[1] + support_force(k, c, yg[G_DT], yg[G_VT])) - t_vt
    resg[G_WR] = I * ypg[G_WR] - loads[2] - t_wr
    resg[G_WT] = I * ypg[G_WT] - loads[3] - t_wt


@helper
def unpack(y, S, lmap, gmap, yl, yg):
    """Scaled compact vector -> unscaled full arrays (switched-off unknowns stay 0)."""
    Z = yl.shape[0]
    nl = lmap.shape[0]
    for j in range(Z):
        for a in range(nl):
            i = j * nl + a
            yl[j, lmap[a]] = y[i] * S[i]
    base = Z * nl
    for b in range(gmap.shape[0]):
        yg[gmap[b]] = y[base + b] * S[base + b]


@njit(inline="always", error_model="numpy")
def full_evaluate(t, y, yp, d):
    """Evaluate every roller and the global rows into the work arrays of ``d``."""
    (P, x, c, S, RS, lmap, gmap, ramp_t, ramp_w, yl, ypl, yg, ypg, resl, resg, contrib,
     q, pr, v, f, fp, load_table, scratch, optional) = d
    # Switched-off unknowns are never written by unpack: they keep the zeros the work arrays
    # were allocated with (system/model.py), so no per-call reset is needed.
    unpack(y, S, lmap, gmap, yl, yg)
    unpack(yp, S, lmap, gmap, ypl, ypg)
    w_ring = ring_speed_at(t, ramp_t, ramp_w)
    kinematics_pass(yl, yg, w_ring, P, x, c, q, v, f, contrib)
    defect_rows(optional, t, yl, x, P[P_W], ramp_t, ramp_w, q)  # none: no code (defects.py)
    contact_pass(P, q, pr, v, f, mixed_marker(optional))  # (optional.py)
    roller_pass(yl, ypl, yg, P, x, resl, contrib, q, f, fp, scratch)
    spin_angle_rows(optional, yl, ypl, resl)  # φ' - ω: with defects only (defects.py)
    if P[P_RR] > 0.5:  # EHL rolling resistance (system/rolling_resistance.py); off: skipped
        rolling_resistance_rows(optional, yl, w_ring, P[P_RR:], x, q, resl)  # (optional.py)
    loads = applied_loads(t, load_table, ramp_t, ramp_w, P[P_UNB], P[P_UNBPH])
    # roller end-flange contacts and the cage centre's rows, where the scene has them
    # (system/optional.py: a scene without any effect compiled apart compiles none)
    flange_rows(optional, yl, yg, w_ring, P, loads[4], resl, resg, contrib)
    global_rows(yg, ypg, P, contrib, resg, loads)
    whirl_rows(optional, yl, yg, ypg, w_ring, P, fp, resg)
    extension_rows(optional, yl, ypl, yg, ypg, w_ring, P, resl, resg)  # (system/extensions.py)


@njit(inline="always", error_model="numpy")
def pack_residual(resl, resg, RS, lmap, gmap, res):
    """Full residual rows -> scaled compact residual."""
    Z = resl.shape[0]
    nl = lmap.shape[0]
    for j in range(Z):
        for a in range(nl):
            i = j * nl + a
            res[i] = resl[j, lmap[a]] / RS[i]
    base = Z * nl
    for b in range(gmap.shape[0]):
        res[base + b] = resg[gmap[b]] / RS[base + b]


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def residual(t, y, yp, res, d):
    """IDA residual callback: res = F(t, y, y') for scaled compact y, y'."""
    full_evaluate(t, y, yp, d)
    pack_residual(d[13], d[14], d[4], d[5], d[6], res)
