"""Trend readings with block error bars (bearingdae/analysis/trends.py) and the claim verdicts
(bearingdae/studies/trends.py).

References: the readings are typed afresh here as explicit loops over a small synthetic
bearing whose every value is known; the error bars against the AR(1) process (see
test_statistics.py: the variance of the n-sample mean of x_k = φ x_{k−1} + e_k is
σ²/(n (1 − φ)²) for n ≫ 1/(1 − φ)); the verdicts against hand-made sweeps.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from bearingdae.analysis import trends as T
from bearingdae.studies.trends import verdict
from conftest import ar1 as _ar1


def ar1(phi: float, n: int, rng) -> np.ndarray:
    return _ar1(phi, n, rng, burn=500)


@pytest.mark.parametrize("phi, coverage", [(0.0, 0.94), (0.2, 0.91)])
def test_block_error_bars_cover_a_correlated_series(phi, coverage):
    """64 blocks of an AR(1) series (neighbouring blocks correlated as in our runs, whose
    half-revolution blocks have lag-1 correlations of -0.4 to +0.5, mostly |ρ1| < 0.25): the
    mean lies within 2 SE of the true mean 0 in at least ``coverage`` of 400 replicates (0.95
    for an exact Gaussian error; 16 blocks at the longest level cost a little), and the SE is
    at most 1.3 times the AR(1) value (not uselessly wide). At φ = 0.5 the coverage falls to
    ~0.89 (the levels have not reached the plateau): what docs/validation.md's plateau and
    repeat checks exclude for the trend runs."""
    rng = np.random.default_rng(20261127)
    est = [T.block_estimate(ar1(phi, 64, rng)) for _ in range(400)]
    z = np.array([e.mean / e.stderr for e in est])
    assert np.mean(np.abs(z) < 2) >= coverage, np.mean(np.abs(z) < 2)
    se = np.mean([e.stderr for e in est])
    assert se < 1.3 / (8 * (1 - phi)), se
    assert all(e.n_blocks == 64 for e in est)


# -- a synthetic bearing: Z = 4 rollers, 2 slices, epicyclic cage speed 2π rad/s (1 rev/s) ----
Z, PER_REV, REVS = 4, 40, 2.0


def synthetic() -> xr.Dataset:
    t = np.arange(int(REVS * PER_REV) + 1) / PER_REV
    az = 2 * np.pi * t[:, None] + 2 * np.pi * np.arange(Z)[None, :] / Z + 0.05
    rng = np.random.default_rng(7)
    q = rng.uniform(0, 10, (t.size, Z, 2, 2))
    v = rng.normal(0, 1, (t.size, Z, 2, 2))
    skew = rng.normal(0, 1e-3, (t.size, Z))
    cage = rng.normal(0, 1, (t.size, Z, 2))
    dims4 = ("time", "roller", "slice", "race")
    return xr.Dataset(
        {"roller_azimuth": (("time", "roller"), az),
         "orbit_speed": (("time", "roller"), 2 * np.pi * (1 - 0.01 * np.cos(az))
                         + rng.normal(0, 0.01, az.shape)),
         "cage_speed": ("time", 2 * np.pi * (0.99 + 0.001 * np.sin(t))),
         "skew_angle": (("time", "roller"), skew), "contact_force": (dims4, q),
         "slip_velocity": (dims4, v), "traction_force": (dims4, 0.1 * q * np.sign(v)),
         "cage_force": (("time", "roller", "end"), cage),
         "slip_velocity_peak": ("time", np.abs(v).max(axis=(1, 2, 3)) * 1.1),
         "skew_angle_peak": ("time", np.abs(skew).max(axis=1) * 1.1),
         "cage_force_peak": ("time", np.abs(cage).max(axis=(1, 2)) * 1.1)},
        coords={"time": t, "roller": np.arange(1, Z + 1), "race": ["inner", "outer"]},
        attrs={"epicyclic_cage_speed_rad_s": 2 * np.pi})


def samples_of_block(t, b, length):
    """Sample k carries the interval (t[k-1], t[k]] (k >= 1): the block that interval is in."""
    return [k for k in range(1, t.size) if np.ceil(t[k] / length - 1e-9) - 1 == b]


def test_readings_typed_afresh():
    ds = synthetic()
    t = ds.time.values
    q, v = ds.contact_force.values, ds.slip_velocity.values
    az, th = ds.roller_azimuth.values, ds.skew_angle.values
    for b in range(4):  # 4 half-revolution blocks in 2 revolutions
        ks = samples_of_block(t, b, 0.5)
        assert len(ks) == PER_REV // 2
        num = sum(q[k, j, s, r] * abs(v[k, j, s, r]) for k in ks for j in range(Z)
                  for s in range(2) for r in range(2))
        assert T.block_values(ds, "sliding_speed", "load_weighted")[b] == pytest.approx(
            num / q[ks].sum(), rel=1e-12)
        inside = [(k, j) for k in ks for j in range(Z)
                  if np.cos(az[k, j]) > np.cos(np.radians(30.0))]
        assert T.block_values(ds, "skew", "loaded_zone")[b] == pytest.approx(
            np.mean([abs(th[k, j]) for k, j in inside]), rel=1e-12)
        assert T.block_values(ds, "sliding_speed", "loaded_zone")[b] == pytest.approx(
            max(abs(v[k, j]).max() for k, j in inside), rel=1e-12)
        per_roller_max = [max(abs(th[k, j]) for k in ks) for j in range(Z)]
        assert T.block_values(ds, "skew", "orbit_amplitude")[b] == pytest.approx(
            np.mean(per_roller_max), rel=1e-12)
        assert T.block_values(ds, "cage_slip", "orbit_mean")[b] == pytest.approx(
            1 - np.mean(ds.cage_speed.values[ks]) / (2 * np.pi), rel=1e-12)
        inner = v[:, :, :, 0]
        spread = max(inner[k, j].max() - inner[k, j].min() for k in ks for j in range(Z))
        assert T.block_values(ds, "slice_slip_difference", "orbit_max")[b] == pytest.approx(
            spread, rel=1e-12)
        # pass peaks: passes of 1/Z revolution, Z/2 = 2 per block
        peak = ds.cage_force_peak.values
        passes = [samples_of_block(t, p, 1.0 / Z) for p in (2 * b, 2 * b + 1)]
        assert T.block_values(ds, "pocket_force", "pass_peak")[b] == pytest.approx(
            np.mean([peak[p].max() for p in passes]), rel=1e-12)


def test_every_reading_gives_one_value_per_whole_block():
    stats = T.trend_statistics(synthetic())
    assert len(stats) == sum(len(r) for _, r in T.READINGS.values())
    assert all(e.n_blocks == 4 and np.isfinite(e.mean) for e in stats.values())


@pytest.mark.parametrize("values, stderr, direction, expected", [
    ([1.0, 2.0, 3.0], [0.1] * 3, +1, "holds"),
    ([1.0, 1.25, 1.1, 3.0], [0.1] * 4, +1, "holds"),        # a dip within 2 SE of the diff.
    ([1.0, 1.6, 1.1, 3.0], [0.1] * 4, +1, "contradicted"),  # a significant dip
    ([3.0, 2.0, 1.0], [0.1] * 3, +1, "contradicted"),
    ([3.0, 2.0, 1.0], [0.1] * 3, -1, "holds"),
    ([1.0, 1.1, 1.2], [0.1] * 3, +1, "not resolved"),       # 2000 -> 2 SE = 0.28 not reached
    ([1.0, 1.0, 1.0], [0.1] * 3, -1, "not resolved"),
])
def test_verdicts(values, stderr, direction, expected):
    assert verdict(values, stderr, direction)[0] == expected


def test_the_size_of_a_contradiction():
    """Largest change against the claim over the range: 3 -> 2 in 1..5 is a quarter."""
    from bearingdae.studies.trends import against_of_range

    assert against_of_range([1.0, 3.0, 2.0, 5.0], +1) == pytest.approx(0.25)
    assert against_of_range([1.0, 3.0, 2.0, 5.0], -1) == pytest.approx(1.0)  # 1 -> 5
    assert against_of_range([1.0, 2.0, 3.0], +1) == 0.0
