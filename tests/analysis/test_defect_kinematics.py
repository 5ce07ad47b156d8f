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
