"""The thermal switch's rules between keys and its conversion to SI (physics.thermal, section
[thermal], lubricant.viscosity_40C_mm2_s / viscosity_100C_mm2_s; theory.md §21).

With ``physics.thermal = "off"`` (the default) the section and the two viscosities must not be
given (they would be ignored) and stay out of the scene's TOML text, so that every existing
scene keeps its text and sweep hashes. With ``"steady"`` the oil's viscosity follows its
temperature: ``lubricant.viscosity_Pa_s`` is not used and must not be given (the model starts
from ρ ν(T) at the oil inlet temperature, system/thermal_network.py, and
run/thermal_coupling.py updates it block by block).
"""

from __future__ import annotations

import dataclasses

from .errors import SceneError
from .si import Lubricant, Thermal

#: ASTM D341's two points when not given: an ISO VG 32 mineral oil of viscosity index ~100
#: (ISO 3448 grade mid-point 32 mm²/s at 40 °C; 5.4 mm²/s at 100 °C). At 870 kg/m³ it has the
#: default lubricant.viscosity_Pa_s = 0.01 (11.5 mm²/s) near 69 °C.
DEFAULT_VISCOSITY_40C_MM2_S = 32.0
DEFAULT_VISCOSITY_100C_MM2_S = 5.4


def check_thermal(m, origin: str, source: dict):
    """(Thermal or None, Lubricant, resolved values by table) of the checked input ``m``;
    ``source`` (the scene's TOML data) loses what the switch leaves unused. SceneError with
    one line naming the key, its value and the fix otherwise."""
    lub = m.lubricant
    # the keys si.Lubricant holds; absent keys (None) take its defaults
    held = {f.name for f in dataclasses.fields(Lubricant)}
    plain = Lubricant(**{k: v for k, v in lub.model_dump(exclude_none=True).items()
                         if k in held})
    if m.physics.thermal != "steady":  # its keys were refused without it (scene/switches.py)
        source.pop("thermal", None)
        source.get("physics", {}).pop("thermal", None)
        return None, plain, {}
    default_mu = type(lub).model_fields["viscosity_Pa_s"].default
    if lub.viscosity_Pa_s != default_mu:
        raise SceneError(
            f"invalid scene ({origin}): 'lubricant.viscosity_Pa_s' = {lub.viscosity_Pa_s!r} is "
            "given but 'physics.thermal' = 'steady' takes the viscosity from the oil "
            "temperature (lubricant.viscosity_40C_mm2_s, viscosity_100C_mm2_s); drop it.")
    nu40 = lub.viscosity_40C_mm2_s if lub.viscosity_40C_mm2_s is not None \
        else DEFAULT_VISCOSITY_40C_MM2_S
    nu100 = lub.viscosity_100C_mm2_s if lub.viscosity_100C_mm2_s is not None \
        else DEFAULT_VISCOSITY_100C_MM2_S
    if not nu100 < nu40:
        key = ("viscosity_100C_mm2_s" if lub.viscosity_100C_mm2_s is not None
               else "viscosity_40C_mm2_s")
        value = nu100 if key.startswith("viscosity_100") else nu40
        raise SceneError(
            f"invalid scene ({origin}): 'lubricant.{key}' = {value!r}: an oil is thinner at "
            f"100 °C than at 40 °C; allowed range: viscosity_100C_mm2_s < viscosity_40C_mm2_s "
            f"({nu100:g} >= {nu40:g} mm²/s).")
    t = m.thermal
    if t.oil_flow_l_min == 0.0 and t.housing_conductance_W_K == 0.0 \
            and t.shaft_conductance_W_K == 0.0:
        raise SceneError(
            f"invalid scene ({origin}): 'thermal.oil_flow_l_min' = 0 with "
            "housing_conductance_W_K = shaft_conductance_W_K = 0 leaves the heat no way out "
            "(no steady temperature); give one of them a value > 0.")
    thermal = Thermal(
        oil_inlet_temperature_C=t.oil_inlet_temperature_C,
        oil_flow_m3_s=t.oil_flow_l_min * 1e-3 / 60.0,
        ambient_temperature_C=t.ambient_temperature_C,
        housing_conductance_W_K=t.housing_conductance_W_K,
        shaft_conductance_W_K=t.shaft_conductance_W_K,
        oil_specific_heat_J_kgK=t.oil_specific_heat_J_kgK,
        oil_heat_transfer_W_m2K=t.oil_heat_transfer_W_m2K,
        steel_conductivity_W_mK=t.steel_conductivity_W_mK,
        temperature_tolerance_K=t.temperature_tolerance_K,
        viscosity_40C_mm2_s=float(nu40), viscosity_100C_mm2_s=float(nu100))
    source.get("lubricant", {}).pop("viscosity_Pa_s", None)  # not used: the oil's temperature
    source["thermal"] = t.model_dump(mode="json")
    resolved = {"lubricant": {"viscosity_40C_mm2_s": float(nu40),
                              "viscosity_100C_mm2_s": float(nu100)}}
    return thermal, plain, resolved
