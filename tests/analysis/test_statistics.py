"""Error bars of run statistics (bearingdae/analysis/statistics.py).

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

from bearingdae.analysis.statistics import (MIN_BATCHES, batch_mean, run_statistics,
                                           with_error)
from conftest import ar1 as _ar1


def ar1(phi: float, n: int, rng) -> np.ndarray:
    return _ar1(phi, n, rng, burn=2000)


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


def test_the_total_power_loss_and_friction_torque_with_their_error_bars():
    """The 0-d mean power loss [W] and friction torque [N mm] are the time means of the totals
    over the loss sources, with the blocking error: white noise of σ per source and sample,
    3 sources, gives SE = σ sqrt(3 / n) for the total; the torque in N mm is 1000 x N m."""
    rng = np.random.default_rng(5)
    n, sigma = 4096, 0.01
    loss = 0.1 + sigma * rng.standard_normal((n, 3))
    torque = 2e-3 + 1e-5 * rng.standard_normal((n, 3))
    ds = xr.Dataset({"power_loss_W": (("time", "loss_source"), loss),
                     "friction_torque_N_m": (("time", "loss_source"), torque)},
                    coords={"time": np.arange(n) * 1e-4}, attrs={"epicyclic_cage_speed_rad_s": 0.0})
    st = run_statistics(ds)
    p, m = st["mean_power_loss_W"], st["mean_friction_torque_N_mm"]
    assert p.mean == pytest.approx(np.mean(loss.sum(axis=1)), rel=1e-12)
    assert p.stderr == pytest.approx(sigma * np.sqrt(3 / n), rel=0.35)
    assert m.mean == pytest.approx(1e3 * np.mean(torque.sum(axis=1)), rel=1e-12)
    assert m.stderr == pytest.approx(1e3 * 1e-5 * np.sqrt(3 / n), rel=0.35)
    from bearingdae.analysis.result_variables import RESULT_VARIABLES

    assert RESULT_VARIABLES["mean_friction_torque_N_mm"].units == "N mm"
    assert RESULT_VARIABLES["mean_power_loss_W"].error == "mean_power_loss_stderr_W"


@pytest.mark.parametrize("value, se, text", [
    (95.05213, 0.0021, "95.0521 ± 0.0021"), (0.00381, 0.00042, "0.00381 ± 0.00042"),
    (12.0, float("nan"), "12"), (1234.5, 12.3, "1234 ± 12")])
def test_value_with_error_is_rounded_to_the_error(value, se, text):
    assert with_error(value, se) == text


@pytest.mark.parametrize("value, se, text", [
    # the skew RMS of a preloaded defect case (defects/inner_spall) in mrad: round-off, which
    # the summary printed as 0.00000000000000003881 ± 0.00000000000000000020
    (3.881e-17, 2.0e-19, "(3.881 ± 0.020)e-17"), (-1.2e-9, 3.4e-10, "(-1.20 ± 0.34)e-09"),
    (0.0, 5.0e-12, "(0.0 ± 5.0)e-12"), (1.234567e-6, 4.5e-8, "(1.235 ± 0.045)e-06")])
def test_a_tiny_value_with_error_shares_a_power_of_ten(value, se, text):
    """More than MAX_DECIMALS decimals: mantissas with a common exponent, the error's two
    significant figures kept."""
    assert with_error(value, se) == text


def test_a_run_carries_its_error_bars():
    """simulate() stores every statistic with its standard error (names with units) and names
    the estimator; the values are those of run_statistics on the Dataset itself."""
    from bearingdae import load_scene, simulate

    ds = simulate(load_scene("yang20_baseline", {"numerics.warmup_cage_revolutions": 0,
                                                 "numerics.cage_revolutions": 0.25,
                                                 "numerics.slices": 4}), progress=False)
    st = run_statistics(ds)
    assert ds["mean_cage_speed_rad_s"].item() == pytest.approx(float(ds.cage_speed.mean()))
    assert ds["mean_cage_speed_stderr_rad_s"].item() == st["mean_cage_speed_rad_s"].stderr > 0
    assert ds["cage_slip_ratio_stderr"].item() == pytest.approx(
        ds["mean_cage_speed_stderr_rad_s"].item() / ds["epicyclic_cage_speed_rad_s"].item())
    assert ds["skew_rms_stderr_rad"].item() > 0 and "Flyvbjerg" in ds.attrs[
        "statistics_estimator"]


def synthetic_peaks(n_passes: int, per_pass: int, rollers: int, epicyclic: float, rng):
    """A Dataset holding a peak trace of independent U(0, 1) samples, ``per_pass`` samples in
    each roller-pass period, and what peak_statistics needs (roller dimension, attribute)."""
    period = 2 * np.pi / (rollers * epicyclic)
    n = n_passes * per_pass + 1
    t = 0.3 + period / per_pass * np.arange(n)
    trace = rng.uniform(size=n)
    trace[0] = np.nan  # the window's first sample closes an interval before it
    return xr.Dataset({"cage_force_peak": ("time", trace)},
                      coords={"time": t, "roller": np.arange(1, rollers + 1)},
                      attrs={"epicyclic_cage_speed_rad_s": epicyclic})


def test_roller_pass_peaks_of_iid_samples_match_order_statistics():
    """Reference: the largest of m independent U(0, 1) samples has mean m/(m+1) and variance
    m/((m+1)²(m+2)) (order statistics of the uniform distribution); with independent blocks
    the error bar of the mean of n block maxima is sqrt(var/n). Over 40 replicates the mean
    estimate is within 3 of its standard errors of m/(m+1) (n = 512 blocks: SE 1e-3), and the
    mean error bar within 15 % of the analytic one (the blocking estimator's scatter, as
    above)."""
    from bearingdae.analysis.statistics import peak_statistics

    rng = np.random.default_rng(20261127)
    m, n, Z, omega = 20, 512, 14, 95.0
    est = [peak_statistics(synthetic_peaks(n, m, Z, omega, rng), omega)
           ["roller_pass_peak_cage_force_N"] for _ in range(40)]
    exact_se = np.sqrt(m / ((m + 1) ** 2 * (m + 2)) / n)
    means = np.array([e.mean for e in est])
    assert abs(means.mean() - m / (m + 1)) < 3 * exact_se / np.sqrt(40)
    assert all(e.batches >= MIN_BATCHES for e in est)
    assert abs(np.mean([e.stderr for e in est]) / exact_se - 1) < 0.15


def test_roller_pass_blocks_are_whole_periods():
    """Blocks of 2π/(Z Ω_e): 20 samples each after the first sample (a sample closes the
    interval before it: one on a block's end belongs to that block); the first sample and the
    samples of a last, incomplete block take no part."""
    from bearingdae.analysis.statistics import block_maxima, roller_pass_blocks

    ds = synthetic_peaks(5, 20, 14, 95.0, np.random.default_rng(1))
    t = ds.time.values
    extra = np.concatenate([t, t[-1] + (t[1] - t[0]) * np.arange(1, 8)])
    b = roller_pass_blocks(extra, 14, 95.0)
    assert b[0] == -1 and np.array_equal(b[1:101], np.repeat(np.arange(5), 20))
    assert np.all(b[101:] == -1)
    v = np.arange(extra.size, dtype=float)
    assert np.array_equal(block_maxima(v, b), [v[b == k].max() for k in range(5)])
    assert roller_pass_blocks(t, 14, 0.0).max() == -1  # at zero speed: no blocks


def test_a_run_reports_its_peak_statistics_with_error_bars():
    """The peak traces of a run and their statistics: each trace's largest value is the
    window's per-step extreme (bit for bit: the intervals partition the counted steps); the
    mean peak per roller pass is recomputed here from the trace by an independent loop over
    the periods; the run summary prints it with its error bar."""
    from bearingdae import load_scene, simulate

    ds = simulate(load_scene("yang20_baseline", {"numerics.warmup_cage_revolutions": 0.05,
                                                 "numerics.cage_revolutions": 0.5}),
                  progress=False)
    assert float(ds.cage_force_peak.max()) == float(ds.cage_force_max.max())
    assert float(ds.contact_pressure_peak.max()) == float(ds.contact_pressure_max.max())
    assert float(ds.skew_angle_peak.max()) == float(ds.skew_angle_max.max())
    assert float(ds.slip_velocity_peak.max()) == float(ds.slip_velocity_max.max())
    period = 2 * np.pi / (ds.sizes["roller"] * ds["epicyclic_cage_speed_rad_s"].item())
    t, f = ds.time.values, ds.cage_force_peak.values
    maxima, start = [], t[0]
    while start + period <= t[-1] * (1 + 1e-12):  # each sample closes the interval before it
        inside = (t > start + 1e-15) & (t <= start + period + 1e-15)
        maxima.append(np.nanmax(f[inside]))
        start += period
    assert ds["roller_pass_peak_cage_force_N"].item() == pytest.approx(np.mean(maxima),
                                                                    rel=1e-12)
    assert ds["roller_pass_peak_cage_force_stderr_N"].item() > 0
    assert "roller_pass_peak_cage_force_N" in run_statistics(ds)
