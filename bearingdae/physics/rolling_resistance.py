"""EHL rolling resistance of the slice contacts (docs/theory.md §19).

Pipeline: physics (pure laws). Called by the residual and Jacobian passes of
system/rolling_resistance.py (compiled inline), by physics/power.py (the power source
``rolling_resistance``, through :func:`slice_forces`, compiled too) and, on B&H's
dimensionless interface, by physics/rolling_force_laws.py (numpy), with ``[physics]
rolling_resistance`` set to a law name (``true``: ``"biboulet_houpert"``). Each law returns
its value with the analytic slopes the Jacobian needs (w.r.t. the load and the speed).

Symbols: w' = q / Δl the slice load per unit length, u the entrainment (mean rolling) speed,
R' the reduced radius, E' = 2/η the reduced modulus (physics/film.py), η₀ the viscosity, α the
pressure-viscosity coefficient, G = α E'. Biboulet & Houpert's interface (Proc. IMechE J 224
(2010) 765-775, eq. 14; "B&H"): U = 2 η₀ u / (E'R') (**the factor 2**), W = w'/(E'R'),
M = W / sqrt(U); F̃ = f / (E'R') with f the rolling force per unit length on each surface.

**Biboulet & Houpert** (``"biboulet_houpert"``, :func:`biboulet_houpert`): their eq. (42), the
fully flooded moment from the rigid-isoviscous (IVR) to the EHL regime, in force form (eqs.
14, 31: p_h b² = E'R'²(8W/π)^(3/2)/4, T̃ = F̃):

    f = K_BH sqrt(2 η₀ u w') (1 + c M^5)^(-1/10),   K_BH = 1.4 (8/π)^(3/2)/4,  c = (1.4/1.45)^10

the IVR asymptote K_BH sqrt(2 η₀ u w') (eq. 40, F̃ = 1.42 sqrt(UW)) at M -> 0 and the EHL one
(eq. 41, 1.47 U^(3/4)) at M -> ∞; fitted to their numerical solutions over L = 4-16,
M = 0.2-200. No blend of ours: one published law over the whole range. **Our
regularisation** (the one thing added): the IVR force's slope in the load, f/(2w'), is
unbounded as w' -> 0, and a roller leaving the load zone takes its slices through w' -> 0
(at 500 r/min IDA's corrector failed there). So sqrt(w') becomes w' / sqrt(w' + w_c):

    f = K_BH sqrt(2 η₀ u) w' / sqrt(w' + w_c) (1 + c M^5)^(-1/10),   w_c = q(ε) / Δl

with w_c the load per length of a slice at the contact smoothing length ε (the approach below
which a load is the regularisation's residue, §4; 12 N/m on the yang20 baseline, whose loaded
slices carry ~1e4 N/m). **Where it sits:** never above B&H's law, hence never above the IVR
asymptote; below it by the factor sqrt(w'/(w' + w_c)) ≥ 1 - w_c/(2 w'): within 0.1 % of it at
w' ≥ 500 w_c, linear in w' (slope K_BH sqrt(2 η₀ u / w_c)) below w_c
(tests/physics/test_rolling_resistance.py holds both bounds).

**Goksem & Hargreaves** (``"goksem_hargreaves"``, the law of ``true`` before B&H's; kept for
comparison, bit for bit): the rolling traction of a fully flooded Newtonian EHL line contact
with inlet shear heating (P. G. Goksem, R. A. Hargreaves, J. Lubrication Technology 100 (1978)
346-352, curve fit of their thermal solutions):

    f = (w' / G) K,    ln K = e(L) ln D - 0.162625 - ln(1 + 0.411483 L^0.707071)
    e(L) = 0.658228 + 0.0106383 L^0.3174603,    D = 11.81220746 G U_GH / W^1.5

with U_GH = η₀ u / (E'R') (half B&H's U) and L = η₀ β u² / k the thermal loading parameter (β
the temperature-viscosity coefficient of the oil, k its thermal conductivity). Isothermal
(L = 0) it is f = 4.318 E'R' (G U_GH)^0.658 W^0.0126 / G (Harris & Kotzalas, Advanced Concepts
of Bearing Technology, 5th ed., 2007, Ch. 5).

**Zhou & Hoeprich** (``"zhou_hoeprich"``, :func:`zhou_hoeprich`; J. Tribol. 113 (1991)
590-597) as B&H's eq. (39) restates it: F̃ = 18.62 U^0.648 W^0.246 G^-0.352 (isothermal).

**The two EHL fits at light load.** Their load exponents (W^0.0126, W^0.246) hold in the
elastic-piezoviscous regime they were fitted to, and would leave a slice that barely touches
with much of a loaded one's force. Each is joined to the rigid-isoviscous force of Martin's
film (1916), h₀ = 4.895 η₀ u R' / w', whose Poiseuille shear on each surface is
f_IV = 2.0796 sqrt(η₀ u w') (Reynolds's cavitation condition; integrated in
tests/physics/test_rolling_resistance.py), linear below w_c as above
(:func:`rigid_isoviscous`), by the smooth minimum f = f_EHL f_IV / sqrt(f_EHL² + f_IV²)
(**our blend**, not a published fit, :func:`_smooth_min`); with Goksem & Hargreaves this is
the law ``true`` meant before, unchanged.

**Starvation** (``lubricant.inlet_film_um`` = h_a; absent: fully flooded, no factor): every
law times B&H's eq. (44), T/T* = (S² + 162.8 S)/(S² + 193.1 S + 1257), S = H_a/H_m* = h_a/h_m*
(both films over R', so B&H's scaling and U's factor 2 cancel in the ratio), fitted by B&H to
IVR and EHL solutions alike (computed down to S = 2, extrapolated below). h_m* is each slice's
own fully flooded minimum film: Martin's IVR film and Pan & Hamrock's EHL minimum film
(physics/film.py, the film outputs' law) joined as sqrt(h_IV² + h_EHL²) (the larger where they
differ by far; B&H's own film fit was not at hand, so this joint is ours). For the two EHL
fits the same ratio is applied: B&H found it independent of the regime (IVR to EHL), and it
is a ratio of a starved to a flooded force of the same contact; that it holds for other
authors' flooded fits is our reading, stated in docs/theory.md §19.

**The slice's signed force** along its rolling sum Σ (physics/kinematics.rolling_sums,
u = |Σ|/2), as the kernels use it (:func:`_slice_rolling_force`):

    H = F(q, ū) (Σ/2) / ū,    F = f Δl,    ū = sqrt((Σ/2)² + u₀²)

ū is the entrainment speed with a smooth floor u₀ (:data:`ROLLING_SPEED_FLOOR_M_S`), so that
H and its slopes stay finite through Σ = 0 (standstill, reversal); (Σ/2)/ū is its sign.
Plain numpy from Python (broadcasting), inlined when called from compiled kernels
(physics/compiled.py)."""

from __future__ import annotations

import numpy as np
from numba import njit

from .compiled import law
from .elementary import exp_, log_
from .film import _MIN, _film_fit

#: Goksem & Hargreaves's fit (module docstring): D factor, exponent e(L) = E0 + E1 L^EL, and
#: ln K's offset and thermal term ln(1 + A L^B)
GH_D_FACTOR = 11.81220746
GH_E0, GH_E1, GH_EL = 0.658228, 0.0106383, 0.3174603
GH_OFFSET, GH_A, GH_B = 0.162625, 0.411483, 0.707071
#: smooth floor u₀ of the entrainment speed [m/s]: a rolling speed this small only occurs at
#: standstill or reversal (working speeds: m/s)
ROLLING_SPEED_FLOOR_M_S = 1e-3
#: Martin's rigid-isoviscous line contact (module docstring): f_IV = IV_FACTOR sqrt(η₀ u w'),
#: 6 √2 I_F / sqrt(C_w) with C_w = 4.895 (h₀ = C_w η₀ u R' / w') and I_F = 0.5422 the shear
#: integral (tests/physics/test_rolling_resistance.py integrates both)
IV_FACTOR = 2.0796226511
#: Biboulet & Houpert (module docstring): eq. (40)-(42) T*_IVR = BH_IVR / M_l, T*_EHL∞ =
#: BH_EHL M_l^(-3/2), blend exponent; F̃_IVR = BH_K sqrt(U W) (eq. 14: p_h b² = E'R²(8W/π)^1.5/4)
BH_IVR, BH_EHL, BH_BLEND = 1.4, 1.45, 10.0
BH_K = BH_IVR * (8.0 / np.pi) ** 1.5 / 4.0
BH_C10 = (BH_IVR / BH_EHL) ** BH_BLEND
#: B&H eq. (44): T/T* = (S² + a S) / (S² + b S + c)
BH_STARVATION = (162.8, 193.1, 1257.0)
#: Zhou & Hoeprich as B&H's eq. (39): F̃ = ZH_FACTOR U^ZH_U W^ZH_W G^ZH_G (B&H's U)
ZH_FACTOR, ZH_U, ZH_W, ZH_G = 18.62, 0.648, 0.246, -0.352
#: Martin's rigid-isoviscous minimum film h_IV = MARTIN_FILM η₀ u R' / w' (C_w of IV_FACTOR)
MARTIN_FILM = 4.895
#: the laws by the code the kernel's parameter vector carries (``rr_law``)
GOKSEM_HARGREAVES, BIBOULET_HOUPERT, ZHOU_HOEPRICH = 1.0, 2.0, 3.0
LAW_CODES = {"biboulet_houpert": BIBOULET_HOUPERT, "goksem_hargreaves": GOKSEM_HARGREAVES,
             "zhou_hoeprich": ZHOU_HOEPRICH}
_TINY = 1e-300  # floor of L (and of w') under the logarithms: L^b is then 0 to the last bit


@law
def goksem_hargreaves(load_per_length_N_m, reduced_radius_m, entrainment_speed_m_s,
                      viscosity_Pa_s, pressure_viscosity_Pa_inv, reduced_modulus_Pa,
                      temperature_viscosity_K_inv, thermal_conductivity_W_m_K):
    """(f [N/m], df/dw' [1], df/du [N s/m²]): rolling force per unit length on each surface of a
    line contact (module docstring), at load per length w' > 0 and entrainment speed u > 0.

    Exponentials and logarithms are physics/elementary.py's (plain arithmetic: the kernels'
    contact loops over them vectorise; within a few ulp of numpy's)."""
    w = np.maximum(load_per_length_N_m, _TINY)
    u = entrainment_speed_m_s
    ER = reduced_modulus_Pa * reduced_radius_m
    G = pressure_viscosity_Pa_inv * reduced_modulus_Pa
    ln_D = log_(GH_D_FACTOR * G * viscosity_Pa_s * u / ER) - 1.5 * log_(w / ER)
    L = viscosity_Pa_s * temperature_viscosity_K_inv * u * u / thermal_conductivity_W_m_K
    ln_L = log_(np.maximum(L, _TINY))
    L_e = exp_(GH_EL * ln_L)  # L^0.3174603
    L_b = exp_(GH_B * ln_L)  # L^0.707071
    e = GH_E0 + GH_E1 * L_e
    thermal = 1.0 + GH_A * L_b
    f = w / G * exp_(e * ln_D - GH_OFFSET) / thermal
    # d ln f / d ln w' = 1 - 1.5 e; d ln f / d ln u = e + ln D de/dln u - dln(thermal)/dln u,
    # with d ln L / d ln u = 2
    f_w = f / w * (1.0 - 1.5 * e)
    f_u = f / u * (e + ln_D * 2.0 * GH_EL * GH_E1 * L_e - 2.0 * GH_B * GH_A * L_b / thermal)
    return f, f_w, f_u


@law
def rigid_isoviscous(load_per_length_N_m, entrainment_speed_m_s, viscosity_Pa_s,
                     light_load_N_m):
    """(f [N/m], df/dw', df/du): the rolling force per unit length on each surface of a rigid,
    isoviscous line contact (Martin's film), f = C_IV sqrt(η₀ u) w' / sqrt(w' + w_c): Martin's
    C_IV sqrt(η₀ u w') above the light load w_c, linear in w' below it (module docstring)."""
    w = np.maximum(load_per_length_N_m, _TINY)
    root = np.sqrt(w + light_load_N_m)
    f = IV_FACTOR * np.sqrt(viscosity_Pa_s * entrainment_speed_m_s) * w / root
    # d/dw' [w' / sqrt(w' + w_c)] = (w' + 2 w_c) / (2 (w' + w_c)^1.5)
    return (f, f * (w + 2.0 * light_load_N_m) / (2.0 * w * (w + light_load_N_m)),
            0.5 * f / entrainment_speed_m_s)


@law
def _smooth_min(a, a_w, a_u, b, b_w, b_u):
    """(f, df/dw', df/du): f = a b / sqrt(a² + b²) of an EHL fit a and the rigid-isoviscous
    force b, with their slopes (**our blend**, module docstring)."""
    root = np.sqrt(a * a + b * b)
    # df/da = (b / root)³, df/db = (a / root)³: bounded ratios, finite for any a, b > 0
    da = b / root
    db = a / root
    da = da * da * da
    db = db * db * db
    return a * b / root, da * a_w + db * b_w, da * a_u + db * b_u


@law
def biboulet_houpert(load_per_length_N_m, reduced_radius_m, entrainment_speed_m_s,
                     viscosity_Pa_s, reduced_modulus_Pa, light_load_N_m):
    """(f [N/m], df/dw' [1], df/du [N s/m²]): Biboulet & Houpert's fully flooded rolling force
    per unit length (their eq. 42 with eq. 14's U = 2 η₀ u / (E'R'), module docstring),

        f = K_BH sqrt(2 η₀ u) w' / sqrt(w' + w_c) (1 + c M^5)^(-1/10),
        M = w' / sqrt(2 η₀ u E' R'),   c = (1.4/1.45)^10,   K_BH = 1.4 (8/π)^(3/2) / 4,

    with the light load w_c of **our regularisation** (0: B&H's law as published, whose
    slope in the load is unbounded at w' -> 0). Never above the IVR asymptote K_BH sqrt(2 η₀
    u w'); within w_c / (2 w') of B&H's law."""
    w = np.maximum(load_per_length_N_m, _TINY)
    two_eta_u = 2.0 * viscosity_Pa_s * entrainment_speed_m_s
    M = w / np.sqrt(two_eta_u * reduced_modulus_Pa * reduced_radius_m)
    cM5 = BH_C10 * M * M * M * M * M
    B = 1.0 + cM5
    x = cM5 / B  # d ln B / d ln M / 5
    # B^(-1/10) sqrt(2 η₀ u / (w' + w_c)): a product and one square root for the slice loops
    g = BH_K * exp_(log_(B) * (-1.0 / BH_BLEND)) * np.sqrt(two_eta_u / (w + light_load_N_m))
    # d ln f / d ln w' = 1 - w'/(2 (w' + w_c)) - x/2;  d ln f / d ln u = 1/2 + x/4
    f = g * w
    return (f, g * (1.0 - 0.5 * w / (w + light_load_N_m) - 0.5 * x),
            f / entrainment_speed_m_s * (0.5 + 0.25 * x))


@law
def zhou_hoeprich(load_per_length_N_m, reduced_radius_m, entrainment_speed_m_s,
                  viscosity_Pa_s, pressure_viscosity_Pa_inv, reduced_modulus_Pa):
    """(f [N/m], df/dw', df/du): Zhou & Hoeprich's fully flooded fit as B&H's eq. (39)
    restates it, f = E'R' 18.62 U^0.648 W^0.246 G^-0.352 with U = 2 η₀ u / (E'R') (module
    docstring)."""
    w = np.maximum(load_per_length_N_m, _TINY)
    ER = reduced_modulus_Pa * reduced_radius_m
    ln_f = (ZH_U * log_(2.0 * viscosity_Pa_s * entrainment_speed_m_s / ER)
            + ZH_W * log_(w / ER) + ZH_G * log_(pressure_viscosity_Pa_inv * reduced_modulus_Pa))
    f = ER * ZH_FACTOR * exp_(ln_f)
    return f, ZH_W * f / w, ZH_U * f / entrainment_speed_m_s


@law
def starvation_ratio(S):
    """(T/T*, d(T/T*)/dS): Biboulet & Houpert's starvation ratio at S = H_a / H_m* (eq. 44)."""
    a, b, c = BH_STARVATION
    num = S * S + a * S
    den = S * S + b * S + c
    return num / den, ((2.0 * S + a) * den - num * (2.0 * S + b)) / (den * den)


@law
def starvation(load_per_length_N_m, reduced_radius_m, entrainment_speed_m_s, viscosity_Pa_s,
               reduced_modulus_Pa, min_film_factor, inlet_film_m):
    """(T/T*, d/dw', d/du): the starvation ratio of a slice whose inlet holds the film h_a,
    at S = h_a / h_m* (module docstring: h_m* the fully flooded minimum film, Martin's
    rigid-isoviscous h_IV = 4.895 η₀ u R'/w' and Pan & Hamrock's EHL h_EHL (physics/film.py)
    joined as sqrt(h_IV² + h_EHL²)). Written as S = h_a w' / D, D = sqrt(C² + h_EHL² w'²),
    C = 4.895 η₀ u R', so that it stays finite as w' -> 0 (S -> 0)."""
    w = np.maximum(load_per_length_N_m, _TINY)
    u = entrainment_speed_m_s
    h_e = _film_fit(w, reduced_radius_m, u, viscosity_Pa_s, reduced_modulus_Pa,
                    min_film_factor, _MIN[1], _MIN[2])[0]
    C = MARTIN_FILM * viscosity_Pa_s * u * reduced_radius_m
    ew = h_e * w
    D2 = C * C + ew * ew
    S = inlet_film_m * w / np.sqrt(D2)
    r, r_S = starvation_ratio(S)
    # d ln D / d ln w' = (1 + a) h_e² w'² / D², d ln D / d ln u = (C² + b h_e² w'²) / D²
    # (a, b: the EHL film's exponents of W' and U)
    S_w = S * (1.0 - (1.0 + _MIN[1]) * ew * ew / D2) / w
    S_u = -S * (C * C + _MIN[2] * ew * ew) / (D2 * u)
    return r, r_S * S_w, r_S * S_u


@law
def rolling_force_per_length(load_per_length_N_m, reduced_radius_m, entrainment_speed_m_s,
                             viscosity_Pa_s, pressure_viscosity_Pa_inv, reduced_modulus_Pa,
                             temperature_viscosity_K_inv, thermal_conductivity_W_m_K,
                             light_load_N_m, law_code, min_film_factor, inlet_film_m):
    """(f [N/m], df/dw', df/du) of the law ``law_code`` (:data:`LAW_CODES`): Biboulet &
    Houpert's (regularised below w_c), or one of the two EHL fits blended with the rigid-
    isoviscous force (:func:`_smooth_min`); times B&H's starvation ratio with an inlet film
    h_a > 0 (:func:`starvation`; 0: fully flooded, no factor)."""
    w, R, u, eta = (load_per_length_N_m, reduced_radius_m, entrainment_speed_m_s,
                    viscosity_Pa_s)
    if law_code == BIBOULET_HOUPERT:
        f, f_w, f_u = biboulet_houpert(w, R, u, eta, reduced_modulus_Pa, light_load_N_m)
    else:
        if law_code == ZHOU_HOEPRICH:
            a, a_w, a_u = zhou_hoeprich(w, R, u, eta, pressure_viscosity_Pa_inv,
                                        reduced_modulus_Pa)
        else:
            a, a_w, a_u = goksem_hargreaves(w, R, u, eta, pressure_viscosity_Pa_inv,
                                            reduced_modulus_Pa, temperature_viscosity_K_inv,
                                            thermal_conductivity_W_m_K)
        b, b_w, b_u = rigid_isoviscous(w, u, eta, light_load_N_m)
        f, f_w, f_u = _smooth_min(a, a_w, a_u, b, b_w, b_u)
    if inlet_film_m > 0.0:
        r, r_w, r_u = starvation(w, R, u, eta, reduced_modulus_Pa, min_film_factor,
                                 inlet_film_m)
        return f * r, f_w * r + f * r_w, f_u * r + f * r_u
    return f, f_w, f_u


@law
def _slice_rolling_force(q_N, rolling_sum_m_s, slice_width_m, reduced_radius_m, viscosity_Pa_s,
                         pressure_viscosity_Pa_inv, reduced_modulus_Pa,
                         temperature_viscosity_K_inv, thermal_conductivity_W_m_K,
                         speed_floor_m_s, light_load_N_m, law_code, min_film_factor,
                         inlet_film_m):
    """(H [N], dH/dq [1], dH/dΣ [N s/m]): the slice's signed rolling force H = F (Σ/2)/ū
    (module docstring) at slice load q and rolling sum Σ (u = |Σ|/2), law
    :func:`rolling_force_per_length`."""
    half = 0.5 * rolling_sum_m_s
    ubar = np.sqrt(half * half + speed_floor_m_s * speed_floor_m_s)
    # (1/Δl: a loop constant, a product per slice)
    f, f_w, f_u = rolling_force_per_length(q_N * (1.0 / slice_width_m), reduced_radius_m, ubar,
                                           viscosity_Pa_s, pressure_viscosity_Pa_inv,
                                           reduced_modulus_Pa, temperature_viscosity_K_inv,
                                           thermal_conductivity_W_m_K, light_load_N_m,
                                           law_code, min_film_factor, inlet_film_m)
    F = f * slice_width_m
    sign = half / ubar
    # dū/dΣ = (Σ/4)/ū = sign/2; d sign/dΣ = u₀² / (2 ū³)
    dsign = 0.5 * speed_floor_m_s * speed_floor_m_s / (ubar * ubar * ubar)
    return F * sign, f_w * sign, f_u * slice_width_m * 0.5 * sign * sign + F * dsign


def law_code(name) -> float:
    """The kernel's code of a law name (:data:`LAW_CODES`; ``True``: biboulet_houpert)."""
    if name is True:
        name = "biboulet_houpert"
    if name not in LAW_CODES:
        raise ValueError(f"rolling resistance law {name!r}: one of {', '.join(LAW_CODES)}")
    return LAW_CODES[name]


def light_load_per_length(slice_stiffness: float, smoothing_m: float,
                          slice_width_m: float) -> float:
    """w_c [N/m]: the load per unit length of a slice at the contact smoothing length ε
    (physics/contact.slice_load at δ = ε), below which every law's rigid-isoviscous side turns
    linear in the load (module docstring: our regularisation)."""
    from .contact import slice_load

    return float(slice_load(smoothing_m, slice_stiffness, smoothing_m)[0]) / slice_width_m


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def _slice_force_loop(q, s, width, Rp, eta, alpha, E, beta, k, u0, wc, code, factor, ha, out):
    for i in range(q.shape[0]):
        out[i] = _slice_rolling_force(q[i], s[i], width, Rp, eta, alpha, E, beta, k, u0, wc,
                                      code, factor, ha)[0]


def slice_forces(q_N, rolling_sum_m_s, slice_width_m: float, reduced_radius_m: float,
                 law: tuple):
    """H [N] of :func:`_slice_rolling_force` for arrays of slice loads and rolling sums of one
    race (broadcast), ``law`` its arguments after the reduced radius (η₀, α, E', β, k, u₀, w_c,
    law code, min-film factor, h_a), in one compiled loop: the starvation's film law
    (physics/film._film_fit) takes scalars, and it is the kernel's arithmetic bit for bit."""
    q, s = np.broadcast_arrays(np.asarray(q_N, dtype=float),
                               np.asarray(rolling_sum_m_s, dtype=float))
    out = np.empty(q.size)
    _slice_force_loop(np.ascontiguousarray(q).reshape(-1), np.ascontiguousarray(s).reshape(-1),
                      float(slice_width_m), float(reduced_radius_m), *map(float, law), out)
    return out.reshape(q.shape)
