"""The thermal coupling of a run (physics.thermal = "steady"; theory.md §21).

Stage: run. The dynamics run in blocks (run/steady.py). After each block
:meth:`ThermalCoupling.after_block` takes the block's mean power loss by source and contact
band areas (system/samples.block_inputs), solves the network's steady state
(system/thermal_network.py), sets each law's viscosity in the model's parameters at the
temperature where its film forms (system/effects.set_temperatures: the raceway contacts at
their ring and roller nodes, the drag and churning at the oil node) and reports whether the
temperatures changed by less than ``thermal.temperature_tolerance_K`` over the block. The
first block runs at the network's answer to the start state's losses
(:meth:`ThermalCoupling.start_from`), or with every node at
lubricant.operating_temperature_C where the scene gives it. Fixed-point iteration:
T_k = network(losses(μ(T_{k-1}))),
under-relaxed once it overshoots (:class:`Relaxation`): a cold inlet's thick oil makes large
losses, the hot network answer thin oil and small losses, and the plain iteration swung
between the two (200 blocks, a roller node at 1330 °C). The convergence test is the fixed
point's residual, the network's answer minus the temperature the block ran at, so relaxing
never fakes a steady state.
"""

from __future__ import annotations

import numpy as np

from ..physics.heat_network import NODES
from ..system.effects import heat_partition, set_temperatures
from ..system.samples import block_inputs
from ..system.thermal_network import network, start_temperature_C
from ..util.warning_lines import BearingdaeWarning

OIL = NODES.index("oil")


class ThermalNotSteadyWarning(BearingdaeWarning):
    """The warm-up cap came before the oil temperature was steady."""


class Relaxation:
    """Under-relaxation of a scalar fixed point x = g(x): the step is ω (g(x) - x), ω = 1
    until the residual g(x) - x changes sign (an overshoot), then halved at every change of
    sign down to :data:`MIN_FACTOR`. A monotone convergence keeps ω = 1: the plain iteration,
    number for number."""

    #: the smallest factor: 1/64 of the step still moves, and 6 halvings tame a swing
    #: steeper than any viscosity law in the package's range
    MIN_FACTOR = 1.0 / 64.0

    def __init__(self):
        self.factor = 1.0
        self.residuals: list[float] = []

    def step(self, x: float, gx: float) -> float:
        """The factor for the step from ``x`` with the map's answer ``gx``."""
        r = float(gx) - float(x)
        if self.residuals and r * self.residuals[-1] < 0.0:
            self.factor = max(0.5 * self.factor, self.MIN_FACTOR)
        self.residuals.append(r)
        return self.factor


class ThermalCoupling:
    """The network and the coupling's history."""

    def __init__(self, model):
        scene = model.scene
        self.model = model
        self.network = network(scene, model.geometry, heat_partition())
        self.tolerance_K = scene.thermal.temperature_tolerance_K
        #: the oil temperature after each block (first: the start's, thermal_network.
        #: start_temperature_C)
        self.oil_C = [start_temperature_C(scene)]
        self.temperatures_C = self.heat_W = None
        self.relaxation = Relaxation()
        #: the node temperatures the last block ran at (the laws' viscosities: _set_read)
        self.run_C = np.full(len(NODES), self.oil_C[0])
        self._set_read()

    @property
    def blocks(self) -> int:
        return len(self.oil_C) - 1

    @property
    def last_change_K(self) -> float:
        """The last block's fixed-point residual: the network's temperature minus the one the
        block ran at, at the node where they differ most (the change when not relaxed)."""
        if self.relaxation.residuals:
            return float(self.relaxation.residuals[-1])
        return float(self.oil_C[-1] - self.oil_C[-2]) if self.blocks else float("nan")

    @property
    def converged(self) -> bool:
        return self.blocks >= 1 and abs(self.last_change_K) < self.tolerance_K

    def start_from(self, t_s: float, y) -> bool:
        """The first block's temperatures: the network's answer to the losses at the run's
        start state (scaled y at t; the drag and churning at the start speeds, the rolling
        resistance at the start loads), unless ``lubricant.operating_temperature_C`` gives
        them. A guess of the fixed point (no block counted, no relaxation): the inlet's
        temperature, the old start, is one block's iteration further from it, and a block
        at its temperatures only shows that the next must run again (near a steady start
        state, one block converges where two did; CHANGELOG.md has the measurement). The
        test of convergence is unchanged: the network's answer to a block's own losses.
        Whether it set them (the viscosities changed)."""
        if self.model.scene.thermal.start_temperature_C is not None:
            return False
        inputs = block_inputs(self.model, np.array([float(t_s)]), np.asarray(y, float)[None])
        T, _ = self.network.solve(inputs["losses"], *inputs["band_area_m2"])
        self.run_C = np.asarray(T, dtype=float)
        self.oil_C[0] = float(self.run_C[OIL])
        self._set_read()
        return True

    def after_block(self, t, Ys) -> bool:
        """Solve the network under the block's losses, set each law's viscosity at the new
        temperatures (system/effects.set_temperatures); whether the temperatures are steady
        (changed less than the tolerance)."""
        inputs = block_inputs(self.model, t, Ys)
        T, q = self.network.solve(inputs["losses"], *inputs["band_area_m2"])
        T = np.asarray(T, dtype=float)
        # the fixed point's residual: the node that moved most (the oil's drag and the films'
        # laws read different nodes), signed
        change = T - self.run_C
        k = int(np.argmax(np.abs(change)))
        w = self.relaxation.step(self.run_C[k], T[k])
        # the next block (or the record) runs at the relaxed temperatures until the fixed
        # point is reached; once the residual is within the tolerance it runs at the network's
        # answer itself. The recorded temperatures and heat are always the network's answer
        # to the block's losses, so the network's balance holds in the result, and a
        # converged run's viscosities are its temperatures'.
        residual = self.relaxation.residuals[-1]
        run = T if w == 1.0 or abs(residual) < self.tolerance_K else self.run_C + w * change
        self._set(T, q, run)
        return self.converged

    def _set(self, T, q, run_C) -> None:
        self.temperatures_C, self.heat_W = np.asarray(T, float), np.asarray(q, float)
        self.run_C = np.asarray(run_C, float)
        self.oil_C.append(float(self.run_C[OIL]))
        self._set_read()

    def _set_read(self) -> None:
        """Each law's viscosity at its temperatures; the record's operating viscosity (and κ)
        is the raceway films' (ISO 281 reads κ where the film forms), the oil's apart."""
        read = set_temperatures(self.model, self.run_C)
        self.film_C, self.viscosity_Pa_s, self.kinematic_mm2_s = read["film"]
        self.oil_viscosity_Pa_s = read["oil"][1]

    def state(self) -> dict:
        """What a warm-up checkpoint keeps (JSON)."""
        return {"oil_C": self.oil_C, "run_C": self.run_C.tolist(), "relaxation": [self.relaxation.factor,
                                                    self.relaxation.residuals],
                "temperatures_C": None if self.temperatures_C is None
                else self.temperatures_C.tolist(),
                "heat_W": None if self.heat_W is None else self.heat_W.tolist()}

    def restore(self, state: dict) -> None:
        """Continue from :meth:`state` (a resumed warm-up)."""
        if not state or state.get("temperatures_C") is None:
            return
        self.oil_C = [float(v) for v in state["oil_C"][:-1]]
        run = state.get("run_C") or [state["oil_C"][-1]] * len(NODES)  # older: all at the oil's
        self._set(state["temperatures_C"], state["heat_W"], run)
        if isinstance(state.get("relaxation"), list) and len(state["relaxation"]) == 2:
            self.relaxation.factor = float(state["relaxation"][0])
            self.relaxation.residuals = [float(r) for r in state["relaxation"][1]]
