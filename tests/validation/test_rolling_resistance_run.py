"""EHL rolling resistance in the dynamics (docs/theory.md §19), on the yang20 baseline (800 N,
3 N m, 2000 r/min).

References:
- the energy balance of the equations of motion (physics/power.py): drive power = Σ power-loss
  sources + rate of change of the kinetic energy, with the new source ``rolling_resistance``
  and the inner ring's share R_i Σ H_i in the drive torque;
- the source against the law evaluated afresh from the recorded loads and speeds (Σ H Σ);
- a published trend: the raceways' drag on the rollers makes the cage skid (Harris &
  Kotzalas, Advanced Concepts of Bearing Technology, 5th ed., 2007, ch. 5): more drag, a
  slower cage;
- a scene without the switch assembles none of it; its keys need the switch.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from physical_checks import power_balance
from bearingdae import simulate
from bearingdae.physics import rolling_resistance as rr
from bearingdae.physics.contact import slice_stiffness
from bearingdae.physics.kinematics import rolling_sums
from bearingdae.scene import SceneError
from bearingdae.system.model import build_model
from bearingdae.system.residual import PARAM_NAMES, P_RR
from conftest import make_scene

BASE = {"radial_load_N": 800.0, "moment_Nm": 3.0, "speed_rpm": 2000.0}
ON = {"physics.rolling_resistance": True}
WINDOW = {"numerics.warmup_cage_revolutions": 0.5, "numerics.cage_revolutions": 0.25,
          "numerics.samples_per_cage_revolution": 5000}


def _run(overrides):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return simulate(make_scene({**WINDOW, **overrides}, operating=BASE), progress=False)


@pytest.fixture(scope="module")
def on():
    return _run(ON)


def test_energy_balance_with_rolling_resistance(on):
    """Drive power = losses + change of kinetic energy; the new source is the largest here
    (the traction law's own loss at the baseline's small slips is well below 1 W)."""
    ds = on
    drive, losses, stored = power_balance(ds)
    assert abs(drive - losses - stored) < 0.01 * drive
    P = ds.power_loss_W.mean("time")
    assert "rolling_resistance" in list(ds.loss_source.values)
    assert float(P.sel(loss_source="rolling_resistance")) > 0.5 * float(P.sum())


def test_file_with_the_effect_keeps_the_units_contract(on, tmp_path):
    import importlib.util
    from pathlib import Path

    from bearingdae.results.netcdf import save

    spec = importlib.util.spec_from_file_location(
        "output_contract", Path(__file__).parents[1] / "results" / "test_output_contract.py")
    contract = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(contract)
    assert_units_contract = contract.assert_units_contract
    path = tmp_path / "rr.nc"
    save(on, path)
    h = assert_units_contract(path)
    assert "rolling_resistance" in h["loss_source"]["description"]
    # the result's complete TOML states the oil keys the defaults decided, and reads back
    import tomllib

    from bearingdae import scene_from_dict

    data = tomllib.loads(on.attrs["scene_toml"])
    assert data["physics"]["rolling_resistance"] == "biboulet_houpert"  # what true means
    assert data["lubricant"]["temperature_viscosity_K_inv"] == 0.03
    assert data["lubricant"]["thermal_conductivity_W_m_K"] == 0.13
    assert scene_from_dict(data).lubricant == make_scene(ON).lubricant


def test_source_is_the_law_at_the_recorded_state(on):
    """Σ H Σ over every slice and race, from the recorded loads and speeds with the law of
    physics/rolling_resistance.py (H = F(q, ū) (Σ/2)/ū) and the scene's oil, evaluated here."""
    ds = on
    m = build_model(make_scene({**WINDOW, **ON}, operating=BASE))
    g, lub = m.geometry, m.scene.lubricant
    d = ds.isel(time=slice(0, None, 250))
    w = d.inner_ring_speed.values[:, None]
    s_i, s_o = rolling_sums(w, d.orbit_speed.values, d.spin_speed.values, g.roller_radius_m,
                            g.inner_race_radius_m, g.outer_race_radius_m)
    q = d.contact_force.values
    wc = rr.light_load_per_length(slice_stiffness(g.slice_width_m, g.roller_length_m,
                                                  g.compliance_m2_N),
                                  m.scene.numerics.contact_smoothing_m, g.slice_width_m)
    total = 0.0
    for c, s, R in ((0, s_i, g.reduced_radius_inner_m), (1, s_o, g.reduced_radius_outer_m)):
        u = np.sqrt((0.5 * s) ** 2 + rr.ROLLING_SPEED_FLOOR_M_S ** 2)[..., None]
        f = rr.rolling_force_per_length(q[..., c] / g.slice_width_m, R, u,
                                        lub.viscosity_Pa_s,
                                        m.scene.engineering.pressure_viscosity_Pa_inv,
                                        2.0 / g.compliance_m2_N, lub.temperature_viscosity_K_inv,
                                        lub.thermal_conductivity_W_m_K, wc,
                                        rr.BIBOULET_HOUPERT, 0.0, 0.0)[0]
        total = total + np.sum(f * g.slice_width_m * np.abs(0.5 * s)[..., None] / u
                               * np.abs(s)[..., None], axis=(1, 2))
    recorded = d.power_loss_W.sel(loss_source="rolling_resistance").values
    np.testing.assert_allclose(recorded, total, rtol=1e-9)


def test_the_starved_source_is_the_law_at_the_recorded_state():
    """With an inlet film: the recorded source (physics/power.py, one compiled loop) against
    the law called from Python slice by slice at the recorded loads and speeds, and below the
    flooded source of the same state (B&H's ratio < 1)."""
    over = {**ON, "lubricant.inlet_film_um": 0.2, "numerics.warmup_cage_revolutions": 0.0,
            "numerics.cage_revolutions": 0.02, "numerics.samples_per_cage_revolution": 2000}
    ds = _run(over)
    m = build_model(make_scene({**WINDOW, **over}, operating=BASE))
    g, lub = m.geometry, m.scene.lubricant
    from bearingdae.physics.film import min_film_factor

    E = 2.0 / g.compliance_m2_N
    alpha = m.scene.engineering.pressure_viscosity_Pa_inv
    wc = rr.light_load_per_length(slice_stiffness(g.slice_width_m, g.roller_length_m,
                                                  g.compliance_m2_N),
                                  m.scene.numerics.contact_smoothing_m, g.slice_width_m)
    d = ds.isel(time=slice(0, None, 10))
    w = d.inner_ring_speed.values[:, None]
    sums = rolling_sums(w, d.orbit_speed.values, d.spin_speed.values, g.roller_radius_m,
                        g.inner_race_radius_m, g.outer_race_radius_m)
    q = d.contact_force.values
    total = flooded = 0.0
    for c, R in ((0, g.reduced_radius_inner_m), (1, g.reduced_radius_outer_m)):
        s = np.broadcast_to(sums[c][..., None], q[..., c].shape)
        for h_a, acc in ((0.2e-6, "total"), (0.0, "flooded")):
            H = np.vectorize(lambda qq, ss: rr._slice_rolling_force(
                qq, ss, g.slice_width_m, R, lub.viscosity_Pa_s, alpha, E,
                lub.temperature_viscosity_K_inv, lub.thermal_conductivity_W_m_K,
                rr.ROLLING_SPEED_FLOOR_M_S, wc, rr.BIBOULET_HOUPERT,
                min_film_factor(E, alpha), h_a)[0])(q[..., c], s)
            P = np.sum(H * s, axis=(1, 2))
            if acc == "total":
                total = total + P
            else:
                flooded = flooded + P
    recorded = d.power_loss_W.sel(loss_source="rolling_resistance").values
    np.testing.assert_allclose(recorded, total, rtol=1e-9)
    assert np.all(total < 0.9 * flooded)


@pytest.mark.slow  # a second run of the window: the CI physics step
def test_more_drag_makes_the_cage_skid_more(on):
    off = _run({})
    slip_off = 1.0 - float(off.cage_speed.mean()) / float(off["epicyclic_cage_speed_rad_s"])
    slip_on = 1.0 - float(on.cage_speed.mean()) / float(on["epicyclic_cage_speed_rad_s"])
    assert slip_on > slip_off + 1e-3, (slip_off, slip_on)
    # the rollers' spin falls behind too: the spin moment r Σ H brakes them
    assert float(on.spin_speed.mean()) < float(off.spin_speed.mean())


def test_nj_with_a_dynamic_ring_starts_and_runs():
    ds = _run({**ON, "bearing.type": "NJ", "operating.axial_load_N": 200.0,
               "physics.ring": "dynamic", "numerics.warmup_cage_revolutions": 0.0,
               "numerics.cage_revolutions": 0.05, "numerics.samples_per_cage_revolution": 400})
    P = ds.power_loss_W.mean("time")
    assert float(P.sel(loss_source="rolling_resistance")) > 0.0
    assert np.isfinite(ds.drive_power_W.values).all()


def test_a_scene_without_the_switch_assembles_none_of_it():
    m = build_model(make_scene(operating=BASE))
    assert not m.params[P_RR:].any()
    assert len(m.params) == len(PARAM_NAMES)
    assert "rolling_resistance" not in make_scene(operating=BASE).source.get("physics", {})


def test_oil_thermal_keys_need_the_switch():
    with pytest.raises(SceneError, match=r"'lubricant.temperature_viscosity_K_inv' = 0.04: .*"
                                         r"physics.rolling_resistance = true"):
        make_scene({"lubricant.temperature_viscosity_K_inv": 0.04})
    with pytest.raises(SceneError, match="thermal_conductivity_W_m_K"):
        make_scene({"lubricant.thermal_conductivity_W_m_K": -1.0, **ON})


@pytest.mark.slow  # two integrators over a tenth of a revolution: the CI physics step
@pytest.mark.parametrize("law", [ON, {"physics.rolling_resistance": "zhou_hoeprich",
                                      "lubricant.inlet_film_um": 0.3}], ids=["bh", "zh-starved"])
def test_newmark_agrees_with_ida(law):
    """The independent integrator (theory.md §12) on the same residual and Jacobian: the
    rolling-resistance power and the speeds over a tenth of a cage revolution (measured:
    1e-5 apart)."""
    over = {**law, "numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 0.1,
            "numerics.samples_per_cage_revolution": 400}
    scene = make_scene(over, operating=BASE)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = simulate(scene, progress=False)
        b = simulate(scene, solver="newmark", progress=False)
    for ds in (a, b):
        assert float(ds.power_loss_W.sel(loss_source="rolling_resistance").mean()) > 0.0
    P = [float(ds.power_loss_W.sel(loss_source="rolling_resistance").mean()) for ds in (a, b)]
    assert P[1] == pytest.approx(P[0], rel=1e-3)
    assert float(b.cage_speed.mean()) == pytest.approx(float(a.cage_speed.mean()), rel=1e-4)
    assert float(b.spin_speed.mean()) == pytest.approx(float(a.spin_speed.mean()), rel=1e-4)


def test_torque_balance_start_sees_the_rolling_resistance():
    """The skid start of solvers/torque_balance.py balances the same residual: with the
    rolling resistance braking the spins and the cage, its cage speed is lower (harris36 at
    1000 N, 5000 r/min, where the start lies below the epicyclic speed), and its spins solve
    their rows with it."""
    from bearingdae.scene import load_scene
    from bearingdae.solvers.algebraic import initial_state
    from bearingdae.solvers.torque_balance import torque_balance_state

    speeds = []
    for on in (False, True):
        m = build_model(load_scene("paper/harris36_5000rpm", {
            "operating.radial_load_N": 1000.0, "numerics.slices": 3,
            "physics.rolling_resistance": on}))
        y0, _ = initial_state(m)
        _, _, info = torque_balance_state(m, y0)
        speeds.append(info["initial_cage_speed_fraction_of_epicyclic"])
    assert 0.0 < speeds[1] < speeds[0] < 1.0, speeds


@pytest.mark.parametrize("kind, Fa", [("NU", 0.0), ("NJ", 200.0), ("NUP", -1000.0)])
@pytest.mark.parametrize("ring", ["quasi-static", "dynamic"])
def test_starts_with_every_bearing_type_and_ring(kind, Fa, ring):
    """The start (static and flange Newton, solvers/algebraic.py) and the first steps of IDA
    with the switch, for the flange types, both axial load signs and both ring models."""
    from bearingdae.solvers.algebraic import initial_state
    from bearingdae.solvers.ida import integrate

    m = build_model(make_scene({**ON, "bearing.type": kind, "operating.axial_load_N": Fa,
                                "physics.ring": ring}, operating=BASE))
    y0, yp0 = initial_state(m)
    r = integrate(m, y0, yp0, np.array([0.0, 2e-4]))
    assert r.success, r.message
    assert np.all(np.isfinite(r.y[-1]))
