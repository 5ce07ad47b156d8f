"""The oil's viscosity laws (physics/oil_viscosity.py, theory.md §21) against the given
points, a published data sheet, ISO 281's formula and finite differences."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearingdae.physics import oil_viscosity as law


def test_walther_passes_through_the_two_given_viscosities():
    A, B = law.walther_constants(40.0, 32.0, 100.0, 5.4)
    assert law.walther_viscosity(40.0, A, B) == pytest.approx(32.0, rel=1e-12)
    assert law.walther_viscosity(100.0, A, B) == pytest.approx(5.4, rel=1e-12)
    assert law.walther_temperature(11.5, A, B) == pytest.approx(69.0, abs=0.2)
    nu = law.walther_viscosity(np.array([0.0, 20.0, 60.0, 120.0]), A, B)
    assert np.all(np.diff(nu) < 0)


def test_walther_against_a_published_point_of_an_iso_vg_32_oil():
    """Shell Tellus S2 M 32 (ISO VG 32, VI 99), technical data sheet: 32 mm²/s at 40 °C,
    5.4 mm²/s at 100 °C, and 338 mm²/s at 0 °C. Extrapolated from the two to 0 °C, ASTM D341
    gives 336 mm²/s; within 3 % (the data sheet's values are rounded "typical" values, and 0 °C
    is an extrapolation 40 K below the two points)."""
    A, B = law.walther_constants(40.0, 32.0, 100.0, 5.4)
    assert law.walther_viscosity(0.0, A, B) == pytest.approx(338.0, rel=0.03)


def test_rated_viscosity_of_iso_281():
    """ISO 281:2007: ν₁ = 45000 n^-0.83 d_m^-0.5 (n < 1000 r/min), 4500 n^-0.5 d_m^-0.5 above;
    the yang20 bearing (d_m = 45 mm) at 2000 r/min needs 15 mm²/s."""
    assert law.rated_viscosity(2000.0, 45.0) == pytest.approx(4500 / math.sqrt(2000 * 45))
    assert law.rated_viscosity(2000.0, 45.0) == pytest.approx(15.0, rel=1e-12)
    assert law.rated_viscosity(500.0, 100.0) == pytest.approx(45000 * 500 ** -0.83 / 10.0)
    assert math.isnan(law.rated_viscosity(0.0, 45.0))  # ISO 281: a turning ring only


def test_temperature_coefficient_is_the_slope_of_ln_viscosity():
    """β = −d ln ν/dT by ASTM D341, against central differences of the viscosity law."""
    A, B = law.walther_constants(40.0, 32.0, 100.0, 5.4)
    for T in (20.0, 60.0, 110.0):
        h = 1e-3
        slope = (math.log(law.walther_viscosity(T + h, A, B))
                 - math.log(law.walther_viscosity(T - h, A, B))) / (2 * h)
        assert law.walther_temperature_coefficient(T, A, B) == pytest.approx(-slope, rel=1e-6)
