"""The thermal coupling of a run (physics.thermal = "steady"; theory.md §21).

Stage: run. The dynamics run in blocks (run/steady.py). After each block
:meth:`ThermalCoupling.after_block` takes the block's mean power loss by source and contact
band areas (system/samples.block_inputs), solves the network's steady state
(system/thermal_network.py), sets the oil viscosity at the new oil temperature in the model's
parameters (the next block's drag, churning, and every law that reads the viscosity) and
reports whether the oil temperature changed by less than ``thermal.temperature_tolerance_K``
over the block. The first block runs with the oil at its inlet temperature. Fixed-point iteration: T_k = network(losses(μ(T_{k-1}))),
under-relaxed once it overshoots (:class:`Relaxation`): a cold inlet's thick oil makes large
losses, the hot network answer thin oil and small losses, and the plain iteration swung
between the two (200 blocks, a roller node at 1330 °C). The convergence test is the fixed
point's residual, the network's answer minus the temperature the block ran at, so relaxing
never fakes a steady state.
"""

from __future__ import annotations

import numpy as np

from ..physics.heat_network import NODES
from ..physics.oil_viscosity import rated_viscosity
from ..system.effects import heat_partition, set_oil_temperature
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
        self.viscosity_Pa_s, self.kinematic_mm2_s = set_oil_temperature(model, self.oil_C[0])

    @property
    def blocks(self) -> int:
        return len(self.oil_C) - 1

    @property
    def last_change_K(self) -> float:
        """The last block's fixed-point residual: the network's oil temperature minus the one
        the block ran at (the change of the oil temperature when not relaxed)."""
        if self.relaxation.residuals:
            return float(self.relaxation.residuals[-1])
        return float(self.oil_C[-1] - self.oil_C[-2]) if self.blocks else float("nan")

    @property
    def converged(self) -> bool:
        return self.blocks >= 1 and abs(self.last_change_K) < self.tolerance_K

    @property
    def rated_mm2_s(self) -> float:
        op = self.model.scene.operating
        n = op.speed_rpm[1][-1] if isinstance(op.speed_rpm, tuple) else op.speed_rpm
        return rated_viscosity(n, self.model.scene.bearing.pitch_diameter_m * 1e3)

    @property
    def rated_ratio(self) -> float:
        return self.kinematic_mm2_s / self.rated_mm2_s

    def after_block(self, t, Ys) -> bool:
        """Solve the network under the block's losses, set the viscosity at the new oil
        temperature; whether the oil temperature is steady (changed less than the tolerance)."""
        inputs = block_inputs(self.model, t, Ys)
        T, q = self.network.solve(inputs["losses"], *inputs["band_area_m2"])
        T = np.asarray(T, dtype=float)
        w = self.relaxation.step(self.oil_C[-1], T[OIL])
        # the next block (or the record) runs at the relaxed oil temperature until the fixed
        # point is reached; once the residual is within the tolerance it runs at the network's
        # answer itself. The recorded temperatures and heat are always the network's answer
        # to the block's losses, so the network's balance holds in the result, and a
        # converged run's viscosity is its oil temperature's.
        residual = self.relaxation.residuals[-1]  # the network's oil minus the block's
        oil = (float(T[OIL]) if w == 1.0 or abs(residual) < self.tolerance_K
               else self.oil_C[-1] + w * residual)
        self._set(T, q, oil)
        return self.converged

    def _set(self, T, q, oil_C: float) -> None:
        self.temperatures_C, self.heat_W = np.asarray(T, float), np.asarray(q, float)
        self.oil_C.append(float(oil_C))
        self.viscosity_Pa_s, self.kinematic_mm2_s = set_oil_temperature(self.model,
                                                                         float(oil_C))

    def state(self) -> dict:
        """What a warm-up checkpoint keeps (JSON)."""
        return {"oil_C": self.oil_C, "relaxation": [self.relaxation.factor,
                                                    self.relaxation.residuals],
                "temperatures_C": None if self.temperatures_C is None
                else self.temperatures_C.tolist(),
                "heat_W": None if self.heat_W is None else self.heat_W.tolist()}

    def restore(self, state: dict) -> None:
        """Continue from :meth:`state` (a resumed warm-up)."""
        if not state or state.get("temperatures_C") is None:
            return
        self.oil_C = [float(v) for v in state["oil_C"][:-1]]
        self._set(state["temperatures_C"], state["heat_W"], state["oil_C"][-1])
        if isinstance(state.get("relaxation"), list) and len(state["relaxation"]) == 2:
            self.relaxation.factor = float(state["relaxation"][0])
            self.relaxation.residuals = [float(r) for r in state["relaxation"][1]]
