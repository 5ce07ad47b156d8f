"""Axial load through the roller end-flange contacts (theory.md §16), on the yang20 baseline
(800 N, 3 N m, 2000 r/min) as NJ and NUP bearings.

References:
- balance: the summed axial flange forces on the inner ring's flanges and on the outer ring's
  equal the applied axial load (the rollers carry it from one ring to the other);
- the quasi-static state with flanges (``solve_static``) against the dynamic mean at 100 r/min;
- trends against published statements: roller end-flange friction skews the rollers (Harris &
  Kotzalas, *Advanced Concepts of Bearing Technology*, 5th ed., 2007, ch. 1, "roller skewing":
  skew grows with the flange friction moment, i.e. with the axial load); Palmgren's
  flange-friction torque M_f = f_f F_a d_m grows with the axial load; the SKF catalogue's
  permissible axial load (physics/flange.permissible_axial_load) as a plausibility warning;
- Newmark-β against IDA (theory.md §12).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from bearingdae import simulate, solve_static
from bearingdae.analysis.guards import PlausibilityWarning
from bearingdae.system.model import build_model
from conftest import make_scene

BASE = {"radial_load_N": 800.0, "moment_Nm": 3.0, "speed_rpm": 2000.0}
WINDOW = {"numerics.warmup_cage_revolutions": 0.5, "numerics.cage_revolutions": 1.0}
#: the window of the fast tier's axial balances, the one the Newmark cross-check runs (so the
#: NJ run at 200 N serves both): the flange sums settle within 0.2 cage revolutions. Measured
#: against :data:`WINDOW`: the same axial sums to 1e-7 (NJ outer 199.874 / 999.867 N, NUP
#: -0.013 % / -0.062 %), the skew RMS 1.04 / 2.42 mrad (2.22 at 1000 N over WINDOW), the
#: flange friction 1.77 / 8.41 W (1.78 / 8.47 W), at a third of the CPU.
SETTLED = {"numerics.warmup_cage_revolutions": 0.2, "numerics.cage_revolutions": 0.3}


def _scene(kind, Fa, window=WINDOW, **operating):
    return make_scene({"bearing.type": kind, "operating.axial_load_N": Fa, **window},
                      operating={**BASE, **operating})


def _run(scene, solver="ida"):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return simulate(scene, solver=solver, progress=False)


def _ring_sums(ds):
    """Time means of the summed axial flange forces on the rollers: by the inner ring's
    flanges (signed, +X) and by the outer ring's (magnitude)."""
    inner = ds.inner_flange_axial_force.sum(("roller", "end"))
    both = ds.flange_axial_force.sum(("roller", "end"))
    outer = both - abs(ds.inner_flange_axial_force).sum(("roller", "end"))
    return float(inner.mean()), float(outer.mean())


@pytest.fixture(scope="module")
def nj_runs():
    return {Fa: _run(_scene("NJ", Fa, SETTLED)) for Fa in (200.0, 1000.0)}


@pytest.mark.parametrize("Fa", [200.0, 1000.0])
def test_axial_equilibrium_nj(nj_runs, Fa):
    """Measured: inner 200.000 / 1000.000 N (the ring's axial row), outer 199.87 / 999.87 N
    (-0.063 % / -0.013 %: the axial centring k_c s of system/flange.py)."""
    inner, outer = _ring_sums(nj_runs[Fa])
    assert abs(inner / Fa - 1.0) < 1e-2
    assert abs(outer / Fa - 1.0) < 1e-2


@pytest.mark.parametrize("Fa", [1000.0, -200.0])
def test_axial_equilibrium_nup_both_directions(Fa):
    inner, outer = _ring_sums(_run(_scene("NUP", Fa, SETTLED)))
    assert abs(inner / Fa - 1.0) < 1e-2
    assert abs(outer / abs(Fa) - 1.0) < 1e-2


@pytest.mark.slow  # a long window: the CI physics step
def test_nup_loaded_the_other_way_mirrors_the_nj():
    """An NUP under -F_a is the NJ under +F_a seen from the other side: the same flange forces
    with the ends swapped."""
    a = _run(_scene("NUP", -200.0))
    b = _run(_scene("NJ", 200.0))
    fa, fb = a.flange_force.mean(("time", "roller")), b.flange_force.mean(("time", "roller"))
    assert float(fa.sel(end="a")) == pytest.approx(float(fb.sel(end="b")), rel=1e-2)
    assert float(fa.sel(end="b")) == pytest.approx(float(fb.sel(end="a")), rel=1e-2)


@pytest.mark.slow  # a long window: the CI physics step
def test_static_state_matches_the_dynamic_mean_at_low_speed():
    """100 r/min: the flange forces, the axial positions and the roller tilts of the
    quasi-static state with flanges against the dynamic run's time means. Measured: flange
    forces 1e-8, axial positions 5e-5, mean tilt 2e-4, inner-race load 1.6e-3 (the friction
    power differs:
    the static state assumes pure rolling, the dynamic rollers settle their spin between the two
    opposite flange slips; theory.md §16)."""
    scene = _scene("NJ", 200.0, speed_rpm=100.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        st = solve_static(scene)
    dyn = _run(scene)
    for name in ("flange_force", "flange_axial_force", "roller_axial_position",
                 "ring_axial_displacement"):
        assert float(dyn[name].mean()) == pytest.approx(float(st[name].mean()), rel=1e-3), name
    assert float(dyn.roller_tilt.mean()) == pytest.approx(float(st.roller_tilt.mean()), rel=5e-3)
    assert float(st.inner_flange_axial_force.sum()) == pytest.approx(200.0, rel=1e-9)


def test_skew_and_flange_friction_grow_with_axial_load(nj_runs):
    """Measured at 200 / 1000 N: skew RMS 1.04 / 2.42 mrad, flange friction 1.77 / 8.41 W
    (4.8x for 5x the load: Palmgren's f_f = P / (ω_i F_a d_m) 9.4e-4 / 8.9e-4)."""
    lo, hi = nj_runs[200.0], nj_runs[1000.0]

    def skew(ds):
        return float(np.sqrt((ds.skew_angle**2).mean()))

    assert skew(hi) > 1.5 * skew(lo)
    p_lo, p_hi = float(lo.flange_friction_power.mean()), float(hi.flange_friction_power.mean())
    assert p_hi > 2.0 * p_lo
    # Palmgren's M_f = f_f F_a d_m is linear in F_a: f_f within 25 % at both loads
    f_lo, f_hi = p_lo / 200.0, p_hi / 1000.0
    assert abs(f_hi / f_lo - 1.0) < 0.25


def test_axial_load_above_the_catalogue_limit_warns():
    """1000 N against 800 N radial: above the catalogue's 0.5 F_r for a single-row bearing."""
    with pytest.warns(PlausibilityWarning, match="permissible axial load"):
        simulate(make_scene({"bearing.type": "NJ", "operating.axial_load_N": 1000.0,
                             "numerics.warmup_cage_revolutions": 0.0,
                             "numerics.cage_revolutions": 0.05},
                            operating=BASE), progress=False)


def test_newmark_agrees_with_ida_with_flanges(nj_runs):
    """Solver cross-check (theory.md §12), measured: cage speed 2e-5, flange friction power
    4e-4, skew RMS 7e-4 apart. The IDA run is the NJ run at 200 N of the axial balance."""
    ida, nm = nj_runs[200.0], _run(_scene("NJ", 200.0, SETTLED), solver="newmark")
    assert float(nm.cage_speed.mean() / ida.cage_speed.mean()) == pytest.approx(1.0, abs=1e-3)
    assert float(nm.flange_friction_power.mean()) == pytest.approx(
        float(ida.flange_friction_power.mean()), rel=1e-2)


def test_a_scene_without_flanges_assembles_none_of_it():
    m = build_model(make_scene(operating=BASE))
    assert "axial_position" not in m.layout.local_names
    assert "ring_axial" not in m.layout.global_names
    nu = build_model(make_scene({"bearing.type": "NU"}, operating=BASE))
    assert "axial_position" in nu.layout.local_names
    assert "ring_axial" not in nu.layout.global_names  # no axial load: the ring is not held


def test_energy_balance_with_flanges():
    """Drive power = losses + change of kinetic energy (physics/power.py) with the flange
    friction as a source and the inner-ring flange friction in the drive torque. The inner
    ring passes ~44 W to the rollers through its flange's friction and takes most of it back
    through the raceway traction: without the flange term the drive power read -38 W."""
    scene = make_scene({"bearing.type": "NJ", "operating.axial_load_N": 200.0,
                        "numerics.warmup_cage_revolutions": 0.5,
                        "numerics.cage_revolutions": 0.25,
                        "numerics.samples_per_cage_revolution": 5000}, operating=BASE)
    ds = _run(scene)
    t = ds.time.values
    span = t[-1] - t[0]

    def mean(v):
        return np.trapezoid(v, t) / span

    drive = mean(ds.drive_power_W.values)
    losses = mean(ds.power_loss_W.sum("loss_source").values)
    stored = (ds.kinetic_energy_J.values[-1] - ds.kinetic_energy_J.values[0]) / span
    assert abs(drive - losses - stored) < 0.01 * drive
    # the flange source against its law typed afresh (theory.md §16) from the recorded normal
    # forces and sliding speeds: Σ μ_f Q V² / sqrt(V² + v_f²), v_f = 1 mm/s, per roller end
    # (each end's other contact is open: measured 2e-12 apart)
    mu, v_f = scene.bearing.flanges.friction, 1e-3
    Q, V = ds.flange_force.values, ds.flange_slip_velocity.values
    recomputed = np.sum(mu * Q * V * V / np.sqrt(V * V + v_f * v_f), axis=(1, 2))
    flange = ds.power_loss_W.sel(loss_source="flange_friction").values
    assert flange.mean() > 0.2 * losses  # the flange is a main source here (1.78 of 3.96 W)
    np.testing.assert_allclose(flange, recomputed, rtol=1e-6)
