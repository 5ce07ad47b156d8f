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


def _scene(**numerics):
    return make_scene(None, numerics=numerics, operating={"speed_rpm": 500.0, "radial_load_N": 800.0,
                                           "moment_Nm": 0.0},
                      physics={"ring": "dynamic"})


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
    scene = _scene(warmup_cage_revolutions=0.25, cage_revolutions=0.5,
                   samples_per_cage_revolution=1280)  # 64 samples per roller pass
    ds = simulate(scene, progress=False)
    window = ds.sel(time=ds.time >= float(ds.record_start_s))
    bpfo = float(ds.defect_frequency_bpfo_Hz)
    dyn = fitted_components(window.time.values,
                            window.ring_displacement.transpose("time", "direction").values, bpfo)
    qs = quasi_static_components(_scene())
    # far above: the highest harmonic compared is amplified by 1 / (1 - (f / f_n)²), < 2 %
    assert (HARMONICS * bpfo / ds.ring_natural_frequencies_Hz.values.min()) ** 2 < 0.02
    # the tangential motion is the larger: a sawtooth that jumps where a roller enters
    assert np.all(qs[:, 1] > 2.5 * qs[:, 0])
    np.testing.assert_allclose(dyn, qs, rtol=0.10)
