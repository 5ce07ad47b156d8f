"""Mixed lubrication in the DAE (theory.md §20): the slice tractions with the asperities' share,
their slopes for the analytic Jacobian, and the asperity tractions for the power loss (numba).

Only a scene with ``[physics] lubrication = "mixed"`` calls anything here: the contact passes of
system/residual.py and system/jacobian_analytic.py test one parameter and take their full-film
loops otherwise, so the default model computes what it did before, bit for bit.

Per slice (physics/mixed.py): the EHL traction F_EHL of the scene's law (physics/traction.py),
the film parameter λ = h_min(q / w, u) / σ of the slice's load q and entrainment speed
u = |Σ| / 2 (physics/film.py, kinematics.rolling_sums; ``residual.kinematics_pass`` leaves u
in the traction array when lubrication is mixed), the asperities' share s(λ) and

    F = (1 - s) F_EHL + s μ_b q sg_b(V)

(sg_b: the regularised sign on the boundary friction's slip scale, physics/mixed.py).

The Jacobian adds, to the EHL law's slopes, the share's along q (through λ and the Hertz
pressure's law already in F_EHL's) and along u (the roller speeds, through the rolling sums:
``jacobian_analytic.roller_blocks`` applies dF/du as it does for the slide-to-roll law).

Both first bound λ from below on each race (:func:`full_film`): where the film carries the
whole load on every slice, they compute the EHL law alone, the same numbers, at the cost of
the full-film model.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..physics.film import _MIN, min_film_factor, reduced_modulus
from ..physics.kinematics import effective_radius, rolling_sums
from ..physics.mixed import (LAMBDA_FULL_FILM, _mixed_slopes, _mixed_traction, asperity_share,
                             boundary_slip_scale, film_constants, film_parameter)
from ..physics.traction import _traction_value_paper, _traction_value_slide_roll
from .effect import Effect, Source

#: the mixed-lubrication parameters, appended to the kernel's parameter vector after the
#: whirl ones: switch, μ_b, σ [m], oil viscosity η₀ [Pa s], E' [Pa], c G^g of h_min, and the
#: boundary friction's slip scale v_b [m/s] (physics/mixed.boundary_slip_scale)
MIXED_PARAM_NAMES = ("mx_on", "mx_mub", "mx_sigma", "mx_visc", "mx_E", "mx_cmin", "mx_vb")
M_ON, M_MUB, M_SIGMA, M_VISC, M_E, M_CMIN, M_VB = range(len(MIXED_PARAM_NAMES))
#: offsets in the traction parameters the caller passes (P[P_TLAW:P_SRU0 + 1] of
#: system/residual.py: law, A, B, C, D, bracket, v₀, then the slide-to-roll A-D, u₀)
T_LAW, T_A, T_B, T_C, T_D, T_ALT, T_V, T_SA, T_SB, T_SC, T_SD, T_SU0 = range(12)


def mixed_parameters(scene, geometry) -> dict:
    """Values of ``MIXED_PARAM_NAMES`` for a scene (all zero with full-film lubrication)."""
    if scene.physics.lubrication != "mixed":
        return {n: 0.0 for n in MIXED_PARAM_NAMES}
    E = reduced_modulus(geometry.compliance_m2_N)
    e = scene.engineering
    return {"mx_on": 1.0, "mx_mub": scene.lubricant.boundary_friction,
            "mx_sigma": e.roughness_m, "mx_visc": scene.lubricant.viscosity_Pa_s, "mx_E": E,
            "mx_cmin": min_film_factor(E, e.pressure_viscosity_Pa_inv),
            "mx_vb": boundary_slip_scale(scene.traction.velocity_scale_m_s)}


@njit(inline="always", error_model="numpy")
def _race_constants(M, width, Rpi, Rpo):
    """The film parameter's constants (physics/mixed.film_constants) of the inner and the
    outer race, once per call rather than per slice."""
    sigma, visc, E, cmin = M[M_SIGMA], M[M_VISC], M[M_E], M[M_CMIN]
    return (film_constants(width, Rpi, visc, E, cmin, sigma),
            film_constants(width, Rpo, visc, E, cmin, sigma))


#: the film parameter's bound (:func:`full_film`) needs λ falling with the load and rising with
#: the speed: Pan & Hamrock's h_min ∝ W'^a U^b with a < 0 < b
assert _MIN[1] < 0.0 < _MIN[2]
#: relative margin of that bound over λ = 3: far above the round-off of the law's logarithms
#: and exponential (a few ulp, physics/elementary.py), so that a contact the bound declares in
#: full film computes λ >= 3 itself, and the share 0 exactly
FULL_FILM_MARGIN = 1e-9


@njit(inline="always", error_model="numpy")
def full_film(M, qf, ff, width, Rpi, Rpo):
    """Whether every slice contact has λ >= 3, so that its share is 0 and its traction the EHL
    law's, bit for bit: λ falls with the load and rises with the entrainment speed, so λ at a
    race's largest load and smallest speed bounds each of its contacts' from below (required
    :data:`FULL_FILM_MARGIN` above 3). False where a load or a speed is not positive (there λ
    takes the law's conventions). A contact whose load or speed is not a number has share 0
    in any case (its λ is not below 3) and takes no part. The reductions pair the two races'
    entries (race = index parity), selects only, so that the loop vectorises; then the law
    twice. A bearing in full film (λ above 3 everywhere, as bearings are designed) then pays
    for mixed lubrication only this test."""
    qi_max = qo_max = 0.0
    qi_min = qo_min = ui_min = uo_min = np.inf
    for m in range(qf.shape[0] >> 1):
        qi, qo, ui, uo = qf[2 * m], qf[2 * m + 1], ff[2 * m], ff[2 * m + 1]
        qi_max = qi if qi > qi_max else qi_max
        qo_max = qo if qo > qo_max else qo_max
        qi_min = qi if qi < qi_min else qi_min
        qo_min = qo if qo < qo_min else qo_min
        ui_min = ui if ui < ui_min else ui_min
        uo_min = uo if uo < uo_min else uo_min
    if not (qi_min > 0.0 and qo_min > 0.0 and ui_min > 0.0 and uo_min > 0.0):
        return False
    (ki0, ki1, ki2), (ko0, ko1, ko2) = _race_constants(M, width, Rpi, Rpo)
    floor = LAMBDA_FULL_FILM * (1.0 + FULL_FILM_MARGIN)
    return (film_parameter(qi_max, ui_min, ki0, ki1, ki2)[0] >= floor
            and film_parameter(qo_max, uo_min, ko0, ko1, ko2)[0] >= floor)


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def mixed_tractions(M, T, qf, pf, vf, ff, width, Rpi, Rpo):
    """The residual's tractions with mixed lubrication, every slice contact (race = index
    parity, as residual.contact_pass): in, loads qf, Hertz pressures pf, slips vf and
    entrainment speeds ff; out, tractions in ff. ``M`` = P[P_MX:], ``T`` the traction
    parameters (module constants). One loop per traction law, each branch-free (every law
    inlined, selects only), so that they vectorise as the full-film loops do; the film
    parameter's per-race constants are taken once (:func:`_race_constants`)."""
    tv = T[T_V]
    mub, vb = M[M_MUB], M[M_VB]
    if full_film(M, qf, ff, width, Rpi, Rpo):
        # the EHL law alone: residual.contact_pass's full-film loops, the values the loops
        # below give where s = 0
        if T[T_LAW] > 0.5:
            sA, sB, sC, sD, su0 = T[T_SA], T[T_SB], T[T_SC], T[T_SD], T[T_SU0]
            for i in range(qf.shape[0]):
                ff[i] = _traction_value_slide_roll(qf[i], vf[i], ff[i], tv, sA, sB, sC, sD,
                                                   su0)
        else:
            tA, tB, tC, tD, alt = T[T_A], T[T_B], T[T_C], T[T_D], T[T_ALT] > 0.5
            for i in range(qf.shape[0]):
                ff[i] = _traction_value_paper(qf[i], vf[i], pf[i], tv, tA, tB, tC, tD, alt)
        return
    (ki0, ki1, ki2), (ko0, ko1, ko2) = _race_constants(M, width, Rpi, Rpo)
    if T[T_LAW] > 0.5:
        sA, sB, sC, sD, su0 = T[T_SA], T[T_SB], T[T_SC], T[T_SD], T[T_SU0]
        for i in range(qf.shape[0]):
            u = ff[i]
            o = i & 1
            F = _traction_value_slide_roll(qf[i], vf[i], u, tv, sA, sB, sC, sD, su0)
            lam = film_parameter(qf[i], u, ko0 if o else ki0, ko1 if o else ki1,
                                 ko2 if o else ki2)[0]
            ff[i] = _mixed_traction(F, qf[i], vf[i], asperity_share(lam)[0], mub, vb)[0]
    else:
        tA, tB, tC, tD, alt = T[T_A], T[T_B], T[T_C], T[T_D], T[T_ALT] > 0.5
        for i in range(qf.shape[0]):
            u = ff[i]
            o = i & 1
            F = _traction_value_paper(qf[i], vf[i], pf[i], tv, tA, tB, tC, tD, alt)
            lam = film_parameter(qf[i], u, ko0 if o else ki0, ko1 if o else ki1,
                                 ko2 if o else ki2)[0]
            ff[i] = _mixed_traction(F, qf[i], vf[i], asperity_share(lam)[0], mub, vb)[0]


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def mixed_slopes(M, T, qf, vf, ff, o, width, Rpi, Rpo):
    """The analytic Jacobian's per-contact values with mixed lubrication: o[0..3] hold the EHL
    law's (F, dF/dV, dF/dq, dF/du) of ``contact_slopes.contact_slopes`` and become the
    mixed ones (physics/mixed._mixed_slopes); qf loads, vf slips, ff entrainment speeds."""
    if full_film(M, qf, ff, width, Rpi, Rpo):  # the EHL law's values stay, as s = 0 keeps them
        return
    mub, vb = M[M_MUB], M[M_VB]
    (ki0, ki1, ki2), (ko0, ko1, ko2) = _race_constants(M, width, Rpi, Rpo)
    for i in range(qf.shape[0]):
        q = qf[i]
        r = i & 1
        lam, lam_q, lam_u = film_parameter(q, ff[i], ko0 if r else ki0, ko1 if r else ki1,
                                           ko2 if r else ki2)
        s, s_lam = asperity_share(lam)
        o[0, i], o[1, i], o[2, i], o[3, i] = _mixed_slopes(
            o[0, i], o[1, i], o[2, i], o[3, i], q, vf[i], s, s_lam * lam_q, s_lam * lam_u,
            mub, vb)


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def asperity_loop(M, x, r, Ri, Ro, paper_slip, width, Rpi, Rpo, ring, orbit, spin, skew,
                   q, v, out_share, out_force):
    """Per sample n, roller, slice and race of a run's recorded states (ring (n,), orbit, spin,
    skew (n, Z), loads q and slips v (n, Z, k, 2)): the share s and the asperity traction
    s μ_b q sg_b(V) into ``out_share``, ``out_force``, with the entrainment speed from the
    rolling sums as residual.kinematics_pass takes it: the kernel's laws again, so that the
    power loss cannot disagree with the equations (analysis/engineering.py)."""
    mub, vb = M[M_MUB], M[M_VB]
    races = _race_constants(M, width, Rpi, Rpo)
    for n in range(q.shape[0]):
        for j in range(q.shape[1]):
            tan_sk = np.tan(skew[n, j]) if paper_slip else 0.0
            for lam_i in range(q.shape[2]):
                r_l = effective_radius(r, x[lam_i], tan_sk)
                s_i, s_o = rolling_sums(ring[n], orbit[n, j], spin[n, j], r_l, Ri, Ro)
                for race in range(2):
                    u = 0.5 * abs(s_o if race else s_i)
                    load = q[n, j, lam_i, race]
                    k0, k1, k2 = races[race]
                    lam = film_parameter(load, u, k0, k1, k2)[0]
                    s = asperity_share(lam)[0]
                    out_share[n, j, lam_i, race] = s
                    out_force[n, j, lam_i, race] = _mixed_traction(
                        0.0, load, v[n, j, lam_i, race], s, mub, vb)[1]


def asperity_tractions(model, M, ring_rad_s, orbit_rad_s, spin_rad_s, skew_rad,
                       contact_force_N, slip_m_s):
    """(share, asperity traction [N]) per (time, roller, slice, race) of a mixed-lubrication
    run (docs/theory.md §20) from its recorded states, by the kernel's laws
    (:func:`asperity_loop`); ``M`` this effect's parameters."""
    g = model.geometry
    q = np.ascontiguousarray(contact_force_N, dtype=float)
    n, Z = q.shape[:2]
    share, force = np.zeros_like(q), np.zeros_like(q)

    def per(a, shape):
        return np.ascontiguousarray(np.broadcast_to(np.asarray(a, dtype=float), shape))

    asperity_loop(np.array(M, dtype=float), model.work_array("x_m"), g.roller_radius_m,
                  g.inner_race_radius_m, g.outer_race_radius_m,
                  model.scene.physics.slip == "paper", g.slice_width_m,
                  g.reduced_radius_inner_m, g.reduced_radius_outer_m, per(ring_rad_s, (n,)),
                  per(orbit_rad_s, (n, Z)), per(spin_rad_s, (n, Z)), per(skew_rad, (n, Z)), q,
                  np.ascontiguousarray(slip_m_s, dtype=float), share, force)
    return share, force


def film_share(model, values, M):
    """The asperities' share of the raceway traction [N] per (time, roller, slice, race): it
    leaves the raceway sources (which keep the film's) for ``asperity_friction``."""
    return asperity_tractions(model, M, values["inner_ring_speed"], values["orbit_speed"],
                              values["spin_speed"], values["skew_angle"],
                              values["contact_force"], values["slip_velocity"])[1]


EFFECT = Effect(
    name="mixed_lubrication", switch="lubrication", params=MIXED_PARAM_NAMES,
    parameters=lambda scene, geometry, context: mixed_parameters(scene, geometry),
    viscosity_params=("mx_visc",), passes=(mixed_tractions, mixed_slopes),
    # Σ F_a V over the slices (docs/theory.md §20): the asperities heat the two surfaces
    # (half the rollers, a quarter each ring)
    sources=(Source("asperity_friction", "asperity contacts of mixed lubrication on both "
                    "raceways (slip x boundary friction on the asperities' share of the load)",
                    (0.25, 0.25, 0.5, 0.0, 0.0)),),
    film_share=film_share, compiled_apart=True)
