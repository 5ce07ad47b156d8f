"""The dynamic ring's recorded vibration (analysis/vibration.py, theory.md §15) and the spectrum
figure's options (plots/plot_spectrum.py, ``plot --spectrum``).

References typed afresh here: a sinusoid's acceleration A ω² and the decimation filter's
transfer function sinc²(f τ) Σ h_j cos(2π f j τ) (pass band, stop band); the triangle-weighted
mean of a sinusoid's acceleration is
-A ω² sinc²(f T) sin(ω t + φ) (the Fourier transform of a unit-area triangle of half-width T),
its interval mean over [t - T, t] is -A ω² sinc(f T) sin(ω (t - T/2) + φ); the natural frequency
of the ring at standstill along the load, sqrt(K/m), with K from two public static solves.
"""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest
import xarray as xr

from bearingdae import simulate, solve_static
from bearingdae.cli import main
from bearingdae.plots.plot_spectrum import draw_spectrum, marker_rows
from bearingdae.analysis.vibration import (RESOLVED_FRACTION_OF_NYQUIST, filtered_acceleration,
                                          natural_frequencies_Hz, vibration_attrs)
from bearingdae.system.model import build_model
from tests.conftest import make_scene

T = 1.0 / 3000.0  # sample interval [s]


def _sine(f_Hz, n=64, A=2e-6, phase=0.3):
    """Samples (t, x, v) of x = A sin(ω t + φ), and the exact acceleration -ω² x."""
    t = 0.01 + T * np.arange(n)
    w = 2.0 * math.pi * f_Hz
    x = A * np.sin(w * t + phase)
    v = A * w * np.cos(w * t + phase)
    return t, x[:, None], v[:, None], -w * w * x[:, None], (A, w, phase)


@pytest.mark.parametrize("fT", [0.13, 0.41, 1.37, 4.9])  # below Nyquist (0.5), above it
def test_a_sinusoid_is_recorded_through_the_triangle_and_the_ends_through_the_boxcar(fT):
    f = fT / T
    t, x, v, a, (A, w, phase) = _sine(f)
    got = filtered_acceleration(t, x, v, a)[:, 0]
    tri = np.sinc(fT) ** 2  # np.sinc(x) = sin(πx)/(πx)
    want = -A * w * w * tri * np.sin(w * t + phase)
    scale = A * w * w
    assert np.max(np.abs(got[1:-1] - want[1:-1])) < 1e-9 * scale
    # the last sample: the mean over its one interval
    box = -A * w * w * np.sinc(fT) * np.sin(w * (t[-1] - 0.5 * T) + phase)
    assert abs(got[-1] - box) < 1e-9 * scale
    box0 = -A * w * w * np.sinc(fT) * np.sin(w * (t[0] + 0.5 * T) + phase)
    assert abs(got[0] - box0) < 1e-9 * scale
    if fT > 0.5:  # an alias: the bare samples carry it at full amplitude, the record weakened
        assert np.max(np.abs(got[1:-1])) < 0.06 * np.max(np.abs(a))


def test_blocks_with_their_neighbours_give_the_whole_record():
    t, x, v, a, _ = _sine(1.37 / T, n=50)
    whole = filtered_acceleration(t, x, v, a)
    parts = []
    for lo, hi in ((0, 17), (17, 40), (40, 50)):
        before = (t[lo - 1], x[lo - 1], v[lo - 1]) if lo else None
        after = (t[hi], x[hi], v[hi]) if hi < t.size else None
        parts.append(filtered_acceleration(t[lo:hi], x[lo:hi], v[lo:hi], a[lo:hi], before,
                                           after))
    np.testing.assert_array_equal(np.concatenate(parts), whole)
    # a lone sample records its equation of motion
    assert filtered_acceleration(t[:1], x[:1], v[:1], a[:1])[0, 0] == a[0, 0]


def _taps_of_sine(fT, n_samples=60, A=2e-6, phase=0.3):
    """Taps (system/taps.py spacing) of x = A sin(ω t + φ) in two directions, the samples'
    times, and ω."""
    from bearingdae.system.taps import TAPS_PER_INTERVAL

    w = 2.0 * math.pi * fT / T
    tt = 0.01 + (T / TAPS_PER_INTERVAL) * np.arange(n_samples * TAPS_PER_INTERVAL + 1)
    xx = np.stack([A * np.sin(w * tt + phase), A * np.cos(w * tt + phase)], axis=-1)
    return (tt, xx), tt[::TAPS_PER_INTERVAL], w


def _fit_amplitude(t, y, w):
    """Least-squares amplitude of the line at ω in y(t)."""
    B = np.column_stack([np.cos(w * t), np.sin(w * t)])
    c = np.linalg.lstsq(B, y, rcond=None)[0]
    return math.hypot(*c)


@pytest.mark.parametrize("fT", [0.05, 0.2, 0.35, 0.4])
def test_the_decimation_filter_passes_the_band(fT):
    """Below 0.8 f_Nyquist (fT <= 0.4) the recorded acceleration of a sinusoid has its
    amplitude A ω² within 5 %, and within 1e-9 relative the amplitude the analytic transfer
    function gives, typed here: sinc²(f τ) Σ h_j cos(2π f j τ), τ = T/R (zero phase)."""
    from bearingdae.analysis.vibration import fir_coefficients, tap_filtered
    from bearingdae.system.taps import TAPS_PER_INTERVAL

    taps, ts, w = _taps_of_sine(fT)
    got, done = tap_filtered(ts, taps)
    assert done.sum() >= 20 and not done[:9].any() and not done[-9:].any()
    A = 2e-6
    h = fir_coefficients()
    tau = T / TAPS_PER_INTERVAL
    j = np.arange(len(h)) - (len(h) - 1) // 2
    f = w / (2 * math.pi)
    H = (math.sin(math.pi * f * tau) / (math.pi * f * tau)) ** 2 * sum(
        hj * math.cos(2 * math.pi * f * jj * tau) for hj, jj in zip(h, j))
    for d in (0, 1):
        amp = _fit_amplitude(ts[done], got[done, d], w)
        assert amp == pytest.approx(A * w * w * H, rel=1e-9)
        assert amp == pytest.approx(A * w * w, rel=0.05)
    # zero phase: the radial record is -A ω² H sin(ω t + φ) itself
    np.testing.assert_allclose(got[done, 0], -A * w * w * H * np.sin(w * ts[done] + 0.3),
                               rtol=0, atol=1e-9 * A * w * w)


@pytest.mark.parametrize("fT", [0.65, 0.8, 1.37, 2.43, 4.95])
def test_the_decimation_filter_stops_what_would_alias(fT):
    """Above 1.3 f_Nyquist (fT >= 0.65: what folds back below 0.7 f_Nyquist) a sinusoid's
    acceleration is recorded below 1e-3 of its amplitude (the bare samples: all of it)."""
    from bearingdae.analysis.vibration import tap_filtered

    taps, ts, w = _taps_of_sine(fT)
    got, done = tap_filtered(ts, taps)
    assert done.sum() >= 20
    assert np.max(np.abs(got[done])) < 1e-3 * 2e-6 * w * w


def test_taps_change_no_sample_of_the_run():
    """IDA's stops at the taps interpolate, they take no step: every sample, extreme and count
    of the record is that of the run without them but the acceleration."""
    from bearingdae.solvers.ida import IDA

    scene = make_scene(operating={"speed_rpm": 2000.0, "radial_load_N": 800.0,
                                  "moment_Nm": 3.0}, physics={"ring": "dynamic"},
                       numerics={"warmup_cage_revolutions": 0.02, "cage_revolutions": 0.05})
    plain = IDA()
    plain.ring_taps = False
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = simulate(scene, progress=False)
        b = simulate(scene, solver=plain, progress=False)
    assert "filter_fir_coefficients" in a.ring_acceleration.attrs
    assert "filter_fir_coefficients" not in b.ring_acceleration.attrs
    for name in a.data_vars:
        if name != "ring_acceleration":
            np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)


def test_the_radial_natural_frequency_at_standstill_is_sqrt_k_over_m():
    """Without tilt, at standstill, the radial mode of the ring is sqrt(K/m) with K the secant
    stiffness of two public static solves (1 %: K is a secant; measured 0.1 %)."""
    over = {"operating": {"speed_rpm": 0.0, "radial_load_N": 800.0},
            "physics": {"ring": "dynamic", "tilt": False}}
    d = [float(solve_static(make_scene(**{**over, "operating": {
        "speed_rpm": 0.0, "radial_load_N": F}})).ring_displacement[0]) for F in (792.0, 808.0)]
    K = 16.0 / (d[1] - d[0])
    model = build_model(make_scene(**over))
    i = model.layout.index("ring_vr")
    m = float(model.mass[i] * model.row_scale[i] / model.scale[i])
    f = natural_frequencies_Hz(model)
    assert f.size == 2
    assert np.min(np.abs(f / (math.sqrt(K / m) / (2 * math.pi)) - 1.0)) < 1e-2


def test_an_undersampled_ring_says_which_sampling_resolves_it():
    scene = make_scene(operating={"speed_rpm": 2000.0, "radial_load_N": 800.0,
                                  "moment_Nm": 3.0}, physics={"ring": "dynamic"})
    attrs = vibration_attrs(build_model(scene))
    note = attrs["ring_vibration_note"]
    assert "\n" not in note and "numerics.samples_per_cage_revolution = " in note
    n = int(note.split("numerics.samples_per_cage_revolution = ")[1].split()[0])
    dense = build_model(make_scene(scene_overrides(n), operating=dict(
        speed_rpm=2000.0, radial_load_N=800.0, moment_Nm=3.0), physics={"ring": "dynamic"}))
    a2 = vibration_attrs(dense)
    assert "ring_vibration_note" not in a2
    f0 = float(np.min(natural_frequencies_Hz(dense)))
    assert f0 <= RESOLVED_FRACTION_OF_NYQUIST * a2["nyquist_frequency_Hz"]
    assert f0 > RESOLVED_FRACTION_OF_NYQUIST * attrs["nyquist_frequency_Hz"]


@pytest.mark.parametrize("case", ["defects/inner_spall", "defects/roller_spall"])
def test_the_preloaded_spall_cases_resolve_every_ring_mode(case):
    """The bundled spalls whose every crossing kicks the ring record all its modes (13.3 and
    26.6 kHz) below 0.8 of their Nyquist frequency: ring_acceleration shows the ringing after
    each impact, and a run of the case prints no note that it cannot."""
    from bearingdae import load_scene

    attrs = vibration_attrs(build_model(load_scene(case)))
    assert "ring_vibration_note" not in attrs, attrs["ring_vibration_note"]
    f = json.loads(attrs["ring_natural_frequencies_Hz"])
    assert max(f) <= RESOLVED_FRACTION_OF_NYQUIST * attrs["nyquist_frequency_Hz"], (f, attrs)


def scene_overrides(n):
    return {"numerics.samples_per_cage_revolution": n}


def test_marker_rows_put_overlapping_labels_on_different_rows():
    rows = marker_rows([0.10, 0.12, 0.50, 0.14, 0.3], [0.1, 0.1, 0.1, 0.1, 0.1])
    assert rows == [0, 1, 0, 2, 0]  # 0.3 starts after row 0's first label ends (0.2)


def _fake_run(frequencies: dict) -> xr.Dataset:
    import json

    t = np.arange(400) / 3000.0
    acc = np.stack([np.sin(2 * np.pi * 300 * t), np.cos(2 * np.pi * 700 * t)], axis=-1)
    return xr.Dataset({"ring_acceleration": (("time", "direction"), acc, {"units": "m s-2"})},
                      coords={"time": t, "direction": ["radial", "tangential"]},
                      attrs={"record_start_s": 0.0,
                             "characteristic_frequencies_Hz": json.dumps(frequencies)})


@pytest.mark.parametrize("layout", [None, "constrained"])
def test_marker_labels_never_overlap_on_the_figure(layout):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ds = _fake_run({"shaft": 33.3, "cage": 15.2, "roller_pass_outer": 303.7,
                    "roller_pass_inner": 363.0, "roller_spin": 186.0})
    fig, axes = plt.subplots(2, 1, figsize=(6, 5), layout=layout)
    for ax in axes:
        draw_spectrum(ax, ds, "ring_acceleration", fmax=1200.0)
    fig.canvas.draw()
    for ax in axes:
        boxes = [t.get_window_extent() for t in ax.texts]
        # the five frequencies and the BPFO's harmonics below 1200 Hz: 2 x and 3 x 303.7 Hz
        assert len(boxes) == 7
        assert [t.get_text() for t in ax.texts if "BPFO" in t.get_text()] == [
            "2× BPFO 607.4 Hz", "3× BPFO 911.1 Hz"]
        for i in range(len(boxes)):
            for j in range(i):
                assert not boxes[i].overlaps(boxes[j]), (ax.texts[i].get_text(),
                                                         ax.texts[j].get_text())
        assert not any(b.overlaps(ax.title.get_window_extent()) for b in boxes)
        assert "Hann window, bin" in ax.get_title()
    plt.close(fig)


@pytest.mark.parametrize("argv, words", [
    (["--fmin", "-3"], "--fmin -3.0"), (["--fmax", "inf"], "--fmax inf"),
    (["--fmin", "100", "--fmax", "10"], "--fmax 10.0"), (["--envelope", "--band", "5"],
                                                         "--band '5'"),
    (["--band", "1,2"], "with --envelope"), (["--envelope", "--band", "9,3"], "--band '9,3'"),
    (["--fmax", "9000"], "Nyquist"), (["--envelope", "--band", "10,9000"], "Nyquist")])
def test_bad_spectrum_options_are_one_line_errors(tmp_path, capsys, argv, words):
    path = tmp_path / "run.nc"
    _fake_run({"roller_pass_inner": 363.0}).assign_attrs(
        Conventions="CF-1.8", bearingdae_version="test").to_netcdf(path)
    assert main(["plot", str(path), "--spectrum", *argv, "-o", str(tmp_path / "s.png")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and err.startswith("bearingdae: error:") and words in err, err
    assert main(["plot", str(path), "--log"]) == 2  # a spectrum option without --spectrum
    assert "with --spectrum" in capsys.readouterr().err


def test_streamed_and_in_memory_records_filter_alike(tmp_path):
    """A record of two streamed blocks (its blocks' edges held for their neighbours) gives
    the ring acceleration of the in-memory run, bit for bit."""
    scene = make_scene(operating={"speed_rpm": 2000.0, "radial_load_N": 800.0},
                       physics={"ring": "dynamic"},
                       numerics={"warmup_cage_revolutions": 0.01, "cage_revolutions": 0.1,
                                 "samples_per_cage_revolution": 7000},
                       output={"variables": ["ring_displacement", "ring_velocity",
                                             "ring_acceleration"]})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mem = simulate(scene, progress=False)
        simulate(scene, progress=False, output=tmp_path / "r.nc")
    with xr.open_dataset(tmp_path / "r.nc") as disk:
        assert disk.sizes["time"] == mem.sizes["time"] > 601  # two blocks
        np.testing.assert_array_equal(disk.ring_acceleration.values,
                                      mem.ring_acceleration.values)
        assert "filter_fir_coefficients" in disk.ring_acceleration.attrs
    # the overview draws the ring's spectrum into a subfigure (plots/plotting.py)
    from bearingdae.plots.plotting import overview

    assert overview(mem, tmp_path / "overview.png").stat().st_size > 0


def test_a_resumed_run_records_the_filtered_acceleration_throughout(tmp_path):
    """Interrupted (as by Ctrl-C) in the record and resumed from its checkpoint: the samples
    before the resume point are filtered with the taps the checkpoint kept, those after it
    with the taps the resumed solver continues (system/taps.py), so every sample, before,
    at and after the resume point, is the uninterrupted run's within 1 % of its largest
    value (before the checkpoint kept the taps, the samples before the resume point recorded
    the triangle mean: up to 30 % of the largest value off)."""
    from bearingdae import SimulationError
    from bearingdae.run.checkpoint import Checkpoint

    class StopAfter(Checkpoint):
        def sample(self, t, y, yp):
            super().sample(t, y, yp)
            if len(self.T) == 40:
                raise KeyboardInterrupt

    scene = make_scene(operating={"speed_rpm": 2000.0, "radial_load_N": 800.0},
                       physics={"ring": "dynamic"},
                       numerics={"warmup_cage_revolutions": 0.02, "cage_revolutions": 0.3,
                                 "samples_per_cage_revolution": 200},
                       output={"variables": ["ring_displacement", "ring_acceleration"]})
    path, path2 = tmp_path / "run.nc.checkpoint.npz", tmp_path / "r.nc.checkpoint.npz"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = simulate(scene, progress=False)
        for p in (path, path2):
            with pytest.raises(SimulationError, match="interrupted"):
                simulate(scene, progress=False, checkpoint=StopAfter(p, every_samples=5))
        resumed = simulate(scene, progress=False, checkpoint=Checkpoint(path, resume=True))
        simulate(scene, progress=False, output=tmp_path / "r.nc",
                 checkpoint=Checkpoint(path2, resume=True))
    a, r = resumed.ring_acceleration, ref.ring_acceleration
    assert np.isfinite(a.values).all() and "filter_fir_coefficients" in a.attrs
    t_resume = json.loads(resumed.attrs["solver_statistics"])["resumed_from_s"]
    assert 10 < int((resumed.time.values < t_resume).sum()) < resumed.sizes["time"] - 10
    scale = float(np.abs(r.values).max())
    worst = np.abs(a.values - r.values).reshape(a.shape[0], -1).max(axis=1) / scale
    assert worst.max() < 1e-2, (np.argmax(worst), worst.max())
    # the streamed record (blocks held for the taps past them) records the same
    with xr.open_dataset(tmp_path / "r.nc") as disk:
        assert json.loads(disk.attrs["solver_statistics"])["resumed_from_s"] == t_resume
        np.testing.assert_allclose(disk.ring_acceleration.values, a.values, rtol=0,
                                   atol=1e-9 * scale)


def test_a_record_after_a_block_by_block_warm_up_is_filtered_from_its_first_sample():
    """``until_steady`` warms up block by block, each a solver call of its own: the ring taps
    run on from block to block into the record (system/taps.py), so its first samples are
    filtered as in one integration; against the same warm-up run in one piece, every sample
    within 1 % of the largest value (before: the record's first 11 samples recorded the
    triangle or end mean, up to 30 % off)."""
    common = {"operating": {"speed_rpm": 2000.0, "radial_load_N": 800.0},
              "physics": {"ring": "dynamic"},
              "output": {"variables": ["ring_displacement", "ring_acceleration"]}}
    numerics = {"cage_revolutions": 0.2, "samples_per_cage_revolution": 200,
                "warmup_cage_revolutions": 0.2}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        blocks = simulate(make_scene(numerics={**numerics, "until_steady": True,
                                               "steady_tolerance": 0.1,
                                               "steady_block_cage_revolutions": 0.05},
                                     **common), progress=False)
        one = simulate(make_scene(numerics=numerics, **common), progress=False)
    assert blocks.sizes["warmup_block"] == 4  # (the least the criterion takes: 0.2 revolution)
    assert float(blocks.record_start_s) == pytest.approx(float(one.record_start_s), rel=1e-12)
    a, r = blocks.ring_acceleration.values, one.ring_acceleration.values
    assert a.shape == r.shape
    worst = np.abs(a - r).reshape(len(a), -1).max(axis=1) / np.abs(r).max()
    assert worst.max() < 1e-2, (np.argmax(worst), worst.max())


@pytest.mark.parametrize("stop_at_sample, blocks_kept", [
    (32, 4),  # in the record (its 12th sample): resumed, the record is computed again
    (18, 3),  # in the last warm-up block: the record reads the taps of two blocks back
])
def test_a_block_by_block_run_interrupted_and_resumed_records_the_uninterrupted_run(
        tmp_path, monkeypatch, stop_at_sample, blocks_kept):
    """A run warmed up in blocks keeps no checkpoint of its record, only the warm-up's
    (``OUT.nc.warmup.npz``): interrupted (as by Ctrl-C) in the record or in a block and
    resumed, it continues from the last block written. The warm-up checkpoint keeps the
    ring taps of the last blocks, which the record's first samples are filtered over, so the
    resumed run is the uninterrupted one bit for bit, every variable (the same state, taps
    and solver start; determinism on one machine). Without the taps the record's first 11
    samples (interrupted in the record; 6 interrupted in the last block) were triangle means,
    up to 0.49 of the largest acceleration off. Blocks of 5 samples here: the filter reads 9
    intervals back, across two blocks."""
    from bearingdae import SimulationError
    from bearingdae.run import progress
    from bearingdae.run.checkpoint import Checkpoint

    scene = make_scene(operating={"speed_rpm": 2000.0, "radial_load_N": 800.0},
                       physics={"ring": "dynamic"},
                       numerics={"cage_revolutions": 0.2, "samples_per_cage_revolution": 100,
                                 "warmup_cage_revolutions": 0.2, "until_steady": True,
                                 "steady_tolerance": 0.1,
                                 "steady_block_cage_revolutions": 0.05})
    real, samples = progress.mark_first_sample, []

    def sample_then_stop():  # (called at every sample, warm-up and record)
        real()
        samples.append(1)
        if len(samples) == stop_at_sample:
            raise KeyboardInterrupt

    path = tmp_path / "r.nc.checkpoint.npz"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = simulate(scene, progress=False)
        with monkeypatch.context() as m, pytest.raises(SimulationError, match="interrupted"):
            m.setattr(progress, "mark_first_sample", sample_then_stop)
            simulate(scene, progress=False, checkpoint=Checkpoint(path))
        warm = tmp_path / "r.nc.warmup.npz"
        with np.load(warm) as z:  # where the interruption landed
            assert len(json.loads(str(z["meta"]))["means"]) == blocks_kept
        resumed = simulate(scene, progress=False, checkpoint=Checkpoint(path, resume=True))
    assert not warm.exists() and ref.sizes["warmup_block"] == 4
    assert "filter_fir_coefficients" in resumed.ring_acceleration.attrs
    a, r = resumed.ring_acceleration.values, ref.ring_acceleration.values
    worst = np.abs(a - r).reshape(len(a), -1).max(axis=1) / np.abs(r).max()
    assert worst.max() == 0.0, (np.flatnonzero(worst), worst.max())
    assert set(resumed.data_vars) == set(ref.data_vars)
    for name in ref.data_vars:
        np.testing.assert_array_equal(resumed[name].values, ref[name].values, err_msg=name)


def test_the_spectrum_figure_carries_the_scene_title(tmp_path, monkeypatch):
    """Which run a spectrum PNG shows: the scene's title above its panels, as on the overview."""
    import matplotlib

    matplotlib.use("Agg")
    from bearingdae.plots import plot_spectrum

    ds = _fake_run({"shaft": 33.3, "roller_pass_outer": 303.7})
    ds.attrs["title"] = "yang20 baseline: 800 N [set: ring.mass_kg = 2]"
    seen = {}

    def keep(fig, path):
        seen["title"] = fig._suptitle.get_text() if fig._suptitle is not None else None
        return path

    monkeypatch.setattr(plot_spectrum, "save_figure", keep)
    plot_spectrum.spectrum_figure(ds, tmp_path / "s.png", fmax=1200.0)
    assert seen["title"].replace("\n", " ") == ds.attrs["title"]
