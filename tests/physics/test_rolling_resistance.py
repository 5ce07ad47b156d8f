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
    H = rr._slice_rolling_force(W_N_M * dx, 2 * U_M_S, dx, R_M, ETA, ALPHA, E, BETA, K, u0, WC, *GH)[0]
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
    loaded = rr._slice_rolling_force(300.0 / 10, 4.0, dx, R_M, ETA, ALPHA, E, BETA, K, u0, WC, *GH)[0]
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
