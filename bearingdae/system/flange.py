"""Roller end-flange contacts in the DAE (theory.md §16): their residual terms, their analytic
Jacobian and their per-contact values for the outputs (numba).

Only a scene with flanges (``[bearing] type``) calls anything here: the kernels of
system/residual.py and system/jacobian_analytic.py test one parameter and skip it otherwise, so
the flangeless model's arithmetic (and its results, bit for bit) is what it was.

Per roller j, over its contacts c (end a/b against the inner/outer ring's flange, where one
exists; physics/flange.py for the laws and signs), with N_x, F_t, spin, skew and tilt loads:

    orbit row   -= arm Σ F_t        (arm = 1, or R_m for the paper's orbit form)
    spin row    -= Σ (-ρ F_t)
    skew row    -= Σ (-x_e F_t)
    tilt row    += Σ (-ρ N_x)        (algebraic: moments about t̂)
    axial row    = Σ N_x - k_c s     (algebraic: the roller's axial balance, new)

and globally the inner ring's axial balance F_a(t) - Σ_j Σ_inner (-N_x)... written, as the
other ring rows, ``own - Σ_j contribution_j`` with contribution_j = Σ_inner N_x (its reaction
-N_x acts on the ring). F_a(t) is the axial column of the load table (physics/loads.py, the law
of the other loads), read by the residual kernel at t and passed in; it does not depend on the
unknowns, so the Jacobian has no term of it. The inner-ring contacts' axial forces at radius
R_m - e also enter the ring's tilt rows (share (R_m - e)(-N_x) projected with cos φ, sin φ like
M_ij).

k_c is a weak axial centring stiffness (1e-6 of the contact scale Q_ref/δ_ref): it fixes the
axial position of a roller that touches no flange (inside its axial play), which the contact
laws alone leave undetermined (theory.md §16). The ring's axial row gets the same -k_c δ_a
(``fl_k_ring``) only where its axial load history reaches 0 (e.g. a load building up from 0):
there no flange holds the ring either. A load that never vanishes (every constant) leaves the
ring's balance exact, F_a - Σ N_x = 0.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..physics.flange import (flange_approach, flange_friction, flange_normal_load,
                              flange_roller_loads, flange_slip, ring_flange_axial)
from .arrayview import compact_positions
from .effect import Effect, Source
from .layout import GLOBAL, LOCAL

#: the name of these kernels in the first-compile notice (util/kernel_cache.py)
KERNEL_GROUP = "flanges"

# full-order indices (system/layout.py)
A_TH, A_OM, A_W, A_SR, A_B, A_AX = (LOCAL.index(n) for n in (
    "azimuth", "orbit_speed", "spin_speed", "skew_rate", "tilt", "axial_position"))
G_GR, G_GT, G_WR, G_WT, G_AX = (GLOBAL.index(n) for n in (
    "ring_gr", "ring_gt", "ring_wr", "ring_wt", "ring_axial"))
NPOS = 6  #: position columns a flange approach depends on (``_approach_slopes``)
NL, NG = len(LOCAL), len(GLOBAL)

#: the flange parameters, appended to the kernel's parameter vector (system/residual.py)
#: (the axial load F_a(t) is not among them: it is a column of the load table, physics/loads.py)
FLANGE_PARAM_NAMES = ("fl_on", "fl_in_a", "fl_in_b", "fl_out_a", "fl_out_b", "fl_K", "fl_cos",
                      "fl_e", "fl_half_play", "fl_mu", "fl_v", "fl_k_c", "fl_eps",
                      "fl_ring", "fl_arm", "fl_ring_dyn", "fl_Rm", "fl_L", "fl_k_ring")
#: where the flange parameters start in the kernel's parameter vector (system/residual.py)
P_FLANGE_OFFSET = 53
(F_ON, F_INA, F_INB, F_OUTA, F_OUTB, F_K, F_COS, F_E, F_H, F_MU, F_V, F_KC, F_EPS, F_RING,
 F_ARM, F_RDYN, F_RM, F_L, F_KRING) = range(len(FLANGE_PARAM_NAMES))
#: per-contact values of ``flange_state``: (Z, 4 contacts, 4); contacts in the order
#: (end a inner, end b inner, end a outer, end b outer), values (Q [N], N_x [N], V [m/s], F_t [N])
CONTACTS = (("a", "inner"), ("b", "inner"), ("a", "outer"), ("b", "outer"))


@njit(inline="always", error_model="numpy")
def _contact(c, PF, s, beta, ring_fl, w_ring, Om, om, sr):
    """Geometry and loads of contact c: (σ, ι, ρ, x_e, Q, dQ/dδ, V, F_t, dF/dQ, dF/dV);
    ``ring_fl``: the inner ring's axial displacement at its flange (``ring_flange_axial``)."""
    sigma = 1.0 if c % 2 == 0 else -1.0
    inner = 1.0 if c < 2 else 0.0
    rho = -PF[F_E] if c < 2 else PF[F_E]
    x_e = 0.5 * sigma * PF[F_L]
    d = flange_approach(sigma, inner, s, beta, rho, ring_fl, PF[F_H])
    Q, Qd = flange_normal_load(d, PF[F_COS], PF[F_K], PF[F_EPS])
    V = flange_slip(inner, w_ring, Om, om, sr, PF[F_RM], rho, x_e)
    F, FQ, FV = flange_friction(Q, V, PF[F_MU], PF[F_V])
    return sigma, inner, rho, x_e, Q, Qd, V, F, FQ, FV


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def flange_pass(yl, yg, w_ring, PF, Fa, resl, resg, contrib, out):
    """Add the flange terms to the roller rows resl and the contributions, write the ring's
    axial row (under the axial load ``Fa`` [N] at this time) into resg and, if ``out`` has rows,
    the per-contact values (``CONTACTS``)."""
    Rm, e, cosa = PF[F_RM], PF[F_E], PF[F_COS]
    dyn = PF[F_RDYN] > 0.5
    total = 0.0
    for j in range(yl.shape[0]):
        s, Om, om, sr = yl[j, A_AX], yl[j, A_OM], yl[j, A_W], yl[j, A_SR]
        th = yl[j, A_TH]
        cphi, sphi = np.cos(th), np.sin(th)
        ring_fl = ring_flange_axial(yg[G_AX], yg[G_GR], yg[G_GT], Rm - e, cphi, sphi)
        Fx = 0.0
        Ft = 0.0
        Msp = 0.0
        Msk = 0.0
        Mtl = 0.0
        ring_ax = 0.0
        for c in range(4):
            if PF[F_INA + c] < 0.5:
                continue
            sigma, inner, rho, x_e, Q, Qd, V, F, FQ, FV = _contact(
                c, PF, s, yl[j, A_B], ring_fl, w_ring, Om, om, sr)
            Nx, Fc, sp, sk, tl = flange_roller_loads(Q, F, sigma, rho, x_e, cosa)
            Fx += Nx
            Ft += Fc
            Msp += sp
            Msk += sk
            Mtl += tl
            ring_ax += inner * Nx
            if out.shape[0] > 0:
                out[j, c, 0] = Q
                out[j, c, 1] = Nx
                out[j, c, 2] = V
                out[j, c, 3] = F
        resl[j, A_OM] -= PF[F_ARM] * Ft
        resl[j, A_W] -= Msp
        resl[j, A_SR] -= Msk
        resl[j, A_B] += Mtl
        resl[j, A_AX] = Fx - PF[F_KC] * s
        contrib[j, G_AX] = ring_ax
        total += ring_ax
        share = -(Rm - e) * ring_ax  # moment share of the inner-ring axial reactions
        if dyn:
            contrib[j, G_WR] -= share * cphi
            contrib[j, G_WT] -= share * sphi
        else:
            contrib[j, G_GR] += share * cphi
            contrib[j, G_GT] += share * sphi
    resg[G_AX] = Fa - total - PF[F_KRING] * yg[G_AX] if PF[F_RING] > 0.5 else 0.0


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def flange_state(yl, yg, w_ring, PF, out):
    """Per-contact values (Q, N_x, V, F_t) of every roller into out (Z, 4, 4) (outputs)."""
    Z = yl.shape[0]
    resl = np.zeros((Z, NL))
    resg = np.zeros(NG)
    contrib = np.zeros((Z, NG))
    for j in range(Z):
        for c in range(4):
            for k in range(4):
                out[j, c, k] = 0.0
    # F_a only enters the ring's axial row, which is not among the per-contact values
    flange_pass(yl, yg, w_ring, PF, 0.0, resl, resg, contrib, out)


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def flange_jacobian(yl, yg, w_ring, PF, S, RS, lmap, gmap, mass, Jd):
    """Add d(flange terms)/dy to the scaled compact matrix Jd, after the flangeless fill
    (system/jacobian_analytic.py) wrote every pattern entry."""
    _flange_jacobian(yl, yg, w_ring, PF, S, RS, lmap, gmap, mass, Jd, False)


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def flange_jacobian_algebraic(yl, yg, w_ring, PF, S, RS, lmap, gmap, mass, Jd):
    """``flange_jacobian`` in the algebraic rows and columns only (mass 0), as
    system/jacobian_algebraic.py needs: the entries are those of the full fill, bit for bit.
    (Two entry points: a literal flag passed to one compiled function made two
    specialisations of it at a cold start.)"""
    _flange_jacobian(yl, yg, w_ring, PF, S, RS, lmap, gmap, mass, Jd, True)


@njit(inline="always", error_model="numpy")
def _flange_jacobian(yl, yg, w_ring, PF, S, RS, lmap, gmap, mass, Jd, alg_only):
    """The body of both entry points (``alg_only``: algebraic rows and columns only)."""
    Rm, e, cosa, arm = PF[F_RM], PF[F_E], PF[F_COS], PF[F_ARM]
    dyn = PF[F_RDYN] > 0.5
    Z = yl.shape[0]
    nl, ng = lmap.shape[0], gmap.shape[0]
    base = Z * nl
    lpos, gpos = compact_positions(lmap, gmap, NL, NG)
    JR = np.zeros((NL, NL + NG))
    JC = np.zeros((NG, NL + NG))
    CG = np.zeros((NG, NG))
    X = NL + G_AX  # the ring's axial column in JR, JC
    if alg_only:  # the algebraic fill writes no axial row or column: they start from zero
        _zero_axial_entries(Z, lmap, gmap, mass, Jd)
    for j in range(Z):
        JR[:, :] = 0.0
        JC[:, :] = 0.0
        s, Om, om, sr, th = yl[j, A_AX], yl[j, A_OM], yl[j, A_W], yl[j, A_SR], yl[j, A_TH]
        cphi, sphi = np.cos(th), np.sin(th)
        ring_fl = ring_flange_axial(yg[G_AX], yg[G_GR], yg[G_GT], Rm - e, cphi, sphi)
        # d(ring_fl)/d(δ_a, γ_r, γ_t, θX)
        a_x, a_gr, a_gt = 1.0, -(Rm - e) * cphi, -(Rm - e) * sphi
        a_th = -(Rm - e) * (-yg[G_GR] * sphi + yg[G_GT] * cphi)
        sg = -1.0 if dyn else 1.0
        share = 0.0
        for c in range(4):
            if PF[F_INA + c] < 0.5:
                continue
            sigma, inner, rho, x_e, Q, Qd, V, F, FQ, FV = _contact(
                c, PF, s, yl[j, A_B], ring_fl, w_ring, Om, om, sr)
            # dδ along the position columns (s, δ_a, β, γ_r, γ_t, θX), then d(Q, F, N_x)
            si = -sigma * inner
            pos = (A_AX, X, A_B, NL + G_GR, NL + G_GT, A_TH)
            dd = (sigma, si * a_x, -sigma * rho, si * a_gr, si * a_gt, si * a_th)
            for k in range(NPOS):
                dQ = Qd * dd[k]
                dF = FQ * dQ
                dN = -sigma * cosa * dQ
                col = pos[k]
                JR[A_OM, col] -= arm * dF
                JR[A_W, col] += rho * dF
                JR[A_SR, col] += x_e * dF
                JR[A_B, col] -= rho * dN
                JR[A_AX, col] += dN
                if inner > 0.5:
                    JC[G_AX, col] += dN
                    JC[G_WR if dyn else G_GR, col] += sg * (-(Rm - e)) * dN * cphi
                    JC[G_WT if dyn else G_GT, col] += sg * (-(Rm - e)) * dN * sphi
            # dF along Ω, ω, ζ (the sliding speed)
            vel = (A_OM, A_W, A_SR)
            dV = (-(Rm + rho), rho, x_e)
            for k in range(3):
                dF = FV * dV[k]
                JR[A_OM, vel[k]] -= arm * dF
                JR[A_W, vel[k]] += rho * dF
                JR[A_SR, vel[k]] += x_e * dF
            if inner > 0.5:
                share += -(Rm - e) * (-sigma * Q * cosa)
        JR[A_AX, A_AX] -= PF[F_KC]
        JC[G_WR if dyn else G_GR, A_TH] -= sg * share * sphi
        JC[G_WT if dyn else G_GT, A_TH] += sg * share * cphi
        # scatter: roller rows, then the contributions (global rows: own - Σ contrib)
        for a in range(nl):
            row = j * nl + a
            if alg_only and mass[row] != 0.0:
                continue
            fa = lmap[a]
            for b in range(nl):
                col = j * nl + b
                if not (alg_only and mass[col] != 0.0):
                    Jd[row, col] += JR[fa, lmap[b]] * S[col] / RS[row]
            for gb in range(ng):
                col = base + gb
                if not (alg_only and mass[col] != 0.0):
                    Jd[row, col] += JR[fa, NL + gmap[gb]] * S[col] / RS[row]
        for ga in range(ng):
            row = base + ga
            if alg_only and mass[row] != 0.0:
                continue
            g = gmap[ga]
            for b in range(nl):
                col = j * nl + b
                if not (alg_only and mass[col] != 0.0):
                    Jd[row, col] -= JC[g, lmap[b]] * S[col] / RS[row]
            for h in range(NG):
                CG[g, h] += JC[g, NL + h]
    CG[G_AX, G_AX] += PF[F_KRING]  # the ring's own axial centring (global row: own - Σ contrib)
    for ga in range(ng):
        row = base + ga
        if alg_only and mass[row] != 0.0:
            continue
        for gb in range(ng):
            col = base + gb
            if not (alg_only and mass[col] != 0.0):
                Jd[row, col] -= CG[gmap[ga], gmap[gb]] * S[col] / RS[row]


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def _zero_axial_entries(Z, lmap, gmap, mass, Jd):
    """Zero the algebraic block's entries in an axial row or column (roller j's own block and
    the global rows and columns): the entries ``flange_jacobian`` then adds to."""
    nl, ng = lmap.shape[0], gmap.shape[0]
    base = Z * nl
    for j in range(Z + 1):
        rows = np.arange(base, base + ng) if j == Z else np.arange(j * nl, (j + 1) * nl)
        for row in rows:
            if mass[row] != 0.0:
                continue
            row_ax = (row >= base and gmap[row - base] == G_AX) or (
                row < base and lmap[row % nl] == A_AX)
            for col in range(Jd.shape[1]):
                if mass[col] != 0.0:
                    continue
                if col < base and j < Z and col // nl != j:
                    continue
                col_ax = (col >= base and gmap[col - base] == G_AX) or (
                    col < base and lmap[col % nl] == A_AX)
                if row_ax or col_ax:
                    Jd[row, col] = 0.0


#: axial centring stiffness k_c as a fraction of the contact scale Q_ref/δ_ref (module doc)
AXIAL_CENTRING_FRACTION = 1e-6


def flange_parameters(scene, geometry, contact_stiffness_N_m: float, ring_axial: bool,
                      axial_loads_N) -> dict:
    """Values of ``FLANGE_PARAM_NAMES`` for a scene (all zero without flanges);
    ``axial_loads_N``: the load table's axial column (the ring is centred where it vanishes)."""
    from ..physics.flange import FLANGE_SLIP_SCALE_M_S, point_contact_stiffness

    fl = scene.bearing.flanges
    if fl is None:
        return {n: 0.0 for n in FLANGE_PARAM_NAMES}
    ina, inb, outa, outb = fl.present
    return {
        "fl_on": 1.0, "fl_in_a": ina, "fl_in_b": inb, "fl_out_a": outa, "fl_out_b": outb,
        "fl_K": point_contact_stiffness(1.0 / geometry.compliance_m2_N, fl.contact_radius_m),
        "fl_cos": np.cos(fl.angle_rad), "fl_e": fl.contact_height_m,
        "fl_half_play": 0.5 * fl.clearance_m, "fl_mu": fl.friction,
        "fl_v": FLANGE_SLIP_SCALE_M_S,
        "fl_k_c": AXIAL_CENTRING_FRACTION * contact_stiffness_N_m,
        "fl_eps": scene.numerics.contact_smoothing_m, "fl_ring": float(ring_axial),
        "fl_arm": geometry.pitch_radius_m if scene.physics.orbit == "paper" else 1.0,
        "fl_ring_dyn": float(scene.physics.ring == "dynamic"),
        "fl_Rm": geometry.pitch_radius_m, "fl_L": geometry.roller_length_m,
        "fl_k_ring": (AXIAL_CENTRING_FRACTION * contact_stiffness_N_m if ring_axial
                      and min(axial_loads_N) <= 0.0 <= max(axial_loads_N) else 0.0),
    }


def flange_contacts(model, t, full_l, full_g) -> np.ndarray:
    """(n, Z, 4, 4) per-contact values (Q, N_x, V, F_t) at every recorded state (unscaled full
    arrays as ``Layout.unpack`` gives them), contacts in system/flange.CONTACTS order."""
    n, Z = full_l.shape[0], full_l.shape[1]
    out = np.zeros((n, Z, 4, 4))
    PF = np.ascontiguousarray(model.params[P_FLANGE_OFFSET:])
    for i in range(n):
        flange_state(np.ascontiguousarray(full_l[i]), np.ascontiguousarray(full_g[i]),
                     model.ring_speed(float(t[i])), PF, out[i])
    return out


def flange_values(model, t, full_l, full_g, PF=None) -> dict[str, np.ndarray]:
    """The flange output variables of a run (analysis/flange.FLANGE_VARIABLES) by name, and
    ``flange_inner_friction_N`` (the inner ring's drive torque), from the unscaled full
    states; ``PF`` (unused: the model's) lets it serve as the declaration's ``values``."""
    c = flange_contacts(model, t, full_l, full_g)
    Q, Nx, V, F = c[..., 0], c[..., 1], c[..., 2], c[..., 3]
    inner, outer = (0, 1), (2, 3)  # (end a, end b) of each ring
    present = np.array(model.scene.bearing.flanges.present, bool)
    Qe = Q[..., inner] + Q[..., outer]
    # sliding speed of the end's contact carrying the larger load (where a flange exists)
    Qi = np.where(present[list(inner)], Q[..., inner], -1.0)
    Qo = np.where(present[list(outer)], Q[..., outer], -1.0)
    slip = np.where(Qi >= Qo, V[..., inner], V[..., outer])
    return {
        "flange_force": Qe,
        "flange_axial_force": np.abs(Nx[..., inner]) + np.abs(Nx[..., outer]),
        "inner_flange_axial_force": Nx[..., inner],
        "flange_slip_velocity": slip,
        "flange_friction_power": np.sum(F * V, axis=(1, 2)),
        # not an output: Σ F_t of the inner ring's contacts, for its drive torque
        # (flange_power)
        "flange_inner_friction_N": np.sum(F[..., inner], axis=(1, 2)),
        "roller_axial_position": full_l[..., LOCAL.index("axial_position")],
        "ring_axial_displacement": full_g[..., GLOBAL.index("ring_axial")],
        # the kernel's own law (physics/loads.py): what the ring's axial row balanced
        "applied_axial_load": model.loads_series(t)[:, 4],
    }


def flange_power(model, t, values, PF, P, drive) -> None:
    """The flanges' power [W] (Σ F_t V over the end-flange contacts, recorded by
    analysis/flange.py) and their drive torque (R_m - e) Σ F_t of the inner ring's contacts
    (appended to ``drive``; docs/theory.md §16)."""
    from ..physics.power import flange_drive_torque

    P[SOURCE.name] = values["flange_friction_power"]
    drive.append(flange_drive_torque(values["flange_inner_friction_N"],
                                     model.geometry.pitch_radius_m - PF[F_E]))


#: the source a bearing with flanges adds (docs/theory.md §16): friction times sliding speed,
#: heating a ring and a roller end (inner or outer: a quarter each)
SOURCE = Source("flange_friction", "roller end-flange sliding friction (slip x friction "
                "force)", (0.25, 0.25, 0.5, 0.0, 0.0))

EFFECT = Effect(
    name="flanges", switch="flange", params=FLANGE_PARAM_NAMES,
    parameters=lambda scene, geometry, c: flange_parameters(
        scene, geometry, c["contact_stiffness_N_m"], c["ring_axial"], c["axial_loads_N"]),
    unknowns=("axial_position", "ring_axial"),
    passes=(flange_pass, flange_jacobian, flange_jacobian_algebraic), sources=(SOURCE,),
    power=flange_power, drive_note=" and of the inner-ring flange friction",
    values=flange_values, compiled_apart=True)
