"""EHL rolling resistance in the DAE (theory.md §19): its residual terms and its analytic
Jacobian (numba); the outputs recompute the forces with the same law (physics/power.py).

Only a scene with ``[physics] rolling_resistance`` set to a law (``true``: Biboulet &
Houpert's) calls anything here: the kernels of
system/residual.py and system/jacobian_analytic.py test one parameter and skip it otherwise, so
the default model's arithmetic (and its results, bit for bit) is what it was.

Per slice contact c (inner, outer) the law of physics/rolling_resistance.py gives the signed
force H_c = F (Σ_c/2)/ū along the contact's rolling sum Σ_c (physics/kinematics.rolling_sums;
H_c Σ_c ≥ 0). On each surface the film's shear acts against its entrainment (force F, on the
roller with arm r about its axis, on the ring with arm R_i about the bearing axis); the inlet
pressure, normal to both surfaces, takes up the film's tangential momentum through the centres
of curvature, in the proportion of the curvatures (roller 2R'/r = 2R_race/R_m of the shear).
Per roller, with Σ over its slices:

    orbit row  -= ((R_i - r) Σ H_i - (R_o + r) Σ H_o) / R_m   (Newton's form; the paper's
                  moment form: R_i Σ H_i - R_o Σ H_o)
    spin row   -= -r (Σ H_i + Σ H_o)

and the inner ring's drive torque adds R_i Σ H_i (results; the ring's speed is prescribed).
These loads do work -Σ_c H_c Σ_c (physics/power.py, source ``rolling_resistance``): the
film's dissipation F · 2u per contact, nothing else. The skew moment of an axially uneven
rolling force is left out (the forces act in the roller's mid-plane).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..physics.kinematics import effective_radius, ring_approach, rolling_sums
from ..physics.rolling_resistance import (BIBOULET_HOUPERT, GOKSEM_HARGREAVES, ZHOU_HOEPRICH,
                                           _slice_rolling_force)
from .arrayview import c_view, compact_positions
from .effect import Effect, Source
from .layout import GLOBAL, LOCAL

A_TH, A_OM, A_W, A_SK, A_U, A_B = (LOCAL.index(n) for n in (
    "azimuth", "orbit_speed", "spin_speed", "skew_angle", "radial_position", "tilt"))
G_DR, G_DT, G_GR, G_GT = (GLOBAL.index(n) for n in ("ring_dr", "ring_dt", "ring_gr", "ring_gt"))
NL, NG = len(LOCAL), len(GLOBAL)

#: the rolling-resistance parameters, appended to the kernel's parameter vector
#: (system/residual.py); R[RR_ON] > 0.5: the effect is on
RR_PARAM_NAMES = ("rr_on", "rr_Rm", "rr_Ri", "rr_Ro", "rr_r", "rr_w", "rr_Rpi", "rr_Rpo",
                  "rr_eta0", "rr_alpha", "rr_E", "rr_beta", "rr_k", "rr_u0",
                  "rr_paper_slip", "rr_paper_orbit", "rr_wc", "rr_law", "rr_hfac", "rr_ha")
(RR_ON, RR_RM, RR_RI, RR_RO, RR_R, RR_W, RR_RPI, RR_RPO, RR_ETA, RR_ALPHA, RR_E, RR_BETA, RR_K,
 RR_U0, RR_SLIP, RR_ORBIT, RR_WC, RR_LAW, RR_HFAC, RR_HA) = range(len(RR_PARAM_NAMES))
#: the scene key of the inlet film that starves this effect's law (studies/calibrate.py fits it)
INLET_FILM_KEY = "lubricant.inlet_film_um"
#: the law's arguments after the reduced radius, in physics/rolling_resistance's order
RR_LAW_ARGS = (RR_ETA, RR_ALPHA, RR_E, RR_BETA, RR_K, RR_U0, RR_WC, RR_LAW, RR_HFAC, RR_HA)


@njit(inline="always", error_model="numpy")
def _arms(PR):
    """(a_i, a_o): the orbit row's generalised force is a_i Σ H_i + a_o Σ H_o."""
    if PR[RR_ORBIT] > 0.5:
        return PR[RR_RI], -PR[RR_RO]
    Rm, r = PR[RR_RM], PR[RR_R]
    return (PR[RR_RI] - r) / Rm, -(PR[RR_RO] + r) / Rm


@njit(inline="always", error_model="numpy")
def _rolling_sums(yl, w_ring, PR, x, out):
    """Every slice's rolling sums Σ (inner, outer) into out (Z, k, 2) (physics/kinematics.py)."""
    Ri, Ro, r = PR[RR_RI], PR[RR_RO], PR[RR_R]
    paper = PR[RR_SLIP] > 0.5
    for j in range(yl.shape[0]):
        Om, om = yl[j, A_OM], yl[j, A_W]
        tan_sk = np.tan(yl[j, A_SK]) if paper else 0.0
        for lam in range(x.shape[0]):
            out[j, lam, 0], out[j, lam, 1] = rolling_sums(
                w_ring, Om, om, effective_radius(r, x[lam], tan_sk), Ri, Ro)


def _flooded_loop(slopes: bool, law_code: float):
    """The fully flooded law ``law_code`` over every contact of a flat array (race = index
    parity), the law's code a constant of the compiled loop: branch-free, it vectorises."""
    @njit(inline="always", error_model="numpy")
    def loop(qf, sf, w, Rpi, Rpo, eta, alpha, E, beta, k, u0, wc, hfac, a, b):
        for i in range(qf.shape[0]):
            H, Hq, Hs = _slice_rolling_force(qf[i], sf[i], w, Rpo if i & 1 else Rpi, eta,
                                             alpha, E, beta, k, u0, wc, law_code, hfac, 0.0)
            if slopes:
                a[i], b[i] = Hq, Hs
            else:
                a[i] = H
    return loop


def _law_loop(slopes: bool):
    """The law over every contact of a flat array (race = index parity): loads qf, rolling
    sums sf in; H into ``a`` (the residual's) or dH/dq, dH/dΣ into ``a``, ``b`` (``slopes``,
    the Jacobian's; a constant of the compiled loop, so the other branch is not compiled).
    Each law fully flooded gets a loop with its code and the inlet film as constants
    (:func:`_flooded_loop`): branch-free, it vectorises (with them read from PR the loop ran
    scalar, at two to three times the cost). A starved contact (an inlet film) takes the
    general loop."""
    bh = _flooded_loop(slopes, BIBOULET_HOUPERT)
    gh = _flooded_loop(slopes, GOKSEM_HARGREAVES)
    zh = _flooded_loop(slopes, ZHOU_HOEPRICH)

    @njit(inline="always", error_model="numpy")
    def loop(qf, sf, PR, a, b):
        w, Rpi, Rpo, eta, alpha, E = (PR[RR_W], PR[RR_RPI], PR[RR_RPO], PR[RR_ETA],
                                      PR[RR_ALPHA], PR[RR_E])
        beta, k, u0, wc = PR[RR_BETA], PR[RR_K], PR[RR_U0], PR[RR_WC]
        code, hfac, ha = PR[RR_LAW], PR[RR_HFAC], PR[RR_HA]
        if code == BIBOULET_HOUPERT and ha == 0.0:  # (the usual law)
            bh(qf, sf, w, Rpi, Rpo, eta, alpha, E, beta, k, u0, wc, hfac, a, b)
        elif code == GOKSEM_HARGREAVES and ha == 0.0:
            gh(qf, sf, w, Rpi, Rpo, eta, alpha, E, beta, k, u0, wc, hfac, a, b)
        elif code == ZHOU_HOEPRICH and ha == 0.0:
            zh(qf, sf, w, Rpi, Rpo, eta, alpha, E, beta, k, u0, wc, hfac, a, b)
        else:
            for i in range(qf.shape[0]):
                H, Hq, Hs = _slice_rolling_force(qf[i], sf[i], w, Rpo if i & 1 else Rpi, eta,
                                                 alpha, E, beta, k, u0, wc, code, hfac, ha)
                if slopes:
                    a[i], b[i] = Hq, Hs
                else:
                    a[i] = H
    return loop


_forces = _law_loop(False)
_slopes = _law_loop(True)


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def rolling_resistance_pass(yl, w_ring, PR, x, q, resl):
    """The rolling-resistance loads of every roller into its orbit and spin rows of ``resl``,
    from the slice loads q (Z, k, 2) of the contact pass. In stages, as the contact pass: the
    rolling sums per roller, the law in one flat loop over all contacts (race = index
    parity, :func:`_law_loop`), the sums per roller."""
    H = np.empty_like(q)
    _rolling_sums(yl, w_ring, PR, x, H)
    Hf = c_view(H, (q.size,))
    _forces(c_view(q, (q.size,)), Hf, PR, Hf, Hf)
    r = PR[RR_R]
    a_i, a_o = _arms(PR)
    for j in range(yl.shape[0]):
        Hi = 0.0
        Ho = 0.0
        for lam in range(x.shape[0]):
            Hi += H[j, lam, 0]
            Ho += H[j, lam, 1]
        resl[j, A_OM] -= a_i * Hi + a_o * Ho
        resl[j, A_W] += r * (Hi + Ho)


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def rolling_resistance_jacobian(yl, yg, w_ring, PR, x, q, pr, contrib, S, RS, lmap, gmap, Jd):
    """Add the rolling resistance's slopes to the orbit and spin rows of the scaled compact
    matrix Jd, from the slice loads q and their slopes pr = dq/dδ that
    system/contact_slopes.py leaves, and (cos φ, sin φ) in contrib[:, G_DR:G_GR]."""
    Ri, Ro, r = PR[RR_RI], PR[RR_RO], PR[RR_R]
    # the law's slopes dH/dq, dH/dΣ of every contact (flat loop, as the pass)
    Hq = np.empty_like(q)
    Hs = np.empty_like(q)
    _rolling_sums(yl, w_ring, PR, x, Hs)
    n = q.size
    _slopes(c_view(q, (n,)), c_view(Hs, (n,)), PR, c_view(Hq, (n,)), c_view(Hs, (n,)))
    a_i, a_o = _arms(PR)
    paper = PR[RR_SLIP] > 0.5
    lpos, gpos = compact_positions(lmap, gmap, NL, NG)
    nl = lmap.shape[0]
    base = yl.shape[0] * nl
    dr, dt, gr, gt = yg[G_DR], yg[G_DT], yg[G_GR], yg[G_GT]
    dHi = np.zeros(NL + NG)
    dHo = np.zeros(NL + NG)
    for j in range(yl.shape[0]):
        om = yl[j, A_W]
        tan_sk = np.tan(yl[j, A_SK]) if paper else 0.0
        sec2 = 1.0 + tan_sk * tan_sk if paper else 0.0
        cphi, sphi = contrib[j, G_DR], contrib[j, G_DT]
        dHi[:] = 0.0
        dHo[:] = 0.0
        for lam in range(x.shape[0]):
            xl = x[lam]
            r_l = effective_radius(r, xl, tan_sk)
            hi_s, ho_s = Hs[j, lam, 0], Hs[j, lam, 1]
            # loads: q_i through θX, u, β and the ring; q_o through u, β (kinematics.py)
            ki = Hq[j, lam, 0] * pr[j, lam, 0]
            ko = Hq[j, lam, 1] * pr[j, lam, 1]
            drho_th = ring_approach(dr, dt, gr, gt, xl, cphi, sphi)[1]
            dHi[A_TH] += ki * drho_th
            dHi[A_U] -= ki
            dHi[A_B] -= ki * xl
            dHi[NL + G_DR] += ki * cphi
            dHi[NL + G_DT] += ki * sphi
            dHi[NL + G_GR] += ki * cphi * xl
            dHi[NL + G_GT] += ki * sphi * xl
            dHo[A_U] += ko
            dHo[A_B] += ko * xl
            # rolling sums: ∂Σ_i/∂(Ω, ω) = (-R_i, r_λ), ∂Σ_o/∂(Ω, ω) = (R_o, r_λ), ∂/∂θz = ω x sec²
            dHi[A_OM] -= hi_s * Ri
            dHi[A_W] += hi_s * r_l
            dHi[A_SK] += hi_s * om * xl * sec2
            dHo[A_OM] += ho_s * Ro
            dHo[A_W] += ho_s * r_l
            dHo[A_SK] += ho_s * om * xl * sec2
        for row_full, ci, co in ((A_OM, -a_i, -a_o), (A_W, r, r)):
            a = lpos[row_full]
            if a < 0:
                continue
            row = j * nl + a
            for b in range(NL):
                pb = lpos[b]
                if pb >= 0:
                    col = j * nl + pb
                    Jd[row, col] += (ci * dHi[b] + co * dHo[b]) * S[col] / RS[row]
            for g in (G_DR, G_DT, G_GR, G_GT):
                pg = gpos[g]
                if pg >= 0:
                    col = base + pg
                    Jd[row, col] += (ci * dHi[NL + g] + co * dHo[NL + g]) * S[col] / RS[row]


def rolling_resistance_parameters(scene, geometry) -> dict:
    """Values of ``RR_PARAM_NAMES`` for a scene (all zero without rolling resistance)."""
    from ..physics import rolling_resistance as law
    from ..physics.contact import slice_stiffness
    from ..physics.film import min_film_factor, reduced_modulus

    if not scene.physics.rolling_resistance:
        return {n: 0.0 for n in RR_PARAM_NAMES}
    g, lub = geometry, scene.lubricant
    E = reduced_modulus(g.compliance_m2_N)
    return {
        "rr_on": 1.0, "rr_Rm": g.pitch_radius_m, "rr_Ri": g.inner_race_radius_m,
        "rr_Ro": g.outer_race_radius_m, "rr_r": g.roller_radius_m, "rr_w": g.slice_width_m,
        "rr_Rpi": g.reduced_radius_inner_m, "rr_Rpo": g.reduced_radius_outer_m,
        "rr_eta0": lub.viscosity_Pa_s,
        "rr_alpha": scene.engineering.pressure_viscosity_Pa_inv,
        "rr_E": E,
        "rr_beta": lub.temperature_viscosity_K_inv, "rr_k": lub.thermal_conductivity_W_m_K,
        "rr_u0": law.ROLLING_SPEED_FLOOR_M_S,
        "rr_paper_slip": float(scene.physics.slip == "paper"),
        "rr_paper_orbit": float(scene.physics.orbit == "paper"),
        "rr_wc": law.light_load_per_length(
            slice_stiffness(g.slice_width_m, g.roller_length_m, g.compliance_m2_N),
            scene.numerics.contact_smoothing_m, g.slice_width_m),
        "rr_law": law.law_code(scene.physics.rolling_resistance),
        "rr_hfac": min_film_factor(E, scene.engineering.pressure_viscosity_Pa_inv),
        "rr_ha": lub.inlet_film_m or 0.0,
    }


def rolling_power(model, t, values, PR, P, drive) -> None:
    """The rolling resistance's power [W] (``P["rolling_resistance"]``) and its inner-ring
    drive torque R_i Σ H_i (appended to ``drive``) per sample, physics/power.py's law with
    this effect's parameters ``PR``."""
    from ..physics.power import rolling_resistance_power

    law = tuple(PR[i] for i in RR_LAW_ARGS)
    P[SOURCE.name], torque, _ = rolling_resistance_power(
        values["contact_force"], values["inner_ring_speed"], values["orbit_speed"],
        values["spin_speed"], values["skew_angle"], model.geometry.x_m,
        (PR[RR_RI], PR[RR_RO], PR[RR_R]), PR[RR_SLIP] > 0.5, PR[RR_W],
        (PR[RR_RPI], PR[RR_RPO]), law)
    drive.append(torque)


#: the source the EHL rolling resistance adds (docs/theory.md §19): the inlet's work on the
#: oil (half the oil, the rest the two surfaces)
SOURCE = Source("rolling_resistance", "EHL rolling resistance of the raceway contacts (film "
                "rolling force x twice the entrainment speed)", (0.125, 0.125, 0.25, 0.0, 0.5))

EFFECT = Effect(
    name="rolling_resistance", switch="rolling_resistance", params=RR_PARAM_NAMES,
    parameters=lambda scene, geometry, context: rolling_resistance_parameters(scene, geometry),
    viscosity_params=("rr_eta0",), temperature_params=("rr_beta",),
    passes=(rolling_resistance_pass, rolling_resistance_jacobian), sources=(SOURCE,),
    power=rolling_power, drive_note=" and the film's rolling resistance", compiled_apart=True)
