"""Scene keys of the thermal switch (scene/thermal_switch.py): off by default and out of the
TOML text, the defaults with "steady", one-line errors naming the key, the value and the range."""

from __future__ import annotations

import pytest

from bearingdae.scene import SceneError
from bearingdae.scene.schema import key_table, valid_keys
from conftest import make_scene


def test_default_scene_is_thermal_off_and_its_toml_is_unchanged():
    s = make_scene()
    assert s.thermal is None and s.physics.thermal == "off"
    for text in (s.to_toml(), s.to_toml(complete=True)):
        assert "thermal" not in text and "viscosity_40C" not in text
    assert s.lubricant.viscosity_Pa_s == 0.01
    # writing the default explicitly is the same scene, with the same text (but the title's
    # note of the override)
    same = make_scene({"physics.thermal": "off"}).to_toml()
    assert same.split("\n", 2)[2] == s.to_toml()


def test_steady_defaults_and_resolved_values():
    s = make_scene({"physics.thermal": "steady", "thermal.oil_flow_l_min": 0.3})
    th = s.thermal
    assert th.oil_flow_m3_s == pytest.approx(0.3e-3 / 60.0)
    assert (th.viscosity_40C_mm2_s, th.viscosity_100C_mm2_s) == (32.0, 5.4)
    text = s.to_toml(complete=True)
    assert "oil_inlet_temperature_C = 40.0" in text and "viscosity_40C_mm2_s = 32.0" in text
    assert "viscosity_Pa_s" not in text  # not used: the oil temperature decides it
    import tomllib

    from bearingdae.scene import scene_from_dict

    again = scene_from_dict(tomllib.loads(text))  # the result file's text is the same scene
    assert again.thermal == th
    assert tomllib.loads(again.to_toml(complete=True)) == tomllib.loads(text)
    keys = valid_keys()
    for k in ("thermal.oil_inlet_temperature_C", "thermal.oil_flow_l_min",
              "thermal.housing_conductance_W_K", "thermal.ambient_temperature_C",
              "physics.thermal", "lubricant.viscosity_40C_mm2_s",
              "lubricant.viscosity_100C_mm2_s"):
        assert k in keys
    assert ("physics.thermal", "'off'") in [(r[0], r[1]) for r in key_table()]


@pytest.mark.parametrize("over, words", [
    ({"thermal.oil_flow_l_min": 1.0}, ["thermal.oil_flow_l_min", "physics.thermal", "steady"]),
    ({"lubricant.viscosity_40C_mm2_s": 46.0},
     ["lubricant.viscosity_40C_mm2_s", "46.0", "viscosity_100C_mm2_s"]),
    ({"lubricant.viscosity_40C_mm2_s": 46.0, "lubricant.viscosity_100C_mm2_s": 6.8},
     ["lubricant.operating_temperature_C", "missing", "[-60, 250]"]),
    ({"lubricant.viscosity_40C_mm2_s": 46.0, "lubricant.viscosity_100C_mm2_s": 6.8,
      "lubricant.operating_temperature_C": 50.0, "lubricant.viscosity_Pa_s": 0.02},
     ["lubricant.viscosity_Pa_s", "0.02", "drop"]),
    ({"lubricant.operating_temperature_C": 50.0},
     ["lubricant.operating_temperature_C", "50.0", "viscosity_40C_mm2_s"]),
    ({"physics.thermal": "steady", "lubricant.viscosity_Pa_s": 0.02},
     ["lubricant.viscosity_Pa_s", "0.02", "drop it", "viscosity_40C_mm2_s"]),
    ({"physics.thermal": "steady", "lubricant.viscosity_40C_mm2_s": 32.0,
      "lubricant.viscosity_100C_mm2_s": 40.0},
     ["viscosity_100C_mm2_s", "40", "< viscosity_40C_mm2_s"]),
    ({"physics.thermal": "steady", "thermal.oil_flow_l_min": -1.0},
     ["oil_flow_l_min", "-1", "0"]),
    ({"physics.thermal": "warm"}, ["physics.thermal", "warm", "steady"]),
    ({"physics.thermal": "steady", "thermal.oil_flow_l_min": 0.0,
      "thermal.housing_conductance_W_K": 0.0, "thermal.shaft_conductance_W_K": 0.0},
     ["thermal.oil_flow_l_min", "no way out", "> 0"]),
    pytest.param({"physics.thermal": "steady", "physics.rolling_resistance": True,
                  "lubricant.temperature_viscosity_K_inv": 0.04},
                 ["temperature_viscosity_K_inv", "0.04", "drop it"], id="beta-given",
                 marks=pytest.mark.skipif("lubricant.temperature_viscosity_K_inv"
                                          not in valid_keys(), reason="no EHL law reads β")),
    ({"output.variables": ["temperature"]}, ["temperature", "physics.thermal", "steady"]),
])
def test_bad_thermal_input_names_field_value_and_range(over, words):
    with pytest.raises(SceneError) as err:
        make_scene(over)
    text = str(err.value)
    assert "Traceback" not in text
    for w in words:
        assert w in text, (w, text)
