"""The effect switches and the keys each alone reads (scene/switches.py): every combination
of switches stores a complete TOML that loads back to the same scene, and every switched key
given without its switch is one line naming the key, its value and the switch to set."""

from __future__ import annotations

import itertools
import tomllib

import pytest

from bearingdae.scene import SceneError, scene_from_dict
from bearingdae.scene.switches import keys_of, switch_fix, switch_key, switched_keys
from conftest import make_scene

#: each switch's settings: off (absent) and every value that switches it on
SETTINGS = {
    "bearing.type": (None, "NU", "N", "NJ", "NUP"),
    "physics.cage_whirl": (None, True),
    "physics.ring": (None, "dynamic"),
    "physics.rolling_resistance": (None, True),
    "physics.lubrication": (None, "mixed"),
    "physics.thermal": (None, "steady"),
}
COMBINATIONS = list(itertools.product(*SETTINGS.values()))


def test_the_matrix_covers_every_switch():
    """Every switch that a key names is in :data:`SETTINGS` (a new effect's switch joins the
    matrix below)."""
    switches = {rule["switch"] for rule in switched_keys().values()}
    assert {switch_key(s) for s in switches} == set(SETTINGS)
    assert len(COMBINATIONS) == 5 * 2 ** 5 == 160


def test_every_switch_combination_stores_a_complete_toml_that_loads_back():
    loaded = 0
    for values in COMBINATIONS:
        over = {k: v for k, v in zip(SETTINGS, values) if v is not None}
        scene = make_scene(over)
        text = scene.to_toml(complete=True)
        try:
            again = scene_from_dict(tomllib.loads(text))
        except SceneError as exc:
            raise AssertionError(f"{over}: the stored TOML does not load: {exc}\n{text}")
        assert again == scene, (over, text)
        loaded += 1
    assert loaded == 160


def test_a_thermal_run_with_rolling_resistance_loads_back():
    """The stored scene holds no temperature-viscosity coefficient: the thermal network
    supplies it (the oil's viscosity law at the oil temperature)."""
    scene = make_scene({"physics.thermal": "steady", "physics.rolling_resistance": True})
    data = tomllib.loads(scene.to_toml(complete=True))
    assert "temperature_viscosity_K_inv" not in data["lubricant"]
    assert data["lubricant"]["thermal_conductivity_W_m_K"] == 0.13
    assert scene_from_dict(data) == scene


@pytest.mark.parametrize("key", sorted(switched_keys()))
def test_each_switched_key_without_its_switch_is_one_line(key):
    """The value given is the key's upper bound or a literal it allows: in range, so only the
    switch rule can refuse it."""
    from bearingdae.scene.schema import _SECTIONS

    section, _, name = key.partition(".")
    field = _SECTIONS[section].model_fields[name]
    value = next((getattr(c, a) for c in field.metadata for a in ("le", "lt")
                  if getattr(c, a, None) is not None), None)
    if value is None:  # a Literal: its last choice
        value = field.annotation.__args__[0].__args__[-1]
    value = value * 0.5 if isinstance(value, float) else value
    with pytest.raises(SceneError) as err:
        make_scene({key: value})
    msg = str(err.value)
    assert len(msg.strip().splitlines()) == 1, msg
    switch = switched_keys()[key]["switch"]
    for words in (f"'{key}'", repr(value), switch_fix(switch), "drop the key"):
        assert words in msg, (words, msg)


def test_boundary_friction_needs_mixed_lubrication():
    with pytest.raises(SceneError) as err:
        make_scene({"lubricant.boundary_friction": 0.2})
    msg = str(err.value)
    assert "'lubricant.boundary_friction' = 0.2" in msg
    assert 'set physics.lubrication = "mixed"' in msg
    assert keys_of("lubrication") == ("lubricant.boundary_friction",)
