"""Cage guidance: the force of a lubricated guiding land on a whirling cage, and where a displaced
cage puts its pockets (theory.md §17).

Stage: physics (between the cage centre's state and the cage's equations of motion,
system/whirl.py). All lengths in m, speeds in m/s or rad/s, forces in N.

**Pocket geometry with a displaced cage.** Pocket j's centre sits at angle ψ = θc + 2π j / Z on
the cage's pitch circle, about the cage centre e = (x, y). Its bars are planes normal to the
pocket's tangent t̂ = (-sin ψ, cos ψ); the roller's lead along t̂ becomes

    s_j = R_m wrap(θX - ψ) - e·t̂,     e·t̂ = -x sin ψ + y cos ψ                         (17.1)
    v_j = R_m (Ω - ω_c) - ė·t̂ + ω_c e·r̂,   e·r̂ = x cos ψ + y sin ψ

(ṫ̂ = -ω_c r̂). The push F_cr of the roller on its bars (theory.md §8) acts on the cage as
-F_cr t̂ at the pocket; the spin friction of the roller on the bar as the radial force
f = -μ_c sg(ω) F_cr r̂ (the bar it touches decides the sign: front bar +, rear bar -, i.e.
the sign of -F_cr), whose moment about the roller's contact point is the cage's spin
friction moment of theory.md §8. About the cage centre the pocket's moment is that of §8 plus
e_r F_cr + e_t f (the arm shortened by the displacement: the roller touches the bar
away from the pitch circle of the displaced cage).

**Land (outer- or inner-land guidance).** The cage rides with radial clearance C on a land of
radius R and width b (each of two rims). The film force is Ocvirk's short-bearing solution of
Reynolds' equation (Ocvirk 1952, NACA TN 2808; in the whirl form of e.g. L. San Andrés,
*Modern Lubrication Theory*, notes 5, Eqs. (5.25)-(5.26), and Childs, *Turbomachinery
Rotordynamics*, 1993, §2.4): for a π-film (Gümbel condition) with eccentricity ratio ε = |e|/C,
its rate ε̇, whirl rate φ̇ of the line of centres and mean surface speed ω̄ = ω_journal + ω_bearing,

    F_e = -(μ R b³ / C²) [ 2 ε² |ω̄/2 - φ̇| / (1-ε²)² + π ε̇ (1 + 2ε²) / (2 (1-ε²)^{5/2}) ]
    F_⊥ =  (μ R b³ / C²) [ π ε (ω̄/2 - φ̇) / (2 (1-ε²)^{3/2}) + 2 ε ε̇ sg(ω̄/2 - φ̇) / (1-ε²)² ]

along the line of centres and 90° ahead of it (in the direction of rotation). The pressure occupies
the half of the clearance where the wedge term is positive; with ω̄/2 - φ̇ > 0 these are the
textbook π-film forces, with ω̄/2 - φ̇ < 0 (whirl faster than the mean speed) the film sits in
the other half, which the |·| and sg(·) express (smoothed with a speed scale s₀). The force on
the cage is the same expression in the cage's own eccentricity for an outer land (cage = journal)
and for an inner land (cage = bearing, the journal's eccentricity is -e: F(-e, -ė) = -F(e, ė)).

Regularisation: the eccentricity is taken as r = sqrt(x² + y² + δ²) (δ = 1e-4 C: the direction
of e is undefined at the centre; the film force there is -(π/2)(μ R b³/C³) ė, isotropic), and
the film's ε is capped smoothly, ε_h = ε / (1 + (ε/ε_max)^40)^(1/40), ε_max = 0.95 (ε_h = ε
within 0.03 % up to ε = 0.85, 0.947 at ε = 1): the film force stays
finite when the film closes, and there a stiff contact takes over,

    G = contact push of the pocket law (physics/cage._bar_push) at penetration r - C,

along -e/|e|, with Coulomb friction μ_L G sg(ω_c - ω_land) against the cage's surface speed.
The film's viscous drag torque is Petroff's (concentric film) T = -2π μ R³ b (ω_c - ω_land)/C
per rim. Each law returns its analytic slopes (tests/physics/test_cage_guidance.py checks them
against central differences and the film force against a quadrature of Reynolds' equation).

Kernels named ``_…`` are physics laws (physics/compiled.py: plain numpy from Python, inlined in
@njit).
"""

from __future__ import annotations

import numpy as np

from .cage import _bar_push
from .compiled import law

#: cap of the film's eccentricity ratio, ε_h = ε / (1 + (ε/ε_max)^n)^(1/n): ε_h = ε within
#: 0.03 % up to ε = 0.85, 0.947 at ε = 1, never above ε_max; past it the contact holds
FILM_ECCENTRICITY_CAP = 0.95
FILM_CAP_SHARPNESS = 40.0
#: regularisation of the eccentricity at the centre, δ / C
CENTRE_REGULARISATION = 1e-4
#: speed scale s₀ [rad/s] of the smooth |·| and sign of ω̄/2 - φ̇ and of the land slip
LAND_SPEED_SCALE_RAD_S = 1e-2
#: default land friction coefficient (boundary friction of a brass cage on steel, oil present)
LAND_FRICTION = 0.1


@law
def _pocket_displacement(cage_x_m, cage_y_m, cage_vx_m_s, cage_vy_m_s, cage_angle_rad,
                         cage_speed_rad_s, pocket_index, rollers):
    """(Δs, Δv, e_r, e_t, ν_r, cos ψ, sin ψ): the change of pocket j's lead and lead rate by the
    cage centre (Eq. 17.1, Δs = -e·t̂, Δv = -ė·t̂ + ω_c e·r̂), the centre along the pocket's r̂
    and t̂ and the centre's velocity along r̂ (slopes: ∂Δs/∂θc = e_r, ∂Δv/∂θc = ν_r + ω_c e_t,
    ∂Δv/∂ω_c = e_r, ∂Δs/∂(x, y) = (sin ψ, -cos ψ) = ∂Δv/∂(ẋ, ẏ), ∂Δv/∂(x, y) = ω_c (cos ψ,
    sin ψ))."""
    psi = cage_angle_rad + 2.0 * np.pi * pocket_index / rollers
    cp, sp = np.cos(psi), np.sin(psi)
    e_r = cage_x_m * cp + cage_y_m * sp
    e_t = -cage_x_m * sp + cage_y_m * cp
    nu_r = cage_vx_m_s * cp + cage_vy_m_s * sp
    nu_t = -cage_vx_m_s * sp + cage_vy_m_s * cp
    return -e_t, -nu_t + cage_speed_rad_s * e_r, e_r, e_t, nu_r, cp, sp


def pocket_displacement(cage_x_m, cage_y_m, cage_vx_m_s, cage_vy_m_s, cage_angle_rad,
                        cage_speed_rad_s, pocket_index, rollers):
    """Change (Δs [m], Δv [m/s]) of pocket j's lead and lead rate by the cage centre (Eq. 17.1)."""
    return _pocket_displacement(cage_x_m, cage_y_m, cage_vx_m_s, cage_vy_m_s, cage_angle_rad,
                                cage_speed_rad_s, pocket_index, rollers)[:2]


@law
def _film_polar(r_m, a_m_s, b_m_s, sum_speed_rad_s, clearance_m, speed_scale_rad_s):
    """Ocvirk π-film forces (F_e, F_⊥) per unit μ R b³ / C², at regularised eccentricity r,
    radial speed a = ṙ and tangential speed b = r φ̇, and their slopes along (r, a, b, ω̄):
    (F_e, F_⊥, Fe_r, Fe_a, Fe_b, Fe_w, Fp_r, Fp_a, Fp_b, Fp_w) (module docstring)."""
    C = clearance_m
    E = FILM_ECCENTRICITY_CAP
    eps = r_m / C
    u = (eps / E) ** FILM_CAP_SHARPNESS
    eh = eps * (1.0 + u) ** (-1.0 / FILM_CAP_SHARPNESS)
    eh_r = (1.0 + u) ** (-1.0 / FILM_CAP_SHARPNESS - 1.0) / C
    D = 1.0 - eh * eh
    D_r = -2.0 * eh * eh_r
    s = 0.5 * sum_speed_rad_s - b_m_s / r_m
    s_r = b_m_s / (r_m * r_m)
    s_b = -1.0 / r_m
    sa = np.sqrt(s * s + speed_scale_rad_s * speed_scale_rad_s)
    sg = s / sa
    dsg = speed_scale_rad_s * speed_scale_rad_s / (sa * sa * sa)
    D2 = D * D
    # A1 = -2 ε² |s| / D²
    A1 = -2.0 * eh * eh * sa / D2
    A1_r = -2.0 * (2.0 * eh * eh_r * sa + eh * eh * sg * s_r) / D2 - 2.0 * A1 * D_r / D
    A1_b = -2.0 * eh * eh * sg * s_b / D2
    A1_w = -eh * eh * sg / D2
    # A2 = -(π a / 2C) (1 + 2ε²) D^-5/2
    g2 = (1.0 + 2.0 * eh * eh) / (D2 * np.sqrt(D))
    g2_r = 4.0 * eh * eh_r / (D2 * np.sqrt(D)) - 2.5 * g2 * D_r / D
    k2 = -0.5 * np.pi / C
    A2 = k2 * a_m_s * g2
    A2_r = k2 * a_m_s * g2_r
    A2_a = k2 * g2
    # B1 = (π/2) s ε D^-3/2
    g3 = eh / (D * np.sqrt(D))
    g3_r = eh_r / (D * np.sqrt(D)) - 1.5 * g3 * D_r / D
    B1 = 0.5 * np.pi * s * g3
    B1_r = 0.5 * np.pi * (s_r * g3 + s * g3_r)
    B1_b = 0.5 * np.pi * s_b * g3
    B1_w = 0.25 * np.pi * g3
    # B2 = (2/C) a sg ε D^-2
    g4 = eh / D2
    g4_r = eh_r / D2 - 2.0 * g4 * D_r / D
    B2 = 2.0 / C * a_m_s * sg * g4
    B2_r = 2.0 / C * a_m_s * (dsg * s_r * g4 + sg * g4_r)
    B2_a = 2.0 / C * sg * g4
    B2_b = 2.0 / C * a_m_s * dsg * s_b * g4
    B2_w = 1.0 / C * a_m_s * dsg * g4
    return (A1 + A2, B1 + B2, A1_r + A2_r, A2_a, A1_b, A1_w, B1_r + B2_r, B2_a, B1_b + B2_b,
            B1_w + B2_w)


@law
def _land_force(x_m, y_m, vx_m_s, vy_m_s, cage_speed_rad_s, land_speed_rad_s, side,
                clearance_m, radius_m, width_m, viscosity_Pa_s, stiffness_N_m, damping_Ns_m,
                smoothing_m, force_scale_N, friction, speed_scale_rad_s):
    """Land force on the cage (F_x, F_y) [N], moment T [N m] about its centre, the contact push
    G [N], and the slopes of (F_x, F_y, T) along (x, y, ẋ, ẏ, ω_c):
    (Fx, Fy, T, G, Fx_x, Fx_y, Fx_vx, Fx_vy, Fx_w, Fy_x, Fy_y, Fy_vx, Fy_vy, Fy_w, T_x, T_y,
    T_vx, T_vy, T_w). ``side``: +1 outer land (the cage's outer surface, land at rest or
    turning at ``land_speed_rad_s``), -1 inner land (the cage's bore on the inner ring's land).
    Two rims of width ``width_m``: film force and drag of both (module docstring)."""
    C = clearance_m
    dlt = CENTRE_REGULARISATION * C
    r = np.sqrt(x_m * x_m + y_m * y_m + dlt * dlt)
    nx, ny = x_m / r, y_m / r
    a = nx * vx_m_s + ny * vy_m_s
    b = nx * vy_m_s - ny * vx_m_s
    # slopes of r, a, b along (x, y, vx, vy)
    r_x, r_y = nx, ny
    a_x, a_y = (vx_m_s - a * nx) / r, (vy_m_s - a * ny) / r
    b_x, b_y = (vy_m_s - b * nx) / r, (-vx_m_s - b * ny) / r
    a_vx, a_vy = nx, ny
    b_vx, b_vy = -ny, nx
    # film (two rims)
    k = 2.0 * viscosity_Pa_s * radius_m * width_m * width_m * width_m / (C * C)
    wbar = cage_speed_rad_s + land_speed_rad_s
    Fe, Fp, Fe_r, Fe_a, Fe_b, Fe_w, Fp_r, Fp_a, Fp_b, Fp_w = _film_polar(
        r, a, b, wbar, C, speed_scale_rad_s)
    Fe, Fp, Fe_r, Fe_a, Fe_b, Fe_w = k * Fe, k * Fp, k * Fe_r, k * Fe_a, k * Fe_b, k * Fe_w
    Fp_r, Fp_a, Fp_b, Fp_w = k * Fp_r, k * Fp_a, k * Fp_b, k * Fp_w
    # contact where the film closes: push G along -n; friction against the surface slip
    G, G_p, G_v = _bar_push(r - C, a, stiffness_N_m, damping_Ns_m, smoothing_m, force_scale_N)
    slip = cage_speed_rad_s - land_speed_rad_s
    sl = np.sqrt(slip * slip + speed_scale_rad_s * speed_scale_rad_s)
    sg = slip / sl
    dsg = speed_scale_rad_s * speed_scale_rad_s / (sl * sl * sl)
    mu = friction
    # total along n (radial) and m (= n rotated +90°): F_n = F_e - G, F_m = F_⊥ - side μ G sg
    Fn = Fe - G
    Fm = Fp - side * mu * G * sg
    Fn_r, Fn_a, Fn_b = Fe_r - G_p, Fe_a - G_v, Fe_b
    Fm_r = Fp_r - side * mu * G_p * sg
    Fm_a = Fp_a - side * mu * G_v * sg
    Fm_b = Fp_b
    Fn_w = Fe_w
    Fm_w = Fp_w - side * mu * G * dsg
    Fx = Fn * nx - Fm * ny
    Fy = Fn * ny + Fm * nx
    # slopes: n = (x, y)/r, dn_x/dx = (1 - nx²)/r, dn_x/dy = -nx ny / r, ...
    nxx, nxy, nyy = (1.0 - nx * nx) / r, -nx * ny / r, (1.0 - ny * ny) / r
    dFn_x = Fn_r * r_x + Fn_a * a_x + Fn_b * b_x
    dFn_y = Fn_r * r_y + Fn_a * a_y + Fn_b * b_y
    dFm_x = Fm_r * r_x + Fm_a * a_x + Fm_b * b_x
    dFm_y = Fm_r * r_y + Fm_a * a_y + Fm_b * b_y
    dFn_vx = Fn_a * a_vx + Fn_b * b_vx
    dFn_vy = Fn_a * a_vy + Fn_b * b_vy
    dFm_vx = Fm_a * a_vx + Fm_b * b_vx
    dFm_vy = Fm_a * a_vy + Fm_b * b_vy
    Fx_x = dFn_x * nx + Fn * nxx - dFm_x * ny - Fm * nxy
    Fx_y = dFn_y * nx + Fn * nxy - dFm_y * ny - Fm * nyy
    Fy_x = dFn_x * ny + Fn * nxy + dFm_x * nx + Fm * nxx
    Fy_y = dFn_y * ny + Fn * nyy + dFm_y * nx + Fm * nxy
    Fx_vx = dFn_vx * nx - dFm_vx * ny
    Fx_vy = dFn_vy * nx - dFm_vy * ny
    Fy_vx = dFn_vx * ny + dFm_vx * nx
    Fy_vy = dFn_vy * ny + dFm_vy * nx
    Fx_w = Fn_w * nx - Fm_w * ny
    Fy_w = Fn_w * ny + Fm_w * nx
    # moment about the cage centre: contact friction -R μ G sg and the film's Petroff drag
    petroff = 2.0 * 2.0 * np.pi * viscosity_Pa_s * radius_m ** 3 * width_m / C
    T = -radius_m * mu * G * sg - petroff * slip
    T_G = -radius_m * mu * sg
    T_x = T_G * (G_p * r_x + G_v * a_x)
    T_y = T_G * (G_p * r_y + G_v * a_y)
    T_vx = T_G * G_v * a_vx
    T_vy = T_G * G_v * a_vy
    T_w = -radius_m * mu * G * dsg - petroff
    return (Fx, Fy, T, G, Fx_x, Fx_y, Fx_vx, Fx_vy, Fx_w, Fy_x, Fy_y, Fy_vx, Fy_vy, Fy_w,
            T_x, T_y, T_vx, T_vy, T_w)


def land_force(x_m, y_m, vx_m_s, vy_m_s, cage_speed_rad_s, land_speed_rad_s, side,
               clearance_m, radius_m, width_m, viscosity_Pa_s, stiffness_N_m, damping_Ns_m,
               smoothing_m, friction=LAND_FRICTION, force_scale_N=None,
               speed_scale_rad_s=LAND_SPEED_SCALE_RAD_S):
    """Land force on the cage (theory.md §17): (F_x [N], F_y [N], T [N m], G [N]) and slopes;
    see ``_land_force``. ``clearance_m`` is the radial clearance C (half the diametral)."""
    f = stiffness_N_m * smoothing_m if force_scale_N is None else force_scale_N
    return _land_force(x_m, y_m, vx_m_s, vy_m_s, cage_speed_rad_s, land_speed_rad_s, side,
                       clearance_m, radius_m, width_m, viscosity_Pa_s, stiffness_N_m,
                       damping_Ns_m, smoothing_m, f, friction, speed_scale_rad_s)


def ocvirk_pi_film(eccentricity_ratio, eccentricity_rate_1_s, whirl_rad_s, sum_speed_rad_s,
                   clearance_m, radius_m, width_m, viscosity_Pa_s):
    """The textbook π-film short-bearing forces (F_r, F_t) [N] (radial, tangential; one land of
    width ``width_m``), for ω̄/2 - φ̇ > 0: the closed form the land law reduces to, unregularised
    (San Andrés, notes 5, Eqs. 5.25-5.26)."""
    e, ed = eccentricity_ratio, eccentricity_rate_1_s
    k = viscosity_Pa_s * radius_m * width_m ** 3 / clearance_m ** 2
    D = 1.0 - e * e
    w = sum_speed_rad_s - 2.0 * whirl_rad_s
    Fr = -k * (e * e * w / D ** 2 + np.pi * (1.0 + 2.0 * e * e) * ed / (2.0 * D ** 2.5))
    Ft = k * (np.pi * e * w / (4.0 * D ** 1.5) + 2.0 * e * ed / D ** 2)
    return Fr, Ft
