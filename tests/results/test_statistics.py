"""Error bars of run statistics (bearingdae/results/statistics.py).

Reference: the AR(1) process x_k = φ x_{k−1} + e_k (e_k white, variance σ²) has the stationary
variance σ²/(1 − φ²) and, for n ≫ 1/(1 − φ), the variance of its n-sample mean
σ²/(n (1 − φ)²) (the integrated autocorrelation time (1 + φ)/(1 − φ) times the white-noise
value). The blocking estimate of one series is itself a random variable (~10-25 % relative
scatter at the level used), so single-series checks allow 40 %, and the check over 40 replicates
compares the mean estimate with the analytic value to 15 %.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from bearingdae.results.statistics import (MIN_BATCHES, batch_mean, run_statistics,
                                           with_error)


def ar1(phi: float, n: int, rng) -> np.ndarray:
    e = rng.standard_normal(n + 2000)
    x = np.empty_like(e)
    x[0] = e[0]
    for k in range(1, e.size):
        x[k] = phi * x[k - 1] + e[k]
    return x[2000:]  # the start-up transient dropped


def analytic_se(phi: float, n: int) -> float:
    return 1.0 / (np.sqrt(n) * (1.0 - phi))


@pytest.mark.parametrize("phi", [0.0, 0.9, 0.98])
def test_blocking_error_matches_the_ar1_value(phi):
    rng = np.random.default_rng(20261125)
    n = 2**15
    estimates = [batch_mean(ar1(phi, n, rng)) for _ in range(40)]
    se = np.array([e.stderr for e in estimates])
    assert abs(se.mean() / analytic_se(phi, n) - 1) < 0.15, (se.mean(), analytic_se(phi, n))
    scatter = np.array([1 / np.sqrt(2 * (e.batches - 1)) for e in estimates])
    assert np.all(np.abs(se / analytic_se(phi, n) - 1) < 3.5 * scatter)
    assert not any(e.correlated for e in estimates)


def test_naive_error_would_be_far_too_small_for_correlated_samples():
    """What the estimator is for: at φ = 0.98 σ/√n is ~7x too small; blocking is not."""
    rng = np.random.default_rng(7)
    x = ar1(0.98, 2**15, rng)
    naive = x.std(ddof=1) / np.sqrt(x.size)
    assert batch_mean(x).stderr > 5 * naive


def test_too_short_a_window_is_flagged_and_tiny_series_have_no_error():
    rng = np.random.default_rng(3)
    short = ar1(0.999, 400, rng)  # correlation time ~2000 samples >> the series
    assert batch_mean(short).correlated
    tiny = batch_mean(np.arange(MIN_BATCHES - 1.0))
    assert np.isnan(tiny.stderr) and tiny.mean == pytest.approx(4.0)


def test_run_statistics_propagate_to_slip_and_rms():
    rng = np.random.default_rng(11)
    n = 4096
    cage = 95.0 + 0.05 * ar1(0.9, n, rng)
    skew = 1e-3 * rng.standard_normal((n, 4))
    ds = xr.Dataset({"cage_speed": (("time",), cage),
                     "skew_angle": (("time", "roller"), skew)},
                    coords={"time": np.arange(n) * 1e-4},
                    attrs={"epicyclic_cage_speed_rad_s": 100.0})
    st = run_statistics(ds)
    c, s = st["mean_cage_speed_rad_s"], st["cage_slip_ratio"]
    assert s.mean == pytest.approx(1 - c.mean / 100.0) and s.stderr == pytest.approx(
        c.stderr / 100.0)
    rms = st["skew_rms_rad"]
    assert rms.mean == pytest.approx(np.sqrt((skew**2).mean()))
    # white per-roller noise: SE(mean x²) = sqrt(2) σ² / sqrt(4 n), so SE(rms) = σ / sqrt(8 n)
    assert rms.stderr == pytest.approx(1e-3 / np.sqrt(8 * n), rel=0.35)
    assert "rms_cage_force_N" not in st


@pytest.mark.parametrize("value, se, text", [
    (95.05213, 0.0021, "95.0521 ± 0.0021"), (0.00381, 0.00042, "0.00381 ± 0.00042"),
    (12.0, float("nan"), "12"), (1234.5, 12.3, "1234 ± 12")])
def test_value_with_error_is_rounded_to_the_error(value, se, text):
    assert with_error(value, se) == text
