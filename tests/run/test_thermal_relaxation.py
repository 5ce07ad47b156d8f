"""The thermal coupling's fixed point under-relaxed once it overshoots (run/thermal_coupling.py).

A cold oil inlet swung the plain iteration between thick oil (large losses, a hot network
answer) and thin oil (small losses, a cold one): 200 blocks, a roller node at 1330 °C. The
reference here is the linear map g(x) = a - b x, whose fixed point a / (1 + b) is known and
whose plain iteration diverges for b > 1 (the swing), typed afresh in the test.
"""

from __future__ import annotations

import pytest

from bearingdae.run.thermal_coupling import Relaxation


def iterate(g, x0: float, steps: int, relax: Relaxation | None):
    xs = [x0]
    for _ in range(steps):
        x = xs[-1]
        w = relax.step(x, g(x)) if relax is not None else 1.0
        xs.append(x + w * (g(x) - x))
    return xs


@pytest.mark.parametrize("b", [1.5, 3.0, 20.0])
def test_an_overshooting_fixed_point_settles_when_relaxed(b):
    a = 100.0
    g = lambda x: a - b * x  # noqa: E731
    fixed = a / (1.0 + b)
    plain = iterate(g, 0.0, 60, None)
    assert abs(plain[-1] - fixed) > 1e3  # the plain iteration swings away
    relaxed = iterate(g, 0.0, 60, Relaxation())
    assert relaxed[-1] == pytest.approx(fixed, abs=1e-6 * a)


def test_a_monotone_fixed_point_is_the_plain_iteration_number_for_number():
    """No overshoot, no relaxation: a thermal run that converged before is unchanged."""
    g = lambda x: 0.5 * x + 30.0  # noqa: E731
    r = Relaxation()
    assert iterate(g, 20.0, 30, r) == iterate(g, 20.0, 30, None) and r.factor == 1.0


def test_the_factor_stops_at_its_floor():
    r = Relaxation()
    for k in range(40):
        r.step(0.0, (-1.0) ** k)
    assert r.factor == Relaxation.MIN_FACTOR
