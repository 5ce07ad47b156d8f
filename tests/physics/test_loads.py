"""Loads as functions of time (physics/loads.py, theory.md §14): the shaft angle against the
exact integral of the speed ramp, the load table against numpy's linear interpolation, the
unbalance load against its closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearingdae.physics.loads import applied_load_series, applied_loads, shaft_angle, table_loads


def test_shaft_angle_is_the_integral_of_the_ramp():
    ramp_t = np.array([0.0, 0.01, 0.03])
    ramp_w = np.array([0.0, 100.0, 300.0])
    # closed form: 0.5 * 100 * 0.01 = 0.5 rad on the first segment, 0.02 * 200 = 4 rad on the
    # second (mean speed 200 rad/s), then 300 rad/s held
    for t, exact in ((0.005, 0.5 * 50.0 * 0.005), (0.01, 0.5), (0.03, 4.5),
                     (0.05, 4.5 + 300.0 * 0.02)):
        assert shaft_angle(t, ramp_t, ramp_w) == pytest.approx(exact, rel=1e-14)
    # against a fine trapezoid sum of np.interp (tolerance: the sum's own error where a ramp
    # point falls between grid points, ~(Δω Δt²) / ψ ≈ 1e-11 here)
    t = np.linspace(0.0, 0.042, 200_001)
    num = np.trapezoid(np.interp(t, ramp_t, ramp_w), t)
    assert shaft_angle(0.042, ramp_t, ramp_w) == pytest.approx(num, rel=1e-10)
    assert shaft_angle(0.2, np.array([0.0]), np.array([50.0])) == pytest.approx(10.0, rel=1e-15)


def test_table_is_linear_between_rows_and_held_at_its_ends(rng):
    n = 1000  # bisection over many rows
    times = np.cumsum(rng.uniform(1e-4, 1e-3, n))
    table = np.column_stack([times, rng.normal(size=(n, 5))])  # F_r, F_t, M, M_t, F_a
    t = np.concatenate([[times[0] - 1.0], rng.uniform(times[0], times[-1], 500), times,
                        [times[-1] + 1.0]])
    got = np.array([table_loads(tk, table) for tk in t])
    for c in range(5):
        np.testing.assert_allclose(got[:, c], np.interp(t, times, table[:, c + 1]),
                                   rtol=0, atol=1e-14)
    one = np.array([[0.0, 800.0, -5.0, 3.0, 0.5, 200.0]])
    assert table_loads(7.0, one) == (800.0, -5.0, 3.0, 0.5, 200.0)


def test_unbalance_turns_with_the_shaft():
    table = np.array([[0.0, 800.0, 10.0, 3.0, 0.0, 200.0]])
    ramp_t, ramp_w = np.array([0.0]), np.array([209.0])
    U, ph = 150.0, math.radians(30.0)
    t = np.linspace(0.0, 0.05, 101)
    got = applied_load_series(t, table, ramp_t, ramp_w, U, ph)
    psi = 209.0 * t + ph
    np.testing.assert_allclose(got[:, 0], 800.0 + U * np.cos(psi), rtol=1e-13)
    np.testing.assert_allclose(got[:, 1], 10.0 + U * np.sin(psi), rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(got[:, 2:], [[3.0, 0.0, 200.0]] * t.size)  # F_a: axial
    # no unbalance: the table's values themselves, bit for bit
    assert applied_loads(0.3, table, ramp_t, ramp_w, 0.0, ph) == (800.0, 10.0, 3.0, 0.0, 200.0)
