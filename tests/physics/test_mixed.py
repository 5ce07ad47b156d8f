"""Mixed lubrication laws (physics/mixed.py, theory.md §20) against references typed afresh.

References: the Greenwood–Tripp integral F_5/2(λ) = (2π)^(-1/2) ∫_λ^∞ (z - λ)^(5/2) e^(-z²/2) dz
by quadrature (Greenwood & Tripp 1970), the share built on it the way theory.md §20 states;
the film fit's own post-processing path (physics/film.line_contact_film); the limits λ → 0
(boundary friction) and λ ≥ 3 (the EHL law unchanged); central differences for every slope.
"""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit
from scipy.integrate import quad

from bearingdae.physics import film
from bearingdae.physics.mixed import (_mixed_slopes, _mixed_traction,
                                      asperity_share, film_constants, film_parameter,
                                      friction_coefficient)
from bearingdae.physics.traction import _traction_force_paper, traction_coefficient_paper


def _f52(lam):
    """Greenwood–Tripp F_5/2(λ) by quadrature of the Gaussian tail."""
    return quad(lambda z: (z - lam) ** 2.5 * np.exp(-0.5 * z * z), lam, np.inf,
                epsabs=1e-14)[0] / np.sqrt(2.0 * np.pi)


def _df52(lam):
    return -2.5 * quad(lambda z: (z - lam) ** 1.5 * np.exp(-0.5 * z * z), lam, np.inf,
                       epsabs=1e-14)[0] / np.sqrt(2.0 * np.pi)


def test_share_follows_the_greenwood_tripp_integral():
    """s(λ) against the same construction on the integral itself: (F(λ) - tangent of F at 3)
    normalised to 1 at λ = 0. The law uses the F_5/2 fit 4.4086e-5 (4 - λ)^6.804, which is
    within 11 % of the integral on [0, 2]; the shares agree to 0.015 absolute."""
    f3, d3 = _f52(3.0), _df52(3.0)

    def reference(lam):
        return (_f52(lam) - f3 - d3 * (lam - 3.0)) / (_f52(0.0) - f3 + 3.0 * d3)

    for lam in np.linspace(0.0, 3.0, 25):
        assert abs(asperity_share(lam)[0] - reference(lam)) < 0.015, lam
    # the fit itself against the integral where it carries the share (λ ≤ 1.5: ± 11 %)
    for lam in (0.0, 0.5, 1.0, 1.5):
        assert 4.4086e-5 * (4.0 - lam) ** 6.804 == pytest.approx(_f52(lam), rel=0.11)


def test_share_limits_smoothness_and_slope():
    assert asperity_share(0.0)[0] == pytest.approx(1.0, abs=1e-14)
    for lam in (3.0, 3.0 + 1e-12, 4.0, 50.0, 1e6):
        assert asperity_share(lam) == (0.0, 0.0)  # exactly: the film carries everything
    # the values theory.md §20 quotes
    assert asperity_share(1.0)[0] == pytest.approx(0.14, abs=0.005)
    assert asperity_share(2.0)[0] == pytest.approx(0.008, abs=0.0005)
    # C¹ at λ = 3: value and slope go to 0 from below
    s, ds = asperity_share(3.0 - 1e-6)
    assert 0.0 < s < 1e-10 and -1e-4 < ds < 0.0
    lams = np.linspace(0.01, 2.99, 60)
    values = [asperity_share(v)[0] for v in lams]
    assert np.all(np.diff(values) < 0.0)  # falls monotonically
    h = 1e-6
    for lam in lams[::7]:
        fd = (asperity_share(lam + h)[0] - asperity_share(lam - h)[0]) / (2 * h)
        assert asperity_share(lam)[1] == pytest.approx(fd, rel=1e-6, abs=1e-10)


@njit(cache=True)
def _film_fit_compiled(w, R, u, visc, E, factor):
    return film._film_fit(w, R, u, visc, E, factor, film._MIN[1], film._MIN[2])


def test_film_law_is_the_post_processing_film_and_has_its_slopes():
    """The kernel's film law (compiled, as the mixed kernel inlines it, and as numpy) against the
    post-processing path of the film outputs, to 1e-12; its slopes against differences."""
    E = film.reduced_modulus(2.0 * (1.0 - 0.3 ** 2) / 208e9)
    alpha, visc = 22e-9, 0.01
    factor = film.min_film_factor(E, alpha)
    rng = np.random.default_rng(7)
    w = rng.uniform(1e3, 5e5, 40)
    R = rng.uniform(2e-3, 8e-3, 40)
    u = rng.uniform(0.1, 20.0, 40)
    h_min = film.line_contact_film(w, R, u, visc, alpha, E)[1]
    for i in range(40):
        h, dh_dw, dh_du = _film_fit_compiled(w[i], R[i], u[i], visc, E, factor)
        assert h == pytest.approx(h_min[i], rel=1e-12)
        assert film._film_fit(w[i], R[i], u[i], visc, E, factor, film._MIN[1],
                              film._MIN[2])[0] == pytest.approx(h_min[i], rel=1e-12)
        # Pan & Hamrock's fit typed afresh
        G, W, U = alpha * E, w[i] / (E * R[i]), visc * u[i] / (E * R[i])
        assert h == pytest.approx(R[i] * 1.714 * W ** -0.128 * U ** 0.694 * G ** 0.568,
                                  rel=1e-12)
        dw, du = 1e-6 * w[i], 1e-6 * u[i]
        fd_w = (_film_fit_compiled(w[i] + dw, R[i], u[i], visc, E, factor)[0]
                - _film_fit_compiled(w[i] - dw, R[i], u[i], visc, E, factor)[0]) / (2 * dw)
        fd_u = (_film_fit_compiled(w[i], R[i], u[i] + du, visc, E, factor)[0]
                - _film_fit_compiled(w[i], R[i], u[i] - du, visc, E, factor)[0]) / (2 * du)
        assert dh_dw == pytest.approx(fd_w, rel=1e-6)
        assert dh_du == pytest.approx(fd_u, rel=1e-6)
    # standstill: no film (λ = 0, the asperities carry all)
    assert _film_fit_compiled(1e5, 4e-3, 0.0, visc, E, factor)[0] == 0.0


ARGS = dict(width=1e-3, R=4e-3, visc=0.01, E=2.28e11, sigma=0.11e-6)


def _lam(q, u):
    """(λ, dλ/dq, dλ/du) of a slice of ARGS as the package computes it (film_parameter)."""
    a = ARGS
    return film_parameter(q, u, *film_constants(a["width"], a["R"], a["visc"], a["E"],
                                                film.min_film_factor(a["E"], 22e-9),
                                                a["sigma"]))


def test_boundary_friction_as_the_film_vanishes_and_ehl_law_above_lambda_3():
    """λ → 0 (entrainment speed → 0): μ = F / q at gross sliding → μ_b; λ ≥ 3: F is the EHL
    law's own value, bit for bit (a select, not arithmetic with a zero share)."""
    q, V, p, v0, mub = 200.0, 0.5, 1.2e9, 1e-12, 0.1
    F_ehl = _traction_force_paper(q, V, p, v0, 0.27, 0.43, 6.93, 0.022, False)[0]
    mus = []
    for u in (1e-2, 1e-4, 1e-6, 1e-9, 0.0):
        lam = _lam(q, u)[0]
        F = _mixed_traction(F_ehl, q, V, asperity_share(lam)[0], mub, v0)[0]
        mus.append(F / q)
    assert mus[-1] == pytest.approx(mub, rel=1e-12)  # no film at all
    assert abs(mus[-2] - mub) < 1e-3 * mub  # λ ~ 1e-5: within 0.1 %
    assert np.all(np.diff(np.abs(np.array(mus) - mub)) <= 0.0)
    for F0 in (F_ehl, -0.0, 0.0, -F_ehl):
        out = _mixed_traction(F0, q, V, asperity_share(3.5)[0], mub, v0)[0]
        assert np.float64(out).tobytes() == np.float64(F0).tobytes()


def test_stribeck_curve_falls_from_boundary_to_ehl_friction():
    """μ(λ) of the mixed model at gross sliding: μ_b at λ = 0, falling monotonically to the EHL
    law's μ at λ = 3 and staying there (the right-hand side of a Stribeck curve)."""
    mu_ehl = float(traction_coefficient_paper(1.0, 1.0e9))
    lam = np.linspace(0.0, 5.0, 101)
    mu = friction_coefficient(lam, mu_ehl, 0.1)
    assert mu[0] == pytest.approx(0.1, rel=1e-12)
    assert np.all(np.diff(mu[lam <= 3.0]) < 0.0)
    assert np.all(mu[lam >= 3.0] == mu_ehl)
    # typed afresh: the share-weighted mean at λ = 1
    s1 = asperity_share(1.0)[0]
    assert friction_coefficient(1.0, mu_ehl, 0.1) == pytest.approx((1 - s1) * mu_ehl + s1 * 0.1)


@pytest.mark.parametrize("V", [0.3, -0.05, 2e-3])
def test_mixed_slopes_match_differences(V):
    """(F, dF/dV, dF/dq, dF/du) of the mixed traction against central differences of the same
    composition (paper law at the slice's Hertz pressure p ∝ sqrt(q), share through λ(q, u));
    v₀ = 1e-3 m/s so that the regularised sign is resolved by the differences."""
    v0, mub, u0, q0 = 1e-3, 0.1, 0.8, 150.0
    c = 1.0e8  # p = c sqrt(q)

    def total(q, V, u):
        p = c * np.sqrt(q)
        F = _traction_force_paper(q, V, p, v0, 0.27, 0.43, 6.93, 0.022, False)[0]
        return _mixed_traction(F, q, V, asperity_share(_lam(q, u)[0])[0], mub, v0)[0]

    p = c * np.sqrt(q0)
    F, FV, Fq, Fp = _traction_force_paper(q0, V, p, v0, 0.27, 0.43, 6.93, 0.022, False)
    Fq = Fq + Fp * 0.5 * p / q0
    lam, lam_q, lam_u = _lam(q0, u0)
    assert 0.2 < lam < 2.5  # in the mixed range
    s, s_l = asperity_share(lam)
    m, mV, mq, mu = _mixed_slopes(F, FV, Fq, 0.0, q0, V, s, s_l * lam_q, s_l * lam_u, mub, v0)
    assert m == pytest.approx(total(q0, V, u0), rel=1e-14)
    hV, hq, hu = 1e-7, 1e-5 * q0, 1e-6 * u0
    assert mV == pytest.approx((total(q0, V + hV, u0) - total(q0, V - hV, u0)) / (2 * hV),
                               rel=1e-5)
    assert mq == pytest.approx((total(q0 + hq, V, u0) - total(q0 - hq, V, u0)) / (2 * hq),
                               rel=1e-5)
    assert mu == pytest.approx((total(q0, V, u0 + hu) - total(q0, V, u0 - hu)) / (2 * hu),
                               rel=1e-5)


def test_folded_film_parameter_matches_pan_hamrock_typed_afresh():
    """film_parameter (the slice loops' form, constants folded into logarithms per race) is
    Pan & Hamrock's minimum film over σ, h = 1.714 R' W'^-0.128 U^0.694 G^0.568 (typed here
    afresh), to round-off; its slopes a λ/q, b λ/u (a = -0.128, b = 0.694) to the same."""
    a = ARGS
    alpha = 22e-9
    cmin = film.min_film_factor(a["E"], alpha)
    k = film_constants(a["width"], a["R"], a["visc"], a["E"], cmin, a["sigma"])
    for q in (1e-3, 0.5, 40.0, 600.0, 3e3):
        for u in (1e-6, 0.3, 5.0, 40.0):
            ER = a["E"] * a["R"]
            W, U, G = q / a["width"] / ER, a["visc"] * u / ER, alpha * a["E"]
            typed = 1.714 * a["R"] * W ** -0.128 * U ** 0.694 * G ** 0.568 / a["sigma"]
            lam, lam_q, lam_u = film_parameter(q, u, *k)
            assert lam == pytest.approx(typed, rel=1e-12)
            assert lam_q == pytest.approx(-0.128 * typed / q, rel=1e-12)
            assert lam_u == pytest.approx(0.694 * typed / u, rel=1e-12)
    # the conventions: standstill no film, no slope; unloaded W' = 1 (no load slope)
    assert film_parameter(100.0, 0.0, *k)[0] == 0.0 and film_parameter(100.0, 0.0, *k)[2] == 0.0
    assert film_parameter(0.0, 5.0, *k)[1] == 0.0
    U = a["visc"] * 5.0 / (a["E"] * a["R"])  # unloaded: W' = 1
    assert film_parameter(0.0, 5.0, *k)[0] == pytest.approx(
        1.714 * a["R"] * U ** 0.694 * (alpha * a["E"]) ** 0.568 / a["sigma"], rel=1e-12)
