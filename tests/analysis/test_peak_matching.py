"""Which order the peaks table names when two fall within one resolution bin
(analysis/defect_frequencies.matches, analysis/spectrum_peaks.py).

Reference, typed here: a bearing of 20 rollers whose BPFO = Z f_c (75.93 Hz) and inner-race
second shaft sideband BPFI − 2 f_s = Z (f_s − f_c) − 2 f_s (18 × 8.47 − 75.93 = 76.53 Hz) lie
0.6 Hz apart, closer than the 1.25 Hz bins
of a 0.8 s record. Impacts at 76.2 Hz (0.27 Hz from BPFO, 0.33 Hz from BPFI − 2 f_s) are
read as what the run's defect can produce: an inner spall's sideband, an outer spall's BPFO,
and both candidates where the scene names no defect (or both kinds).
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from bearingdae.analysis.defect_frequencies import defect_kinds, matches, orders
from bearingdae.analysis.spectrum_peaks import format_table, spectrum_peaks

FS, N = 20_000.0, 16_000  # 0.8 s: bins of 1.25 Hz
SHAFT, BPFO, BPFI, SPIN, Z = 8.47, 75.93, 93.47, 46.5, 20  # BPFI = Z f_s - BPFO
RATE = 76.2


def _scene(*kinds: str) -> str:
    return "".join(f'[[defects]]\non = "{k}"\nlength_mm = 1.0\nwidth_mm = 2.0\n'
                   f"depth_um = 10.0\n" for k in kinds)


def synthetic(*kinds: str) -> xr.Dataset:
    """Gaussian pulses at RATE on a 3 kHz carrier, with the typed characteristic frequencies
    and a scene naming defects of ``kinds``."""
    t = np.arange(N) / FS
    phase = (t * RATE) % 1.0
    pulses = np.exp(-0.5 * (np.minimum(phase, 1.0 - phase) / 0.08) ** 2)
    x = pulses * np.sin(2 * np.pi * 3000.0 * t)
    a = np.stack([x, 0.5 * x], axis=1)
    freqs = {"shaft": SHAFT, "cage": BPFO / Z, "roller_pass_outer": BPFO,
             "roller_pass_inner": BPFI, "roller_spin": SPIN}
    ds = xr.Dataset(
        {"ring_acceleration": (("time", "direction"), a, {"units": "m s-2"}),
         "characteristic_frequencies_Hz": ("frequency_name", list(freqs.values()),
                                           {"units": "Hz"})},
        coords={"time": t, "direction": ["radial", "tangential"],
                "frequency_name": list(freqs)})
    ds.attrs["scene_toml"] = 'title = "typed"\n' + _scene(*kinds)
    return ds


#: the typed frequency of each order near RATE
TYPED = {"BPFO": BPFO, "BPFI−2×fs": BPFI - 2 * SHAFT}


@pytest.mark.parametrize("kinds, order, also", [
    ((), "BPFO", "BPFI−2×fs"),
    (("inner",), "BPFI−2×fs", None),
    (("outer",), "BPFO", None),
    (("outer", "inner"), "BPFO", "BPFI−2×fs"),
    (("roller",), "BPFO", "BPFI−2×fs"),  # neither possible: both candidates, nearest first
])
def test_the_defects_kind_decides_between_orders_in_one_bin(kinds, order, also):
    table = spectrum_peaks(synthetic(*kinds), 1, band_Hz=(2000.0, 4000.0), fmax_Hz=120.0)
    p = table.peaks[0]
    assert table.spectrum.attrs["bin_width_Hz"] == pytest.approx(1.25)
    assert abs(p.frequency_Hz - RATE) < 0.2
    assert (p.order, tuple(n for n, _ in p.others)) == (order, (also,) if also else ())
    # each offset is the peak's distance from that order's own typed frequency
    assert p.offset_Hz == pytest.approx(p.frequency_Hz - TYPED[order], abs=1e-9)
    for name, offset in p.others:
        assert offset == pytest.approx(p.frequency_Hz - TYPED[name], abs=1e-9)
    row = format_table(table, "typed.nc").splitlines()[-1]
    assert (f"{order} or {also}" if also else order) in row
    shown = [float(v) for v in row.split(order, 1)[1].replace(f"or {also}", "").split()
             if v != "/"]
    assert shown == pytest.approx([p.frequency_Hz - TYPED[n] for n in (order, also) if n],
                                  abs=5e-4)


def test_second_sidebands_and_kinds_from_the_scene():
    cands = orders({"bpfo": BPFO, "bpfi": BPFI, "bsf": SPIN, "2bsf": 2 * SPIN,
                    "ftf": BPFO / Z}, SHAFT, 120.0, sidebands=2)
    labels = {o.label: o.frequency_Hz for o in cands}
    assert labels["BPFI−2×fs"] == pytest.approx(BPFI - 2 * SHAFT)
    assert labels["2×BSF+2×FTF"] == pytest.approx(2 * SPIN + 2 * BPFO / Z)
    assert "BPFI−2×fs" not in {o.label for o in orders({"bpfi": BPFI}, SHAFT, 120.0)}
    near = matches(76.2, cands, 1.25)
    assert [o.label for o in near] == ["BPFO", "BPFI−2×fs"]
    assert [o.label for o in matches(76.2, cands, 1.25, frozenset({"inner"}))] == ["BPFI−2×fs"]
    assert defect_kinds(synthetic("inner", "roller")) == {"inner", "roller"}
    assert defect_kinds(xr.Dataset()) == frozenset()
