"""An effect written only here: a constant moment M_e against each roller's spin, one law and
one declaration (system/effect.Effect) registered with system/extensions.register_effect, no
other file changed. It passes the checks every effect passes: its Jacobian block against
finite differences, the energy balance with its power source, its key refused without its
switch and absent from the complete TOML, its variable in a run and stacked in a sweep, its
heat in a thermal run. docs/adding-an-effect.md shows this module as its example.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from numba import njit
from pydantic import ConfigDict, Field

from bearingdae.scene.histories import _Section
from bearingdae.system.effect import Effect, Source
from bearingdae.system.extensions import register_effect, unregister_effect
from bearingdae.system.layout import LOCAL

SPIN = LOCAL.index("spin_speed")  #: the spin row and unknown ω of each roller
ORBIT = LOCAL.index("orbit_speed")  #: its orbit speed Ω
SPIN_SCALE_RAD_S = 1.0  #: ω - Ω over which the moment turns with the spin's sign


# ---- the law (a physics/ module's job): M = M_e tanh((ω - Ω)/ω_s), against the spin ----
# (ω - Ω: the roller's spin against the ground, physics/power.py's convention)
@njit
def roller_moment(spin_rad_s, moment_N_m, scale_rad_s):
    """The moment against the spin [N m]: M_e, its sign the spin's, smoothed over ω_s."""
    return moment_N_m * np.tanh(spin_rad_s / scale_rad_s)


@njit
def roller_moment_slope(spin_rad_s, moment_N_m, scale_rad_s):
    """dM/d(ω - Ω) [N m s]."""
    c = np.cosh(spin_rad_s / scale_rad_s)
    return moment_N_m / (scale_rad_s * c * c)


# ---- the declaration: its key, parameters, passes, power source and output variable ----
class RollerMomentInput(_Section):
    """``[roller_moment]``: read by ``physics.roller_moment`` alone."""

    model_config = ConfigDict(json_schema_extra={"switch": "roller_moment"})
    moment_N_m: float = Field(default=2e-4, gt=0.0, le=1.0, description="moment against "
                              "each roller's spin")


@njit
def moment_rows(yl, ypl, yg, ypg, w_ring, PE, resl, resg):
    """Each roller's spin row I_x ω' - [... - M]: + M (``PE`` = (M_e, ω_s))."""
    for j in range(yl.shape[0]):
        resl[j, SPIN] += roller_moment(yl[j, SPIN] - yl[j, ORBIT], PE[0], PE[1])


@njit
def moment_block(yl, yg, w_ring, PE, S, RS, lmap, gmap, Jd):
    """d(moment_rows)/d(ω, Ω) in the scaled iteration matrix (each roller's spin row)."""
    nl = lmap.shape[0]
    a_w = a_o = -1
    for a in range(nl):
        if lmap[a] == SPIN:
            a_w = a
        elif lmap[a] == ORBIT:
            a_o = a
    for j in range(yl.shape[0]):
        row, col_w, col_o = j * nl + a_w, j * nl + a_w, j * nl + a_o
        slope = roller_moment_slope(yl[j, SPIN] - yl[j, ORBIT], PE[0], PE[1])
        Jd[row, col_w] += slope * S[col_w] / RS[row]
        Jd[row, col_o] -= slope * S[col_o] / RS[row]


def moment_parameters(scene, geometry, context) -> dict:
    section = scene.extensions.get("roller_moment")  # (None: the switch is off: all 0)
    return {"rm_M": section.moment_N_m if section else 0.0,
            "rm_ws": SPIN_SCALE_RAD_S if section else 0.0}


def moment_power(model, t, values, own, P, drive) -> None:
    """Its source: M (ω - Ω) summed over the rollers [W]."""
    spin = np.asarray(values["spin_speed"]) - np.asarray(values["orbit_speed"])
    P["roller_moment"] = np.sum(roller_moment(spin, own[0], own[1]) * spin, axis=-1)


def moment_values(model, t, full_l, full_g, own) -> dict:
    spin = full_l[..., SPIN] - full_l[..., ORBIT]
    return {"roller_extra_moment": roller_moment(spin, own[0], own[1])}


ROLLER_MOMENT = Effect(
    name="roller_moment", switch="roller_moment", params=("rm_M", "rm_ws"),
    parameters=moment_parameters, passes=(moment_rows, moment_block),
    sources=(Source("roller_moment", "a moment against each roller's spin",
                    (0.0, 0.0, 1.0, 0.0, 0.0)),),  # heat: the rollers
    power=moment_power, values=moment_values, section=RollerMomentInput,
    switch_description="a moment against each roller's spin ([roller_moment])",
    variables={"roller_extra_moment": (("roller",), "N m",
                                       "moment against the roller's spin")})


@pytest.fixture(scope="module", autouse=True)
def registered():
    """A module of the user's would call ``register_effect(ROLLER_MOMENT)`` as it is
    imported; here for this module's tests alone (the others see the package as it is)."""
    register_effect(ROLLER_MOMENT)
    yield ROLLER_MOMENT
    unregister_effect(ROLLER_MOMENT)


# ---- the generic checks ----
from bearingdae import scene_from_dict, simulate  # noqa: E402
from bearingdae.scene import SceneError  # noqa: E402
from bearingdae.system import effects  # noqa: E402
from bearingdae.system.model import build_model  # noqa: E402
from conftest import make_scene  # noqa: E402

ON = {"physics.roller_moment": True, "roller_moment.moment_N_m": 2e-3}
LOADS = {"radial_load_N": 800.0, "moment_Nm": 3.0, "speed_rpm": 2000.0}
RUN_MOMENT_N_M = 2e-5


def test_its_key_is_refused_without_its_switch_and_absent_from_the_complete_toml():
    with pytest.raises(SceneError, match=r"'roller_moment.moment_N_m' = 0.002: is read by "
                       r"roller_moment only \('physics.roller_moment' = false\); set "
                       r"physics.roller_moment = true"):
        make_scene({"roller_moment.moment_N_m": 2e-3})
    off = make_scene().to_toml(complete=True)
    assert "roller_moment" not in off
    on = make_scene(ON)
    assert on.extensions["roller_moment"].moment_N_m == 2e-3
    import tomllib

    data = tomllib.loads(on.to_toml(complete=True))
    assert data["physics"]["roller_moment"] is True
    assert data["roller_moment"] == {"moment_N_m": 2e-3}
    assert scene_from_dict(data).extensions == on.extensions  # the complete TOML reads back
    assert effects.is_on(ROLLER_MOMENT, on) and not effects.is_on(ROLLER_MOMENT, make_scene())


def test_its_parameters_follow_the_others_and_are_zero_off():
    P_on = build_model(make_scene(ON)).params
    P_off = build_model(make_scene()).params
    s = effects.param_slice(ROLLER_MOMENT)
    assert s.start == len(effects.PARAM_NAMES) and s.stop == P_on.size
    assert list(P_on[s]) == [2e-3, SPIN_SCALE_RAD_S] and list(P_off[s]) == [0.0, 0.0]
    np.testing.assert_array_equal(P_on[:s.start], P_off[:s.start])


@pytest.fixture(scope="module")
def run():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        # (the window and sampling of the other effects' balances, e.g.
        # tests/validation/test_rolling_resistance_run.py: the means need dense samples)
        # a moment small against the traction (2e-5 N m: the rollers keep rolling, ~0.5 W)
        return simulate(make_scene({**ON, "roller_moment.moment_N_m": RUN_MOMENT_N_M,
                                    "numerics.warmup_cage_revolutions": 0.5,
                                    "numerics.cage_revolutions": 0.25,
                                    "numerics.samples_per_cage_revolution": 5000},
                                   operating=LOADS), progress=False)


@pytest.mark.slow  # its kernels compile in the test's process (not cached)
def test_its_jacobian_block_matches_central_differences():
    from bearingdae.solvers.algebraic import initial_state
    from bearingdae.solvers.ida import check_jacobian, integrate

    m = build_model(make_scene(ON, operating=LOADS))
    y0, yp0 = initial_state(m)
    r = integrate(m, y0, yp0, np.array([0.0, 2e-3]))
    assert r.success, r.message
    assert check_jacobian(m, r.y[-1], r.yp[-1], jacobian="analytic", rel_step=1e-7) < 2e-4
    # near zero spin, where the block's entries are largest: the law's slope against its
    # own central differences, typed afresh
    w = np.linspace(-3.0, 3.0, 13)
    h = 1e-6
    fd = (roller_moment(w + h, 2e-3, 1.0) - roller_moment(w - h, 2e-3, 1.0)) / (2 * h)
    np.testing.assert_allclose(roller_moment_slope(w, 2e-3, 1.0), fd, rtol=1e-7)


@pytest.mark.slow  # its kernels compile in the test's process (not cached)
def test_its_variable_and_power_in_a_run_and_the_energy_balance(run):
    from physical_checks import power_balance

    ds = run
    assert ds["roller_extra_moment"].dims == ("time", "roller")
    assert ds["roller_extra_moment"].attrs["units"] == "N m"
    spin = ds.spin_speed.values - ds.orbit_speed.values
    np.testing.assert_allclose(ds["roller_extra_moment"].values,
                               RUN_MOMENT_N_M * np.tanh(spin / SPIN_SCALE_RAD_S), rtol=1e-12)
    assert "roller_moment" in list(ds.loss_source.values)
    P = ds.power_loss_W.sel(loss_source="roller_moment").values
    np.testing.assert_allclose(P, np.sum(RUN_MOMENT_N_M * np.tanh(spin) * spin, axis=-1),
                               rtol=1e-9)
    drive, losses, stored = power_balance(ds)
    assert abs(drive - losses - stored) < 0.01 * drive
    assert float(np.mean(P)) > 0.05 * losses  # 5 times the balance's tolerance: it counts


@pytest.mark.slow  # its kernels compile in the test's process (not cached)
def test_the_energy_balance_holds_when_the_moment_dominates_the_losses():
    """A moment 1000 times the run's above (2e-2 N m per roller): it brakes every roller's
    spin against the traction, and its power is most of the bearing's loss. The balance
    drive = losses + d(stored)/dt still closes, so the power source counts M·(ω − Ω), the
    work the moment does on the roller's spin relative to the cage, not M·ω."""
    from physical_checks import power_balance

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = simulate(make_scene({**ON, "roller_moment.moment_N_m": 2e-2,
                                  "numerics.warmup_cage_revolutions": 0.5,
                                  "numerics.cage_revolutions": 0.25,
                                  "numerics.samples_per_cage_revolution": 5000},
                                 operating=LOADS), progress=False)
    drive, losses, stored = power_balance(ds)
    assert abs(drive - losses - stored) < 0.01 * drive
    P = float(ds.power_loss_W.sel(loss_source="roller_moment").mean())
    assert P > 0.5 * losses  # the moment's own power is the larger part of the loss


def test_its_heat_reaches_the_thermal_network():
    """A block's losses carry its source, and the rollers' node gets exactly its power: the
    network's heat with it less the heat without it."""
    from bearingdae.solvers.algebraic import initial_state
    from bearingdae.system.samples import block_inputs
    from bearingdae.system.thermal_network import network

    scene = make_scene({**ON, "physics.thermal": "steady", "operating.speed_rpm": 3000.0})
    model = build_model(scene)
    y0, _ = initial_state(model)
    inputs = block_inputs(model, np.array([0.0, 1e-4]), np.array([y0, y0]))
    assert [s.name for s in effects.sources(scene)][-1] == "roller_moment"
    spin = (model.geometry.pure_rolling_spin(model.ring_speed(0.0))
            - model.geometry.epicyclic_orbit_speed(model.ring_speed(0.0)))
    expected = model.geometry.rollers * 2e-3 * np.tanh(spin) * spin
    assert inputs["losses"]["roller_moment"] == pytest.approx(expected, rel=1e-6)
    net = network(scene, model.geometry, effects.heat_partition())
    _, q = net.solve(inputs["losses"], *inputs["band_area_m2"])
    without = {k: v for k, v in inputs["losses"].items() if k != "roller_moment"}
    _, q0 = net.solve(without, *inputs["band_area_m2"])
    assert q - q0 == pytest.approx(np.array([0.0, 0.0, expected, 0.0, 0.0]), abs=1e-12)


@pytest.mark.slow  # its kernels compile in the test's process (not cached)
def test_its_heat_in_a_thermal_run():
    """A thermal run with the effect: its source among the losses, and the rollers' node
    heated by its power on top of the others' (the last block's losses, partitioned)."""
    ds = simulate(make_scene({"physics.roller_moment": True, "physics.thermal": "steady",
                              "numerics.samples_per_cage_revolution": 40,
                              "numerics.cage_revolutions": 0.25,
                              "numerics.warmup_cage_revolutions": 0.5,
                              "numerics.steady_block_cage_revolutions": 0.5,
                              "numerics.max_warmup_cage_revolutions": 10.0,
                              "numerics.slices": 4, "operating.radial_load_N": 800.0,
                              "operating.speed_rpm": 4000.0}), progress=False)
    assert ds.thermal_blocks.attrs["converged"] == 1
    P = ds.power_loss_W.mean("time")
    own = float(P.sel(loss_source="roller_moment"))
    assert own > 0.5 * float(P.sum())  # (2e-4 N m on every roller: the largest source)
    partition = effects.heat_partition()
    rollers = sum(float(P.sel(loss_source=s)) * partition[s][2] for s in P.loss_source.values)
    heat = ds.heat_input_W.values[list(ds.thermal_node.values).index("rollers")]
    assert float(heat) == pytest.approx(rollers, rel=0.2)
    assert float(heat) > 0.8 * own  # without its source the rollers would get far less


@pytest.mark.slow  # its kernels compile in the test's process (not cached)
def test_its_variable_is_stacked_in_a_sweep(tmp_path):
    """Along the sweep's axis (its own key), one roller's orbit of its variable: the law at
    the orbit's spin, written afresh here."""
    from bearingdae.studies.sweep import run_sweep

    path = tmp_path / "moment.toml"
    path.write_text('base = "yang20_baseline"\n[overrides]\n'
                    '"physics.roller_moment" = true\n'
                    '"numerics.warmup_cage_revolutions" = 0.0\n'
                    '"numerics.cage_revolutions" = 1.3\n'
                    '[axes]\n"roller_moment.moment_N_m" = [2e-4, 2e-3]\n')
    ds = run_sweep(path, tmp_path / "moment.nc", scheduler="synchronous", progress=False)
    assert list(ds.status.values) == ["completed", "completed"]
    stacked = ds["roller_extra_moment"]
    assert stacked.dims[-1] == "azimuth" and stacked.shape[0] == 2
    # the law's bound M_e, reached where the roller spins (the tanh flat), at each point
    for M, orbit in zip((2e-4, 2e-3), stacked.values):
        assert np.all(np.abs(orbit) <= M * (1 + 1e-12))
        assert np.max(np.abs(orbit)) == pytest.approx(M, rel=1e-6)
    assert stacked.attrs["units"] == "N m"


def test_its_scene_compiles_in_one_process_on_a_cold_start(monkeypatch):
    """A cold start hands the Jacobian and the projection to a second process
    (run/integrate.compile_aside), which imports the package, not the user's module: a scene
    with an extension keeps them in the run's process, a scene without hands them over."""
    from bearingdae import IDA
    from bearingdae.run import integrate
    from bearingdae.solvers.sundials import callbacks

    asked = []
    monkeypatch.setattr(callbacks, "compile_aside",
                        lambda kind, busy_ok=False, optional=False, scene=None:
                        asked.append((kind, scene)) or False)
    plain, extended = make_scene(), make_scene(ON)
    integrate.compile_aside(IDA(), extended)
    assert asked == []
    integrate.compile_aside(IDA(), plain)
    assert asked == [("analytic", plain)]
