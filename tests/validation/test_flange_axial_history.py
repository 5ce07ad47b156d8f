"""An axial load that changes in time (theory.md §14, §16) on the NJ baseline (800 N, 3 N m,
2000 r/min): a ramp 200 -> 1000 N inside the recorded window.

References:
- balance at every sample: the summed axial forces of the inner ring's flanges on the rollers
  equal the applied axial load at that time (the ring's axial row is algebraic), with the 1 %
  of the constant case (tests/validation/test_flange_axial.py);
- the recorded ``applied_axial_load`` is the scene's table (np.interp of its points);
- the quasi-static state with flanges uses the load at t = 0;
- Newmark-β against IDA under the ramp (theory.md §12).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from bearingdae import simulate, solve_static
from conftest import make_scene

BASE = {"radial_load_N": 800.0, "moment_Nm": 3.0, "speed_rpm": 2000.0}
#: 200 -> 1000 N between 40 and 70 ms (the record runs from ~33 ms to ~100 ms)
RAMP = {"times_s": [0.0, 0.04, 0.07], "values_N": [200.0, 200.0, 1000.0]}
WINDOW = {"numerics.warmup_cage_revolutions": 0.5, "numerics.cage_revolutions": 1.0}


def _run(scene, solver="ida"):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return simulate(scene, solver=solver, progress=False)


def _inner_sum(ds):
    return ds.inner_flange_axial_force.sum(("roller", "end")).values


@pytest.fixture(scope="module")
def ramp_run():
    return _run(make_scene({"bearing.type": "NJ", **WINDOW},
                           operating={**BASE, "axial_load_N": RAMP}))


def test_applied_axial_load_is_the_table(ramp_run):
    t = ramp_run.time.values
    assert t[0] < 0.04 and t[-1] > 0.07  # the window holds the whole ramp
    applied = ramp_run.applied_axial_load
    assert applied.attrs["units"] == "N" and "axial" in applied.attrs["long_name"]
    np.testing.assert_allclose(applied.values, np.interp(t, RAMP["times_s"], RAMP["values_N"]),
                               rtol=1e-14)


def test_inner_flanges_carry_the_axial_load_at_every_sample(ramp_run):
    """Measured: max relative deviation 1.8e-14 (the ring's axial row, solved to round-off by
    the projection of every output sample); the outer ring's flanges 6.3e-4 (k_c s)."""
    applied = ramp_run.applied_axial_load.values
    carried = _inner_sum(ramp_run)
    assert np.max(np.abs(carried / applied - 1.0)) < 1e-2
    # the outer ring's flanges carry it too (less the weak centring k_c s, theory.md §16)
    both = ramp_run.flange_axial_force.sum(("roller", "end")).values
    outer = both - np.abs(ramp_run.inner_flange_axial_force).sum(("roller", "end")).values
    assert np.max(np.abs(outer / applied - 1.0)) < 1e-2


def test_flange_friction_follows_the_ramp(ramp_run):
    t = ramp_run.time.values
    p = ramp_run.flange_friction_power.values
    before, after = p[t < 0.04].mean(), p[t > 0.075].mean()
    # Palmgren's M_f = f_f F_a d_m: ~5x for 5x the load (measured 1.78 -> 8.50 W)
    assert after > 2.0 * before


def test_an_axial_load_building_up_from_zero():
    """0 -> 1000 N from 15 to 30 ms: the ring's axial unknown, held by no flange at first, is
    centred weakly (system/flange.py); its share k_c δ_a of the balance stays below 1 % of the
    load. Measured: largest |carried - applied| 0.013 N (1.3e-5 of 1000 N)."""
    ramp = {"times_s": [0.0, 0.015, 0.03], "values_N": [0.0, 0.0, 1000.0]}
    ds = _run(make_scene({"bearing.type": "NJ", "numerics.warmup_cage_revolutions": 0.2,
                          "numerics.cage_revolutions": 0.3},
                         operating={**BASE, "axial_load_N": ramp}))
    applied = ds.applied_axial_load.values
    assert applied.min() == 0.0 and applied.max() == 1000.0
    assert np.max(np.abs(_inner_sum(ds) - applied)) < 1e-2 * applied.max()


def test_static_state_takes_the_axial_load_at_t0():
    scene = make_scene({"bearing.type": "NJ"}, operating={
        **BASE, "speed_rpm": 100.0,
        "axial_load_N": {"times_s": [0.0, 1.0], "values_N": [300.0, 1000.0]}})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        st = solve_static(scene)
    assert float(st.inner_flange_axial_force.sum()) == pytest.approx(300.0, rel=1e-9)
    assert float(st.applied_axial_load) == 300.0


def test_newmark_agrees_with_ida_under_the_ramp():
    """Solver cross-check (theory.md §12) with the ramp inside a short window (record ~13 to
    33 ms, ramp 200 -> 1000 N from 15 to 30 ms). Measured: cage speed 8e-6, flange friction
    power 1.2e-4 apart; both carry the applied load at every sample to 1.5e-14."""
    ramp = {"times_s": [0.0, 0.015, 0.03], "values_N": [200.0, 200.0, 1000.0]}
    scene = make_scene({"bearing.type": "NJ", "numerics.warmup_cage_revolutions": 0.2,
                        "numerics.cage_revolutions": 0.3},
                       operating={**BASE, "axial_load_N": ramp})
    ida, nm = _run(scene), _run(scene, solver="newmark")
    assert float(nm.cage_speed.mean() / ida.cage_speed.mean()) == pytest.approx(1.0, abs=1e-3)
    assert float(nm.flange_friction_power.mean()) == pytest.approx(
        float(ida.flange_friction_power.mean()), rel=1e-2)
    for ds in (ida, nm):
        applied = ds.applied_axial_load.values
        assert np.max(np.abs(_inner_sum(ds) / applied - 1.0)) < 1e-2
    np.testing.assert_allclose(nm.applied_axial_load.interp(time=ida.time.values),
                               ida.applied_axial_load.values, rtol=1e-12)
