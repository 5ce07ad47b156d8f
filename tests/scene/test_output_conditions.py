"""Each output variable declares the condition under which it exists
(scene/sections/output.py: OUTPUT_VARIABLES names it, PRESENT_WHEN declares those that are not
a switch); the refusal of ``output.variables`` (scene/switches.refuse_unswitched_outputs) and
the docs' table (scene/keydoc.output_reference) read the declaration, so a variable with a new
condition needs no code of its own."""

from __future__ import annotations

import pytest

from bearingdae.scene import SceneError
from bearingdae.scene.keydoc import key_reference
from bearingdae.scene.sections import output
from conftest import make_scene


@pytest.mark.parametrize("name, setting", [
    ("temperature", 'set physics.thermal = "steady"'),
    ("ring_velocity", 'set physics.ring = "dynamic"'),
    ("cage_center", "set physics.cage_whirl = true"),
    ("flange_force", "set bearing.type = "),
    ("roller_spin_angle_rad", 'on = "roller"'),
])
def test_a_variable_whose_condition_is_unmet_is_refused_naming_it_and_the_setting(
        name, setting):
    with pytest.raises(SceneError) as err:
        make_scene({"output.variables": [name]})
    text = str(err.value)
    assert "\n" not in text and f"asks for '{name}'" in text and setting in text, text


def test_a_new_condition_is_one_declaration_read_by_the_refusal_and_the_docs(monkeypatch):
    """A variable under a condition of its own (here: more than 20 rollers) is refused where
    it does not hold and listed in the docs with its words, with no other code."""
    rule = output.PresentWhen(lambda m: m.bearing.rollers > 20, "more than 20 rollers",
                              lambda m: f"the bearing has {m.bearing.rollers} rollers",
                              "set bearing.rollers > 20")
    monkeypatch.setitem(output.PRESENT_WHEN, "many_rollers", rule)
    monkeypatch.setitem(output.OUTPUT_VARIABLES, "roller_crowd", "many_rollers")
    with pytest.raises(SceneError) as err:
        make_scene({"output.variables": ["roller_crowd"], "bearing.rollers": 12})
    assert str(err.value).endswith("'output.variables' asks for 'roller_crowd' but the "
                                   "bearing has 12 rollers; drop it or set bearing.rollers "
                                   "> 20."), str(err.value)
    make_scene({"output.variables": ["roller_crowd"], "bearing.rollers": 24})  # holds: loads
    assert "| `roller_crowd` | more than 20 rollers |" in key_reference()


def test_the_docs_table_lists_every_variable_with_its_condition():
    page = key_reference()
    for name in output.OUTPUT_VARIABLES:
        assert f"| `{name}` |" in page, name
    assert "| `temperature` | physics.thermal = \"steady\" |" in page
    assert "| `inner_ring_speed` | always |" in page
    assert '| `roller_spin_angle_rad` | a [[defects]] or [[waviness]] entry with on = "roller"' \
        in page
