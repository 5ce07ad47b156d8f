"""exp_, log_ and root9 of physics/elementary.py (the contact loop's vectorisable elementary
functions) against numpy's libm-based exp, log and power.

Reference: numpy (correctly rounded to within 1 ulp). Tolerances are the error bounds that
physics/elementary.py states. The compiled and the numpy evaluation run the same operations in
the same order, except that the compiled polynomial steps are fused multiply-adds (one rounding
instead of two): they agree to 1 ulp (exp_), 2 ulp (log_) and 2e-15 relative (root9), so the
static solve (numpy) and the DAE kernels (numba) share one law to round-off. ``mod_`` (the
pocket wrap) is np.mod bit for bit.
"""

from __future__ import annotations

import numba
import numpy as np

from bearingdae.physics.elementary import EXP_ZERO_BELOW, exp_, log_, mod_, root9


@numba.njit(error_model="numpy")
def _map(fn_id, x):
    out = np.empty_like(x)
    for i in range(x.size):
        if fn_id == 0:
            out[i] = exp_(x[i])
        elif fn_id == 1:
            out[i] = log_(x[i])
        else:
            out[i] = root9(x[i])
    return out


def _ulp(a, b):
    return np.max(np.abs(a - b) / np.spacing(np.abs(b)))


def test_exp_within_2_ulp_and_exactly_zero_below_the_cut(rng):
    x = np.concatenate([rng.uniform(EXP_ZERO_BELOW, 709.0, 20000), rng.uniform(-5, 5, 20000),
                        [0.0, -1.0, 1.0, EXP_ZERO_BELOW, 709.0]])
    got = _map(0, x)
    assert _ulp(got, np.exp(x)) <= 2.0
    assert _ulp(got, exp_(x)) <= 1.0  # numba == numpy up to the fused multiply-adds
    assert exp_(0.0) == 1.0
    assert _map(0, np.array([-708.5, -1e300, -np.inf]))[:3].tolist() == [0.0, 0.0, 0.0]
    assert np.isnan(_map(0, np.array([np.nan]))[0])


def test_log_within_4_ulp_on_positive_normal_numbers(rng):
    x = np.concatenate([np.exp(rng.uniform(-700, 700, 20000)), rng.uniform(0.5, 2.0, 20000),
                        [1.0, np.sqrt(2.0), 2.0, 2.2250738585072014e-308]])
    got, ref = _map(1, x), np.log(x)
    far = np.abs(ref) > 0.1  # near x = 1, log x -> 0: an absolute bound (2 ulp of 1)
    assert _ulp(got[far], ref[far]) <= 4.0
    assert np.abs(got - ref)[~far].max() <= 4.5e-16
    numpy_twin = log_(x)
    assert _ulp(got[far], numpy_twin[far]) <= 2.0
    assert np.abs(got - numpy_twin)[~far].max() <= 2.3e-16
    assert log_(1.0) == 0.0


def test_root9_in_the_slice_load_range(rng):
    """s^(1/9) for the smoothed approaches of the contact law, 1e-25 .. 1e-3 m: within 2e-15
    relative (log's absolute error times 1/9); numba == numpy to the same 2e-15."""
    s = np.exp(rng.uniform(np.log(1e-25), np.log(1e-3), 50000))
    got = _map(2, s)
    np.testing.assert_allclose(got, s ** (1.0 / 9.0), rtol=2e-15, atol=0)
    np.testing.assert_allclose(got, root9(s), rtol=2e-15, atol=0)  # log_'s 2 ulp, through exp_


@numba.njit(error_model="numpy")
def _mod_map(x, y):
    out = np.empty_like(x)
    for i in range(x.size):
        out[i] = mod_(x[i], y)
    return out


def test_mod_is_numpy_mod_bitwise(rng):
    """Reference: np.mod (floored remainder, fmod-based and exact). The compiled fma form must
    give the same double everywhere, also at and next to exact multiples of 2π (where x / y
    rounds onto an integer), for negative x, signed zeros, tiny x, inf and NaN."""
    y = 2.0 * np.pi
    k = np.arange(-3000, 3000) * y
    x = np.concatenate([rng.uniform(-1e4, 1e4, 200000), rng.uniform(-10, 10, 200000), k,
                        np.nextafter(k, np.inf), np.nextafter(k, -np.inf), k + 1e-13,
                        [0.0, -0.0, 1e-300, -1e-300, np.pi, -np.pi, np.inf, -np.inf, np.nan]])
    with np.errstate(invalid="ignore"):
        ref = np.mod(x, y)
    got = _mod_map(x, y)
    same = (got == ref) & (np.signbit(got) == np.signbit(ref))
    assert np.all(same | (np.isnan(got) & np.isnan(ref)))
