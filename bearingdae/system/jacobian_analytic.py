"""Analytic iteration matrix dF/dy + c_j dF/dy' of system/residual.py (numba).

Why: the structured finite differences of system/jacobian.py cost n_local + n_global + 1
residual evaluations per Jacobian (14 on the baseline), about half of all kernel work of an IDA
run. Every law of the kernel already returns its analytic slopes
(physics/contact.py, traction.py, cage.py), so the exact Jacobian costs about one evaluation. The roller end-flange terms
(theory.md §16) are added by system/flange.py after this fill, in scenes with flanges only, and
the cage centre's (theory.md §17) by system/whirl.py, in scenes with cage whirl only.

Structure (the same as the residual's): roller j's rows depend on its own unknowns and the
global ones; the global rows are ``own terms - Σ_j contribution_j``. Per roller we form, in the
kernel's full (unscaled) order, the NL x (NL + 6) block of d(roller rows)/d(local, cage and ring
position) and the NG x (NL + 6) block of d(contribution_j)/d(local, cage and ring position), then
scatter into the scaled compact matrix J[r, c] = dF_full/dy_full · S[c] / RS[r] (switched-off
unknowns are simply not scattered).

The slopes of the drag laws and of the dynamic ring's own terms are system/jacobian_scalars.py's.

Every formula here is the derivative of one line of system/residual.py; tests compare the
result with central differences of the residual (tests/system/test_jacobian.py).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..physics.cage import _pocket_force, _spin_friction_torque
from ..physics.kinematics import effective_radius, end_positions, ring_approach, rolling_sums
from ..physics.compiled import copy2
from .jacobian import gather_csc
from .layout import GLOBAL, LOCAL
from .optional import (defect_marker, extension_block, mixed_marker, optional_jacobian,
                       rolling_resistance_block)
from .defects import A_PHI, defect_rows, defect_slopes, spin_angle_slopes
from .residual import (
    A_B, A_OM, A_SK, A_SR, A_TH, A_U, A_W, G_DR, G_DT, G_GR, G_GT, G_TC, G_VR, G_VT, G_WC,
    G_WR, G_WT, P_CAGE, P_CD, P_RDYN, P_SUPC, P_SUPK,
    P_CP, P_DRAG, P_EPSP, P_FP, P_GYRO, P_IT, P_IX, P_KP, P_L,
    P_MASS, P_MUC, P_ORBIT, P_R, P_RI, P_RM, P_RO, P_SLIP, P_SPIN,
    P_TLAW, P_W, P_Z, P_SPINF, P_WH, P_RR, P_MX, cage_pocket_lead, kinematics_pass,
    ring_speed_at,
    unpack,
)
from .jacobian_scalars import (_ring_own_slope, cage_side_slope, orbit_drag_slope,
                               roller_end_slope)
from .contact_slopes import contact_slopes

NL, NG = len(LOCAL), len(GLOBAL)
NV = NL + NG  # derivative vectors: the local unknowns, then the global ones
# A roller's rows and its contributions depend on the first six global unknowns only (cage,
# ring position): never on the ring's velocities. The per-roller loops stop there, so a
# quasi-static ring costs what it did before the ring velocities existed.
NGR = 6
NVR = NL + NGR


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def roller_blocks(yl, yg, w_ring, P, x, q, pr, tr, contrib, JR, JC, dF, S, RS, lmap, gmap, Jd,
                  CG, marker):
    """Per roller j: d(roller j's NL full rows)/d(local, global) into JR (NL, NV) and
    d(contribution_j) into JC (NG, NV), from the per-contact loads q, slopes pr and traction
    values and slopes ``tr`` of ``contact_slopes`` and (cos φ, sin φ) that
    ``kinematics_pass`` left in contrib[:, G_DR:G_GR], then scattered into the scaled compact Jd;
    the contributions' global columns summed into CG. ``dF`` is (7, NV) scratch for the
    derivative of the slice sums. One call for the bearing, the roller loop inside (a call
    per roller passed every array argument field by field)."""
    nl = lmap.shape[0]
    ng = gmap.shape[0]
    base = yl.shape[0] * nl
    for j in range(yl.shape[0]):
        Z = int(P[P_Z])
        Rm, Ri, Ro, r, L = P[P_RM], P[P_RI], P[P_RO], P[P_R], P[P_L]
        th, Om, om = yl[j, A_TH], yl[j, A_OM], yl[j, A_W]
        sk, sr, phi = yl[j, A_SK], yl[j, A_SR], yl[j, A_PHI]
        dr, dt, gr, gt = yg[G_DR], yg[G_DT], yg[G_GR], yg[G_GT]
        cphi, sphi = contrib[j, G_DR], contrib[j, G_DT]  # cos θX, sin θX of kinematics_pass
        k = x.shape[0]
        paper_slip = P[P_SLIP] > 0.5
        tan_sk = np.tan(sk) if paper_slip else 0.0
        sec2 = 1.0 + tan_sk * tan_sk if paper_slip else 0.0
        slide_roll = P[P_TLAW] > 0.5 or P[P_MX] > 0.5  # (mixed: the film's dF/du)
        # Rows of dF: 0 Qi, 1 Qo, 2 Mi (Σ x qi), 3 Mo, 4 SFi, 5 SFo, 6 SxF (Σ x (Fi + Fo)).
        for a in range(7):
            for b in range(NVR):
                dF[a, b] = 0.0
        Qi = 0.0
        Mi = 0.0
        SFi = 0.0
        SFo = 0.0
        for lam in range(k):
            xl = x[lam]
            drho_th = ring_approach(dr, dt, gr, gt, xl, cphi, sphi)[1]
            qi, kqi, kqo = q[j, lam, 0], pr[j, lam, 0], pr[j, lam, 1]
            Fi, FiV, Fiq = tr[0, j, lam, 0], tr[1, j, lam, 0], tr[2, j, lam, 0]
            Fo, FoV, Foq = tr[0, j, lam, 1], tr[1, j, lam, 1], tr[2, j, lam, 1]
            r_l = effective_radius(r, xl, tan_sk)
            drl_sk = xl * sec2
            # rolling-speed slopes of the slide-to-roll law along Ω, ω, θz (u = |Σ| / 2)
            ui_Om = 0.0
            ui_om = 0.0
            ui_sk = 0.0
            uo_Om = 0.0
            uo_om = 0.0
            uo_sk = 0.0
            if slide_roll:
                ri_, ro_ = rolling_sums(w_ring, Om, om, r_l, Ri, Ro)
                si = 0.5 * tr[3, j, lam, 0] * (1.0 if ri_ >= 0.0 else -1.0)
                so = 0.5 * tr[3, j, lam, 1] * (1.0 if ro_ >= 0.0 else -1.0)
                ui_Om = -Ri * si
                ui_om = r_l * si
                ui_sk = om * drl_sk * si
                uo_Om = Ro * so
                uo_om = r_l * so
                uo_sk = om * drl_sk * so
            Qi += qi
            Mi += xl * qi
            SFi += Fi
            SFo += Fo
            # dqi over (θX, u, β, δr, δt, γr, γt); dqo over (u, β)
            gi_th = kqi * drho_th
            gi_dr = kqi * cphi
            gi_dt = kqi * sphi
            # slice loads
            dF[0, A_TH] += gi_th
            dF[0, A_U] -= kqi
            dF[0, A_B] -= kqi * xl
            dF[0, NL + G_DR] += gi_dr
            dF[0, NL + G_DT] += gi_dt
            dF[0, NL + G_GR] += gi_dr * xl
            dF[0, NL + G_GT] += gi_dt * xl
            dF[1, A_U] += kqo
            dF[1, A_B] += kqo * xl
            dF[2, A_TH] += xl * gi_th
            dF[2, A_U] -= xl * kqi
            dF[2, A_B] -= xl * xl * kqi
            dF[2, NL + G_DR] += xl * gi_dr
            dF[2, NL + G_DT] += xl * gi_dt
            dF[2, NL + G_GR] += xl * xl * gi_dr
            dF[2, NL + G_GT] += xl * xl * gi_dt
            dF[3, A_U] += xl * kqo
            dF[3, A_B] += xl * xl * kqo
            # traction, inner: through qi and Vi (and u_i)
            fi_q = Fiq
            fi_th = fi_q * gi_th
            fi_u = -fi_q * kqi
            fi_b = -fi_q * kqi * xl
            fi_dr = fi_q * gi_dr
            fi_dt = fi_q * gi_dt
            fi_Om = -FiV * Ri + ui_Om
            fi_om = -FiV * r_l + ui_om
            fi_sr = FiV * xl
            fi_sk = -FiV * om * drl_sk + ui_sk
            # traction, outer: through qo and Vo (and u_o)
            fo_u = Foq * kqo
            fo_b = Foq * kqo * xl
            fo_Om = -FoV * Ro + uo_Om
            fo_om = FoV * r_l + uo_om
            fo_sr = FoV * xl
            fo_sk = FoV * om * drl_sk + uo_sk
            for row, wgt_i, wgt_o in ((4, 1.0, 0.0), (5, 0.0, 1.0), (6, xl, xl)):
                dF[row, A_TH] += wgt_i * fi_th
                dF[row, A_OM] += wgt_i * fi_Om + wgt_o * fo_Om
                dF[row, A_W] += wgt_i * fi_om + wgt_o * fo_om
                dF[row, A_SK] += wgt_i * fi_sk + wgt_o * fo_sk
                dF[row, A_SR] += wgt_i * fi_sr + wgt_o * fo_sr
                dF[row, A_U] += wgt_i * fi_u + wgt_o * fo_u
                dF[row, A_B] += wgt_i * fi_b + wgt_o * fo_b
                dF[row, NL + G_DR] += wgt_i * fi_dr
                dF[row, NL + G_DT] += wgt_i * fi_dt
                dF[row, NL + G_GR] += wgt_i * fi_dr * xl
                dF[row, NL + G_GT] += wgt_i * fi_dt * xl
            # local defects' and waviness' slopes along θX and φ (system/defects.py; none:
            # no code)
            defect_slopes(marker, j, th, phi, xl, P[P_W], kqi, kqo, Fiq, Foq, dF)

        for a in range(NL):
            for b in range(NVR):
                JR[a, b] = 0.0
        for a in range(NG if P[P_RDYN] > 0.5 else NGR):
            for b in range(NVR):
                JC[a, b] = 0.0

        # pocket (theory.md §8): end forces and their slopes along s and v
        dFcr_th = dFcr_Om = dFcr_sk = dFcr_sr = dFcr_tc = dFcr_wc = 0.0
        dMcz_th = dMcz_Om = dMcz_sk = dMcz_sr = dMcz_tc = dMcz_wc = 0.0
        dMs_th = dMs_Om = dMs_om = dMs_sk = dMs_sr = dMs_tc = dMs_wc = 0.0
        if P[P_CAGE] > 0.5:
            half = 0.5 * L
            # a displaced cage's other slopes: system/whirl.py
            lead, rate = cage_pocket_lead(th, Om, yg, j, Z, Rm, P[P_WH] > 0.5)
            s_a, s_b = end_positions(lead, sk, L)
            v_a, v_b = end_positions(rate, sr, L)
            Fa, Fa_s, Fa_v = _pocket_force(s_a, v_a, P[P_CP], P[P_KP], P[P_CD], P[P_EPSP], P[P_FP])
            Fb, Fb_s, Fb_v = _pocket_force(s_b, v_b, P[P_CP], P[P_KP], P[P_CD], P[P_EPSP], P[P_FP])
            # d(s_a, s_b)/dθX = R_m, /dθc = -R_m, /dθz = ∓L/2; the same for (v_a, v_b) along
            # (Ω, ω_c, ζ) (physics/kinematics.py)
            # d(Fa, Fb)/d(θX, Ω, θz, ζ, θc, ω_c)
            a_th, a_Om, a_sk, a_sr = Fa_s * Rm, Fa_v * Rm, -half * Fa_s, -half * Fa_v
            b_th, b_Om, b_sk, b_sr = Fb_s * Rm, Fb_v * Rm, half * Fb_s, half * Fb_v
            dFcr_th, dFcr_Om, dFcr_sk, dFcr_sr = a_th + b_th, a_Om + b_Om, a_sk + b_sk, a_sr + b_sr
            dFcr_tc, dFcr_wc = -dFcr_th, -dFcr_Om
            dMcz_th, dMcz_Om = half * (b_th - a_th), half * (b_Om - a_Om)
            dMcz_sk, dMcz_sr = half * (b_sk - a_sk), half * (b_sr - a_sr)
            dMcz_tc, dMcz_wc = -dMcz_th, -dMcz_Om
            _, Ms_a, Ms_b, Ms_om = _spin_friction_torque(Fa, Fb, om, r, P[P_MUC], P[P_SPIN],
                                                         P[P_SPINF])
            dMs_th = Ms_a * a_th + Ms_b * b_th
            dMs_Om = Ms_a * a_Om + Ms_b * b_Om
            dMs_sk = Ms_a * a_sk + Ms_b * b_sk
            dMs_sr = Ms_a * a_sr + Ms_b * b_sr
            dMs_om = Ms_om
            dMs_tc, dMs_wc = -dMs_th, -dMs_Om

        dFD_Om = 0.0
        dMlr_om = 0.0
        if P[P_DRAG] > 0.5:
            dFD_Om = orbit_drag_slope(Om, P)
            dMlr_om = roller_end_slope(om, P)

        mass = P[P_MASS]
        Ix, It = P[P_IX], P[P_IT]
        G = NL + G_TC
        W = NL + G_WC
        # θX' - Ω
        JR[A_TH, A_OM] = -1.0
        spin_angle_slopes(marker, JR)  # φ' - ω, with defects only (system/defects.py)
        # orbit
        if P[P_ORBIT] < 0.5:
            for b in range(NVR):
                JR[A_OM, b] = -(dF[4, b] + dF[5, b])
        else:
            for b in range(NVR):
                JR[A_OM, b] = -(Ri * dF[4, b] + Ro * dF[5, b])
        arm = 1.0 if P[P_ORBIT] < 0.5 else Rm
        JR[A_OM, A_TH] -= arm * dFcr_th
        JR[A_OM, A_OM] -= arm * (dFcr_Om - dFD_Om)
        JR[A_OM, A_SK] -= arm * dFcr_sk
        JR[A_OM, A_SR] -= arm * dFcr_sr
        JR[A_OM, G] -= arm * dFcr_tc
        JR[A_OM, W] -= arm * dFcr_wc
        # spin: r (SFi - SFo) + M_spin - M_lr
        for b in range(NVR):
            JR[A_W, b] = -r * (dF[4, b] - dF[5, b])
        JR[A_W, A_TH] -= dMs_th
        JR[A_W, A_OM] -= dMs_Om
        JR[A_W, A_W] -= dMs_om - dMlr_om
        JR[A_W, A_SK] -= dMs_sk
        JR[A_W, A_SR] -= dMs_sr
        JR[A_W, G] -= dMs_tc
        JR[A_W, W] -= dMs_wc
        # θz' - ζ
        JR[A_SK, A_SR] = -1.0
        # skew: -SxF + M_cz - gyro
        for b in range(NVR):
            JR[A_SR, b] = dF[6, b]
        JR[A_SR, A_TH] -= dMcz_th
        JR[A_SR, A_OM] -= dMcz_Om
        JR[A_SR, A_SK] -= dMcz_sk
        JR[A_SR, A_SR] -= dMcz_sr
        JR[A_SR, G] -= dMcz_tc
        JR[A_SR, W] -= dMcz_wc
        if P[P_GYRO] > 0.5:
            k_g = Ix - It
            ssk, csk = np.sin(sk), np.cos(sk)
            JR[A_SR, A_OM] += k_g * (om + 2.0 * Om * csk) * ssk
            JR[A_SR, A_W] += k_g * Om * ssk
            JR[A_SR, A_SK] += k_g * Om * (-Om * ssk * ssk + (om + Om * csk) * csk)
        # radial and tilt balance
        for b in range(NVR):
            JR[A_U, b] = dF[0, b] - dF[1, b]
            JR[A_B, b] = dF[2, b] - dF[3, b]
        JR[A_U, A_OM] += 2.0 * mass * Rm * Om

        # contributions to the global rows: M_cage = -Rm F_cr + M_spin; ring sums Qi, Mi
        JC[G_WC, A_TH] = -Rm * dFcr_th + dMs_th
        JC[G_WC, A_OM] = -Rm * dFcr_Om + dMs_Om
        JC[G_WC, A_W] = dMs_om
        JC[G_WC, A_SK] = -Rm * dFcr_sk + dMs_sk
        JC[G_WC, A_SR] = -Rm * dFcr_sr + dMs_sr
        JC[G_WC, G] = -Rm * dFcr_tc + dMs_tc
        JC[G_WC, W] = -Rm * dFcr_wc + dMs_wc
        for b in range(NVR):
            JC[G_DR, b] = dF[0, b] * cphi
            JC[G_DT, b] = dF[0, b] * sphi
            JC[G_GR, b] = dF[2, b] * cphi
            JC[G_GT, b] = dF[2, b] * sphi
        JC[G_DR, A_TH] -= Qi * sphi
        JC[G_DT, A_TH] += Qi * cphi
        JC[G_GR, A_TH] -= Mi * sphi
        JC[G_GT, A_TH] += Mi * cphi
        if P[P_RDYN] > 0.5:  # a dynamic ring: the shares enter its momentum rows, negated
            for b in range(NVR):
                JC[G_VR, b] = -JC[G_DR, b]
                JC[G_VT, b] = -JC[G_DT, b]
                JC[G_WR, b] = -JC[G_GR, b]
                JC[G_WT, b] = -JC[G_GT, b]
                JC[G_DR, b] = 0.0
                JC[G_DT, b] = 0.0
                JC[G_GR, b] = 0.0
                JC[G_GT, b] = 0.0
        # scatter into the scaled compact matrix; the contributions' global columns summed
        for a in range(nl):
            row = j * nl + a
            fa = lmap[a]
            for b in range(nl):
                col = j * nl + b
                Jd[row, col] = JR[fa, lmap[b]] * S[col] / RS[row]
            for gb in range(ng):
                col = base + gb
                Jd[row, col] = JR[fa, NL + gmap[gb]] * S[col] / RS[row]
        for ga in range(ng):
            row = base + ga
            g = gmap[ga]
            for b in range(nl):
                col = j * nl + b
                Jd[row, col] = -JC[g, lmap[b]] * S[col] / RS[row]
            for gb in range(NGR):
                CG[g, gb] += JC[g, NL + gb]


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def fill_jacobian_analytic(t, y, yp, cj, d, jd):
    """Dense scaled iteration matrix dF/dy + cj·diag(mass) (pattern entries) into jd[0]."""
    Jd, mass, JR, JC, dF, CG = jd[0], jd[3], jd[4], jd[5], jd[6], jd[7]
    P, x, c, S, RS, lmap, gmap = d[0], d[1], d[2], d[3], d[4], d[5], d[6]
    ramp_t, ramp_w, yl, yg = d[7], d[8], d[9], d[11]
    unpack(y, S, lmap, gmap, yl, yg)
    w_ring = ring_speed_at(t, ramp_t, ramp_w)
    Z = yl.shape[0]
    nl = lmap.shape[0]
    ng = gmap.shape[0]
    base = Z * nl
    n = y.shape[0]
    # No zeroing of Jd: every entry written below is assigned on every call (the diagonal before
    # its += cj·mass), and the rest stay at the zeros Jd was allocated with. Zeroing the dense
    # N x N matrix cost ~9 µs per call in a run (a 170 kB memset, cache-cold), for nothing.
    for a in range(NG):
        for b in range(NG):
            CG[a, b] = 0.0
    # per-contact loads, slopes and tractions of the whole bearing first (two vectorised passes,
    # the first shared with the residual), then each roller's blocks; d's per-slice arrays
    # (q, pr, v, f: the residual's diagnostics) serve as scratch, as in the FD Jacobian
    q, pr, v, f, contrib = d[16], d[17], d[18], d[19], d[15]
    tr = np.empty((4,) + q.shape)
    kinematics_pass(yl, yg, w_ring, P, x, c, q, v, f, contrib)
    defect_rows(d[23], t, yl, x, P[P_W], ramp_t, ramp_w, q)
    contact_slopes(P, q, pr, v, f, tr, mixed_marker(d[23]))  # (optional.py)
    roller_blocks(yl, yg, w_ring, P, x, q, pr, tr, contrib, JR, JC, dF, S, RS, lmap, gmap, Jd, CG,
                  defect_marker(d[23]))
    if P[P_RR] > 0.5:  # EHL rolling resistance (system/rolling_resistance.py, optional.py)
        rolling_resistance_block(d[23], yl, yg, w_ring, P[P_RR:], x, q, pr, contrib, S, RS,
                                 lmap, gmap, Jd)
    # global rows: own terms - Σ_j contributions
    wc = yg[G_WC]
    own_wc = 0.0
    if P[P_DRAG] > 0.5:
        own_wc = cage_side_slope(wc, P)
    dyn_ring = P[P_RDYN] > 0.5
    k_sup, c_sup = P[P_SUPK], P[P_SUPC]
    for ga in range(ng):
        row = base + ga
        g = gmap[ga]
        for gb in range(ng):
            col = base + gb
            h = gmap[gb]
            val = -CG[g, h]
            if g == G_TC and h == G_WC:
                val -= 1.0
            if g == G_WC and h == G_WC:
                val += own_wc
            if dyn_ring:
                val += _ring_own_slope(g, h, k_sup, c_sup)
            Jd[row, col] = val * S[col] / RS[row]
    # roller end-flange contacts and the cage centre, where the scene has them
    optional_jacobian(d[23], yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd)
    extension_block(d[23], yl, yg, w_ring, P, S, RS, lmap, gmap, Jd)  # (system/extensions.py)
    for i in range(n):
        Jd[i, i] += cj * mass[i]


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def jacobian_analytic_sparse(t, y, yp, res, cj, JJ, d, jd):
    """IDA ``jacfn`` for linsolver='sparse': JJ is the CSC data array of the pattern."""
    fill_jacobian_analytic(t, y, yp, cj, d, jd)
    gather_csc(jd[0], jd[1], jd[2], JJ)


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def jacobian_analytic_dense(t, y, yp, res, cj, JJ, d, jd):
    """IDA ``jacfn`` for linsolver='dense': JJ is the (N, N) matrix."""
    fill_jacobian_analytic(t, y, yp, cj, d, jd)
    copy2(JJ, jd[0])  # (a loop: physics/compiled.copy2)


def analytic_work(model, rows, cols):
    """Work arrays of ``fill_jacobian_analytic`` for a model and its CSC pattern order."""
    n = model.size
    return (np.zeros((n, n)), rows, cols, model.mass.copy(), np.zeros((NL, NV)),
            np.zeros((NG, NV)), np.zeros((7, NV)), np.zeros((NG, NG)))
