"""The peaks table (analysis/spectrum_peaks.py) on signals typed here.

Reference: a carrier at a ring resonance struck by short pulses that repeat at a known BPFO
(an outer-race defect's impacts, Randall & Antoni 2011, §2): its envelope is the pulse train,
whose spectrum has lines at BPFO and its harmonics, strongest at BPFO. The same pulses at
BPFI, modulated once per shaft revolution (an inner-race defect passing through the load
zone), add lines at BPFI ± f_s. The frequencies are chosen off the bins, the match is within
one bin.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from bearingdae.analysis.spectrum_peaks import format_table, spectrum_peaks

FS, N = 20_000.0, 16_000      # 0.8 s: bins of 1.25 Hz
F_CARRIER, BAND = 3000.0, (2000.0, 4000.0)
SHAFT, BPFO, BPFI = 8.3333, 75.93, 90.74


def synthetic(rate_Hz: float, modulation_Hz: float = 0.0) -> xr.Dataset:
    """A run-like Dataset: ring acceleration (time, direction) of pulses at ``rate_Hz`` on the
    carrier, optionally modulated at ``modulation_Hz``, with the characteristic frequencies of
    a bearing whose BPFO and BPFI are the module's."""
    t = np.arange(N) / FS
    phase = (t * rate_Hz) % 1.0  # Gaussian pulses 0.08 period wide: harmonics fall off
    pulses = np.exp(-0.5 * (np.minimum(phase, 1.0 - phase) / 0.08) ** 2)
    if modulation_Hz:
        pulses = pulses * (1.0 + 0.6 * np.cos(2 * np.pi * modulation_Hz * t))
    x = pulses * np.sin(2 * np.pi * F_CARRIER * t)
    rng = np.random.default_rng(1)
    a = np.stack([0.3 * x, x], axis=1) + 0.01 * rng.standard_normal((N, 2))
    Z = 20
    cage = BPFO / Z
    freqs = {"shaft": SHAFT, "cage": cage, "roller_pass_outer": BPFO,
             "roller_pass_inner": BPFI, "roller_spin": 46.5}
    return xr.Dataset(
        {"ring_acceleration": (("time", "direction"), a, {"units": "m s-2"}),
         "characteristic_frequencies_Hz": ("frequency_name", list(freqs.values()),
                                           {"units": "Hz"})},
        coords={"time": t, "direction": ["radial", "tangential"],
                "frequency_name": list(freqs)})


def test_the_strongest_envelope_peak_of_outer_race_impacts_is_bpfo():
    table = spectrum_peaks(synthetic(BPFO), 5, band_Hz=BAND, fmax_Hz=400.0)
    width = table.spectrum.attrs["bin_width_Hz"]
    first = table.peaks[0]
    assert first.order == "BPFO" and abs(first.frequency_Hz - BPFO) <= width
    assert [p.order for p in table.peaks[:4]] == ["BPFO", "2×BPFO", "3×BPFO", "4×BPFO"]
    assert table.source == "pure rolling"  # the file has neither speeds nor measured values
    assert first.by_direction["tangential"] > 2.0 * first.by_direction["radial"]
    text = format_table(table, "synthetic.nc")
    assert text.count("\n") == 3 + 5 and "BPFO 75.93 Hz" in text


def test_inner_race_impacts_show_the_shaft_sidebands():
    table = spectrum_peaks(synthetic(BPFI, SHAFT), 6, band_Hz=BAND, fmax_Hz=200.0)
    orders = [p.order for p in table.peaks]
    assert orders[0] == "BPFI"
    assert {"BPFI−fs", "BPFI+fs"} <= set(orders), orders


def test_a_peak_far_from_every_order_is_unmatched():
    table = spectrum_peaks(synthetic(61.0), 1, band_Hz=BAND, fmax_Hz=100.0)
    assert table.peaks[0].order is None and "unmatched" in format_table(table, "x")


def test_a_count_below_one_is_refused():
    with pytest.raises(ValueError, match="--peaks 0"):
        spectrum_peaks(synthetic(BPFO), 0)


def _two_lines(samples: int = 64) -> xr.Dataset:
    """A ring acceleration of two sines exactly on bins 2 and 5: under the Hann window each is a
    line with about half its height in the bins either side, so (0, 6 bins] holds two local
    maxima."""
    t = np.arange(samples) / FS
    a = 2.0 * np.sin(2 * np.pi * 2 * FS / samples * t) + np.sin(2 * np.pi * 5 * FS / samples * t)
    return xr.Dataset({"ring_acceleration": (("time",), a, {"units": "m s-2"})},
                      coords={"time": t})


def test_fewer_peaks_than_asked_say_why():
    ds = _two_lines()
    width = FS / 64
    table = spectrum_peaks(ds, 5, envelope=False, fmax_Hz=6.5 * width)
    assert [p.frequency_Hz / width for p in table.peaks] == pytest.approx([2.0, 5.0], abs=0.05)
    last = format_table(table, "two.nc").splitlines()[-1]
    assert last.startswith("2 of the 5 peaks asked for: the spectrum has only 2 local maxima")
    assert "6 bins of 312.5 Hz" in last
    full = format_table(spectrum_peaks(ds, 2, envelope=False, fmax_Hz=6.5 * width), "two.nc")
    assert "peaks asked for" not in full  # as many as asked: nothing to explain


@pytest.mark.parametrize("physics, output, why", [
    ("", "", 'the ring is quasi-static (physics.ring = "quasi-static")'),
    ('[physics]\nring = "dynamic"\n', '[output]\nvariables = ["ring_displacement"]\n',
     "the file does not record ring_acceleration (output.variables)")])
def test_a_spectrum_not_of_the_acceleration_says_of_what_and_why(physics, output, why):
    ds = synthetic(BPFO).rename({"ring_acceleration": "ring_displacement"})
    ds["ring_displacement"].attrs["units"] = "m"
    ds.attrs["scene_toml"] = 'title = "typed"\n' + physics + output
    text = format_table(spectrum_peaks(ds, 2, band_Hz=BAND, fmax_Hz=400.0), "disp.nc")
    head, note = text.splitlines()[:2]
    assert "envelope spectrum of ring_displacement" in head and "[m]" in head
    assert note.startswith("spectrum of ring_displacement, not ring_acceleration: ")
    assert why in note
    text = format_table(spectrum_peaks(synthetic(BPFO), 2, band_Hz=BAND, fmax_Hz=400.0), "a")
    assert "not ring_acceleration" not in text  # the default variable: no note


def test_an_order_a_bin_off_is_not_matched_and_the_rule_is_stated():
    """Impacts 1 Hz (0.8 of a 1.25 Hz bin) above BPFO: BPFO lies in the next bin, not the
    peak's; nothing else lies within half a bin (BPFI − 2 fs = 74.07 Hz)."""
    rate = BPFO + 1.0
    table = spectrum_peaks(synthetic(rate), 1, band_Hz=BAND, fmax_Hz=100.0)
    p = table.peaks[0]
    assert abs(p.frequency_Hz - rate) < 0.2
    assert p.order is None and p.others == ()
    text = format_table(table, "x")
    assert "within its resolution bin, |offset| <= 0.625 Hz (half the bin width)" in text
