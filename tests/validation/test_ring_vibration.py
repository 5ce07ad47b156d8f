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
from bearingdae.analysis.spectrum import amplitude_spectrum
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


# ---- the recorded acceleration at the default sampling (analysis/vibration.py) --------------
def _baseline_dynamic(samples, revolutions=3.0, warmup=1.0):
    """yang20_baseline (800 N, 3 N·m, 2000 r/min) with the dynamic ring."""
    from bearingdae import load_scene

    scene = load_scene("yang20_baseline", overrides={
        "physics.ring": "dynamic", "numerics.samples_per_cage_revolution": samples,
        "numerics.cage_revolutions": revolutions, "numerics.warmup_cage_revolutions": warmup,
        "output.variables": ["cage_speed", "ring_displacement", "ring_velocity",
                             "ring_acceleration"]})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return simulate(scene, progress=False)


def _line_over_local_median(spec, f0):
    """The largest amplitude within one bin of f0 over the median of the bins within ±25 % of
    f0 (three bins either side of the line left out)."""
    f, a = spec.frequency.values, spec.values
    df = spec.attrs["bin_width_Hz"]
    near = np.abs(f - f0) <= df
    around = (np.abs(f - f0) <= 0.25 * f0) & (np.abs(f - f0) > 3 * df)
    return float(a[near].max() / np.median(a[around]))


def _peaks(spec, fmax, n):
    """Frequencies of the n largest local maxima below fmax."""
    f, a = spec.frequency.values, spec.values
    i = np.flatnonzero((a[1:-1] > a[:-2]) & (a[1:-1] >= a[2:]) & (f[1:-1] < fmax)) + 1
    return f[i[np.argsort(a[i])[::-1][:n]]]


def test_roller_pass_line_stands_out_of_the_acceleration_at_the_default_sampling_short():
    """A short record (1 cage revolution): the roller pass on the outer race >= 10x the local
    median of the acceleration spectrum, radially (bare samples: 0.4x)."""
    ds = _baseline_dynamic(200, revolutions=1.0, warmup=0.25)
    f = json.loads(ds.attrs["characteristic_frequencies_Hz"])["roller_pass_outer"]
    spec = amplitude_spectrum(ds, "ring_acceleration").sel(direction="radial")
    assert _line_over_local_median(spec, f) >= 10.0


@pytest.fixture(scope="module")
def default_and_dense():
    return _baseline_dynamic(200), _baseline_dynamic(4000)


@pytest.mark.slow
def test_roller_pass_line_stands_out_of_the_acceleration_at_the_default_sampling(
        default_and_dense):
    """Baseline with the dynamic ring, 3 recorded cage revolutions at 200 samples each: the
    roller pass >= 10x the local median in both directions (measured 800x radial, 324x
    tangential; the bare samples 0.4x, 0.6x, the triangle mean without taps 135x, 46x)."""
    ds, _ = default_and_dense
    f = json.loads(ds.attrs["characteristic_frequencies_Hz"])["roller_pass_outer"]
    for direction in ("radial", "tangential"):
        spec = amplitude_spectrum(ds, "ring_acceleration").sel(direction=direction)
        assert _line_over_local_median(spec, f) >= 10.0, direction


def _same_peaks(default, dense, n, direction):
    spec = amplitude_spectrum(default, "ring_acceleration").sel(direction=direction)
    ref = amplitude_spectrum(dense, "ring_acceleration").sel(direction=direction)
    nyquist = 0.5 / spec.attrs["sample_interval_s"]
    df = spec.attrs["bin_width_Hz"]
    ref_peaks = _peaks(ref, 0.8 * nyquist, 12)
    for fp in _peaks(spec, 0.8 * nyquist, n):
        assert np.min(np.abs(ref_peaks - fp)) <= df, (fp, ref_peaks)


@pytest.mark.slow
@pytest.mark.parametrize("direction", ["radial", "tangential"])
def test_largest_acceleration_peaks_are_those_of_a_run_sampled_twenty_times_denser(
        default_and_dense, direction):
    """The three largest peaks below 0.8 f_Nyquist are peaks of the 20x denser run (within a
    bin, among its 12 largest). Measured: radial 606, 303, 910 Hz (dense 607, 304, 906);
    tangential 1208, 910, 303 Hz (dense 1210, 906, 304). With the triangle mean alone (no
    taps) the third radial one is the 7.4 kHz mode folded back to 1187 Hz."""
    _same_peaks(*default_and_dense, 3, direction)
