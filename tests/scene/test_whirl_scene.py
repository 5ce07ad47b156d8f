"""Scene keys of the cage whirl (scene/whirl.py): defaults, resolved values, and one-line errors
that name the field, the value and the allowed range."""

from __future__ import annotations

import pytest

from bearingdae.scene import SceneError
from conftest import make_scene


def test_default_scene_has_no_whirl_and_its_toml_is_unchanged():
    s = make_scene()
    assert not s.physics.cage_whirl and s.cage.guidance == "roller"
    assert "whirl" not in s.to_toml(complete=True) and "land_" not in s.to_toml(complete=True)


def test_land_defaults_are_half_the_pocket_clearance_and_the_side_rim():
    s = make_scene({"physics.cage_whirl": True, "cage.guidance": "outer-land"})
    c = s.cage
    assert c.land_clearance_m == pytest.approx(0.5 * c.pocket_clearance_m)
    Dw = s.bearing.roller_diameter_m
    assert c.land_width_m == pytest.approx(0.25 * Dw)  # (L + 0.5 D_w - L) / 2
    assert "land_clearance_mm" in s.to_toml(complete=True)


@pytest.mark.parametrize("over, words", [
    ({"cage.guidance": "outer-land"}, ["cage.guidance", "outer-land", "cage_whirl = true"]),
    ({"cage.mass_kg": 0.1}, ["cage.mass_kg", "0.1", "cage_whirl"]),
    ({"physics.cage_whirl": True, "physics.cage": False}, ["physics.cage_whirl", "physics.cage"]),
    ({"physics.cage_whirl": True, "cage.land_clearance_mm": 0.05},
     ["cage.land_clearance_mm", "0.05", "land-guided"]),
    ({"physics.cage_whirl": True, "cage.guidance": "outer-land", "cage.land_width_mm": 5.0},
     ["cage.land_width_mm", "5.0", "allowed range [0.01, 1]"]),
    ({"physics.cage_whirl": True, "cage.guidance": "inner-land", "cage.land_clearance_mm": -1.0},
     ["land_clearance_mm", "-1"]),
    ({"physics.cage_whirl": True, "cage.guidance": "sideways"}, ["guidance", "sideways"]),
])
def test_bad_whirl_keys_name_the_field_value_and_fix(over, words):
    with pytest.raises(SceneError) as info:
        make_scene(over)
    text = str(info.value)
    assert "Traceback" not in text
    for w in words:
        assert w in text, (w, text)
