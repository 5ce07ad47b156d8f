"""EHL rolling resistance law (physics/rolling_resistance.py, docs/theory.md §19).

References: Goksem & Hargreaves's fit typed afresh from the paper's formula (J. Lubrication
Technology 100 (1978) 346-352, as quoted with its thermal factor), its isothermal form as
Harris & Kotzalas quote it (4.318 (GU)^0.658 W^0.0126 R / α), Martin's rigid-isoviscous film
integrated here from Reynolds's equation, and central differences for the slopes.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from bearingdae.physics import rolling_resistance as rr

# one slice contact of the yang20 baseline's loaded zone (inner race): 300 N over 25.5 mm,
# 2 m/s, VG 10-like oil at 0.01 Pa s, α = 22 GPa⁻¹, steel E' = 227.5 GPa
W_N_M, R_M, U_M_S = 300.0 / 25.5e-3, 1.822e-3, 2.0
ETA, ALPHA, E = 0.01, 22e-9, 2.2747e11
BETA, K = 0.03, 0.13
# w_c: the yang20 baseline's load per length at the contact smoothing length (1 nm)
WC = 12.0
#: the law arguments after w_c of Goksem & Hargreaves's law, fully flooded
GH = (rr.GOKSEM_HARGREAVES, 0.0, 0.0)


def _gh_afresh(w, R, u, eta, alpha, E, beta, k):
    """Goksem & Hargreaves's rolling traction per unit length, typed from the paper's fit."""
    G = alpha * E
    W = w / (E * R)
    U = eta * u / (E * R)
    L = eta * beta * u ** 2 / k
    D = 11.81220746 * G * U / W ** 1.5
    Kt = math.exp((0.658228 + 0.0106383 * L ** 0.3174603) * math.log(D)
                  - (0.162625 + math.log(1 + 0.411483 * L ** 0.707071)))
    return Kt * W * R / alpha


def test_one_contact_against_the_law_typed_afresh():
    for beta in (0.0, BETA, 0.5):  # isothermal, a mineral oil, strong inlet heating
        f = rr.goksem_hargreaves(W_N_M, R_M, U_M_S, ETA, ALPHA, E, beta, K)[0]
        assert f == pytest.approx(_gh_afresh(W_N_M, R_M, U_M_S, ETA, ALPHA, E, beta, K),
                                  rel=1e-10)
    # the blend with Martin's film, and the slice's signed force (Σ = 2u, well above u₀)
    a = _gh_afresh(W_N_M, R_M, U_M_S, ETA, ALPHA, E, BETA, K)
    b = 2.0796226511 * math.sqrt(ETA * U_M_S) * W_N_M / math.sqrt(W_N_M + WC)
    blend = a * b / math.sqrt(a * a + b * b)
    f = rr.rolling_force_per_length(W_N_M, R_M, U_M_S, ETA, ALPHA, E, BETA, K, WC, *GH)[0]
    assert f == pytest.approx(blend, rel=1e-10)
    dx = 2.55e-3
    u0 = rr.ROLLING_SPEED_FLOOR_M_S
    H = rr._slice_rolling_force(W_N_M * dx, 2 * U_M_S, dx, R_M, ETA, ALPHA, E, BETA, K, u0, WC,
                                *GH)[0]
    ubar = math.sqrt(U_M_S ** 2 + u0 ** 2)
    f_bar = rr.rolling_force_per_length(W_N_M, R_M, ubar, ETA, ALPHA, E, BETA, K, WC, *GH)[0]
    assert H == pytest.approx(f_bar * dx * U_M_S / ubar, rel=1e-12)


def test_isothermal_law_is_the_harris_kotzalas_form():
    """L = 0: f = 4.318 (G U)^0.658 W^0.0126 R / α (the published rounding of the same fit)."""
    G, U, W = ALPHA * E, ETA * U_M_S / (E * R_M), W_N_M / (E * R_M)
    harris = 4.318 * (G * U) ** 0.658 * W ** 0.0126 * R_M / ALPHA
    f = rr.goksem_hargreaves(W_N_M, R_M, U_M_S, ETA, ALPHA, E, 0.0, K)[0]
    # the quoted exponents are the fit's rounded to three digits (0.658228 -> 0.658): 0.4 % at
    # G U ~ 1e-7
    assert f == pytest.approx(harris, rel=6e-3)
    hot = rr.goksem_hargreaves(W_N_M, R_M, 20.0, ETA, ALPHA, E, BETA, K)[0]
    cold = rr.goksem_hargreaves(W_N_M, R_M, 20.0, ETA, ALPHA, E, 0.0, K)[0]
    assert hot < 0.95 * cold  # the inlet heating lowers it at high speed


def test_martin_film_constants():
    """Martin's rigid-isoviscous line contact integrated from Reynolds's equation: gap
    h₀ (1 + ξ²), cavitation at ξ* with p = dp/dξ = 0; load w' = C_w η u R / h₀ and the
    Poiseuille shear on each surface -(h/2) dp/dx, whose integral gives f = C sqrt(η u w')."""
    def p(x, s):
        return quad(lambda t: (t * t - s * s) / (1 + t * t) ** 3, -np.inf, x,
                    epsabs=1e-14, epsrel=1e-13)[0]

    s = brentq(lambda s: p(s, s), 0.3, 0.7, xtol=1e-14)
    C_w = 24.0 * quad(lambda x: p(x, s), -np.inf, s, epsabs=1e-13, epsrel=1e-12, limit=200)[0]
    I_F = quad(lambda t: (t * t - s * s) / (1 + t * t) ** 2, -np.inf, s, epsabs=1e-14,
               epsrel=1e-13)[0]
    assert C_w == pytest.approx(4.9, abs=0.01)  # Martin's classic coefficient
    assert rr.IV_FACTOR == pytest.approx(6.0 * math.sqrt(2.0) * I_F / math.sqrt(C_w), rel=1e-8)


@pytest.mark.parametrize("w, u", [(W_N_M, U_M_S), (20.0, 1.5), (1e-6, 0.3), (5e5, 30.0)])
def test_slopes_are_the_derivatives(w, u):
    def blend(*args):
        return rr.rolling_force_per_length(*args, WC, *GH)

    for fn in (rr.goksem_hargreaves, blend):
        f, f_w, f_u = fn(w, R_M, u, ETA, ALPHA, E, BETA, K)
        h = 1e-6
        dw = (fn(w * (1 + h), R_M, u, ETA, ALPHA, E, BETA, K)[0]
              - fn(w * (1 - h), R_M, u, ETA, ALPHA, E, BETA, K)[0]) / (2 * h * w)
        du = (fn(w, R_M, u * (1 + h), ETA, ALPHA, E, BETA, K)[0]
              - fn(w, R_M, u * (1 - h), ETA, ALPHA, E, BETA, K)[0]) / (2 * h * u)
        assert f_w == pytest.approx(dw, rel=1e-6)
        assert f_u == pytest.approx(du, rel=1e-6)
    dx, u0 = 2.55e-3, rr.ROLLING_SPEED_FLOOR_M_S
    q = w * dx
    for S in (2 * u, -2 * u, 1e-4, 0.0):  # through reversal and below the floor
        H, H_q, H_s = rr._slice_rolling_force(q, S, dx, R_M, ETA, ALPHA, E, BETA, K, u0, WC, *GH)
        hq, hs = 1e-6 * q, 1e-7 * max(abs(S), 1e-2)
        fq = (rr._slice_rolling_force(q + hq, S, dx, R_M, ETA, ALPHA, E, BETA, K, u0, WC, *GH)[0]
              - rr._slice_rolling_force(q - hq, S, dx, R_M, ETA, ALPHA, E, BETA, K, u0, WC, *GH)[0])
        fs = (rr._slice_rolling_force(q, S + hs, dx, R_M, ETA, ALPHA, E, BETA, K, u0, WC, *GH)[0]
              - rr._slice_rolling_force(q, S - hs, dx, R_M, ETA, ALPHA, E, BETA, K, u0, WC, *GH)[0])
        assert H_q == pytest.approx(fq / (2 * hq), rel=1e-6, abs=1e-12)
        assert H_s == pytest.approx(fs / (2 * hs), rel=1e-5, abs=1e-12)
        assert H * S >= 0.0  # it always dissipates


def test_the_force_vanishes_with_the_load():
    """A slice in the gap (regularisation residue, 1e-20 N) gets no rolling force to speak of;
    the EHL fit alone would give it most of a loaded slice's."""
    dx, u0 = 2.55e-3, rr.ROLLING_SPEED_FLOOR_M_S
    loaded = rr._slice_rolling_force(300.0 / 10, 4.0, dx, R_M, ETA, ALPHA, E, BETA, K, u0, WC,
                                     *GH)[0]
    gap = rr._slice_rolling_force(1e-20, 4.0, dx, R_M, ETA, ALPHA, E, BETA, K, u0, WC, *GH)[0]
    ehl_gap = rr.goksem_hargreaves(1e-20 / dx, R_M, 2.0, ETA, ALPHA, E, BETA, K)[0] * dx
    assert gap < 1e-9 * loaded
    assert ehl_gap > 0.5 * loaded


def test_light_load_tail_is_lipschitz_and_martin_above_it():
    """Below w_c the rigid-isoviscous force is linear in the load (slope bounded as w' -> 0,
    where Martin's sqrt(w') has an unbounded one); above it, Martin's law to w_c / (2 w')."""
    g = 2.0796226511 * math.sqrt(ETA * U_M_S)
    slopes = [rr.rigid_isoviscous(w, U_M_S, ETA, WC)[1] for w in (1e-12, 1e-6, 1e-2, WC)]
    assert max(slopes) <= g / math.sqrt(WC) * (1 + 1e-9)  # sup of the slope, at w' -> 0
    assert slopes[0] == pytest.approx(g / math.sqrt(WC), rel=1e-6)
    for w in (500 * WC, 1e4 * WC):
        f = rr.rigid_isoviscous(w, U_M_S, ETA, WC)[0]
        assert f / (g * math.sqrt(w)) == pytest.approx(1 - WC / (2 * w), rel=WC ** 2 / w ** 2 * 2)


def test_light_load_is_the_slice_load_at_the_smoothing_length():
    """w_c = q(ε)/Δl from Palmgren's law typed afresh (δ = A Q^0.9 / l^0.8, A = 1.36 η^0.9,
    η = 2 (1 - ν²)/E) with the smoothed approach s(ε) = (ε + sqrt(2) ε)/2 of theory.md §4."""
    from bearingdae.physics.contact import slice_stiffness

    eps, L, k = 1e-9, 25.5e-3, 10
    dx = L / k
    eta = 2 * (1 - 0.3 ** 2) / 2.08e11
    A = 1.36 * eta ** 0.9
    s = 0.5 * (1 + math.sqrt(2)) * eps
    Q = (s * L ** 0.8 / A) ** (1 / 0.9)  # the whole roller's load at the approach s
    wc = rr.light_load_per_length(slice_stiffness(dx, L, eta), eps, dx)
    assert wc == pytest.approx(Q / L, rel=1e-9)
    assert 5.0 < wc < 30.0  # the yang20 order of magnitude WC stands for


# --- the three laws in the kernel's form, starvation, and the light-load bound -------------

BH_K = 1.4 * (8.0 / math.pi) ** 1.5 / 4.0  # B&H eq. (40) in force form: F̃_IVR = K sqrt(UW)


def _bh_afresh(w, R, u, eta, E):
    """B&H's eq. (42) with eq. (14)'s U (factor 2), typed in Hertzian units and converted."""
    U, W = 2.0 * eta * u / (E * R), w / (E * R)
    M = W / math.sqrt(U)
    T = M ** -1.5 * 1.4 * math.sqrt(M) / (1.0 + (1.4 / 1.45 * math.sqrt(M)) ** 10) ** 0.1
    return T * (8.0 * W / math.pi) ** 1.5 / 4.0 * E * R  # t_l / (E'R²) = F̃; f = F̃ E'R


def _starved_afresh(w, R, u, eta, alpha, E, h_a):
    """B&H's eq. (44) at S = h_a / h_m*, h_m* = sqrt(h_IV² + h_EHL²): Martin's 4.895 η u R/w
    and Pan & Hamrock's 1.714 R W^-0.128 U^0.694 G^0.568 (U = η u/(E'R), their own U)."""
    h_iv = 4.895 * eta * u * R / w
    h_ehl = (1.714 * R * (w / (E * R)) ** -0.128 * (eta * u / (E * R)) ** 0.694
             * (alpha * E) ** 0.568)
    S = h_a / math.hypot(h_iv, h_ehl)
    return (S * S + 162.8 * S) / (S * S + 193.1 * S + 1257.0)


def _law(code, h_a=0.0):
    from bearingdae.physics.film import min_film_factor

    return (code, min_film_factor(E, ALPHA), h_a)


@pytest.mark.parametrize("w", [1e-3, 1.0, WC, 300.0, W_N_M, 5e5])
def test_biboulet_houpert_is_their_eq_42_and_starved_their_eq_44(w):
    f = rr.biboulet_houpert(w, R_M, U_M_S, ETA, E, 0.0)[0]
    assert f == pytest.approx(_bh_afresh(w, R_M, U_M_S, ETA, E), rel=1e-12)
    for h_a in (0.05e-6, 0.3e-6, 3e-6):
        starved = rr.rolling_force_per_length(w, R_M, U_M_S, ETA, ALPHA, E, BETA, K, 0.0,
                                              *_law(rr.BIBOULET_HOUPERT, h_a))[0]
        assert starved / f == pytest.approx(
            _starved_afresh(w, R_M, U_M_S, ETA, ALPHA, E, h_a), rel=1e-12)
    # Zhou & Hoeprich, as B&H's eq. (39) prints it in their U
    U, W, G = 2 * ETA * U_M_S / (E * R_M), w / (E * R_M), ALPHA * E
    zh = rr.zhou_hoeprich(w, R_M, U_M_S, ETA, ALPHA, E)[0]
    assert zh == pytest.approx(18.62 * U ** 0.648 * W ** 0.246 * G ** -0.352 * E * R_M,
                               rel=1e-12)


def test_the_light_load_regularisation_sits_below_the_ivr_asymptote_within_its_fraction():
    """Never above B&H's IVR asymptote K sqrt(2 η u w') (nor B&H's law), and below B&H's law
    by at most w_c/(2w'): 0.1 % at w' >= 500 w_c; a finite slope as w' -> 0."""
    for u in (1e-3, 0.3, U_M_S, 30.0):
        for w in WC * np.logspace(-12, 8, 81):
            f = rr.biboulet_houpert(w, R_M, u, ETA, E, WC)[0]
            ivr = BH_K * math.sqrt(2 * ETA * u * w)
            bh = _bh_afresh(w, R_M, u, ETA, E)
            assert f <= ivr * (1 + 1e-12) and f <= bh * (1 + 1e-12)
            assert f >= bh * (1 - WC / (2 * w)) * (1 - 1e-12)
            if w >= 500 * WC:
                assert f >= 0.999 * bh
    slope = rr.biboulet_houpert(1e-12 * WC, R_M, U_M_S, ETA, E, WC)[1]
    assert slope == pytest.approx(BH_K * math.sqrt(2 * ETA * U_M_S / WC), rel=1e-9)


@pytest.mark.parametrize("code", [rr.GOKSEM_HARGREAVES, rr.BIBOULET_HOUPERT, rr.ZHOU_HOEPRICH])
@pytest.mark.parametrize("h_a", [0.0, 0.2e-6])
@pytest.mark.parametrize("w, u", [(W_N_M, U_M_S), (20.0, 1.5), (1e-6, 0.3), (5e5, 30.0)])
def test_every_law_s_slopes_are_its_derivatives(code, h_a, w, u):
    law = _law(code, h_a)
    dx, u0 = 2.55e-3, rr.ROLLING_SPEED_FLOOR_M_S
    q = w * dx

    def H(q, S):
        return rr._slice_rolling_force(q, S, dx, R_M, ETA, ALPHA, E, BETA, K, u0, WC, *law)

    for S in (2 * u, -2 * u, 1e-4, 0.0):
        h, h_q, h_s = H(q, S)
        dq, ds = 1e-6 * q, 1e-7 * max(abs(S), 1e-2)
        assert h_q == pytest.approx((H(q + dq, S)[0] - H(q - dq, S)[0]) / (2 * dq),
                                    rel=1e-6, abs=1e-12)
        assert h_s == pytest.approx((H(q, S + ds)[0] - H(q, S - ds)[0]) / (2 * ds),
                                    rel=1e-5, abs=1e-12)
        assert h * S >= 0.0


def test_the_compiled_loop_is_the_law():
    """physics/power.py's forces (one compiled loop) against the law from Python."""
    q = np.array([1e-20, 0.05, 3.0, 30.0, 300.0])
    s = np.array([4.0, -2.0, 1e-4, 0.0, 10.0])
    dx, u0 = 2.55e-3, rr.ROLLING_SPEED_FLOOR_M_S
    for code in rr.LAW_CODES.values():
        for h_a in (0.0, 0.2e-6):
            law = (ETA, ALPHA, E, BETA, K, u0, WC, *_law(code, h_a))
            got = rr.slice_forces(q, s, dx, R_M, law)
            want = [rr._slice_rolling_force(a, b, dx, R_M, *law)[0] for a, b in zip(q, s)]
            np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-300)


def test_the_scene_names_the_laws_the_kernel_knows():
    from bearingdae.scene.sections.physics import ROLLING_LAWS

    assert set(ROLLING_LAWS) == set(rr.LAW_CODES)
    assert rr.law_code(True) == rr.BIBOULET_HOUPERT == rr.law_code(ROLLING_LAWS[0])
    with pytest.raises(ValueError, match="zhou_hoeprich"):
        rr.law_code("palmgren")
