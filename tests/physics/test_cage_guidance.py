"""The cage's guiding-land law (physics/cage_guidance.py, theory.md §17).

References:
- the film force against an independent quadrature of the short-bearing Reynolds equation
  (pressure ∫p dz = -μ b³ G(θ)/h³, Gümbel cavitation p ≥ 0; Ocvirk 1952), at ε̇ = 0 where the
  π-film is the exact cavitated solution: 0.2 % up to ε = 0.6 (quadrature error ~1e-6; the
  film's smooth eccentricity cap moves ε by < 1e-8 there);
- Ocvirk's load capacity and attitude angle: a cage under a constant load settles there (1e-3);
- the textbook π-film closed form with squeeze (San Andrés, notes 5, Eqs. 5.25-5.26) for
  ω̄/2 - φ̇ > 0: 0.2 %;
- the small-eccentricity limit (ε = 0.002; the next terms are O(ε)): the film as an isotropic damper -(π/2)(μ R b³ / C³) ė plus the
  cross-coupled stiffness (π/4) ω̄ μ R b³ / C³ (ẑ × e), per rim: 1 %;
- the slopes against complex-step derivatives of the law itself: 1e-9.
"""

from __future__ import annotations

import numpy as np
import pytest

from bearingdae.physics.cage_guidance import (_land_force, land_force, ocvirk_pi_film,
                                              pocket_displacement)

MU, R, B, C = 0.01, 0.03, 2.5e-3, 25e-6  # viscosity, land radius, rim width, radial clearance
K, CD, EPS = 1e7, 50.0, 1e-8  # contact: stiffness, damping, smoothing


def _film(x, y, vx, vy, wc, wl=0.0, side=1.0):
    """Land force of ONE rim with the contact switched off (the law has two rims)."""
    out = land_force(x, y, vx, vy, wc, wl, side, C, R, B, MU, 0.0, 0.0, EPS, friction=0.0,
                     force_scale_N=1e-100)
    return 0.5 * out[0], 0.5 * out[1]


def _reynolds_quadrature(eps, eps_dot, whirl, wbar, n=200_001):
    """(F_e, F_⊥) [N] on the journal, one rim: ∫ p⁺ over the clearance (module docstring)."""
    th = np.linspace(0.0, 2.0 * np.pi, n)
    h = C * (1.0 - eps * np.cos(th))
    G = C * (eps * (0.5 * wbar - whirl) * np.sin(th) - eps_dot * np.cos(th))
    P = np.clip(-MU * B**3 * G / h**3, 0.0, None)
    Fe = -R * np.trapezoid(P * np.cos(th), th)
    Fp = -R * np.trapezoid(P * np.sin(th), th)
    return Fe, Fp


@pytest.mark.parametrize("eps", [0.1, 0.3, 0.5, 0.6])
@pytest.mark.parametrize("whirl_over_wbar", [0.0, 0.25, 0.8, -0.3])
def test_film_force_is_the_cavitated_short_bearing_solution(eps, whirl_over_wbar):
    wbar = 95.0
    whirl = whirl_over_wbar * wbar
    ang = 0.7  # the line of centres, anywhere
    e = eps * C
    x, y = e * np.cos(ang), e * np.sin(ang)
    vx, vy = -whirl * y, whirl * x  # pure whirl at φ̇, ε̇ = 0
    Fx, Fy = _film(x, y, vx, vy, wbar)
    Fe = Fx * np.cos(ang) + Fy * np.sin(ang)
    Fp = -Fx * np.sin(ang) + Fy * np.cos(ang)
    Qe, Qp = _reynolds_quadrature(eps, 0.0, whirl, wbar)
    scale = np.hypot(Qe, Qp)
    assert abs(Fe - Qe) < 2e-3 * scale and abs(Fp - Qp) < 2e-3 * scale


@pytest.mark.parametrize("eps, eps_dot, whirl", [(0.2, 30.0, 10.0), (0.5, -50.0, 20.0),
                                                 (0.4, 100.0, -30.0)])
def test_film_force_matches_the_textbook_pi_film_with_squeeze(eps, eps_dot, whirl):
    wbar = 95.0
    ang = -1.2
    e = eps * C
    n = np.array([np.cos(ang), np.sin(ang)])
    m = np.array([-n[1], n[0]])
    v = eps_dot * C * n + whirl * e * m
    Fx, Fy = _film(*(e * n), *v, wbar)
    Fr, Ft = ocvirk_pi_film(eps, eps_dot, whirl, wbar, C, R, B, MU)
    got = np.array([Fx, Fy])
    want = Fr * n + Ft * m
    assert np.abs(got - want).max() < 2e-3 * np.abs(want).max()


def test_small_eccentricity_limit_is_a_damper_and_a_cross_coupled_spring():
    wbar = 95.0
    k3 = MU * R * B**3 / C**3
    e = np.array([0.002 * C, -0.001 * C])
    v = np.array([3e-5, 5e-5])
    Fx, Fy = _film(*e, *v, wbar)
    want = -0.5 * np.pi * k3 * v + 0.25 * np.pi * wbar * k3 * np.array([-e[1], e[0]])
    assert np.allclose([Fx, Fy], want, rtol=1e-2, atol=1e-2 * np.abs(want).max())


def test_inner_land_is_the_outer_law_with_the_journal_reversed():
    """The force on a cage riding on the inner ring: -F(-e, -ė) = F(e, ė) with the sum speed of
    cage and ring (module docstring)."""
    e, v = (0.3 * C, 0.2 * C), (1e-3, -2e-3)
    out = _film(*e, *v, 95.0, 200.0, side=-1.0)
    rev = _film(-e[0], -e[1], -v[0], -v[1], 95.0, 200.0, side=-1.0)
    assert np.allclose(out, [-rev[0], -rev[1]], rtol=1e-12)


@pytest.mark.parametrize("state", [
    (0.3 * C, -0.2 * C, 1e-3, 4e-4, 95.0, 0.0, 1.0),  # film
    (0.8 * C, 0.55 * C, -2e-3, 1e-3, 95.0, 0.0, 1.0),  # in contact (r > C), outer land
    (-0.7 * C, -0.75 * C, 2e-4, -1e-3, 95.0, 209.0, -1.0),  # in contact, inner land
    (1e-9, -2e-9, 1e-5, 2e-5, 95.0, 0.0, 1.0),  # near the centre
    (0.2 * C, 0.1 * C, 1e-3, 4e-3, 95.0, 0.0, 1.0),  # whirl faster than ω̄ / 2
])
def test_land_slopes_match_central_differences(state):
    x, y, vx, vy, wc, wl, side = state
    args = (side, C, R, B, MU, K, CD, EPS, K * EPS, 0.1, 1e-2)
    out = np.array(_land_force(x, y, vx, vy, wc, wl, *args))
    base = [x, y, vx, vy, wc]
    for k in range(5):
        # complex step (Squire & Trapp 1998): every operation of the law is analytic, so
        # Im f(x + i h) / h is the slope to round-off, with no cancellation
        h = 1e-30 * max(abs(base[k]), 1e-6)
        z = [complex(b) for b in base]
        z[k] += 1j * h
        ref = np.imag(np.array(_land_force(*z, wl, *args))[:3]) / h
        got = out[[4 + k, 9 + k, 14 + k]]
        assert np.allclose(got, ref, rtol=1e-9, atol=1e-12 * np.abs(out[4:]).max()), (k, got, ref)


def test_displaced_cage_moves_each_pocket_by_the_centre_along_its_tangent():
    """Δs = -e·t̂ at ψ, Δv = -ė·t̂ + ω_c e·r̂ (Eq. 17.1): a cage shifted along +x moves the
    pocket at ψ = 90° (t̂ = -x̂) back by |e|, so its roller leads by |e|; at ψ = 0 the shift is
    radial (no lead) but the pocket turning at ω_c sweeps it along t̂ at ω_c |e|."""
    Z = 4
    ds, dv = pocket_displacement(1e-5, 0.0, 0.0, 0.0, 0.0, 0.0, 1, Z)  # pocket 1 at ψ = 90°
    assert np.isclose(ds, 1e-5) and dv == 0.0
    ds, dv = pocket_displacement(1e-5, 0.0, 0.0, 0.0, 0.0, 10.0, 0, Z)  # ψ = 0: t̂ = ŷ
    assert np.isclose(ds, 0.0, atol=1e-20) and np.isclose(dv, 10.0 * 1e-5)


def test_a_cage_under_a_constant_load_settles_at_ocvirks_eccentricity_and_attitude():
    """A cage of 37 g on the outer land (two rims), turning at 95 rad/s, under a constant load
    W along -y, integrated from the centre (scipy's LSODA over 0.2 s): it settles where the short
    bearing carries W, Ocvirk's load capacity per rim
    W = (μ ω R b³ / (4 C²)) ε / (1-ε²)² sqrt(π² (1-ε²) + 16 ε²), with the attitude angle
    tan φ = π sqrt(1-ε²) / (4 ε) between the load line and the line of centres, ahead in the
    direction of rotation (e.g. Childs 1993, §2.4). ε₀ = 0.85 > 0.756: stable. Tolerances
    1e-3 on ε and 2e-3 rad on φ (the film's cap moves ε_h by 3e-4 here)."""
    from numba import njit
    from scipy.integrate import solve_ivp

    w, m, eps0 = 95.0, 0.037, 0.85
    per_rim = MU * w * R * B**3 / (4 * C**2) * eps0 / (1 - eps0**2) ** 2 * np.sqrt(
        np.pi**2 * (1 - eps0**2) + 16 * eps0**2)
    W = 2 * per_rim

    @njit
    def rhs(t, s):
        o = _land_force(s[0], s[1], s[2], s[3], w, 0.0, 1.0, C, R, B, MU, K, CD, EPS, K * EPS,
                        0.0, 1e-2)
        return np.array([s[2], s[3], o[0] / m, (o[1] - W) / m])

    sol = solve_ivp(rhs, (0.0, 0.2), [0.0, 0.0, 0.0, 0.0], method="LSODA", rtol=1e-10,
                    atol=[1e-14, 1e-14, 1e-11, 1e-11])
    assert sol.success
    x, y, vx, vy = sol.y[:, -1]
    assert np.hypot(vx, vy) < 1e-6 * w * C  # at rest
    eps = np.hypot(x, y) / C
    assert abs(eps - eps0) < 1e-3, eps
    phi = np.arctan2(x, -y)  # from the load line (-y) towards +x: ahead, rotation about +z
    assert abs(phi - np.arctan(np.pi * np.sqrt(1 - eps0**2) / (4 * eps0))) < 2e-3, phi
