"""The characteristic defect frequencies (analysis/defect_frequencies.py, physics/frequencies.py).

References: pure rolling against Harris's closed forms typed here (Harris & Kotzalas, *Rolling
Bearing Analysis*, 5th ed., Vol. 1, §8; contact angle 0, outer ring fixed, γ = D/d_m):

    BPFO = Z/2 f_s (1 − γ cos α),  BPFI = Z/2 f_s (1 + γ),  BSF = d_m/(2D) f_s (1 − γ²),
    FTF = f_s/2 (1 − γ);

the measured ones against a run's own cage and roller spin speeds through independent
relations: FTF is the mean cage speed in Hz, BPFO = Z FTF (Z rollers pass a point of the
fixed outer race per cage revolution), BPFO + BPFI = Z f_s, BSF the mean roller spin in Hz.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from bearingdae.analysis.defect_frequencies import (defect_frequency_attrs, match, orders,
                                                    run_defect_frequencies, variable_name)
from bearingdae.analysis.result_variables import RESULT_VARIABLES, results_of
from bearingdae.physics.frequencies import characteristic_frequencies


@pytest.mark.parametrize("Z, D, dm, fs", [
    (20, 4.0e-3, 45.0e-3, 2000.0 / 60.0),   # yang20 at the baseline speed
    (13, 7.5e-3, 39.0e-3, 30.0),            # a small bearing, few large rollers
    (36, 9.0e-3, 160.0e-3, 2.5)])           # a large one, slow
def test_pure_rolling_values_are_harris(Z, D, dm, fs):
    g, cos_a = D / dm, math.cos(0.0)
    harris = {"bpfo": Z / 2 * fs * (1 - g * cos_a), "bpfi": Z / 2 * fs * (1 + g),
              "bsf": dm / (2 * D) * fs * (1 - g * g), "ftf": fs / 2 * (1 - g)}
    harris["2bsf"] = 2 * harris["bsf"]
    attrs = defect_frequency_attrs(characteristic_frequencies(Z, D, dm, fs), Z, None, None)
    assert set(attrs) == {variable_name(k, True) for k in harris}  # no measured ones
    for key, ref in harris.items():
        assert attrs[variable_name(key, True)] == pytest.approx(ref, rel=1e-12), key


def test_every_defect_frequency_is_a_result_variable_in_hz():
    for key in ("bpfo", "bpfi", "bsf", "2bsf", "ftf"):
        for pure in (False, True):
            q = RESULT_VARIABLES[variable_name(key, pure)]
            assert q.units == "Hz" and ("pure rolling" in q.long_name) == pure


@pytest.fixture(scope="module")
def short_run(tmp_path_factory):
    """The baseline over 0.05 cage revolution, streamed to a file and read back."""
    from bearingdae import load_scene, simulate

    path = tmp_path_factory.mktemp("defects") / "run.nc"
    scene = load_scene("yang20_baseline", {"numerics.warmup_cage_revolutions": 0,
                                           "numerics.cage_revolutions": 0.05})
    simulate(scene, output=path, progress=False)
    with xr.open_dataset(path) as ds:
        return ds.load()


def test_a_run_records_its_measured_defect_frequencies(short_run):
    ds = short_run
    Z = ds.sizes["roller"]
    fs = 2000.0 / 60.0
    start = float(ds.record_start_s)
    window = ds.sel(time=ds.time >= start)
    f_c = float(window.cage_speed.mean()) / (2 * math.pi)
    spin = float(window.spin_speed.mean()) / (2 * math.pi)
    measured = {k: float(ds[variable_name(k)]) for k in ("bpfo", "bpfi", "bsf", "2bsf", "ftf")}
    assert measured["ftf"] == pytest.approx(f_c, rel=1e-9)
    assert measured["bpfo"] == pytest.approx(Z * f_c, rel=1e-9)
    assert measured["bpfo"] + measured["bpfi"] == pytest.approx(Z * fs, rel=1e-9)
    assert measured["bsf"] == pytest.approx(spin, rel=1e-9)
    assert measured["2bsf"] == pytest.approx(2 * spin, rel=1e-9)
    # slip: measured differs from pure rolling, by little on the baseline
    pure = float(ds[variable_name("bpfo", True)])
    assert measured["bpfo"] != pure and measured["bpfo"] == pytest.approx(pure, rel=2e-2)
    assert ds[variable_name("bpfo")].attrs["units"] == "Hz"
    assert "BPFO" in ds[variable_name("bpfo")].attrs["long_name"]
    stacked = results_of(ds)  # what a sweep stacks per point
    assert {variable_name(k, p) for k in measured for p in (False, True)} <= set(stacked)
    freqs, shaft, source = run_defect_frequencies(ds)
    assert freqs == measured and shaft == pytest.approx(fs) and source.startswith("measured")


def test_a_file_without_them_falls_back_to_its_speeds_then_pure_rolling(short_run):
    names = [n for n in short_run.data_vars if n.startswith("defect_frequency_")]
    old = short_run.drop_vars(names)
    freqs, _, source = run_defect_frequencies(old)
    assert source.startswith("measured")
    assert freqs["ftf"] == pytest.approx(float(old.cage_speed.mean()) / (2 * math.pi))
    freqs, _, source = run_defect_frequencies(old.drop_vars(["cage_speed", "spin_speed"]))
    assert source == "pure rolling"
    assert freqs["bpfo"] == pytest.approx(float(short_run[variable_name("bpfo", True)]))


def test_orders_carry_harmonics_and_the_sidebands_that_apply():
    freqs = {"bpfo": 30.0, "bpfi": 50.0, "bsf": 12.0, "2bsf": 24.0, "ftf": 1.5}
    got = {o.label: o.frequency_Hz for o in orders(freqs, 4.0, 110.0)}
    assert got["2×BPFO"] == 60.0 and got["3×BPFO"] == 90.0 and "4×BPFO" not in got
    assert got["BPFI−fs"] == 46.0 and got["BPFI+fs"] == 54.0 and got["2×BPFI+fs"] == 104.0
    assert got["2×BSF"] == 24.0 and got["2×BSF−FTF"] == 22.5 and got["4×BSF+FTF"] == 49.5
    assert got["FTF"] == 1.5 and got["fs"] == 4.0 and "BPFO−fs" not in got
    assert "3×FTF" in got and "4×FTF" not in got and "4×fs" not in got  # few slow lines
    o = orders(freqs, 4.0, 110.0)
    assert match(60.2, o, 0.25).label == "2×BPFO"
    assert match(61.0, o, 0.25) is None


def test_the_quasi_static_ring_over_a_pitch_has_the_load_line_symmetry():
    """varying_compliance: with a roller on the load line the set is mirror-symmetric about
    it, so the radial displacement is even in the set's position and the tangential one odd
    (zero at position 0); its amplitudes are the Fourier components of that record."""
    from bearingdae import load_scene
    from bearingdae.analysis.varying_compliance import varying_compliance

    vc = varying_compliance(load_scene("yang20_baseline", {"operating.moment_Nm": 0.0,
                                                           "operating.speed_rpm": 500.0}),
                            positions=16, harmonics=3)
    d = vc.ring_displacement.values
    mirror = d[(-np.arange(16)) % 16]
    np.testing.assert_allclose(mirror[:, 0], d[:, 0], rtol=1e-9)
    np.testing.assert_allclose(mirror[:, 1], -d[:, 1], atol=1e-6 * np.abs(d[:, 1]).max())
    # across the load a sawtooth: on the load line it sits at the middle of its jump
    assert abs(d[0, 1]) < 1e-3 * np.abs(d[:, 1]).max()
    k = np.arange(1, 4)
    j = np.arange(16) / 16
    for c in range(2):  # least-squares sines and cosines: the amplitudes another way
        A = np.column_stack([np.ones(16)] + [f(2 * np.pi * kk * j) for kk in k
                                             for f in (np.cos, np.sin)])
        coef = np.linalg.lstsq(A, d[:, c], rcond=None)[0]
        np.testing.assert_allclose(vc.amplitude.values[:, c], np.hypot(coef[1::2], coef[2::2]),
                                   rtol=1e-6, atol=1e-15)


def test_a_peak_between_two_orders_takes_the_nearer():
    freqs = {"bpfo": 75.65, "bpfi": 91.02, "bsf": 46.43, "2bsf": 92.86, "ftf": 3.78}
    o = orders(freqs, 8.333, 200.0)
    assert match(91.5, o, 1.9).label == "BPFI" and match(92.5, o, 1.9).label == "2×BSF"
    assert match(20.7, o, 18.5).label == "2×fs"


def test_every_harmonic_in_range_carries_its_sidebands():
    """BPFI ± m f_s and 2×BSF ± m FTF (m = 1, 2) around every harmonic taken, typed here:
    363.0 Hz × 4 − 2 × 33.33 Hz = 1385.3 Hz lies below 4 × 363.0 = 1452 Hz, and 4 × 363.0 −
    33.33 lies below an fmax of 1451 Hz although 4 × BPFI itself is above it."""
    bpfi, fs, bsf, ftf = 363.0, 100.0 / 3.0, 186.0, 15.18
    freqs = {"bpfo": 303.7, "bpfi": bpfi, "bsf": bsf, "2bsf": 2 * bsf, "ftf": ftf}
    got = {o.label: o.frequency_Hz for o in orders(freqs, fs, 1451.0, sidebands=2)}
    assert got["4×BPFI−2×fs"] == pytest.approx(4 * bpfi - 2 * fs)
    assert got["4×BPFI−fs"] == pytest.approx(4 * bpfi - fs) and "4×BPFI" not in got
    assert "4×BPFI+fs" not in got  # above fmax
    assert got["6×BSF+2×FTF"] == pytest.approx(6 * bsf + 2 * ftf)
    expected = {f"{k}×BPFI{s}{m}" for k in range(1, 5) for s in "−+" for m in ("fs", "2×fs")
                if 0 < k * bpfi + (1 if s == "+" else -1) * (1 if m == "fs" else 2) * fs
                <= 1451.0}
    shown = {lab.replace("1×", "") for lab in expected}
    assert shown == {lab for lab in got if "BPFI" in lab and ("fs" in lab)}


def test_the_speeds_fallback_reads_the_recorded_window(short_run):
    """A file without the measured variables: FTF from the mean cage speed over the recorded
    window (time >= record_start_s), as the spectra read it, not over the warm-up too."""
    names = [n for n in short_run.data_vars if n.startswith("defect_frequency_")]
    t = short_run.time.values
    start = float(t[t.size // 2])
    old = short_run.drop_vars(names)
    # a warm-up whose cage ran 10 % slower: the whole record's mean would move FTF by ~5 %
    slow = old.cage_speed.where(old.time >= start, 0.9 * old.cage_speed)
    old = old.assign(cage_speed=slow)
    old["record_start_s"] = xr.DataArray(start, attrs=short_run.record_start_s.attrs)
    freqs, _, source = run_defect_frequencies(old)
    window = float(old.cage_speed.sel(time=old.time >= start).mean()) / (2 * math.pi)
    assert source.startswith("measured")
    assert freqs["ftf"] == pytest.approx(window, rel=1e-12)
    assert abs(float(old.cage_speed.mean()) / (2 * math.pi) / window - 1.0) > 0.02
