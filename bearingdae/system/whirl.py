"""Cage whirl in the DAE (theory.md §17): the cage centre's rows, the pockets' and the land's
loads on the cage, their analytic Jacobian and the land force for the outputs (numba).

Only a scene with ``[physics] cage_whirl = true`` calls anything here: the kernels of
system/residual.py and system/jacobian_analytic.py test one parameter and skip it otherwise, so
the model without whirl computes what it did before, bit for bit.

Unknowns (system/layout.py): the cage centre e = (x, y) and its velocity (ẋ, ẏ), x along the
ring's δ_r (φ = 0), y along δ_t. Rows, after the roller and global rows of system/residual.py:

    x' - ẋ = 0,  y' - ẏ = 0
    m_c ẍ - (F_land,x + Σ_j F_pocket,j,x) = 0,  m_c ÿ - (... y) = 0
    cage rotation row (theory.md §10)  -= Σ_j ΔM_j + T_land

with, per pocket (physics/cage_guidance.py), F_pocket,j = -F_cr t̂_ψ + f r̂_ψ,
f = -μ_c sg(ω_j) F_cr, ΔM_j = e_r F_cr + e_t f (the moment about the displaced centre minus the
moment of theory.md §8), and the land force and moment of physics/cage_guidance._land_force
(outer or inner land; none for a roller-guided cage). The pocket leads of the roller rows
already include the displacement (residual.roller_pass calls ``_pocket_displacement``).

The Jacobian (``whirl_jacobian``) is added after the whirl-free fill, which evaluated the pocket
forces at the displaced leads but took ∂s/∂θc = -R_m, ∂v/∂ω_c = -R_m and no cage-centre
columns: here go the rest of those slopes (the pocket's extra dependence on θc, ω_c, x, y, ẋ, ẏ)
and every slope of the new rows and of ΔM, T_land.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..physics.cage import _pocket_force, _spin_friction_torque
from ..physics.cage_guidance import (LAND_SPEED_SCALE_RAD_S, _land_force,
                                     _pocket_displacement)
from ..physics.kinematics import end_positions, pocket_lead, pocket_lead_rate
from .arrayview import compact_positions
from .effect import Effect, Source, Viscosity
from .layout import GLOBAL, LOCAL

#: the name of these kernels in the first-compile notice (util/kernel_cache.py)
KERNEL_GROUP = "cage whirl"

A_TH, A_OM, A_W, A_SK, A_SR = (LOCAL.index(n) for n in (
    "azimuth", "orbit_speed", "spin_speed", "skew_angle", "skew_rate"))
G_TC, G_WC, G_CX, G_CY, G_VX, G_VY = (GLOBAL.index(n) for n in (
    "cage_angle", "cage_speed", "cage_x", "cage_y", "cage_vx", "cage_vy"))
NL, NG = len(LOCAL), len(GLOBAL)

#: the whirl parameters, appended to the kernel's parameter vector after the flange ones
WHIRL_PARAM_NAMES = ("wh_on", "wh_mass", "wh_land", "wh_side", "wh_C", "wh_R", "wh_b",
                     "wh_visc", "wh_K", "wh_c", "wh_eps", "wh_f", "wh_mu", "wh_s0",
                     "wh_inner", "wh_Z", "wh_Rm", "wh_L", "wh_cp", "wh_Kp", "wh_cd", "wh_epsp",
                     "wh_fp", "wh_muc", "wh_spin", "wh_spinf", "wh_r", "wh_arm", "wh_cr")
(W_ON, W_MASS, W_LAND, W_SIDE, W_C, W_R, W_B, W_VISC, W_K, W_CD, W_EPS, W_F, W_MU, W_S0,
 W_INNER, W_Z, W_RM, W_L, W_CP, W_KP, W_CDP, W_EPSP, W_FP, W_MUC, W_SPIN, W_SPINF, W_RR,
 W_ARM, W_CR) = range(len(WHIRL_PARAM_NAMES))


@njit(inline="always", error_model="numpy")
def _land(yg, w_ring, PW):
    """The land law at the cage state (all zero for a roller-guided cage)."""
    if PW[W_LAND] < 0.5:
        z = 0.0
        return (z, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z, z)
    return _land_force(yg[G_CX], yg[G_CY], yg[G_VX], yg[G_VY], yg[G_WC],
                       PW[W_INNER] * w_ring, PW[W_SIDE], PW[W_C], PW[W_R], PW[W_B], PW[W_VISC],
                       PW[W_K], PW[W_CD], PW[W_EPS], PW[W_F], PW[W_MU], PW[W_S0])


@njit(inline="always", error_model="numpy")
def _sign(om, scale):
    """sg(ω) = ω / sqrt(ω² + ω₀²) and its slope (the spin friction's, physics/cage.py)."""
    rw = np.sqrt(om * om + scale * scale)
    return om / rw, scale * scale / (rw * rw * rw)


@njit(inline="always", error_model="numpy")
def _radial_pocket(yg, PW, e_r, e_t, cp, sp):
    """The pocket's radial push on its roller F_ρ (along r̂_ψ; the cage gets -F_ρ r̂_ψ) and its
    slopes along (θc, ω_c, x, y, ẋ, ẏ): the roller sits at ρ = -e_r from the pocket centre
    radially, moving at ρ̇ = -(ν_r + ω_c e_t), and meets the bar's radial lips beyond ±c_ρ/2
    (the pocket law of physics/cage.py on the radial coordinate)."""
    wc = yg[G_WC]
    vx, vy = yg[G_VX], yg[G_VY]
    nu_r = vx * cp + vy * sp
    nu_t = -vx * sp + vy * cp
    rho = -e_r
    rate = -(nu_r + wc * e_t)
    F, F_s, F_v = _pocket_force(rho, rate, PW[W_CR], PW[W_KP], PW[W_CDP], PW[W_EPSP], PW[W_FP])
    # slopes of (ρ, ρ̇) along θc, ω_c, x, y, ẋ, ẏ (de_r/dψ = e_t, de_t/dψ = -e_r, dν_r/dψ = ν_t)
    return (F, F_s * (-e_t) + F_v * (-(nu_t - wc * e_r)), F_v * (-e_t),
            F_s * (-cp) + F_v * wc * sp, F_s * (-sp) - F_v * wc * cp, F_v * (-cp), F_v * (-sp))


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def whirl_pass(yl, yg, ypg, w_ring, PW, fp, resg, out):
    """The cage centre's rows into resg and the pockets' and land's extra moment into the cage
    rotation row (after residual.global_rows); pocket end forces from fp (residual.roller_pass,
    at the displaced leads). ``out`` (3,): land force (x, y) [N] and contact push G [N]."""
    Z = yl.shape[0]
    muc = PW[W_MUC]
    Fx = 0.0
    Fy = 0.0
    dM = 0.0
    for j in range(Z):
        Fcr = fp[j, 0] + fp[j, 1]
        sg = _sign(yl[j, A_W], PW[W_SPIN])[0]
        _, _, e_r, e_t, _, cp, sp = _pocket_displacement(yg[G_CX], yg[G_CY], yg[G_VX],
                                                         yg[G_VY], yg[G_TC], yg[G_WC], j, Z)
        f = -muc * sg * Fcr
        Fx += Fcr * sp + f * cp
        Fy += -Fcr * cp + f * sp
        dM += e_r * Fcr + e_t * f
        Fr = _radial_pocket(yg, PW, e_r, e_t, cp, sp)[0]
        Fx -= Fr * cp
        Fy -= Fr * sp
    land = _land(yg, w_ring, PW)
    resg[G_WC] -= dM + land[2]
    resg[G_CX] = ypg[G_CX] - yg[G_VX]
    resg[G_CY] = ypg[G_CY] - yg[G_VY]
    resg[G_VX] = PW[W_MASS] * ypg[G_VX] - (land[0] + Fx)
    resg[G_VY] = PW[W_MASS] * ypg[G_VY] - (land[1] + Fy)
    if out.shape[0] > 0:
        out[0] = land[0]
        out[1] = land[1]
        out[2] = land[3]


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def whirl_jacobian(yl, yg, w_ring, PW, S, RS, lmap, gmap, Jd):
    """Add the whirl slopes (module docstring) to the scaled compact matrix Jd, after the
    whirl-free fill (system/jacobian_analytic.py) wrote every pattern entry."""
    Z = yl.shape[0]
    nl, ng = lmap.shape[0], gmap.shape[0]
    base = Z * nl
    lpos, gpos = compact_positions(lmap, gmap, NL, NG)
    Rm, L, arm, muc = PW[W_RM], PW[W_L], PW[W_ARM], PW[W_MUC]
    half = 0.5 * L
    x, y, vx, vy, tc, wc = yg[G_CX], yg[G_CY], yg[G_VX], yg[G_VY], yg[G_TC], yg[G_WC]
    # derivative vectors over the full (local, global) columns: pocket force F_cr, roller rows
    dFcr = np.zeros(NL + NG)
    rows_cage = np.zeros((3, NL + NG))  # d(ΔM_j + base-pocket extra, F_x,j, F_y,j)
    ext = (G_TC, G_WC, G_CX, G_CY, G_VX, G_VY)
    for j in range(Z):
        th, Om, om, sk, sr = yl[j, A_TH], yl[j, A_OM], yl[j, A_W], yl[j, A_SK], yl[j, A_SR]
        ds, dv, e_r, e_t, nu_r, cp, sp = _pocket_displacement(x, y, vx, vy, tc, wc, j, Z)
        s_a, s_b = end_positions(pocket_lead(th, tc, j, Z, Rm) + ds, sk, L)
        v_a, v_b = end_positions(pocket_lead_rate(Om, wc, Rm) + dv, sr, L)
        Fa, Fa_s, Fa_v = _pocket_force(s_a, v_a, PW[W_CP], PW[W_KP], PW[W_CDP], PW[W_EPSP],
                                       PW[W_FP])
        Fb, Fb_s, Fb_v = _pocket_force(s_b, v_b, PW[W_CP], PW[W_KP], PW[W_CDP], PW[W_EPSP],
                                       PW[W_FP])
        _, Ms_a, Ms_b, _ = _spin_friction_torque(Fa, Fb, om, PW[W_RR], muc, PW[W_SPIN],
                                                 PW[W_SPINF])
        Fcr = Fa + Fb
        sg, dsg = _sign(om, PW[W_SPIN])
        # the extra slopes of (s, v) along (θc, ω_c, x, y, ẋ, ẏ) (physics/cage_guidance.py)
        ex_s = (e_r, 0.0, sp, -cp, 0.0, 0.0)
        ex_v = (nu_r + wc * e_t, e_r, wc * cp, wc * sp, sp, -cp)
        for k in range(NL + NG):
            dFcr[k] = 0.0
            rows_cage[0, k] = 0.0
            rows_cage[1, k] = 0.0
            rows_cage[2, k] = 0.0
        # the roller rows along the extra columns, and the base cage moment's extra part
        for m in range(6):
            g = ext[m]
            dFa = Fa_s * ex_s[m] + Fa_v * ex_v[m]
            dFb = Fb_s * ex_s[m] + Fb_v * ex_v[m]
            dF = dFa + dFb
            dMs = Ms_a * dFa + Ms_b * dFb
            dMcz = half * (dFb - dFa)
            col = gpos[g]
            if col >= 0:
                c = base + col
                row = j * nl + lpos[A_OM]
                Jd[row, c] -= arm * dF * S[c] / RS[row]
                row = j * nl + lpos[A_W]
                Jd[row, c] -= dMs * S[c] / RS[row]
                if lpos[A_SR] >= 0:
                    row = j * nl + lpos[A_SR]
                    Jd[row, c] -= dMcz * S[c] / RS[row]
            rows_cage[0, NL + g] += -Rm * dF + dMs
            dFcr[NL + g] = dF
        # F_cr along the local columns and the base part of θc, ω_c (residual.roller_pass)
        dFcr[A_TH] = Rm * (Fa_s + Fb_s)
        dFcr[A_OM] = Rm * (Fa_v + Fb_v)
        dFcr[A_SK] = half * (Fb_s - Fa_s)
        dFcr[A_SR] = half * (Fb_v - Fa_v)
        dFcr[NL + G_TC] += -Rm * (Fa_s + Fb_s)
        dFcr[NL + G_WC] += -Rm * (Fa_v + Fb_v)
        # ΔM = F_cr (e_r - μ sg e_t), F_x = F_cr (sin ψ - μ sg cos ψ), F_y = F_cr (-cos ψ - μ sg sin ψ)
        kM = e_r - muc * sg * e_t
        kx = sp - muc * sg * cp
        ky = -cp - muc * sg * sp
        for k in range(NL + NG):
            rows_cage[0, k] += dFcr[k] * kM
            rows_cage[1, k] = dFcr[k] * kx
            rows_cage[2, k] = dFcr[k] * ky
        # through sg(ω) and ψ, e_r, e_t (de_r/dψ = e_t, de_t/dψ = -e_r)
        rows_cage[0, A_W] += -Fcr * muc * dsg * e_t
        rows_cage[1, A_W] += -Fcr * muc * dsg * cp
        rows_cage[2, A_W] += -Fcr * muc * dsg * sp
        rows_cage[0, NL + G_TC] += Fcr * (e_t + muc * sg * e_r)
        rows_cage[1, NL + G_TC] += Fcr * (cp + muc * sg * sp)
        rows_cage[2, NL + G_TC] += Fcr * (sp - muc * sg * cp)
        rows_cage[0, NL + G_CX] += Fcr * (cp + muc * sg * sp)
        rows_cage[0, NL + G_CY] += Fcr * (sp - muc * sg * cp)
        # scatter: global rows are own - Σ contributions
        for i in range(3):
            g_row = (G_WC, G_VX, G_VY)[i]
            if gpos[g_row] < 0:
                continue
            row = base + gpos[g_row]
            for a in range(nl):
                c = j * nl + a
                Jd[row, c] -= rows_cage[i, lmap[a]] * S[c] / RS[row]
            for b in range(ng):
                c = base + b
                Jd[row, c] -= rows_cage[i, NL + gmap[b]] * S[c] / RS[row]
    # the pockets' radial pushes: cage force -F_ρ r̂_ψ, a function of the global unknowns only
    RX = np.zeros(6)
    RY = np.zeros(6)
    for j in range(Z):
        _, _, e_r, e_t, _, cp, sp = _pocket_displacement(x, y, vx, vy, tc, wc, j, Z)
        F, d_tc, d_wc, d_x, d_y, d_vx, d_vy = _radial_pocket(yg, PW, e_r, e_t, cp, sp)
        dF = (d_tc, d_wc, d_x, d_y, d_vx, d_vy)
        for m in range(6):
            RX[m] -= dF[m] * cp
            RY[m] -= dF[m] * sp
        RX[0] += F * sp  # d(-F cos ψ)/dθc
        RY[0] -= F * cp  # d(-F sin ψ)/dθc
    for i in range(2):
        row = base + gpos[(G_VX, G_VY)[i]]
        for m in range(6):
            c = base + gpos[ext[m]]
            Jd[row, c] -= (RX[m] if i == 0 else RY[m]) * S[c] / RS[row]
    # own terms: x' - ẋ, y' - ẏ; the land's force and moment
    land = _land(yg, w_ring, PW)
    cols = (G_CX, G_CY, G_VX, G_VY, G_WC)
    for i, g_row in ((0, G_VX), (1, G_VY), (2, G_WC)):
        row = base + gpos[g_row]
        for m in range(5):
            c = base + gpos[cols[m]]
            Jd[row, c] -= land[4 + 5 * i + m] * S[c] / RS[row]
    for g_row, g_col in ((G_CX, G_VX), (G_CY, G_VY)):
        row = base + gpos[g_row]
        c = base + gpos[g_col]
        Jd[row, c] -= S[c] / RS[row]


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def land_state(yg, w_ring, PW, out):
    """Land force (x, y) [N], contact push [N] and moment on the cage [N m] at one state into
    out (4,) (outputs, power accounting)."""
    land = _land(yg, w_ring, PW)
    out[0] = land[0]
    out[1] = land[1]
    out[2] = land[3]
    out[3] = land[2]


def translating_mass(values: dict) -> float:
    """The cage's translating mass [kg] among the model's parameter ``values`` (0: no
    whirl), the mass of its centre's momentum rows."""
    return values["wh_mass"]


def whirl_parameters(scene, geometry, params: dict, cage_mass_kg: float) -> dict:
    """Values of ``WHIRL_PARAM_NAMES`` for a scene (all zero without whirl); ``params``: the
    kernel's other parameter values by name (system/model.py), whose pocket laws are shared."""
    from ..physics.cage import cage_annulus, pocket_damping
    from ..physics.cage_guidance import LAND_FRICTION

    if not scene.physics.cage_whirl:
        return {n: 0.0 for n in WHIRL_PARAM_NAMES}
    cg = scene.cage
    g = geometry
    r_i, r_o, _ = cage_annulus(g.pitch_radius_m, 2 * g.roller_radius_m, g.roller_length_m)
    land = cg.guidance != "roller"
    inner = cg.guidance == "inner-land"
    mass = cg.mass_kg if cg.mass_kg is not None else cage_mass_kg
    K = cg.pocket_stiffness_N_m
    return {
        "wh_on": 1.0, "wh_mass": mass, "wh_land": float(land), "wh_side": -1.0 if inner else 1.0,
        "wh_C": 0.5 * cg.land_clearance_m, "wh_R": r_i if inner else r_o,
        "wh_b": cg.land_width_m, "wh_visc": scene.lubricant.viscosity_Pa_s, "wh_K": K,
        "wh_c": pocket_damping(K, mass, cg.damping_ratio), "wh_eps": cg.smoothing_m,
        "wh_f": K * cg.smoothing_m, "wh_mu": LAND_FRICTION if cg.land_friction is None
        else cg.land_friction, "wh_s0": LAND_SPEED_SCALE_RAD_S, "wh_inner": float(inner),
        "wh_Z": g.rollers, "wh_Rm": g.pitch_radius_m, "wh_L": g.roller_length_m,
        "wh_cp": params["cp"], "wh_Kp": params["Kp"], "wh_cd": params["cdamp"],
        "wh_epsp": params["eps_p"], "wh_fp": params["f_p"], "wh_muc": params["mu_c"],
        "wh_spin": params["spin_scale"], "wh_spinf": params["spin_f"], "wh_r": params["r"],
        "wh_arm": g.pitch_radius_m if scene.physics.orbit == "paper" else 1.0,
        "wh_cr": cg.pocket_clearance_m,  # radial play of a roller in its pocket
    }


def whirl_values(model, t, full_l, full_g, PW) -> dict[str, np.ndarray]:
    """The whirl output variables of a run (analysis/whirl.WHIRL_VARIABLES) by name, and what
    the power accounting reads (:func:`whirl_powers`), from the unscaled full global states
    (n, NG) and this effect's parameters ``PW``."""
    PW = np.ascontiguousarray(PW)
    n = full_g.shape[0]
    land = np.zeros((n, 4))
    for i in range(n):
        land_state(np.ascontiguousarray(full_g[i]), model.ring_speed(float(t[i])), PW, land[i])
    centre = np.stack([full_g[:, GLOBAL.index("cage_x")], full_g[:, GLOBAL.index("cage_y")]],
                      axis=-1)
    velocity = np.stack([full_g[:, GLOBAL.index("cage_vx")],
                         full_g[:, GLOBAL.index("cage_vy")]], axis=-1)
    # not outputs: the land's force vector and moment and the centre's velocity, for the power
    # accounting (whirl_power)
    return {"cage_center": centre, "cage_land_force": np.hypot(land[:, 0], land[:, 1]),
            "cage_velocity": velocity, "cage_land_force_xy": land[:, :2],
            "cage_land_moment": land[:, 3]}


def whirl_powers(model, t, values, PW) -> dict[str, np.ndarray]:
    """The power terms a whirling cage adds (docs/theory.md §17; W, per sample), from the
    recorded states and the kernel's laws: ``pocket_impact`` the pockets' work at the lead
    rates of the displaced pockets (Eq. 17.1: the extra -Σ F_cr Δv) and of their radial lips
    (-Σ F_ρ ρ̇); ``pocket_friction`` the roller-bar friction's work on the cage's radial sliding
    (-Σ f (ė·r̂ + ω_c e·t̂)); ``cage_land`` the land's loss -(F·ė + T (ω_c - ω_land)); and
    ``drive_torque`` the inner ring's extra drive (the land's moment T, inner land only);
    ``PW`` this effect's parameters."""
    from ..physics.cage import pocket_force
    from ..physics.cage_guidance import pocket_displacement

    Z = model.geometry.rollers
    c = np.asarray(values["cage_center"])[:, None, :]
    v = np.asarray(values["cage_velocity"])[:, None, :]
    wc = np.asarray(values["cage_speed"], float)[:, None]
    tc = np.asarray(values["cage_angle"], float)[:, None]
    j = np.arange(Z)[None, :]
    dv = pocket_displacement(c[..., 0], c[..., 1], v[..., 0], v[..., 1], tc, wc, j, Z)[1]
    psi = tc + 2.0 * np.pi * j / Z
    cp, sp = np.cos(psi), np.sin(psi)
    e_r = c[..., 0] * cp + c[..., 1] * sp
    e_t = -c[..., 0] * sp + c[..., 1] * cp
    nu_r = v[..., 0] * cp + v[..., 1] * sp
    radial_rate = nu_r + wc * e_t  # d(e·r̂)/dt at the pocket
    F = np.asarray(values["cage_force"])
    Fcr = F[..., 0] + F[..., 1]
    om = np.asarray(values["spin_speed"])
    sg = om / np.sqrt(om * om + PW[W_SPIN] ** 2)
    f = -PW[W_MUC] * sg * Fcr
    F_rho = pocket_force(-e_r, -radial_rate, PW[W_CR], PW[W_KP], PW[W_CDP], PW[W_EPSP],
                         PW[W_FP])[0]
    land_speed = PW[W_INNER] * np.asarray(values["inner_ring_speed"], float)
    Fl = np.asarray(values["cage_land_force_xy"])
    T = np.asarray(values["cage_land_moment"])
    vc = np.asarray(values["cage_velocity"])
    return {
        "pocket_impact": -np.sum(Fcr * dv, axis=-1) + np.sum(F_rho * radial_rate, axis=-1),
        "pocket_friction": -np.sum(f * radial_rate, axis=-1),
        "cage_land": -(np.sum(Fl * vc, axis=-1) + T * (wc[:, 0] - land_speed)),
        "drive_torque": T * PW[W_INNER],
    }


def whirl_power(model, t, values, PW, P, drive) -> None:
    """A whirling cage's power terms (:func:`whirl_powers`): added to the pocket sources, the
    land's source ``cage_land``, and the land's moment appended to ``drive``."""
    extra = whirl_powers(model, t, values, PW)
    for key in ("pocket_impact", "pocket_friction"):
        P[key] = P[key] + extra[key]
    P[SOURCE.name] = extra["cage_land"]
    drive.append(extra["drive_torque"])


#: the source a whirling cage adds (docs/theory.md §17): the guiding land's film and contact,
#: -(F·ė + T (ω_c - ω_land)); its film heats half the cage, half the oil
SOURCE = Source("cage_land", "guiding land of a whirling cage: film drag, squeeze and contact "
                "friction (work of the land's force and moment on the cage)",
                (0.0, 0.0, 0.0, 0.5, 0.5))

def land_film(scene) -> tuple[str, ...]:
    """Where the cage's land film forms: between the cage and the guiding ring's land (the oil
    node for a roller-guided cage, whose land law is off)."""
    guidance = scene.cage.guidance
    ring = {"inner-land": "inner_ring", "outer-land": "outer_ring"}.get(guidance)
    return ("oil",) if ring is None else ("cage", ring)


EFFECT = Effect(
    name="cage_whirl", switch="cage_whirl", params=WHIRL_PARAM_NAMES,
    parameters=lambda scene, geometry, c: whirl_parameters(scene, geometry, c["values"],
                                                           c["cage_mass_kg"]),
    viscosity_params=(Viscosity("wh_visc", land_film),), unknowns=("cage_x", "cage_y", "cage_vx", "cage_vy"),
    passes=(whirl_pass, whirl_jacobian), sources=(SOURCE,), power=whirl_power,
    values=whirl_values, compiled_apart=True)
