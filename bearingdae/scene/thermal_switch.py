"""The oil's description and the thermal switch's rules between keys, converted to SI
(physics.thermal, section [thermal], lubricant.viscosity_40C_mm2_s / viscosity_100C_mm2_s /
operating_temperature_C; theory.md §21).

A scene describes its oil once, and the thermal switch changes its temperatures, never the oil:

* ``lubricant.viscosity_Pa_s`` alone: an oil of that viscosity. Without the switch the laws
  read it as given (bit for bit as before). A thermal run needs the oil's viscosity at other
  temperatures, so a ``viscosity_Pa_s`` other than the default with ``"steady"`` is one error
  that asks for the viscosity-temperature data instead.
* The default 0.01 Pa s (or nothing) is the default oil, ISO VG 32 (ASTM D341 through 32 and
  5.4 mm²/s), which at 870 kg/m³ has 0.01 Pa s near 69 °C: the thermal switch reads that oil
  at the network's temperatures.
* ``viscosity_40C_mm2_s`` and ``viscosity_100C_mm2_s`` with ``operating_temperature_C``:
  without the switch the laws read ρ ν(T_op) (ASTM D341, set by
  system/thermal_network.start_scene); with it, ν at the network's
  temperatures (system/effects.set_temperatures), the first block starting at T_op.

With ``physics.thermal = "off"`` the section stays out of the scene's TOML text, so that every
existing scene keeps its text and sweep hashes.
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


def _given(lub, source: dict, key: str) -> bool:
    return key in source.get("lubricant", {}) and getattr(lub, key) is not None


def _refuse_viscosity(lub, origin: str, why: str) -> None:
    """SceneError if ``lubricant.viscosity_Pa_s`` is other than its default (the default
    0.01 Pa s is the default oil's, ISO VG 32 near 69 °C: the same oil)."""
    if lub.viscosity_Pa_s != type(lub).model_fields["viscosity_Pa_s"].default:
        raise SceneError(f"invalid scene ({origin}): 'lubricant.viscosity_Pa_s' = "
                         f"{lub.viscosity_Pa_s!r} {why}")


def _oil_data(lub, origin: str, source: dict):
    """(ν40, ν100) [mm²/s] the scene gives (None, None: none), checked."""
    n40, n100 = (_given(lub, source, "viscosity_40C_mm2_s"),
                 _given(lub, source, "viscosity_100C_mm2_s"))
    if n40 != n100:
        key, value = (("viscosity_40C_mm2_s", lub.viscosity_40C_mm2_s) if n40 else
                      ("viscosity_100C_mm2_s", lub.viscosity_100C_mm2_s))
        other = "viscosity_100C_mm2_s" if n40 else "viscosity_40C_mm2_s"
        raise SceneError(
            f"invalid scene ({origin}): 'lubricant.{key}' = {value!r} is given without "
            f"'lubricant.{other}': ASTM D341 needs both points; give both (e.g. 32 and 5.4 "
            "for an ISO VG 32 oil).")
    if not n40:
        return None, None
    _refuse_viscosity(lub, origin, "is given with lubricant.viscosity_40C_mm2_s and "
                      "viscosity_100C_mm2_s: one oil has one description; drop viscosity_Pa_s "
                      "(the laws read the viscosity at lubricant.operating_temperature_C).")
    return lub.viscosity_40C_mm2_s, lub.viscosity_100C_mm2_s


def _check_order(origin: str, nu40: float, nu100: float, given_100: bool) -> None:
    if not nu100 < nu40:
        key = "viscosity_100C_mm2_s" if given_100 else "viscosity_40C_mm2_s"
        value = nu100 if given_100 else nu40
        raise SceneError(
            f"invalid scene ({origin}): 'lubricant.{key}' = {value!r}: an oil is thinner at "
            f"100 °C than at 40 °C; allowed range: viscosity_100C_mm2_s < viscosity_40C_mm2_s "
            f"({nu100:g} >= {nu40:g} mm²/s).")


def check_thermal(m, origin: str, source: dict):
    """(Thermal or None, Lubricant, resolved values by table) of the checked input ``m``;
    ``source`` (the scene's TOML data) loses what the switch leaves unused. SceneError with
    one line naming the key, its value and the fix otherwise."""
    lub = m.lubricant
    # the keys si.Lubricant holds; absent keys (None) take its defaults
    held = {f.name for f in dataclasses.fields(Lubricant)}
    plain = Lubricant(**{k: v for k, v in lub.model_dump(exclude_none=True).items()
                         if k in held})
    nu40, nu100 = _oil_data(lub, origin, source)
    t_op = lub.operating_temperature_C if _given(lub, source, "operating_temperature_C") \
        else None
    if nu40 is None and t_op is not None:
        raise SceneError(
            f"invalid scene ({origin}): 'lubricant.operating_temperature_C' = {t_op!r} is "
            "given without the oil's viscosity-temperature data; give "
            "lubricant.viscosity_40C_mm2_s and viscosity_100C_mm2_s, or drop it.")
    if m.physics.thermal != "steady":  # its keys were refused without it (scene/switches.py)
        source.pop("thermal", None)
        source.get("physics", {}).pop("thermal", None)
        if nu40 is None:
            return None, plain, {}
        _check_order(origin, nu40, nu100, True)
        if t_op is None:
            raise SceneError(
                f"invalid scene ({origin}): 'lubricant.operating_temperature_C' is missing: "
                "an oil given by its viscosity-temperature data needs the temperature at "
                "which the laws read it, in [-60, 250] °C.")
        # ρ ν(T_op) is the system's (system/thermal_network.start_scene: ASTM D341 is a law);
        # NaN until then, so that nothing reads a viscosity the scene does not have
        return None, dataclasses.replace(plain, viscosity_Pa_s=float("nan")), {}
    _refuse_viscosity(lub, origin, "is one viscosity, but 'physics.thermal' = 'steady' reads "
                      "the oil at the network's temperatures: drop it and give the oil's "
                      "viscosity-temperature data (lubricant.viscosity_40C_mm2_s, "
                      "viscosity_100C_mm2_s).")
    given_100 = nu40 is not None
    nu40 = DEFAULT_VISCOSITY_40C_MM2_S if nu40 is None else nu40
    nu100 = DEFAULT_VISCOSITY_100C_MM2_S if nu100 is None else nu100
    _check_order(origin, nu40, nu100, given_100)
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
        viscosity_40C_mm2_s=float(nu40), viscosity_100C_mm2_s=float(nu100),
        start_temperature_C=None if t_op is None else float(t_op))
    source.get("lubricant", {}).pop("viscosity_Pa_s", None)  # not used: the oil's temperature
    source["thermal"] = t.model_dump(mode="json")
    resolved = {"lubricant": {"viscosity_40C_mm2_s": float(nu40),
                              "viscosity_100C_mm2_s": float(nu100)}}
    # the thermal run reads the oil's data from Thermal (with its defaults resolved)
    plain = dataclasses.replace(plain, viscosity_40C_mm2_s=None, viscosity_100C_mm2_s=None,
                                operating_temperature_C=None)
    return thermal, plain, resolved
