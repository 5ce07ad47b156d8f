"""The thermal network of a model and the oil viscosity the kernel reads (physics.thermal =
"steady"; theory.md §21).

Stage: system (scene + geometry -> the network's conductances; the parameter vector's
viscosity entries). The laws are physics/heat_network.py and physics/oil_viscosity.py;
run/thermal_coupling.py couples the network to the dynamics block by block, through
system/effects.set_oil_temperature. The kernel reads the oil viscosity from its parameter
vector (``model.params``, the same memory as the compiled callbacks' work buffer): changing it
there between two blocks changes the next block's drag, churning and every other law that
reads it, without compiling anything.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..physics import heat_network as law
from ..physics import oil_viscosity as oil
from ..physics.cage import cage_annulus
from .effect import Effect


def walther_of(scene) -> tuple[float, float]:
    """ASTM D341's (A, B) of the scene's oil (lubricant.viscosity_40C_mm2_s, _100C_; with
    physics.thermal their resolved values, ISO VG 32 by default)."""
    src = scene.thermal if scene.thermal is not None else scene.lubricant
    return oil.walther_constants(40.0, src.viscosity_40C_mm2_s, 100.0,
                                 src.viscosity_100C_mm2_s)


def oil_viscosity_Pa_s(scene, temperature_C: float) -> tuple[float, float]:
    """(dynamic [Pa s], kinematic [mm²/s]) viscosity of the scene's oil at ``temperature_C``:
    ASTM D341 through lubricant.viscosity_40C_mm2_s and viscosity_100C_mm2_s, η = ρ ν."""
    nu = float(oil.walther_viscosity(temperature_C, *walther_of(scene)))
    return scene.lubricant.oil_density_kg_m3 * nu * 1e-6, nu


def oil_temperature_coefficient(scene, temperature_C: float) -> float:
    """β = −d ln η/dT [1/K] of the scene's oil at ``temperature_C`` (ASTM D341's law)."""
    return oil.walther_temperature_coefficient(temperature_C, *walther_of(scene))


def with_viscosity(scene, viscosity_Pa_s: float):
    """``scene`` with its lubricant's viscosity replaced (the post-processing's film and power
    read it there; the scene's TOML text and identity are unchanged)."""
    return dataclasses.replace(scene, lubricant=dataclasses.replace(
        scene.lubricant, viscosity_Pa_s=float(viscosity_Pa_s)))


def start_temperature_C(scene) -> float:
    """Where a thermal run's first block reads the oil: lubricant.operating_temperature_C if
    given, else the oil inlet temperature."""
    th = scene.thermal
    return (th.oil_inlet_temperature_C if th.start_temperature_C is None
            else th.start_temperature_C)


def start_scene(scene):
    """The scene a model reads its oil viscosity from: a thermal run's at its start
    temperature (:func:`start_temperature_C`); an oil given by its viscosity-temperature
    data, at lubricant.operating_temperature_C; other scenes unchanged (the same object)."""
    if scene.thermal is not None:
        mu, _ = oil_viscosity_Pa_s(scene, start_temperature_C(scene))
        return with_viscosity(scene, mu)
    if scene.lubricant.viscosity_40C_mm2_s is None:
        return scene
    mu, _ = oil_viscosity_Pa_s(scene, scene.lubricant.operating_temperature_C)
    return with_viscosity(scene, mu)


@dataclasses.dataclass(frozen=True)
class Network:
    """The fixed part of the network (every link but the roller-race contacts, which follow
    the contact loads): conductances [W/K] and the fixed temperatures [°C]."""

    links: dict  #: {(node, node): G} between nodes (no contacts)
    to_fixed: np.ndarray  #: (n,) each node's conductance to fixed temperatures
    fixed_flow: np.ndarray  #: (n,) g_b T_b [W]
    conductivity_W_mK: float
    roller_radius_m: float
    parts: dict  #: each conductance by name, for the record
    partition: dict  #: {power source: shares of the nodes} (system/effects.heat_partition)

    def solve(self, mean_loss_W: dict, band_area_inner_m2: float, band_area_outer_m2: float):
        """(temperatures [°C] (n,), heat into each node [W] (n,)) of the steady network under
        the mean losses by source and the contacts' summed band areas (physics/heat_network.py)."""
        links = dict(self.links)
        k, r = self.conductivity_W_mK, self.roller_radius_m
        links[("inner_ring", "rollers")] = law.contact_conductance(k, band_area_inner_m2, r)
        links[("outer_ring", "rollers")] = law.contact_conductance(k, band_area_outer_m2, r)
        q = law.node_heat(mean_loss_W, self.partition)
        G = law.conductance_matrix(links, self.to_fixed)
        return law.steady_temperatures(G, q, self.fixed_flow), q


def network(scene, geometry, partition: dict) -> Network:
    """The network of a scene's bearing (theory.md §21) with the heat ``partition`` of the
    power sources (system/effects.heat_partition): rings of the roller length's width,
    bore to inner raceway and outer raceway to outside diameter; convection h A from the
    raceways, the rollers' surfaces and ends, the cage's faces and cylinders; the oil flow."""
    th, g, b = scene.thermal, geometry, scene.bearing
    k, h = th.steel_conductivity_W_mK, th.oil_heat_transfer_W_m2K
    L, r, Z = g.roller_length_m, g.roller_radius_m, g.rollers
    Ri, Ro = g.inner_race_radius_m, g.outer_race_radius_m
    cri, cro, _ = cage_annulus(g.pitch_radius_m, 2.0 * r, L)
    areas = {"inner_ring": 2.0 * math.pi * Ri * L, "outer_ring": 2.0 * math.pi * Ro * L,
             "rollers": Z * (2.0 * math.pi * r * L + 2.0 * math.pi * r * r),
             "cage": 2.0 * math.pi * (cri + cro) * L + 2.0 * math.pi * (cro ** 2 - cri ** 2)}
    shaft = law.series(law.shell_conductance(k, L, 0.5 * b.bore_m, Ri),
                       th.shaft_conductance_W_K)
    housing = law.series(law.shell_conductance(k, L, Ro, 0.5 * b.outer_diameter_m),
                         th.housing_conductance_W_K)
    flow = scene.lubricant.oil_density_kg_m3 * th.oil_specific_heat_J_kgK * th.oil_flow_m3_s
    n = len(law.NODES)
    to_fixed, fixed_flow = np.zeros(n), np.zeros(n)
    for node, G, T in (("inner_ring", shaft, th.ambient_temperature_C),
                       ("outer_ring", housing, th.ambient_temperature_C),
                       ("oil", flow, th.oil_inlet_temperature_C)):
        i = law.NODES.index(node)
        to_fixed[i] += G
        fixed_flow[i] += G * T
    links = {(node, "oil"): h * a for node, a in areas.items()}
    parts = {"shaft_path_W_K": shaft, "housing_path_W_K": housing, "oil_flow_W_K": flow,
             **{f"convection_{node}_W_K": h * a for node, a in areas.items()}}
    return Network(links, to_fixed, fixed_flow, k, r, parts, partition)


#: the thermal network (physics.thermal = "steady"): no parameters or sources of its own; it
#: sets the viscosity parameters every effect declares (system/effects.set_oil_temperature)
EFFECT = Effect(name="thermal", switch="thermal")
