"""``physics.friction_model`` and the rolling-resistance keys (scene/friction_model.py,
scene/sections/physics.py, docs/theory.md §19).

References: the key's contract as the issue spells it ("full" = Biboulet & Houpert's rolling
resistance, mixed lubrication and the steady thermal network, an explicit switch wins), and
the complete TOML's own promise: it loads back to the same scene.
"""

from __future__ import annotations

import dataclasses
import tomllib

import pytest

from bearingdae import SceneError, scene_from_dict
from tests.conftest import make_scene

FULL = {"physics.friction_model": "full"}


def _untitled(scene):
    """The scene but its title (which names the keys --set)."""
    return dataclasses.replace(scene, title="")


def test_paper_is_the_default_and_changes_nothing():
    plain, paper = make_scene(), make_scene({"physics.friction_model": "paper"})
    assert _untitled(paper) == _untitled(plain)
    assert plain.physics.rolling_resistance is False
    assert plain.physics.lubrication == "full-film" and plain.physics.thermal == "off"


def test_full_switches_the_three_on():
    p = make_scene(FULL).physics
    assert (p.rolling_resistance, p.lubrication, p.thermal) == ("biboulet_houpert", "mixed",
                                                                "steady")
    # the same scene as the three switches set by hand
    by_hand = make_scene({"physics.rolling_resistance": True, "physics.lubrication": "mixed",
                          "physics.thermal": "steady"})
    assert _untitled(make_scene(FULL)) == _untitled(by_hand)


@pytest.mark.parametrize("key, value, read", [
    ("physics.lubrication", "full-film", ("lubrication", "full-film")),
    ("physics.rolling_resistance", False, ("rolling_resistance", False)),
    ("physics.rolling_resistance", "zhou_hoeprich", ("rolling_resistance", "zhou_hoeprich")),
    ("physics.thermal", "off", ("thermal", "off")),
])
def test_an_explicit_switch_wins(key, value, read):
    p = make_scene({**FULL, key: value}).physics
    assert getattr(p, read[0]) == read[1]
    others = {"rolling_resistance": "biboulet_houpert", "lubrication": "mixed",
              "thermal": "steady"}
    for name, on in others.items():
        if name != read[0]:
            assert getattr(p, name) == on


@pytest.mark.parametrize("overrides", [FULL, {**FULL, "physics.lubrication": "full-film"},
                                       {**FULL, "lubricant.inlet_film_um": 0.25},
                                       {"physics.rolling_resistance": "goksem_hargreaves",
                                        "lubricant.inlet_film_um": 2.0}])
def test_the_complete_toml_round_trips(overrides):
    scene = make_scene(overrides)
    text = scene.to_toml(complete=True)
    again = scene_from_dict(tomllib.loads(text))
    assert again == scene
    data, back = tomllib.loads(text), tomllib.loads(again.to_toml(complete=True))
    data.pop("title"), back.pop("title")
    assert back == data  # the same keys and values (their order aside)


def test_the_inlet_film_reaches_the_scene_in_metres():
    s = make_scene({**FULL, "lubricant.inlet_film_um": 0.25})
    assert s.lubricant.inlet_film_m == pytest.approx(0.25e-6, rel=1e-15)
    assert make_scene(FULL).lubricant.inlet_film_m is None  # absent: fully flooded


@pytest.mark.parametrize("overrides, words", [
    ({"lubricant.inlet_film_um": 0.3},
     ["'lubricant.inlet_film_um' = 0.3", "rolling resistance", "physics.rolling_resistance"]),
    ({**FULL, "physics.rolling_resistance": False, "lubricant.inlet_film_um": 0.3},
     ["'lubricant.inlet_film_um' = 0.3", "physics.rolling_resistance"]),
    ({"physics.rolling_resistance": True, "lubricant.inlet_film_um": 0.0},
     ["'lubricant.inlet_film_um' = 0.0", "[0.001, 1000]"]),
    ({"physics.rolling_resistance": "palmgren"},
     ["'physics.rolling_resistance' = 'palmgren'", '"biboulet_houpert"', '"zhou_hoeprich"']),
    ({"physics.friction_model": "catalogue"},
     ["'physics.friction_model' = 'catalogue'", "'paper' or 'full'"]),
])
def test_bad_values_are_refused_in_one_line_naming_key_value_and_range(overrides, words):
    with pytest.raises(SceneError) as exc:
        make_scene(overrides)
    text = str(exc.value)
    problems = [ln for ln in text.splitlines()[1:]] or [text]
    assert len(problems) == 1, text
    for w in words:
        assert w in text, (w, text)
