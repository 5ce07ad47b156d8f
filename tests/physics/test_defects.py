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
    """Reachable depth on a flat surface (a pitted radius so large that its curvature is nil):
    the sag of a 2 mm radius cylinder over a 1 mm chord, typed afresh: 2 - sqrt(4 - 0.25) mm =
    0.0635 mm; a shallower pit is reached to its bottom, and so is one longer than the roller's
    diameter."""
    flat = 1e9
    assert defect_depth(1e-3, 1e-3, flat, True, 2e-3, True) == pytest.approx(
        (2.0 - math.sqrt(3.75)) * 1e-3, rel=1e-9)
    assert defect_depth(10e-6, 1e-3, flat, True, 2e-3, True) == 10e-6
    assert defect_depth(1e-3, 5e-3, flat, True, 2e-3, True) == 1e-3  # the roller fits in


def _reach_by_construction(pitted_R, pitted_convex, length, bridging_R, bridging_convex):
    """The depth the bridging circle reaches below the pitted surface at the pit's centre, by
    coordinates: that surface point at the origin, the bridging body on the +y side; the pitted
    circle's centre at (0, -R_p) (convex) or (0, +R_p) (concave: the outer race around the
    roller); the pit's edges at arc length ±l/2 on it. The bridging circle touches both edges:
    its centre on the y axis at distance R_b from them, above them (convex: the roller) or
    below (concave: the outer race holding the roller), and its surface point on the axis."""
    a = 0.5 * length / pitted_R
    ex = pitted_R * math.sin(a)
    ey = (-1.0 if pitted_convex else 1.0) * pitted_R * (1.0 - math.cos(a))
    leg = math.sqrt(bridging_R ** 2 - ex ** 2)
    point_y = ey + leg - bridging_R if bridging_convex else ey - leg + bridging_R
    return -point_y


@pytest.mark.parametrize("pitted, bridging", [
    ((20.5e-3, True), (2e-3, True)),     # inner-race pit, bridged by the roller
    ((24.5e-3, False), (2e-3, True)),    # outer-race pit, bridged by the roller
    ((2e-3, True), (20.5e-3, True)),     # roller pit at the inner race
    ((2e-3, True), (24.5e-3, False)),    # roller pit at the outer race
])
def test_the_reach_into_a_pit_follows_both_curvatures(pitted, bridging):
    """A pit 0.5 mm long (arc) on the yang20 bearing's surfaces, deeper than any reach: the
    depth the other surface reaches, against circles placed by coordinates; the races'
    curvature moves it by about r/R (+10 % on the inner race, -8 % on the outer)."""
    length = 0.5e-3
    got = defect_depth(1e-3, length, pitted[0], pitted[1], bridging[0], bridging[1])
    want = _reach_by_construction(pitted[0], pitted[1], length, bridging[0], bridging[1])
    assert got == pytest.approx(want, rel=1e-9)
    # against the roller's own sag over the same chord: about ±r/R more (theory.md §4)
    race_R, roller_R = max(pitted[0], bridging[0]), min(pitted[0], bridging[0])
    R_p = pitted[0]
    c = R_p * math.sin(0.5 * length / R_p)
    own = roller_R - math.sqrt(roller_R ** 2 - c * c)
    sign = 1.0 if race_R == 20.5e-3 else -1.0
    assert got / own - 1.0 == pytest.approx(sign * roller_R / race_R, rel=0.01)


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
