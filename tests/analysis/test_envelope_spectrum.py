"""The envelope spectrum (analysis/spectrum.envelope_spectrum) on a signal typed here.

Reference: an amplitude-modulated carrier x = (1 + d t/T + m cos 2π f_m t) cos 2π f_c t whose
amplitude also drifts over the record (a transient dying out): its Hilbert envelope is
1 + d t/T + m cos 2π f_m t (Randall & Antoni 2011, §2), so the envelope spectrum has one line
of amplitude m at f_m; the envelope's mean and drift must leave nothing at the lowest
frequencies, where they were the panel's largest feature.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from bearingdae.analysis.spectrum import envelope_spectrum


def test_an_am_carrier_gives_its_modulation_line_and_no_mean():
    fs, n = 20_000.0, 8000  # 0.4 s: bins of 2.5 Hz
    t = np.arange(n) / fs
    fc, fm, m = 3000.0, 125.0, 0.3
    x = (1 + 0.5 * t / t[-1] + m * np.cos(2 * np.pi * fm * t)) * np.cos(2 * np.pi * fc * t)
    ds = xr.Dataset({"ring_acceleration": (("time",), x, {"units": "m s-2"})},
                    coords={"time": t})
    spec = envelope_spectrum(ds, "ring_acceleration", (2000.0, 4000.0))
    f, a = spec.frequency.values, spec.values.ravel()
    line = a[np.argmin(np.abs(f - fm))]
    assert abs(line - m) <= 0.02 * m  # the modulation depth, Hann-windowed on a bin
    assert a[f < fm / 2].max() <= 0.01 * line, a[f < fm / 2].max()  # no mean, no drift
