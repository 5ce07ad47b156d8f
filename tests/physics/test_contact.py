"""Sliced contact law (theory.md §4) against Palmgren's closed form, and the Jacobian slopes."""

from __future__ import annotations

import numpy as np
import pytest

from bearingdae.physics.contact import (
    hertz_pressure,
    palmgren_approach,
    palmgren_coefficient,
    slice_load,
    slice_stiffness,
)
from bearingdae.physics.geometry import elastic_compliance, profile_drop, slice_centres

ETA_STEEL = elastic_compliance(207e9, 0.3, 207e9, 0.3)


def test_palmgren_coefficient_in_mm_N_units():
    # Palmgren: δ = 3.84e-5 Q^0.9 / l^0.8 in mm and N for steel on steel (theory.md §4).
    delta_m = palmgren_approach(1000.0, 0.02, ETA_STEEL)
    delta_mm_reference = 3.84e-5 * 1000.0**0.9 / 20.0**0.8
    assert delta_m * 1e3 == pytest.approx(delta_mm_reference, rel=3e-3)  # 3.84 is rounded
    assert palmgren_coefficient(ETA_STEEL) > 0


@pytest.mark.parametrize("slices", [1, 10, 37])
@pytest.mark.parametrize("load_N", [1.0, 850.0, 5.0e4])
def test_sum_of_slice_loads_is_palmgren(slices, load_N):
    """One roller, one contact, flat profile: Σ q_λ must reproduce δ = A Q^0.9 / l^0.8.

    Reference: Palmgren's closed-form line-contact law (theory.md §4) to 1e-9. The smoothing length
    is taken ~0 here: the regularisation changes a loaded slice by (ε/2δ)², documented.
    """
    L = 0.0255
    delta = palmgren_approach(load_N, L, ETA_STEEL)
    K = slice_stiffness(L / slices, L, ETA_STEEL)
    q, _ = slice_load(np.full(slices, delta), K, 1e-18)
    assert q.sum() == pytest.approx(load_N, rel=1e-9)


def test_regularisation_error_is_eps_over_2delta_squared():
    # s(δ) = δ + ε²/(4δ) + O(ε⁴): relative load error (10/9)(ε/2δ)² for δ >> ε.
    K, eps, d = 1e11, 1e-9, 1e-6
    q, _ = slice_load(np.array([d]), K, eps)
    exact = K * d ** (10 / 9)
    assert q[0] / exact - 1 == pytest.approx((10 / 9) * (eps / (2 * d)) ** 2, rel=1e-3)


def test_slice_load_slope_matches_finite_difference():
    K, eps = 3.1e8, 1e-9
    d = np.array([-5e-6, -1e-9, 0.0, 3e-10, 2e-6, 4e-5])
    q, g = slice_load(d, K, eps)
    h = 1e-6 * np.maximum(np.abs(d), eps)
    fd = (slice_load(d + h, K, eps)[0] - slice_load(d - h, K, eps)[0]) / (2 * h)
    np.testing.assert_allclose(g, fd, rtol=1e-6)
    assert np.all(q > 0) and np.all(g > 0)  # regularised: positive, monotone


def test_hertz_pressure_line_contact():
    # p0 = sqrt(P' E* / (π R)), P' = q/w: Johnson, Contact Mechanics, Eq. 4.45.
    q, w, R = 100.0, 2e-3, 1.8e-3
    p = hertz_pressure(q, w, R, ETA_STEEL)
    assert p == pytest.approx(np.sqrt(q / w / ETA_STEEL / (np.pi * R)), rel=1e-14)
    assert hertz_pressure(-1.0, w, R, ETA_STEEL) == 0.0


def test_slice_centres_and_end_crown():
    x = slice_centres(25.5e-3, 10)
    assert x[0] == pytest.approx(-25.5e-3 / 2 + 1.275e-3) and np.allclose(x, -x[::-1])
    # yang20 with k = 10: end-slice centres sit exactly at L_s/2, so the crown does not act
    # (theory.md §3 note).
    c = profile_drop(x, "end-crown", 25.5e-3, 22.95e-3, 20e-3)
    assert np.abs(c).max() < 1e-18
    c30 = profile_drop(slice_centres(25.5e-3, 30), "end-crown", 25.5e-3, 22.95e-3, 20e-3)
    xe = 25.5e-3 / 2 - 25.5e-3 / 60 - 22.95e-3 / 2
    assert c30[-1] == pytest.approx(20e-3 - np.sqrt(20e-3**2 - xe**2), rel=1e-12)


def test_other_profiles_are_symmetric_and_non_negative():
    x = slice_centres(20e-3, 21)
    for prof in ("full-crown", "logarithmic"):
        c = profile_drop(x, prof, 20e-3, 17e-3, 40e-3, design_load_N=1000.0,
                         compliance_m2_N=ETA_STEEL)
        assert np.all(c >= 0) and np.allclose(c, c[::-1]) and c[10] == 0.0
