"""The healthy bearing's vibration at the roller pass: varying compliance (Sunnersjö 1978,
J. Sound Vib. 58(3), 363-373).

A radially loaded bearing whose rollers are equally spaced changes its stiffness as the roller
set turns: the ring's static displacement under a constant load is periodic in the roller-set
position with the period of one roller pitch, so a turning roller set moves the ring at the
outer-race roller pass BPFO = Z f_c and its harmonics even without a defect. Far below the
ring's first natural frequency the ring follows that quasi-static motion: its displacement
amplitude at k BPFO, in each direction, is the k-th Fourier component of the quasi-static
displacement over one pitch.

Reference, solved afresh here: 32 static solves of the scene (solvers/static.py through
analysis/static_state.py) with the roller set turned by j/32 of a pitch, their discrete Fourier
components; against the dynamic ring's displacement over the recorded window, fitted by least
squares with a mean, a linear drift and the harmonics of the run's measured BPFO. The baseline
bearing at 500 r/min, 800 N, no moment: BPFO ≈ 76 Hz, the ring's first mode ≈ 2.2 kHz
(dynamic amplification of the third harmonic (3·76/2200)² ≈ 1 %).
"""

from __future__ import annotations

import numpy as np
import pytest

from bearingdae import simulate
from bearingdae.analysis.static_state import scene_static, turned_azimuths
from bearingdae.physics.geometry import make_geometry

from conftest import make_scene

POSITIONS = 32  # roller-set positions over one pitch
HARMONICS = 3   # BPFO and its first harmonics compared


def _scene(pocket_clearance_mm=None, **numerics):
    cage = {} if pocket_clearance_mm is None else {"pocket_clearance_mm": pocket_clearance_mm}
    return make_scene(None, numerics=numerics, operating={"speed_rpm": 500.0,
                                                          "radial_load_N": 800.0,
                                                          "moment_Nm": 0.0},
                      physics={"ring": "dynamic"}, cage=cage)


#: the dynamic runs: 0.25 cage revolution of warm-up, 0.5 recorded (10 roller passes), 64
#: samples per roller pass (a sawtooth's harmonics fold back onto the first three from the
#: 61st on: negligible)
RUN = {"warmup_cage_revolutions": 0.25, "cage_revolutions": 0.5,
       "samples_per_cage_revolution": 1280}


def _run(pocket_clearance_mm=None):
    ds = simulate(_scene(pocket_clearance_mm, **RUN), progress=False)
    window = ds.sel(time=ds.time >= float(ds.record_start_s))
    # far above: the highest harmonic compared is amplified by 1 / (1 - (f / f_n)²), < 2 %
    bpfo = float(ds.defect_frequency_bpfo_Hz)
    assert (HARMONICS * bpfo / ds.ring_natural_frequencies_Hz.values.min()) ** 2 < 0.02
    return window, bpfo


def quasi_static_components(scene) -> np.ndarray:
    """(HARMONICS, 2) amplitudes [m] of the quasi-static ring displacement (radial,
    tangential) at 1, 2, ... times the roller-pass frequency."""
    g = make_geometry(scene)
    Z = g.rollers
    d = np.array([scene_static(scene, g, turned_azimuths(g, j / POSITIONS))[0].z[2 * Z:2 * Z + 2]
                  for j in range(POSITIONS)])
    c = np.fft.rfft(d, axis=0) / POSITIONS
    return 2.0 * np.abs(c[1:HARMONICS + 1])


def fitted_components(t, x, f_Hz) -> np.ndarray:
    """Amplitudes of the harmonics 1..HARMONICS of ``f_Hz`` in ``x`` (n, 2), fitted by least
    squares with a mean and a linear drift."""
    cols = [np.ones_like(t), t - t.mean()]
    for k in range(1, HARMONICS + 1):
        cols += [np.cos(2 * np.pi * k * f_Hz * t), np.sin(2 * np.pi * k * f_Hz * t)]
    coef = np.linalg.lstsq(np.array(cols).T, x, rcond=None)[0]
    return np.hypot(coef[2::2], coef[3::2])


@pytest.mark.slow
def test_the_ring_vibrates_at_bpfo_with_the_quasi_static_compliance():
    """Sunnersjö's reference assumes equally spaced rollers: the pockets here hold them to
    0.01 mm (the baseline's 0.1 mm lets the rollers entering the load zone bunch by up to
    ±0.25°, which moves the third radial harmonic by about 10 %: the next test)."""
    window, bpfo = _run(pocket_clearance_mm=0.01)
    dyn = fitted_components(window.time.values,
                            window.ring_displacement.transpose("time", "direction").values, bpfo)
    qs = quasi_static_components(_scene(pocket_clearance_mm=0.01))
    # the tangential motion is the larger: a sawtooth that jumps where a roller enters
    assert np.all(qs[:, 1] > 2.5 * qs[:, 0])
    np.testing.assert_allclose(dyn, qs, rtol=0.10)


@pytest.mark.slow
def test_the_baseline_ring_follows_the_compliance_of_its_own_roller_positions():
    """With the baseline's pocket clearance the rollers are not equally spaced; the static
    solve at the run's own roller azimuths, sample by sample, still gives the ring's vibration
    at BPFO and its harmonics (within 3 %: the ring is quasi-static far below its mode)."""
    scene = _scene()
    window, bpfo = _run()
    g = make_geometry(scene)
    Z = g.rollers
    azimuths = window.roller_azimuth.transpose("time", "roller").values
    qs = np.array([scene_static(scene, g, a)[0].z[2 * Z:2 * Z + 2] for a in azimuths])
    t = window.time.values
    dyn = fitted_components(t, window.ring_displacement.transpose("time", "direction").values,
                            bpfo)
    np.testing.assert_allclose(dyn, fitted_components(t, qs, bpfo), rtol=0.03)
