"""The thermal coupling of a run (physics.thermal = "steady", run/thermal_coupling.py,
theory.md §21): it converges, its network balances, the oil warms with speed, the viscosity it
sets is the one the kernel and the post-processing use, and a scene without it assembles none
of it."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from bearingdae import simulate
from bearingdae.physics.heat_network import NODES
from bearingdae.physics.oil_viscosity import rated_viscosity
from bearingdae.system.model import build_model
from bearingdae.system.residual import PARAM_NAMES
from bearingdae.system.effects import heat_partition, set_viscosity
from bearingdae.system.thermal_network import network, oil_viscosity_Pa_s
from conftest import make_scene

#: short blocks and records: the coupling's arithmetic, not converged dynamics
SHORT = {"numerics.samples_per_cage_revolution": 40, "numerics.cage_revolutions": 0.25,
         "numerics.warmup_cage_revolutions": 0.5, "numerics.steady_block_cage_revolutions": 0.5,
         "numerics.max_warmup_cage_revolutions": 10.0, "numerics.slices": 4,
         "operating.radial_load_N": 800.0, "physics.thermal": "steady"}
#: the default oil (ISO VG 32, scene/thermal_switch.py) by its data, so that a test can give
#: the first block's temperature (lubricant.operating_temperature_C needs the data)
DEFAULT_OIL = {"lubricant.viscosity_40C_mm2_s": 32.0, "lubricant.viscosity_100C_mm2_s": 5.4}


def thermal_run(speed_rpm, **over):
    return simulate(make_scene({**SHORT, "operating.speed_rpm": speed_rpm, **over}),
                    progress=False)


def test_a_scene_without_the_switch_assembles_none_of_it():
    model = build_model(make_scene({"operating.speed_rpm": 2000.0}))
    assert model.thermal is None and model.scene.thermal is None
    assert model.params[PARAM_NAMES.index("mu_oil")] == 0.01


def test_the_viscosity_is_the_kernels_parameter_set_in_place():
    """set_viscosity writes the parameter vector the compiled kernels read (the work buffer's
    memory): the residual's drag changes with it, no model is rebuilt."""
    model = build_model(make_scene({"operating.speed_rpm": 2000.0, "numerics.slices": 4}))
    assert any(np.shares_memory(model.params, w) for w in model.work)
    from bearingdae.solvers.algebraic import initial_state

    y, yp = initial_state(model)
    r1 = model.residual(0.0, y, yp)
    set_viscosity(model, 0.05)
    r2 = model.residual(0.0, y, yp)
    assert model.params[PARAM_NAMES.index("mu_oil")] == 0.05
    assert model.scene.lubricant.viscosity_Pa_s == 0.05
    assert not np.array_equal(r1, r2)


def test_coupled_run_converges_and_its_network_balances(capsys):
    ds = thermal_run(6000.0, **{"thermal.oil_flow_l_min": 0.02})
    blocks = int(ds.thermal_blocks)
    with capsys.disabled():
        print(f"\n[thermal] 6000 r/min: oil {float(ds.temperature.sel(thermal_node='oil')):.2f}"
              f" °C after {blocks} blocks, last change "
              f"{float(ds.oil_temperature_last_change_K):.3g} K, kappa "
              f"{float(ds.viscosity_ratio_kappa):.3g}")
    assert ds.thermal_blocks.attrs["converged"] == 1 and blocks >= 1
    assert abs(float(ds.oil_temperature_last_change_K)) < 0.5
    # the heat balance of the steady network: all heat leaves through the fixed temperatures
    scene = make_scene({**SHORT, "operating.speed_rpm": 6000.0, "thermal.oil_flow_l_min": 0.02})
    net = network(scene, build_model(scene).geometry, heat_partition())
    T, q = ds.temperature.values, ds.heat_input_W.values
    out = np.sum(net.to_fixed * T - net.fixed_flow)
    assert out == pytest.approx(q.sum(), rel=1e-9)
    # the heat is the record's power loss partitioned (up to the last block's own mean)
    assert q.sum() == pytest.approx(float(ds.power_loss_W.mean("time").sum()), rel=0.2)
    # the viscosity the record's raceway films ran with is their temperature's, by ASTM D341:
    # the mean of each race's ring and roller nodes (the drag's is the oil node's)
    Tn = {n: float(ds.temperature.sel(thermal_node=n)) for n in NODES}
    film_C = 0.25 * (Tn["inner_ring"] + Tn["outer_ring"] + 2.0 * Tn["rollers"])
    mu, nu = oil_viscosity_Pa_s(scene, film_C)
    assert float(ds.operating_viscosity_Pa_s) == pytest.approx(mu, rel=1e-12)
    assert float(ds.viscosity_ratio_kappa) == pytest.approx(
        nu / rated_viscosity(6000.0, 45.0), rel=1e-12)
    for name in ("temperature", "heat_input_W", "operating_viscosity_Pa_s",
                 "viscosity_ratio_kappa", "thermal_blocks"):
        assert ds[name].attrs["units"] and ds[name].attrs["long_name"]


def test_energy_balance_closes_at_the_viscosity_the_coupling_set():
    """Drive power = Σ sources + dE/dt over a densely sampled record (tests/physical_checks.py),
    the sources computed at the coupled viscosity: the kernel ran at that viscosity too (the
    orbit drag, most of the loss here, is ∝ the viscosity's laminar share: a kernel left at
    the start's viscosity would miss the balance by far more than 1 %)."""
    from physical_checks import power_balance

    ds = thermal_run(2000.0, **{"numerics.samples_per_cage_revolution": 4000,
                                "numerics.cage_revolutions": 0.1})
    start, _ = oil_viscosity_Pa_s(make_scene(SHORT), 40.0)
    assert abs(float(ds.operating_viscosity_Pa_s) / start - 1.0) > 0.05  # it did change
    drive, losses, stored = power_balance(ds)
    assert abs(drive - losses - stored) < 0.01 * drive


@pytest.mark.slow
def test_oil_temperature_rises_with_speed(capsys):
    oil = []
    for n in (1000.0, 4000.0, 12000.0):
        ds = thermal_run(n, **{"thermal.oil_flow_l_min": 0.02})
        oil.append(float(ds.temperature.sel(thermal_node="oil")))
    with capsys.disabled():
        print(f"\n[thermal] oil temperature at 1000, 4000, 12000 r/min: "
              + ", ".join(f"{t:.2f}" for t in oil) + " °C")
    assert oil[0] < oil[1] < oil[2]


def test_streamed_file_is_the_in_memory_run_and_keeps_the_units_contract(tmp_path):
    """The file of ``bearingdae run`` (streamed) has the thermal variables of the in-memory
    Dataset, the node labels as a CF label coordinate, units and long names on each."""
    from tests.results.test_output_contract import assert_units_contract

    scene = make_scene({**SHORT, "operating.speed_rpm": 3000.0})
    mem = simulate(scene, progress=False)
    simulate(scene, progress=False, output=tmp_path / "t.nc").close()
    with xr.open_dataset(tmp_path / "t.nc") as ds:
        assert list(ds.thermal_node.values) == list(NODES)
        assert ds.temperature.attrs["units"] == "degC" and int(ds.thermal_blocks) >= 1
        for name in ("temperature", "heat_input_W", "operating_viscosity_Pa_s",
                     "viscosity_ratio_kappa", "thermal_blocks"):
            np.testing.assert_allclose(ds[name].values, mem[name].values, rtol=1e-9)
    assert_units_contract(tmp_path / "t.nc")
    from bearingdae import save

    assert_units_contract(save(mem, tmp_path / "m.nc"))  # the in-memory Dataset saved
    from tests.results.test_output_contract import cfchecks

    for name in ("t.nc", "m.nc"):  # the CF checker: no error, no warning (degC, the label)
        work = tmp_path / f"cf-{name}"
        work.mkdir()
        r = cfchecks(tmp_path / name, work)
        assert r["counts"]["ERRORS detected"] == 0 and r["counts"]["WARNINGS given"] == 0, \
            r["output"]
        assert r["findings"] == [], r["output"]


def test_the_coupling_state_resumes_a_warm_up(monkeypatch):
    """A warm-up checkpoint keeps the coupling's state (run/steady.py): restored, a new
    coupling has the same oil temperatures, node temperatures and viscosity."""
    from bearingdae.run import thermal_coupling as coupling

    scene = make_scene({**SHORT, "operating.speed_rpm": 3000.0})
    losses = {"losses": {"orbit_drag": 4.0, "raceway_inner": 0.5}, "band_area_m2": (2e-6, 3e-6)}
    monkeypatch.setattr(coupling, "block_inputs", lambda model, t, Ys: losses)
    first = coupling.ThermalCoupling(build_model(scene))
    first.after_block(None, None)
    first.after_block(None, None)
    assert first.blocks == 2 and first.converged  # the same losses: no change the 2nd time
    again = coupling.ThermalCoupling(build_model(scene))
    again.restore(first.state())
    assert again.oil_C == first.oil_C and again.viscosity_Pa_s == first.viscosity_Pa_s
    np.testing.assert_array_equal(again.temperatures_C, first.temperatures_C)
    mu = again.model.params[PARAM_NAMES.index("mu_oil")]
    start, _ = oil_viscosity_Pa_s(scene, 40.0)  # a model starts with the oil at its inlet
    assert build_model(scene).params[PARAM_NAMES.index("mu_oil")] == pytest.approx(start)
    assert mu == first.oil_viscosity_Pa_s != pytest.approx(start)


def test_every_viscosity_parameter_of_the_scene_follows():
    """The whirling cage's land film reads its own viscosity entry: set with the drag's."""
    model = build_model(make_scene({"operating.speed_rpm": 2000.0, "physics.cage_whirl": True,
                                    "numerics.slices": 4}))
    set_viscosity(model, 0.042)
    for name in ("mu_oil", "wh_visc"):
        assert model.params[PARAM_NAMES.index(name)] == 0.042


@pytest.mark.slow
@pytest.mark.parametrize("over", [
    {"bearing.type": "NJ", "operating.axial_load_N": 200.0, "physics.ring": "dynamic"},
    {"bearing.type": "NUP", "operating.axial_load_N": -150.0},
    {"physics.cage_whirl": True},
], ids=["NJ-dynamic-ring", "NUP-negative-axial", "cage-whirl"])
def test_coupling_with_the_other_effects(over):
    """With flanges (their friction heats rings and rollers), a dynamic ring, a whirling cage
    (its land): the coupling converges and its heat is the record's losses partitioned."""
    ds = thermal_run(4000.0, **over)
    assert ds.thermal_blocks.attrs["converged"] == 1
    extra = "flange_friction" if "bearing.type" in over else "cage_land"
    assert extra in list(ds.loss_source.values)
    assert float(ds.heat_input_W.sum()) == pytest.approx(
        float(ds.power_loss_W.mean("time").sum()), rel=0.2)


@pytest.mark.slow
def test_newmark_agrees_with_ida_on_the_temperatures():
    """The independent integrator (Newmark-β) through the same coupling: the node
    temperatures agree to 0.1 K (IDA and Newmark differ by their integration errors only)."""
    from bearingdae import Newmark

    scene = make_scene({**SHORT, "operating.speed_rpm": 12000.0})
    a = simulate(scene, progress=False)
    b = simulate(scene, solver=Newmark(), progress=False)
    assert int(a.thermal_blocks) == int(b.thermal_blocks)
    np.testing.assert_allclose(a.temperature.values, b.temperature.values, atol=0.1)


@pytest.mark.slow
def test_a_cold_inlet_settles():
    """Oil entering at -60 °C into an oil bath at 10 000 r/min: thick oil, large losses, then a
    hot network answer and thin oil. The under-relaxed fixed point (run/thermal_coupling.py) settles
    within the warm-up cap at temperatures a bearing can have, judged on its residual."""
    ds = thermal_run(10000.0, **{"thermal.oil_inlet_temperature_C": -60.0,
                                 "thermal.oil_flow_l_min": 0.0})
    assert ds.thermal_blocks.attrs["converged"] == 1
    assert abs(float(ds.oil_temperature_last_change_K)) < ds.oil_temperature_last_change_K.attrs[
        "tolerance_K"]
    T = ds.temperature.values
    assert np.all(np.isfinite(T)) and T.max() < 250.0 and T.min() > -60.0


def test_the_first_block_starts_at_the_network_answer_to_the_start_losses(monkeypatch):
    """ThermalCoupling.start_from: losses that do not depend on the temperature make the
    network's answer to the start's losses the fixed point itself, so the first block
    converges; with lubricant.operating_temperature_C given the first block starts there."""
    from bearingdae.run import thermal_coupling as coupling

    scene = make_scene({**SHORT, "operating.speed_rpm": 3000.0})
    losses = {"losses": {"orbit_drag": 4.0, "raceway_inner": 0.5}, "band_area_m2": (2e-6, 3e-6)}
    monkeypatch.setattr(coupling, "block_inputs", lambda model, t, Ys: losses)
    c = coupling.ThermalCoupling(build_model(scene))
    assert c.start_from(0.0, None)
    net = network(scene, c.model.geometry, heat_partition())
    T, _ = net.solve(losses["losses"], *losses["band_area_m2"])
    np.testing.assert_allclose(c.run_C, T, rtol=1e-12)
    assert c.oil_C == [pytest.approx(T[NODES.index("oil")], rel=1e-12)] and c.blocks == 0
    c.after_block(None, None)
    assert c.blocks == 1 and c.converged and abs(c.last_change_K) < 1e-9
    given = make_scene({**SHORT, **DEFAULT_OIL, "operating.speed_rpm": 3000.0,
                        "lubricant.operating_temperature_C": 45.0})
    c = coupling.ThermalCoupling(build_model(given))
    assert not c.start_from(0.0, None) and np.all(c.run_C == 45.0)


def test_the_start_guess_lands_on_the_fixed_point_the_inlet_start_reaches():
    """The run started at the network's answer to the start losses and the run started with
    every node at the inlet temperature (operating_temperature_C = the inlet's: the old
    start) converge to the same temperatures, within the coupling's tolerance, and the same
    loss, within the record's spread; the guess takes fewer blocks."""
    guess = thermal_run(3000.0)
    inlet = thermal_run(3000.0, **DEFAULT_OIL, **{"lubricant.operating_temperature_C": 40.0})
    tol = guess.temperature.attrs.get("tolerance_K", 0.5)
    assert int(guess.thermal_blocks) < int(inlet.thermal_blocks)
    np.testing.assert_allclose(guess.temperature.values, inlet.temperature.values, atol=tol)
    a, b = (float(ds.mean_power_loss_W) for ds in (guess, inlet))
    spread = 3.0 * max(float(ds.mean_power_loss_stderr_W) for ds in (guess, inlet))
    assert abs(a - b) < max(spread, 0.01 * b)
