"""The dynamic ring's vibration (theory.md §15) against references.

- Varying compliance (Sunnersjö 1978; Harris & Kotzalas Vol. 1 §8): under a pure radial load
  the largest line of the ring displacement spectrum above the shaft frequency is the roller
  pass on the outer race Z f_c, within one frequency bin.
- Unbalance: the ring's response at the shaft frequency is that of a linear single-degree-of-
  freedom system, X = U C / (1 - m ω² C) per direction, C the bearing's compliance from static
  solves averaged over the roller positions of one pitch; tolerance 10 % (measured 3 %: the
  rotating load moves the load zone, the compliance is not linear).
"""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest

from bearingdae import simulate
from bearingdae.physics.geometry import make_geometry
from bearingdae.results.spectrum import amplitude_spectrum
from bearingdae.solvers import static
from tests.conftest import make_scene

SPEED = 2000.0
VARIABLES = ["cage_speed", "ring_displacement", "ring_velocity", "ring_acceleration",
             "applied_load"]


def _run(unbalance_N, revolutions):
    scene = make_scene(operating={"speed_rpm": SPEED, "radial_load_N": 800.0,
                                  "unbalance_N": unbalance_N},
                       physics={"ring": "dynamic"},
                       numerics={"warmup_cage_revolutions": 0.25,
                                 "cage_revolutions": revolutions,
                                 "samples_per_cage_revolution": 200},
                       output={"variables": VARIABLES})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return scene, simulate(scene, progress=False)


def test_roller_pass_line_of_the_varying_compliance():
    _, ds = _run(0.0, 1.5)
    f = json.loads(ds.attrs["characteristic_frequencies_Hz"])
    spec = amplitude_spectrum(ds, "ring_displacement").sel(direction="radial")
    above = spec.where(spec.frequency > 1.5 * f["shaft"], drop=True)
    peak = float(above.frequency[int(np.argmax(above.values))])
    assert abs(peak - f["roller_pass_outer"]) <= spec.attrs["bin_width_Hz"]


def test_unbalance_response_is_the_single_dof_estimate():
    U = 100.0
    scene, ds = _run(U, 1.0)
    t = ds.time.values
    rec = t >= ds.attrs["record_start_s"]
    w = SPEED * 2.0 * math.pi / 60.0
    basis = np.column_stack([np.cos(w * t[rec]), np.sin(w * t[rec]), np.ones(rec.sum()),
                             t[rec]])

    def amplitude(x):  # least squares on the record: the line at the shaft frequency
        c = np.linalg.lstsq(basis, x[rec], rcond=None)[0]
        return math.hypot(c[0], c[1])

    g = make_geometry(scene)
    C = np.zeros(2)  # compliance per direction, averaged over one roller pitch
    for s in np.linspace(0.0, 1.0, 8, endpoint=False):
        az = g.azimuth0_rad + s * 2.0 * math.pi / g.rollers
        z = [static.solve(static.make_problem(g, [800.0 + dF, dT, 0.0, 0.0], w,
                                              scene.numerics.contact_smoothing_m,
                                              azimuth_rad=az)).z[2 * g.rollers:]
             for dF, dT in ((0.0, 0.0), (10.0, 0.0), (0.0, 10.0))]
        C += np.array([(z[1][0] - z[0][0]) / 10.0, (z[2][1] - z[0][1]) / 10.0]) / 8.0
    m = ds.attrs["ring_mass_kg"]
    for d, direction in enumerate(("radial", "tangential")):
        X = U * C[d] / (1.0 - m * w * w * C[d])
        got = amplitude(ds.ring_displacement.sel(direction=direction).values)
        assert got == pytest.approx(X, rel=0.1), (direction, got, X)
    # the applied load is the unbalance itself: amplitude U in each direction
    for direction in ("radial", "tangential"):
        assert amplitude(ds.applied_load.sel(direction=direction).values) == pytest.approx(
            U, rel=1e-9)
