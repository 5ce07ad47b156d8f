"""The bundled roller spall (cases/defects/roller_spall.toml): what a vibration analyst reads.

Reference: the kinematics of a point on a roller (Randall & Antoni 2011, §2.1; Harris's
closed forms typed afresh below). A spall on a roller meets the outer race and the inner race
once each per revolution of the roller relative to the cage: twice per revolution, so its
impacts repeat at 2×BSF, not at BSF (the two impacts of one revolution are alike: the roller
carries the same load on both races). They happen only while the roller crosses the load
zone, once per cage revolution, so the envelope spectrum's line at 2×BSF carries sidebands at
± FTF. The frequencies are the run's own (its mean spin speed relative to the cage), within
one resolution bin; the pure-rolling ones within the slip of a lightly loaded run.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

#: recorded cage revolutions: 0.26 s at 2000 r/min, bins of 3.8 Hz, the ± FTF (15 Hz)
#: sidebands four bins off 2×BSF (372 Hz) and BPFI (363 Hz) more than two
REVOLUTIONS = 4.0


@pytest.mark.slow
def test_roller_spall_envelope_peak_is_twice_the_roller_spin_frequency():
    from bearingdae import load_scene, simulate
    from bearingdae.analysis.spectrum_peaks import spectrum_peaks

    s = load_scene("defects/roller_spall", {"numerics.cage_revolutions": REVOLUTIONS,
                                            "numerics.warmup_cage_revolutions": 0.25})
    ds = simulate(s)
    assert ds.attrs["solver_status"] == "completed"
    # pure rolling, typed afresh: yang20, d_m = 45 mm, D_w = 4 mm, Z = 20, 2000 r/min
    f_s, d_m, D_w, Z = 2000.0 / 60.0, 45e-3, 4e-3, 20
    gamma = D_w / d_m
    ftf_pure = 0.5 * f_s * (1.0 - gamma)
    bsf_pure = f_s * d_m / (2.0 * D_w) * (1.0 - gamma * gamma)
    bpfo_pure = Z * ftf_pure
    # the run's own: its mean roller spin and cage speeds (slip included)
    t0 = float(ds.attrs.get("record_start_s", ds.time[0])) if "record_start_s" in ds.attrs \
        else float(ds.time[0])
    rec = ds.sel(time=ds.time >= t0)
    bsf = float(rec.spin_speed.mean()) / (2.0 * math.pi)
    ftf = float(rec.cage_speed.mean()) / (2.0 * math.pi)
    assert bsf == pytest.approx(bsf_pure, rel=0.02)
    assert ftf == pytest.approx(ftf_pure, rel=0.02)

    table = spectrum_peaks(ds, 12, fmax_Hz=5.0 * Z * ftf)
    width = float(table.spectrum.attrs["bin_width_Hz"])
    assert width < 0.25 * ftf  # the sidebands resolved
    assert table.defect_frequencies["2bsf"] == pytest.approx(2.0 * bsf, abs=0.5 * width)
    first = table.peaks[0]
    assert abs(first.frequency_Hz - 2.0 * bsf) <= width, [
        (round(p.frequency_Hz, 1), p.order) for p in table.peaks]
    assert abs(first.frequency_Hz - 2.0 * bsf_pure) <= width + 0.02 * 2.0 * bsf_pure
    assert first.frequency_Hz < 5.0 * bpfo_pure
    # the sidebands 2×BSF ± FTF: peaks among the strongest, within a bin of each
    for side in (-1.0, 1.0):
        near = [p for p in table.peaks if abs(p.frequency_Hz - (2.0 * bsf + side * ftf)) <= width]
        assert near, (side, [(round(p.frequency_Hz, 1), p.order) for p in table.peaks])
    spec = table.spectrum
    total = np.sqrt((spec.transpose("frequency", ...).values.reshape(spec.frequency.size, -1)
                     ** 2).sum(axis=1))
    assert np.median(total) < 0.1 * first.amplitude  # lines, not noise
