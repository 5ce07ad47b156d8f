"""An effect written only here: a constant extra moment M_e on each roller's spin, declared
once (system/effect.Effect) and handed to the generic machinery of system/effects.py with no
other file changed.

What it reaches today: its source and heat partition (the thermal network's heat), its
power in the power accounting of a block, and its residual pass with its Jacobian block
checked against finite differences on its own. What it cannot reach without changing other
files, and why:

* its scene switch and key: the scene's sections are static pydantic models that refuse an
  unknown key (``extra="forbid"``); a key needs its field in scene/sections/ (whose metadata
  then names its switch, scene/switches.py, and the refusal and the complete TOML follow);
* its pass inside a run: the residual and Jacobian kernels (system/residual.py,
  system/jacobian_analytic.py, system/optional.py) are numba functions compiled with a fixed
  parameter vector and a fixed set of passes, and the compiled SUNDIALS callbacks take the
  work tuple of system/model.py; a pass enters a run only through those files, so neither the
  energy balance of a run with it nor its output variable in a run or a sweep can be shown.
"""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit

from bearingdae.solvers.algebraic import initial_state
from bearingdae.system import effects
from bearingdae.system.effect import Effect, Source
from bearingdae.system.layout import LOCAL
from bearingdae.system.model import build_model
from bearingdae.system.samples import block_inputs
from bearingdae.system.thermal_network import network
from conftest import make_scene

MOMENT_N_M = 2e-4  #: M_e, against the roller's spin relative to its orbit
SPIN = LOCAL.index("spin_speed")


# ---- the law (physics) and the pass and its Jacobian block (system), typed here ----
@njit
def moment_pass(yl, PM, resl):
    """The spin rows I_x ω' - [... - M_e]: + M_e on each roller (``PM`` = (M_e,))."""
    for j in range(yl.shape[0]):
        resl[j, SPIN] += PM[0]


@njit
def moment_jacobian(yl, PM, Jl):
    """d(moment_pass)/d(yl): a constant moment has none (the block is zero)."""
    for j in range(yl.shape[0]):
        for i in range(yl.shape[1]):
            Jl[j, SPIN, i] += 0.0


def moment_power(model, t, values, own, P, drive) -> None:
    """Its source: M_e (ω - Ω) summed over the rollers, per sample [W]."""
    rel = np.asarray(values["spin_speed"]) - np.asarray(values["orbit_speed"])
    P["roller_moment"] = np.sum(MOMENT_N_M * rel, axis=-1)


ROLLER_MOMENT = Effect(
    name="roller_moment", switch=None, passes=(moment_pass, moment_jacobian),
    sources=(Source("roller_moment", "a constant moment against each roller's spin",
                    (0.0, 0.0, 1.0, 0.0, 0.0)),),
    power=moment_power)


@pytest.fixture
def declared(monkeypatch):
    monkeypatch.setattr(effects, "EFFECTS", (*effects.EFFECTS, ROLLER_MOMENT))


def test_its_jacobian_block_is_the_finite_difference_of_its_pass():
    rng = np.random.default_rng(1)
    yl, PM = rng.normal(size=(4, len(LOCAL))), np.array([MOMENT_N_M])
    J = np.zeros((4, len(LOCAL), len(LOCAL)))
    moment_jacobian(yl, PM, J)
    base = np.zeros_like(yl)
    moment_pass(yl, PM, base)
    for i in range(len(LOCAL)):
        y = yl.copy()
        y[:, i] += 1e-6
        r = np.zeros_like(yl)
        moment_pass(y, PM, r)
        np.testing.assert_allclose((r - base) / 1e-6, J[:, :, i], atol=1e-9)
    assert np.all(base[:, SPIN] == MOMENT_N_M)


def test_its_heat_reaches_the_thermal_network(declared):
    """A block's losses carry its source, the partition its row, and the rollers' node gets
    exactly its power: the network's heat with it less the heat without it."""
    scene = make_scene({"physics.thermal": "steady", "operating.speed_rpm": 3000.0})
    model = build_model(scene)
    y0, _ = initial_state(model)
    Ys = np.array([y0, y0])
    inputs = block_inputs(model, np.array([0.0, 1e-4]), Ys)
    assert [s.name for s in effects.sources(scene)][-1] == "roller_moment"
    spin = model.geometry.pure_rolling_spin(model.ring_speed(0.0))
    orbit = model.geometry.epicyclic_orbit_speed(model.ring_speed(0.0))
    expected = MOMENT_N_M * model.geometry.rollers * (spin - orbit)
    assert inputs["losses"]["roller_moment"] == pytest.approx(expected, rel=1e-6)
    partition = effects.heat_partition()
    net = network(scene, model.geometry, partition)
    _, q = net.solve(inputs["losses"], *inputs["band_area_m2"])
    without = {k: v for k, v in inputs["losses"].items() if k != "roller_moment"}
    _, q0 = net.solve(without, *inputs["band_area_m2"])
    assert q - q0 == pytest.approx(np.array([0.0, 0.0, expected, 0.0, 0.0]), abs=1e-12)
