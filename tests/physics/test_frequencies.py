"""Characteristic frequencies (physics/frequencies.py) against pure-rolling kinematics solved
here afresh, and against the roller spin and cage speed of a dynamic run.

Reference: with the outer ring fixed and no slip, the cage frame sees the inner raceway turn
at ω_s − ω_c and the outer at −ω_c; rolling without slip on both races gives two linear
equations for the cage speed ω_c and the roller spin ω_r (Harris & Kotzalas, Vol. 1, §8):

    (ω_s − ω_c) R_i = ω_r r,    ω_c R_o = ω_r r,

R_i = (d_m − D_w)/2, R_o = (d_m + D_w)/2, r = D_w/2. A point of the outer race sees Z rollers
pass per cage revolution (BPFO = Z f_c), a point of the inner race Z per revolution relative
to the cage (BPFI = Z (f_s − f_c)).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from bearingdae import simulate
from bearingdae.physics.frequencies import characteristic_frequencies

from conftest import make_scene


def _kinematic(rollers, D, dm, f_s):
    """(f_c, BPFO, BPFI, f_spin) [Hz] from the two no-slip conditions, solved numerically."""
    w_s = 2.0 * math.pi * f_s
    R_i, R_o, r = (dm - D) / 2.0, (dm + D) / 2.0, D / 2.0
    # unknowns (ω_c, ω_r): R_i ω_c + r ω_r = R_i ω_s ;  R_o ω_c − r ω_r = 0
    w_c, w_r = np.linalg.solve([[R_i, r], [R_o, -r]], [R_i * w_s, 0.0])
    f_c = w_c / (2.0 * math.pi)
    return f_c, rollers * f_c, rollers * (f_s - f_c), w_r / (2.0 * math.pi)


@pytest.mark.parametrize("seed", range(6))
def test_frequencies_are_those_of_rolling_without_slip(seed):
    rng = np.random.default_rng(seed)
    Z = int(rng.integers(8, 60))
    dm = float(rng.uniform(0.02, 0.5))
    D = float(rng.uniform(0.05, 0.3)) * dm
    f_s = float(rng.uniform(1.0, 500.0))
    f = characteristic_frequencies(Z, D, dm, f_s)
    f_c, bpfo, bpfi, spin = _kinematic(Z, D, dm, f_s)
    assert f["shaft"] == f_s
    for name, ref in (("cage", f_c), ("roller_pass_outer", bpfo),
                      ("roller_pass_inner", bpfi), ("roller_spin", spin)):
        assert f[name] == pytest.approx(ref, rel=1e-12), name
    # the two roller passes add up to Z shaft revolutions (the rollers pass the inner race
    # at the shaft speed less the cage's)
    assert f["roller_pass_outer"] + f["roller_pass_inner"] == pytest.approx(Z * f_s, rel=1e-12)


def test_a_dynamic_run_rolls_at_the_kinematic_spin_and_records_its_frequencies():
    """The baseline (800 N, 3 N·m, 2000 r/min) after a quarter cage revolution: the loaded
    rollers (inner-race load > 50 N) spin at the kinematic roller spin within 0.1 % (they
    barely slip there), the cage turns within 1 % of the kinematic cage speed (its slip is
    ~0.4 %), and the file's frequencies are the kinematic ones at the run's geometry."""
    scene = make_scene(operating={"radial_load_N": 800.0, "moment_Nm": 3.0,
                                  "speed_rpm": 2000.0},
                       numerics={"warmup_cage_revolutions": 0.25, "cage_revolutions": 0.25,
                                 "samples_per_cage_revolution": 200},
                       output={"variables": ["spin_speed", "contact_force", "cage_speed"]})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = simulate(scene, progress=False)
    b = scene.bearing
    D, dm = b.roller_diameter_m, b.pitch_diameter_m
    f_c, bpfo, bpfi, spin = _kinematic(b.rollers, D, dm, 2000.0 / 60.0)
    f = ds.characteristic_frequencies_Hz.to_series()
    assert f["roller_pass_inner"] == pytest.approx(bpfi, rel=1e-12)
    assert f["roller_pass_outer"] == pytest.approx(bpfo, rel=1e-12)
    assert f["roller_spin"] == pytest.approx(spin, rel=1e-12)
    loaded = ds.contact_force.sel(race="inner").sum("slice") > 50.0
    measured = float(ds.spin_speed.where(loaded).mean()) / (2.0 * math.pi)
    assert measured == pytest.approx(spin, rel=1e-3)
    assert float(ds.cage_speed.mean()) / (2.0 * math.pi) == pytest.approx(f_c, rel=1e-2)
