"""The mixed-lubrication keys (theory.md §20): ``physics.lubrication``,
``lubricant.boundary_friction``: defaults that leave every scene's TOML as it was, bad input
refused in one line naming the key, the value and what is allowed."""

from __future__ import annotations

import pytest

from bearingdae.scene import SceneError
from conftest import make_scene


def test_default_scene_is_full_film_and_its_toml_is_unchanged():
    s = make_scene()
    assert s.physics.lubrication == "full-film" and s.lubricant.boundary_friction == 0.1
    assert "lubrication" not in s.to_toml(complete=True)
    assert "boundary_friction" not in s.to_toml(complete=True)


def test_mixed_scene_states_its_boundary_friction_in_the_complete_toml():
    s = make_scene({"physics.lubrication": "mixed"})
    assert s.physics.lubrication == "mixed" and s.lubricant.boundary_friction == 0.1
    text = s.to_toml(complete=True)
    assert 'lubrication = "mixed"' in text and "boundary_friction = 0.1" in text
    assert make_scene({"physics.lubrication": "mixed", "lubricant.boundary_friction": 0.13}
                      ).lubricant.boundary_friction == 0.13


@pytest.mark.parametrize("over, words", [
    ({"physics.lubrication": "boundary"}, ("lubrication", "boundary", "full-film", "mixed")),
    ({"lubricant.boundary_friction": 1.5}, ("boundary_friction", "1.5", "[0, 1]")),
    ({"lubricant.boundary_friction": -0.1}, ("boundary_friction", "-0.1", "[0, 1]")),
])
def test_bad_mixed_input_names_field_value_and_range(over, words):
    with pytest.raises(SceneError) as err:
        make_scene(over)
    msg = str(err.value)
    assert len(msg.strip().splitlines()) == 2, msg  # the scene's name, then the one finding
    for w in words:
        assert w in msg, (w, msg)
