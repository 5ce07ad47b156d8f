"""Traction (theory.md §7), roller-cage pocket (theory.md §8, §2) and lubricant (theory.md §9) laws.

Each test names its reference: a hand-computed value, a limit, an equation of docs/theory.md, a conservation
law, or a finite difference (central, relative 1e-6) for every analytic derivative.
"""

from __future__ import annotations

import math

import numba
import numpy as np
import pytest

from bearingdae.physics import cage, lubricant, traction

A, B, C, D = 0.27, 0.43, 6.93, 0.022  # paper constants (theory.md §7)


def central_difference(f, x, h):
    """(f(x+h) - f(x-h)) / (actual step): the step is measured after rounding of x ± h."""
    xp, xm = x + h, x - h
    return (f(xp) - f(xm)) / (xp - xm)


def assert_slope(analytic, fd):
    """Relative 1e-6 per entry; entries below 1e-8 of the largest are compared absolutely at
    that level (there the finite difference is only round-off of a much larger function)."""
    fd = np.asarray(fd)
    np.testing.assert_allclose(analytic, fd, rtol=1e-6, atol=1e-8 * np.max(np.abs(fd)))


# --------------------------------------------------------------------------- traction (§7)

def test_paper_mu_at_hand_computed_point():
    """V = 1 m/s, p = 1 GPa by hand: 0.27 e^(-0.43·6.93)(1 - e^(-1/0.43)) + 0.022(1 - e^(-6.93))."""
    e_bc = math.exp(-0.43 * 6.93)  # 0.050791
    mu_std = 0.27 * e_bc * (1 - math.exp(-1 / 0.43)) + 0.022 * (1 - math.exp(-6.93))
    mu_alt = 0.27 * e_bc * (1 - math.exp(-0.43)) + 0.022 * (1 - math.exp(-6.93))
    assert mu_std == pytest.approx(0.0343536, abs=1e-7)
    assert traction.traction_coefficient_paper(1.0, 1e9) == pytest.approx(mu_std, rel=1e-12)
    assert traction.traction_coefficient_paper(-1.0, 1e9, bracket="exp(-B/p)") == pytest.approx(
        mu_alt, rel=1e-12)


@pytest.mark.parametrize("bracket", traction.BRACKETS)
def test_paper_mu_limits(bracket):
    """Limits of theory.md §7: μ(0, p) = 0; p → 0 leaves D(1 - e^(-CV)); V → ∞ tends to D; μ ≥ 0."""
    V = np.linspace(0.0, 20.0, 201)
    for p in (0.0, 1e-30, 1e3, 2e9):
        mu = traction.traction_coefficient_paper(V, np.full_like(V, p), bracket=bracket)
        assert np.all(np.isfinite(mu)) and np.all(mu >= 0.0)
        assert mu[0] == 0.0
    mu0 = traction.traction_coefficient_paper(V, 0.0 * V, bracket=bracket)
    np.testing.assert_allclose(mu0, D * (1 - np.exp(-C * V)), rtol=1e-14, atol=1e-300)
    assert traction.traction_coefficient_paper(200.0, 1e9, bracket=bracket) == pytest.approx(D)


def same_force(value, full):
    """Equal to 4 ulp (NaN where the other is NaN, infinities alike)."""
    np.testing.assert_allclose(value, full, rtol=4 * np.finfo(float).eps, atol=0.0)


@pytest.mark.parametrize("alt", [False, True])
def test_paper_mu_derivatives_match_finite_difference(alt):
    V, p = np.meshgrid([0.003, 0.2, 1.0, 4.0], [0.05, 0.6, 1.7, 3.0])
    _, dmu_dV, dmu_dp = traction._mu_paper(V, p, A, B, C, D, alt)
    fd_V = central_difference(lambda v: traction._mu_paper(v, p, A, B, C, D, alt)[0], V, 1e-6 * V)
    fd_p = central_difference(lambda q: traction._mu_paper(V, q, A, B, C, D, alt)[0], p, 1e-6 * p)
    assert_slope(dmu_dV, fd_V)
    assert_slope(dmu_dp, fd_p)


@pytest.mark.parametrize("bracket", traction.BRACKETS)
def test_traction_force_derivatives_match_finite_difference(bracket):
    """dF/dV, dF/dq (fixed p), dF/dp of F = μ q sg(V), including |V| ~ v₀ where sg bends."""
    q = np.array([3.0, 150.0, 800.0, 40.0, 75.0])
    V = np.array([-2.0, -3e-5, 4e-5, 0.02, 1.3])
    p = np.array([0.4e9, 1.1e9, 0.9e9, 2.2e9, 0.05e9])
    v0 = 1e-4

    def F(q_, V_, p_):
        return traction.traction_force(q_, V_, p_, v0, bracket=bracket)[0]

    _, dF_dV, dF_dq, dF_dp = traction.traction_force(q, V, p, v0, bracket=bracket)
    assert_slope(dF_dV, central_difference(lambda x: F(q, x, p), V, 1e-6 * abs(V)))
    assert_slope(dF_dq, central_difference(lambda x: F(x, V, p), q, 1e-6 * q))
    assert_slope(dF_dp, central_difference(lambda x: F(q, V, x), p, 1e-6 * p))


def test_traction_force_is_smooth_through_zero_slip():
    """Kink at V = 0 (theory.md §7): F odd, F(0) = 0, dF/dV continuous; far from 0, F = μ q sign V."""
    v0, q, p = 1e-4, 500.0, 1.2e9
    # An exactly mirrored grid (V[i] == -V[-1-i] bit for bit): np.linspace is not symmetric
    # to the last bit (numpy 2.4: V[25] + V[1975] = -1.6e-19), and the law is exactly odd only
    # at exactly opposite arguments.
    half = np.linspace(0.0, 5 * v0, 1001)
    V = np.concatenate([-half[:0:-1], half])
    assert np.array_equal(V, -V[::-1])
    F, dF, _, _ = traction.traction_force(q, V, p, v0)
    assert np.array_equal(F, -F[::-1])  # odd: F(-V) = -F(V) exactly (sign symmetry of the law)
    assert F[1000] == 0.0
    assert np.max(np.abs(np.diff(dF))) < 0.01 * np.max(np.abs(dF))
    far = traction.traction_force(q, -0.5, p, v0)[0]
    mu = traction.traction_coefficient_paper(0.5, p)
    assert far == pytest.approx(-mu * q, rel=1e-7)  # sg(V) = 1 - O((v₀/V)²)


def test_regularised_sign():
    """sg(v) = v/sqrt(v² + s²): odd, → ±1, slope 1/s at 0, slope matches finite difference."""
    s = 0.3
    v = np.array([-4.0, -0.1, 0.0, 0.05, 2.0])
    np.testing.assert_allclose(traction.regularised_sign(v, s), -traction.regularised_sign(-v, s))
    assert traction.regularised_sign(1e6, s) == pytest.approx(1.0, abs=1e-12)
    assert traction.regularised_sign_slope(0.0, s) == pytest.approx(1 / s)
    fd = central_difference(lambda x: traction.regularised_sign(x, s), v, 1e-6)
    np.testing.assert_allclose(traction.regularised_sign_slope(v, s), fd, rtol=1e-6)


def test_slide_roll_law():
    """μ(s) = (A + B s)e^(-Cs) + D (theory.md §7): hand value, μ(0) = A + D = 0, documented peak."""
    c = traction.SLIDE_ROLL_DEFAULTS
    s = 0.05
    hand = (c["A"] + c["B"] * s) * math.exp(-c["C"] * s) + c["D"]  # 0.0686
    mu = traction.traction_coefficient_slide_roll(0.5, 10.0, rolling_speed_floor_m_s=0.0)
    assert mu == pytest.approx(hand, rel=1e-12)
    assert traction.traction_coefficient_slide_roll(0.0, 3.0) == 0.0
    grid = np.linspace(0, 1, 100001)
    mu_grid = traction._mu_slide_roll(grid, c["A"], c["B"], c["C"], c["D"])[0]
    assert mu_grid.max() == pytest.approx(0.069, abs=1e-3)
    assert grid[mu_grid.argmax()] == pytest.approx(0.055, abs=3e-3)


def test_slide_roll_force_derivatives_match_finite_difference():
    a, b, cc, d = (traction.SLIDE_ROLL_DEFAULTS[k] for k in "ABCD")
    q = np.array([10.0, 300.0, 90.0])
    V = np.array([-0.3, 2e-5, 0.8])
    u = np.array([5.0, -2.0, 0.004])

    def F(q_, V_, u_):
        return traction._traction_force_slide_roll(q_, V_, u_, 1e-4, a, b, cc, d, 1e-3)

    _, dV, dq, du = F(q, V, u)
    assert_slope(dV, central_difference(lambda x: F(q, x, u)[0], V, 1e-6 * abs(V)))
    assert_slope(dq, central_difference(lambda x: F(x, V, u)[0], q, 1e-6 * q))
    assert_slope(du, central_difference(lambda x: F(q, V, x)[0], u, 1e-6 * abs(u)))


def test_unknown_bracket_is_rejected_with_the_choices():
    with pytest.raises(ValueError, match=r"exp\(-p/B\)"):
        traction.traction_force(1.0, 1.0, 1e9, 1e-4, bracket="1-exp(-p/B)")


def test_traction_kernels_compile_with_numba():
    """The kernels are numba-compatible: njit on float64 scalars reproduces numpy exactly-ish."""
    args = (120.0, -0.37, 1.3e9, 1e-4, A, B, C, D, True)
    np.testing.assert_allclose(numba.njit(traction._traction_force_paper)(*args),
                               traction._traction_force_paper(*args), rtol=1e-13)
    a, b, cc, d = (traction.SLIDE_ROLL_DEFAULTS[k] for k in "ABCD")
    args = (50.0, 0.2, 4.0, 1e-4, a, b, cc, d, 1e-3)
    np.testing.assert_allclose(numba.njit(traction._traction_force_slide_roll)(*args),
                               traction._traction_force_slide_roll(*args), rtol=1e-13)


@pytest.mark.parametrize("alt", [False, True])
def test_traction_value_kernels_equal_the_full_kernels_bitwise(alt):
    """Reference: F of the full kernels (value and slopes). The residual's value-only entry
    points must give the same double, also where exp_(-B C |V| / p) is exactly 0 (below
    EXP_ZERO_BELOW: unloaded slice at the pressure floor) and for NaN / inf inputs."""
    full_p, value_p = numba.njit(traction._traction_force_paper), numba.njit(
        traction._traction_value_paper)
    a, b, cc, d = (traction.SLIDE_ROLL_DEFAULTS[k] for k in "ABCD")
    full_s, value_s = numba.njit(traction._traction_force_slide_roll), numba.njit(
        traction._traction_value_slide_roll)
    loads = [0.0, 2e-7, 0.05, 19.0, 54.0, np.nan, np.inf]
    slips = [0.0, 1e-13, -3e-5, 0.02, -0.4, 7.0, np.nan, -np.inf]
    pressures = [0.0, 4e4, 2e7, 3.6e8, 1.5e9, np.nan, np.inf]
    shortcut = 0
    for q in loads:
        for v in slips:
            for p in pressures:
                args = (q, v, p, 1e-12, A, B, C, D, alt)
                # The residual's value-only kernel and the Jacobian's full kernel must give the
                # same F (same operations in the same order): to a few ulp, not to the last
                # bit, which would hold the test to one compiler's instruction selection.
                same_force(value_p(*args), full_p(*args)[0])
                x = -B * C * abs(v) / max(p * 1e-9, traction.PRESSURE_FLOOR_GPA)
                shortcut += bool(x <= traction.EXP_ZERO_BELOW)
                args = (q, v, p * 1e-9, 1e-4, a, b, cc, d, 1e-3)  # p stands in for u here
                same_force(value_s(*args), full_s(*args)[0])
    assert shortcut > 20  # the exact-zero range of exp_ was exercised


# --------------------------------------------------------------------------- cage (§8, §2)

K_POCKET, C_POCKET, EPS, CLEAR = 1e7, 5.0, 1e-8, 1e-4  # N/m, N s/m, m, m


def pocket(s, v):
    return cage.pocket_force(s, v, CLEAR, K_POCKET, C_POCKET, EPS)


def exact_pocket(s, v):
    """The unregularised law of theory.md §8, clipped so that it never pulls."""
    front = np.minimum(-K_POCKET * (s - CLEAR / 2) - C_POCKET * v, 0.0) * (s > CLEAR / 2)
    rear = np.maximum(K_POCKET * (-s - CLEAR / 2) - C_POCKET * v, 0.0) * (s < -CLEAR / 2)
    return front + rear


def test_pocket_lead_wraps_about_the_pocket_centre():
    """s_j = R_m wrap(θX - θc - 2πj/Z) (theory.md §8, j from 0), wrapped to (-π, π]."""
    Rm, Z = 0.0225, 20
    theta_c = 0.3
    for j in (0, 7, 19):
        centre = theta_c + 2 * np.pi * j / Z
        assert cage.pocket_lead(centre, theta_c, j, Z, Rm) == pytest.approx(0.0, abs=1e-15)
        assert cage.pocket_lead(centre + 1e-3 + 4 * np.pi, theta_c, j, Z, Rm) == pytest.approx(
            Rm * 1e-3, rel=1e-9)
        assert cage.pocket_lead(centre - 2e-3 - 2 * np.pi, theta_c, j, Z, Rm) == pytest.approx(
            -Rm * 2e-3, rel=1e-9)
    a = np.linspace(-9.0, 9.0, 1001)
    w = cage.wrap_angle(a)
    assert np.all((w > -np.pi) & (w <= np.pi))
    np.testing.assert_allclose(np.cos(w), np.cos(a), atol=1e-12)
    assert cage.wrap_angle(np.pi) == np.pi and cage.wrap_angle(-np.pi) == np.pi


def test_end_positions():
    """s_a = s - (L/2)θz (end a, x = +L/2), s_b = s + (L/2)θz (theory.md §8)."""
    s_a, s_b = cage.end_positions(1e-5, 2e-3, 0.0255)
    assert s_a == pytest.approx(1e-5 - 0.01275 * 2e-3)
    assert s_b == pytest.approx(1e-5 + 0.01275 * 2e-3)


@pytest.mark.parametrize("s", [CLEAR / 2 + 1e-6, CLEAR / 2 + 3e-5, -CLEAR / 2 - 2e-6])
@pytest.mark.parametrize("v", [-0.2, 0.0, 0.05])
def test_pocket_force_matches_exact_law_in_contact(s, v):
    """|δ| >> ε, |F| >> f: the regularised force is theory.md §8's -K(s - c_p/2) - c v (front) or
    +K(-s - c_p/2) - c v (rear), up to K ε²/(4δ) (smooth penetration) + f²/(4|F|) (smooth clip),
    f = K ε."""
    delta = abs(s) - CLEAR / 2
    exact = exact_pocket(s, v)
    error_bound = K_POCKET * EPS**2 / (4 * delta) + (K_POCKET * EPS) ** 2 / (4 * abs(exact))
    assert pocket(s, v)[0] == pytest.approx(exact, rel=1e-9, abs=1.01 * error_bound)


def test_pocket_force_dead_band_and_never_pulls():
    """In the dead band F ≈ 0 (tail (ε/2δ)² f/2 per bar); leaving a bar faster than the spring
    relaxes, F stays a push (the exact law's clip), never a pull."""
    s = np.linspace(-0.45 * CLEAR, 0.45 * CLEAR, 101)
    gap = CLEAR / 2 - np.abs(s)
    tail = (EPS / (2 * gap)) ** 2 * K_POCKET * EPS  # both bars, generous
    assert np.all(np.abs(pocket(s, 0.3)[0]) < tail)
    assert abs(pocket(0.0, 0.3)[0]) < 1e-12
    front = pocket(CLEAR / 2 + 1e-7, -10.0)[0]  # K δ = 1 N, c v = -50 N: exact law gives 0
    rear = pocket(-CLEAR / 2 - 1e-7, 10.0)[0]
    assert -1e-3 < front <= 0.0 and 0.0 <= rear < 1e-3
    v = np.linspace(-20, 20, 401)
    assert np.all(pocket(CLEAR / 2 + 2e-6, v)[0] <= 0.0)
    assert np.all(pocket(-CLEAR / 2 - 2e-6, v)[0] >= 0.0)


def test_pocket_force_is_smooth_across_the_bar_and_the_clip():
    """Kinks of the exact law (theory.md §8) at s = c_p/2 and where -K δ - c v changes sign: the
    regularised F and its slopes vary continuously (no jump of order K or c between grid points
    ε/200 or f/200 apart), and it approaches the exact law away from the kinks. The damping
    switching on over ε adds up to c v/(2ε) to the stiffness at onset (module docstring)."""
    v_in = 0.01
    s = CLEAR / 2 + np.linspace(-20 * EPS, 20 * EPS, 8001)
    F, dFds, _ = pocket(s, v_in)
    lipschitz = K_POCKET + C_POCKET * v_in / (2 * EPS)
    assert np.max(np.abs(np.diff(F))) < 1.01 * lipschitz * (s[1] - s[0])
    assert np.max(np.abs(np.diff(dFds))) < 0.02 * lipschitz
    far = np.abs(s - CLEAR / 2) > 10 * EPS
    # error K ε²/(4δ) ≤ K ε/40 at δ = 10 ε, plus f²/(4|F|) from the clip
    np.testing.assert_allclose(F[far], exact_pocket(s[far], v_in), atol=0.03 * K_POCKET * EPS)
    f = K_POCKET * EPS
    delta = 1e-6
    v_clip = -K_POCKET * delta / C_POCKET  # -K δ - c v = 0 here
    v = v_clip + np.linspace(-20, 20, 8001) * f / C_POCKET
    F, _, dFdv = pocket(CLEAR / 2 + delta, v)
    assert np.max(np.abs(np.diff(F))) < 1.01 * C_POCKET * (v[1] - v[0])
    assert np.max(np.abs(np.diff(dFdv))) < 0.02 * C_POCKET


@pytest.mark.parametrize("s", [0.0, CLEAR / 2 - 3 * EPS, CLEAR / 2, CLEAR / 2 + 2 * EPS,
                               CLEAR / 2 + 1e-6, -CLEAR / 2 + EPS, -CLEAR / 2 - 4e-6])
@pytest.mark.parametrize("v", [-0.3, 0.0, 0.2, -2.0])
def test_pocket_force_derivatives_match_finite_difference(s, v):
    F, dFds, dFdv = pocket(s, v)
    fd_s = central_difference(lambda x: pocket(x, v)[0], s, 1e-4 * EPS)
    fd_v = central_difference(lambda x: pocket(s, x)[0], v, 1e-6 * max(abs(v), 1e-3))
    assert dFds == pytest.approx(fd_s, rel=1e-6, abs=1e-9 * K_POCKET)
    assert dFdv == pytest.approx(fd_v, rel=1e-6, abs=1e-9 * C_POCKET)


def test_pocket_loads_and_virtual_work():
    """F_cr = F_a + F_b, M_cz = (L/2)(F_b - F_a) = Σ_e F_e ∂s_e/∂θz (virtual work, theory.md §8),
    spin friction -r μ_c(|F_a| + |F_b|) sign(ω) once |ω| >> ω₀."""
    L, r, Rm, mu_c = 0.0255, 0.002, 0.0225, 0.002
    Fa, Fb, w = -3.0, 0.5, 400.0
    f_cr, m_cz, m_spin, m_cage = cage.pocket_loads(Fa, Fb, w, L, r, Rm, mu_c)
    assert f_cr == pytest.approx(-2.5)
    h = 1e-7  # virtual skew
    sa0, sb0 = cage.end_positions(0.0, 0.0, L)
    sa1, sb1 = cage.end_positions(0.0, h, L)
    assert m_cz == pytest.approx(Fa * (sa1 - sa0) / h + Fb * (sb1 - sb0) / h, rel=1e-9)
    assert m_spin == pytest.approx(-r * mu_c * 3.5, rel=1e-6)
    assert cage.pocket_loads(Fa, Fb, -w, L, r, Rm, mu_c)[2] == pytest.approx(-m_spin)
    assert cage.pocket_loads(0.0, 0.0, w, L, r, Rm, mu_c)[2] == 0.0


@pytest.mark.parametrize("Fa,Fb,w", [(-3.0, 0.5, 400.0), (2.0, 1e-3, -1e-3), (0.0, -7.0, 0.02)])
def test_pocket_interaction_conserves_angular_momentum_about_X(Fa, Fb, w):
    """theory.md §8: the pocket forces are internal to rollers + cage. Roller: d/dt(m R_m² Ω) =
    R_m F_cr and, ω > 0 being spin about -X, d/dt(-I_x ω) = -M_spin; cage: M_cage. Sum = 0."""
    L, r, Rm, mu_c = 0.0255, 0.002, 0.0225, 0.002
    f_cr, _, m_spin, m_cage = cage.pocket_loads(Fa, Fb, w, L, r, Rm, mu_c)
    assert Rm * f_cr - m_spin + m_cage == pytest.approx(0.0, abs=1e-15)
    assert Rm * f_cr + (-Rm * f_cr) == 0.0  # orbit torque on roller vs cage reaction


@pytest.mark.parametrize("Fa,Fb,w", [(-3.0, 0.4, 5e-3), (1e-6, -2e-6, -300.0)])
def test_spin_friction_derivatives_match_finite_difference(Fa, Fb, w):
    """M = -r μ_c (|F_a| + |F_b|) sg(ω) with smooth |F|: slopes by central differences,
    including |F| ~ f = 1e-6 N and |ω| ~ ω₀ = 1e-2 rad/s where the smoothing acts."""
    args = (0.002, 0.002, 1e-2, 1e-6)  # r, μ_c, ω₀, f

    def M(a, b, x):
        return cage._spin_friction_torque(a, b, x, *args)[0]

    _, dFa, dFb, dw = cage._spin_friction_torque(Fa, Fb, w, *args)
    assert dFa == pytest.approx(central_difference(lambda x: M(x, Fb, w), Fa, 1e-6 * abs(Fa)),
                                rel=1e-6)
    assert dFb == pytest.approx(central_difference(lambda x: M(Fa, x, w), Fb, 1e-6 * abs(Fb)),
                                rel=1e-6)
    assert dw == pytest.approx(central_difference(lambda x: M(Fa, Fb, x), w, 1e-6 * abs(w)),
                               rel=1e-6)


def test_cage_mass_inertia_against_hand_formula():
    """theory.md §2 cage: brass annulus of thickness 0.6 D_w on the pitch circle, width L + 0.5 D_w,
    minus Z box pockets (D_w + c_p) × L × t. Hand numbers for yang20 (R_m = 22.5 mm, D_w = 4 mm,
    L = 25.5 mm, Z = 20, c_p = 0.1 mm)."""
    Rm, Dw, L, Z, cp, rho = 0.0225, 0.004, 0.0255, 20, 1e-4, 8500.0
    ri, ro, W = cage.cage_annulus(Rm, Dw, L)
    assert (ri, ro, W) == pytest.approx((0.0213, 0.0237, 0.0275))
    m_ann = rho * math.pi * (0.0237**2 - 0.0213**2) * 0.0275
    m_p = rho * 0.0041 * 0.0255 * 0.0024
    I_hand = 0.5 * m_ann * (0.0237**2 + 0.0213**2) - 20 * m_p * (
        Rm**2 + (0.0024**2 + 0.0041**2) / 12)
    m, I = cage.cage_mass_inertia(Rm, Dw, L, Z, cp, rho)
    assert m == pytest.approx(m_ann - 20 * m_p, rel=1e-12)
    assert m == pytest.approx(0.036653, rel=1e-4)
    assert I == pytest.approx(I_hand, rel=1e-12)
    assert I == pytest.approx(m * Rm**2, rel=0.01)  # thin ring: I ≈ m R_m²
    m0, I0 = cage.cage_mass_inertia(Rm, Dw, L, 0, cp, rho)  # no pockets: plain annulus
    assert I0 == pytest.approx(0.5 * m0 * (ro**2 + ri**2), rel=1e-12)


def test_cage_rejects_pockets_that_do_not_fit():
    with pytest.raises(ValueError, match="rollers = 40"):
        cage.cage_mass_inertia(0.0225, 0.004, 0.0255, 40, 1e-4)


def test_pocket_damping_default():
    """c = 2 ζ sqrt(K m), ζ = 0.1 (theory.md §2)."""
    assert cage.pocket_damping(1e7, 2.5e-3) == pytest.approx(0.2 * math.sqrt(2.5e4))


def test_cage_kernels_compile_with_numba():
    args = (CLEAR / 2 + 3 * EPS, -0.1, CLEAR, K_POCKET, C_POCKET, EPS, K_POCKET * EPS)
    np.testing.assert_allclose(numba.njit(cage._pocket_force)(*args), cage._pocket_force(*args),
                               rtol=1e-13)
    args = (-3.0, 0.5, 400.0, 0.0255, 0.002, 0.0225, 0.002, 1e-2, 1e-6)
    np.testing.assert_allclose(numba.njit(cage._pocket_loads)(*args), cage._pocket_loads(*args),
                               rtol=1e-13)
    args = (1.234, 0.2, 7, 20, 0.0225)
    assert numba.njit(cage.pocket_lead)(*args) == pytest.approx(cage.pocket_lead(*args),
                                                                rel=1e-14)


# --------------------------------------------------------------------------- lubricant (§9)

def test_effective_density():
    """ρ_e = X ρ_oil + (1 - X) ρ_air: theory.md §2 defaults X = 0.015, 870 kg/m³, air 1.2 kg/m³."""
    assert lubricant.effective_density(0.015, 870.0) == pytest.approx(14.232)


CD_TABLE = [(0.1, 60.0), (1.0, 10.0), (10.0, 3.0), (100.0, 1.8), (1e3, 1.0), (1e4, 1.2),
            (2e5, 1.2), (3e5, 0.9), (4e5, 0.65), (5e5, 0.3)]


@pytest.mark.parametrize("re,cd", CD_TABLE)
def test_drag_coefficient_at_table_nodes(re, cd):
    """theory.md §9 table of C_D(Re) for a cylinder in cross-flow."""
    assert lubricant.drag_coefficient_cylinder(re) == pytest.approx(cd, rel=1e-12)


def test_drag_coefficient_between_nodes_and_clamped():
    """Linear in log10 Re between nodes (our reading of "log-linear"), constant outside."""
    cd = lubricant.drag_coefficient_cylinder
    assert cd(math.sqrt(0.1 * 1.0)) == pytest.approx(35.0)  # half-way in log10 Re
    assert cd(math.sqrt(1e4 * 2e5)) == pytest.approx(1.2)  # plateau
    assert cd(0.0) == 60.0 and cd(1e-9) == 60.0 and cd(1e9) == pytest.approx(0.3)
    re = np.logspace(-4, 7, 997)
    np.testing.assert_allclose(cd(re), np.interp(np.log10(re), np.log10([r for r, _ in CD_TABLE]),
                                                 [c for _, c in CD_TABLE]), rtol=1e-12)


def test_orbit_drag_hand_value_and_symmetry():
    """F_D = ½ C_D ρ_e D_w L (R_m Ω)² sign Ω (theory.md §9); Re = ρ D_w R_m|Ω|/μ = 100 → C_D = 1.8."""
    args = (0.025, 0.004, 0.02, 10.0, 1e-3)  # R_m, D_w, L, ρ_e, μ
    F = lubricant.orbit_drag_force(100.0, *args)
    assert F == pytest.approx(0.5 * 1.8 * 10.0 * 0.004 * 0.02 * 2.5**2, rel=1e-12)
    assert lubricant.orbit_drag_force(-100.0, *args) == pytest.approx(-F)
    assert lubricant.orbit_drag_force(0.0, *args) == 0.0
    assert lubricant.orbit_drag_force(1e-9, *args) / 1e-9 < 1e-12  # Ω|Ω|: C¹ with zero slope


def test_churning_laminar_branch():
    """Re < 3e5: ½ρω²r⁵·3.87/√Re (theory.md §9), which is twice von Kármán's one-face torque
    (π/2)(0.6159) ρ r⁴ sqrt(ν ω³) (both sides of the disk: the roller's two end faces)."""
    rho, mu, r, w = 14.232, 0.01, 0.002, 1500.0
    re = rho * w * r**2 / mu
    assert re < 3e5
    M = lubricant.churning_moment(w, r, rho, mu)
    assert M == pytest.approx(0.5 * rho * w**2 * r**5 * 3.87 / math.sqrt(re), rel=1e-12)
    von_karman_one_face = 0.5 * math.pi * 0.6159 * rho * r**4 * math.sqrt(mu / rho * w**3)
    assert M == pytest.approx(2 * von_karman_one_face, rel=1e-3)
    assert lubricant.roller_end_churning(w, r, rho, mu) == M
    assert lubricant.churning_moment(-w, r, rho, mu) == pytest.approx(-M)


def test_churning_turbulent_branch():
    """Re ≥ 3e5: ½ρω²r⁵·0.146/Re^0.2 (theory.md §9)."""
    rho, mu, r, w = 870.0, 0.01, 0.05, 2000.0
    re = rho * w * r**2 / mu
    assert re > 3e5
    M = lubricant.churning_moment(w, r, rho, mu)
    assert M == pytest.approx(0.5 * rho * w**2 * r**5 * 0.146 / re**0.2, rel=1e-12)


def test_churning_vanishes_smoothly_at_rest():
    """Laminar law: M ∝ ω^1.5 → 0 as ω → 0, finite (no 0/0 at Re = 0)."""
    args = (0.002, 14.232, 0.01)
    assert lubricant.churning_moment(0.0, *args) == 0.0
    m1, m4 = (lubricant.churning_moment(w, *args) for w in (1e-6, 4e-6))
    assert m4 / m1 == pytest.approx(8.0, rel=1e-12)
    assert np.all(np.isfinite(lubricant.churning_moment(np.array([0.0, -1e-300, 1e-300]), *args)))


def test_churning_compiled_equals_numpy_on_both_branches():
    """Reference: the same law evaluated in Python on each float (scalar libm pow, as in the
    kernel; numpy's array power may differ by 1 ulp). The compiled law skips the turbulent
    branch's power where Re <= 3e5 (its floored factor is then a constant): the same double
    on both sides of the transition, at it, and for ω = 0, ±inf and NaN."""
    args = (0.002, 14.232, 0.01)
    compiled = numba.njit(lambda w: lubricant.churning_moment(w, *args))
    re_per_w = args[1] * args[0] ** 2 / args[2]
    w = np.concatenate([np.linspace(-2e8, 2e8, 4001), [0.0, 3e5 / re_per_w, -3e5 / re_per_w,
                                                       np.inf, -np.inf, np.nan]])
    got = np.array([compiled(v) for v in w])
    with np.errstate(invalid="ignore"):  # inf * 0 in the branch not taken, as in the kernel
        ref = np.array([lubricant.churning_moment(float(v), *args) for v in w])
    assert np.all((got == ref) | (np.isnan(got) & np.isnan(ref)))
    assert (np.abs(w) * re_per_w > 3e5).sum() > 100 and (np.abs(w) * re_per_w < 3e5).sum() > 100


def test_churning_annulus():
    """Cage side faces: r⁵ → r_o⁵ - r_i⁵ with Re from r_o (theory.md §9); r_i = 0 is the disk."""
    rho, mu, w = 14.232, 0.01, 500.0
    ri, ro = 0.0213, 0.0237
    M = lubricant.cage_side_churning(w, ri, ro, rho, mu)
    re = rho * w * ro**2 / mu
    assert M == pytest.approx(0.5 * rho * w**2 * (ro**5 - ri**5) * 3.87 / math.sqrt(re),
                              rel=1e-12)
    assert lubricant.churning_moment_annulus(w, 0.0, ro, rho, mu) == pytest.approx(
        lubricant.churning_moment(w, ro, rho, mu), rel=1e-14)


def test_lubricant_kernels_compile_with_numba():
    args = (180.0, 0.0225, 0.004, 0.0255, 14.232, 0.01)
    assert numba.njit(lubricant.orbit_drag_force)(*args) == pytest.approx(
        lubricant.orbit_drag_force(*args), rel=1e-13)
    for w in (3e3, 3e7):  # both churning branches
        args = (w, 0.0213, 0.0237, 14.232, 0.01)
        assert numba.njit(lubricant.cage_side_churning)(*args) == pytest.approx(
            lubricant.cage_side_churning(*args), rel=1e-13)
