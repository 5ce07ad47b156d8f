"""The kinematics of a spall in a run: the bundled outer- and inner-race spalls
(cases/defects/) through the envelope spectrum (analysis/spectrum_peaks.py).

References: the pure-rolling ball-pass frequencies typed here from the geometry (Harris &
Kotzalas 2007, §12: BPFO = Z/2 f_s (1 - D/d_m), BPFI = Z/2 f_s (1 + D/d_m)); a defect on a race
strikes the ring once per roller that crosses it, so the envelope of the ring's vibration
repeats at that race's ball-pass frequency (Randall & Antoni 2011, §2), and an inner-race
defect's strikes are modulated once per shaft revolution as it passes the load zone, which
adds sidebands at BPFI ± f_s. The run measures its own cage speed (slip included); the
strongest envelope peak below 5× BPFO must be the defect's frequency from those speeds within
one resolution bin.
"""

from __future__ import annotations

import numpy as np
import pytest

from bearingdae import load_scene, simulate
from bearingdae.analysis.spectrum_peaks import spectrum_peaks
from bearingdae.physics.geometry import make_geometry

pytestmark = pytest.mark.slow

#: recorded cage revolutions: one resolves BPFO (bins of ~15 Hz against ~300 Hz); the inner
#: spall needs bins well under the shaft speed (33 Hz) to part the sidebands: three, ~5 Hz
RUNS = {"outer": 1.0, "inner": 3.0}
#: a sideband is "present" when the envelope spectrum has a local maximum within one bin of it
#: at least this far above the spectrum's median below 5× BPFO (measured: 27.7 and 29.3 dB at the
#: case's 4400 samples per cage revolution)
SIDEBAND_ABOVE_FLOOR_DB = 20.0


@pytest.fixture(scope="module", params=sorted(RUNS))
def spall_run(request):
    race = request.param
    s = load_scene(f"defects/{race}_spall", {"numerics.cage_revolutions": RUNS[race],
                                            "numerics.warmup_cage_revolutions": 0.1})
    return race, s, simulate(s, progress=False)


def pure_rolling(s) -> dict:
    """BPFO and BPFI from the geometry and the shaft speed (Harris), typed afresh."""
    g = make_geometry(s)
    Z, fs = g.rollers, s.operating.speed_rpm / 60.0
    D = 2.0 * g.roller_radius_m
    dm = g.outer_race_radius_m + g.inner_race_radius_m  # pitch diameter: between the races
    return {"bpfo": 0.5 * Z * fs * (1.0 - D / dm), "bpfi": 0.5 * Z * fs * (1.0 + D / dm)}


def test_the_measured_defect_frequencies_are_pure_rolling_within_the_slip(spall_run):
    """The file's pure-rolling values are Harris's; the measured ones differ from them by the
    cage slip alone: BPFO = Z f_c moves by the slip, BPFI = Z (f_s - f_c) by f_c / (f_s - f_c)
    (< 1 here) times it."""
    _, s, ds = spall_run
    pure = pure_rolling(s)
    slip = abs(float(ds.cage_slip_ratio))
    assert 0.0 < slip < 0.02
    for k in ("bpfo", "bpfi"):
        assert float(ds[f"defect_frequency_{k}_pure_rolling_Hz"]) == pytest.approx(pure[k],
                                                                                   rel=1e-9)
        measured = float(ds[f"defect_frequency_{k}_Hz"])
        assert abs(measured / pure[k] - 1.0) <= slip * (1.0 + 1e-6), (k, measured, pure[k])


def test_the_strongest_envelope_peak_is_the_races_ball_pass_frequency(spall_run):
    race, _, ds = spall_run
    key = "bpfo" if race == "outer" else "bpfi"
    table = spectrum_peaks(ds, 1, fmax_Hz=5.0 * float(ds.defect_frequency_bpfo_Hz))
    width = table.spectrum.attrs["bin_width_Hz"]
    assert table.source.startswith("measured")
    peak = table.peaks[0]
    expected = float(ds[f"defect_frequency_{key}_Hz"])
    assert abs(peak.frequency_Hz - expected) <= width, (peak, expected, width)
    assert peak.order == key.upper()


def test_the_inner_spall_shows_sidebands_at_the_shaft_speed(spall_run):
    race, s, ds = spall_run
    if race != "inner":
        pytest.skip("the sidebands belong to the inner-race spall")
    table = spectrum_peaks(ds, 1)
    spec = table.spectrum
    f = spec.frequency.values
    a = np.sqrt((spec.transpose("frequency", ...).values.reshape(f.size, -1) ** 2).sum(axis=1))
    width = spec.attrs["bin_width_Hz"]
    fs = s.operating.speed_rpm / 60.0
    assert width < 0.25 * fs  # the sidebands lie four bins and more from BPFI
    below = (f > 0.0) & (f < 5.0 * float(ds.defect_frequency_bpfo_Hz))
    floor = np.median(a[below])
    bpfi = float(ds.defect_frequency_bpfi_Hz)
    for side in (bpfi - fs, bpfi + fs):
        near = np.flatnonzero(np.abs(f - side) <= width)
        k = near[np.argmax(a[near])]
        assert a[k] > a[k - 1] and a[k] >= a[k + 1], side  # a local maximum, not a flank
        assert 20.0 * np.log10(a[k] / floor) >= SIDEBAND_ABOVE_FLOOR_DB, (side, a[k], floor)


def test_the_inner_spalls_second_sidebands_come_from_watching_one_direction(spall_run):
    """Why BPFI ± 2 f_s outweighs BPFI ± f_s in each direction's envelope of the preloaded
    inner spall: the strikes turn with the shaft, so a fixed direction sees each one
    projected, |cos ψ|, which repeats twice per revolution; with the preload every strike is
    nearly alike around the circle. The envelope of the ring's vibration as a vector (both
    directions' envelopes combined, which no projection modulates) keeps BPFI ± f_s (the
    load zone) and loses BPFI ± 2 f_s. Envelopes typed afresh here: a Butterworth band-pass
    around the ring's highest mode (± 20 %), the Hilbert transform's magnitude, its spectrum
    under a Hann window."""
    from scipy.signal import butter, hilbert, sosfiltfilt

    race, s, ds = spall_run
    if race != "inner":
        pytest.skip("the sidebands belong to the inner-race spall")
    rec = ds.sel(time=ds.time >= float(ds.record_start_s))
    t = rec.time.values
    acc = rec.ring_acceleration.transpose("time", "direction").values
    rate = 1.0 / float(np.mean(np.diff(t)))
    mode = float(ds.ring_natural_frequencies_Hz.max())
    sos = butter(4, [0.8 * mode, 1.2 * mode], btype="band", fs=rate, output="sos")
    env = [np.abs(hilbert(sosfiltfilt(sos, acc[:, d]))) for d in range(2)]

    def lines(e):
        e = e - e.mean()
        w = np.hanning(e.size)
        f = np.fft.rfftfreq(e.size, 1.0 / rate)
        a = np.abs(np.fft.rfft(e * w)) * 2.0 / w.sum()
        fs, bpfi = s.operating.speed_rpm / 60.0, float(ds.defect_frequency_bpfi_Hz)

        def at(f0):  # the largest within a bin of f0
            return a[np.abs(f - f0) <= f[1]].max()

        return (at(bpfi - fs) + at(bpfi + fs)), (at(bpfi - 2 * fs) + at(bpfi + 2 * fs))

    for e in env:  # each direction: the projection's |cos ψ| dominates
        first, second = lines(e)
        assert second > first, (first, second)
    first, second = lines(np.hypot(*env))  # the vector: the load zone's ± f_s only
    assert first > 10.0 * second, (first, second)
