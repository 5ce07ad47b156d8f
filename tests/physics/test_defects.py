"""The laws of local defects and waviness (physics/defects.py), against values typed afresh:
the cylinder's sag over a chord, the ramp's ends, the covered share of a slice, the waviness
slope by central differences and the shaft angle by a fine trapezoid sum of the speed law."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearingdae.physics.defects import (EDGE_MIN_M, defect_depth, defect_profile,
                                        defect_separation, edge_ramp, waviness_separation,
                                        width_share)
from bearingdae.physics.loads import shaft_angle
from bearingdae.system.residual import ring_speed_at


def test_a_roller_rides_over_a_short_pit():
    """Reachable depth: the sag of a 2 mm radius cylinder over a 1 mm chord, typed afresh:
    2 - sqrt(4 - 0.25) mm = 0.0635 mm; a shallower pit is reached to its bottom."""
    assert defect_depth(1e-3, 1e-3, 2e-3) == pytest.approx((2.0 - math.sqrt(3.75)) * 1e-3)
    assert defect_depth(10e-6, 1e-3, 2e-3) == 10e-6
    assert defect_depth(10e-6, 5e-3, 2e-3) == 10e-6  # longer than the roller: no limit


def test_profile_ramps_and_ends():
    half, e = 1e-3, 0.2e-3
    assert defect_profile(0.0, half, e) == (1.0, 0.0)
    assert defect_profile(0.79e-3, half, e)[0] == 1.0
    assert defect_profile(1.0e-3, half, e) == (0.0, 0.0)
    assert defect_profile(-1.2e-3, half, e) == (0.0, 0.0)
    # mid-ramp: u = 1/2 -> 3/4 - 1/4 = 1/2; slope -6 u (1 - u)/e = -1.5/e on the s > 0 side
    v, dv = defect_profile(0.9e-3, half, e)
    assert v == pytest.approx(0.5) and dv == pytest.approx(-1.5 / e)
    assert defect_profile(-0.9e-3, half, e)[1] == pytest.approx(1.5 / e)
    assert edge_ramp(0.0, 2e-3) == EDGE_MIN_M
    assert edge_ramp(0.3e-3, 2e-3) == 0.3e-3
    assert edge_ramp(0.3e-3, 0.2e-3) == 0.1e-3  # never more than half the length
    assert edge_ramp(0.0, 4e-6) == 2e-6


@pytest.mark.parametrize("phi", [0.011, -0.0123, 0.0125, 0.3])
def test_separation_slope_by_central_differences(phi):
    args = (0.0, 0.0245, 0.5e-3, 0.2e-3, 30e-6)
    h = 1e-8
    up, down = defect_separation(phi + h, *args)[0], defect_separation(phi - h, *args)[0]
    assert defect_separation(phi, *args)[1] == pytest.approx((up - down) / (2 * h), rel=1e-5,
                                                            abs=1e-9)
    w_up, w_down = waviness_separation(phi + h, 7, 1e-6, 0.4)[0], waviness_separation(
        phi - h, 7, 1e-6, 0.4)[0]
    assert waviness_separation(phi, 7, 1e-6, 0.4)[1] == pytest.approx((w_up - w_down) / (2 * h),
                                                                     rel=1e-6)


def test_width_share():
    w = 2e-3
    assert width_share(0.0, w, 3e-3) == 1.0
    assert width_share(3e-3, w, 3e-3) == pytest.approx(0.5)  # the border at the slice centre
    assert width_share(5e-3, w, 3e-3) == 0.0
    assert width_share(0.0, w, 0.5e-3) == pytest.approx(0.5)  # a narrow defect: its fraction


@pytest.mark.parametrize("t", [0.0, 0.004, 0.01, 0.0175, 0.05])
def test_shaft_angle_is_the_integral_of_the_speed_law(t):
    ramp_t = np.array([0.002, 0.01, 0.02])
    ramp_w = np.array([50.0, 200.0, 150.0])
    tau = np.linspace(0.0, t, 20001)
    w = np.array([ring_speed_at(x, ramp_t, ramp_w) for x in tau])
    ref = float(np.sum(0.5 * (w[1:] + w[:-1]) * np.diff(tau))) if t > 0 else 0.0
    assert shaft_angle(t, ramp_t, ramp_w) == pytest.approx(ref, rel=1e-7, abs=1e-12)
    assert shaft_angle(t, np.array([0.0]), np.array([100.0])) == pytest.approx(100.0 * t)
