"""Scene keys of the flanges (scene/flanges.py): defaults, resolved values, and one-line errors
that name the field, the value and the allowed range."""

from __future__ import annotations

import math

import pytest

from bearingdae.scene import SceneError
from conftest import make_scene


def test_default_scene_has_no_flanges_and_its_toml_is_unchanged():
    s = make_scene()
    assert s.bearing.flanges is None and s.operating.axial_load_N == 0.0
    assert "type" not in s.to_toml() and "flange" not in s.to_toml(complete=True)


def test_nj_defaults_put_the_contact_mid_flange():
    s = make_scene({"bearing.type": "NJ", "operating.axial_load_N": 200.0})
    f = s.bearing.flanges
    r = 0.5 * s.bearing.roller_diameter_m
    assert f.present == (0, 1, 1, 1)
    assert f.contact_height_m == pytest.approx(r - 0.5 * (f.height_m + f.corner_radius_m))
    assert f.end_radius_m * math.sin(f.angle_rad) == pytest.approx(f.contact_height_m)
    assert "roller_end_radius_mm" in s.to_toml(complete=True)


@pytest.mark.parametrize("over, words", [
    ({"operating.axial_load_N": 100.0}, ["operating.axial_load_N", "100", "NJ"]),
    ({"bearing.flange_angle_deg": 1.0}, ["bearing.flange_angle_deg", "bearing.type"]),
    ({"bearing.type": "NU", "operating.axial_load_N": 5.0}, ["axial_load_N", "allowed: 0"]),
    ({"bearing.type": "NJ", "operating.axial_load_N": -5.0}, ["axial_load_N", "-5", "[0, 1e8]"]),
    ({"bearing.type": "NJ", "bearing.flange_height_mm": 3.0}, ["flange_height_mm", "3",
                                                              "allowed"]),
    ({"bearing.type": "NJ", "bearing.roller_end_radius_mm": 10.0},
     ["roller_end_radius_mm", "10", "allowed range"]),
    ({"bearing.type": "NJ", "bearing.roller_end": "flat", "bearing.roller_end_radius_mm": 100.0},
     ["roller_end_radius_mm", "spherical"]),
])
def test_bad_flange_input_names_field_value_and_range(over, words):
    with pytest.raises(SceneError) as err:
        make_scene(over)
    msg = str(err.value)
    for w in words:
        assert w in msg, (w, msg)


def test_out_of_range_keys_are_refused_by_the_schema():
    with pytest.raises(SceneError, match="flange_angle_deg"):
        make_scene({"bearing.type": "NJ", "bearing.flange_angle_deg": 20.0})
    with pytest.raises(SceneError, match="type"):
        make_scene({"bearing.type": "NN"})


def test_flange_outputs_need_flanges():
    with pytest.raises(SceneError, match="'bearing.type' = not given removes it"):
        make_scene({"output.variables": ["flange_force"]})


@pytest.mark.parametrize("angle, end_radius", [(5e-324, None), (5e-324, 5000.0),
                                               (0.0005, None), (0.0005, 5000.0)])
def test_a_rib_angle_too_small_for_any_end_radius_is_refused_at_the_angle(angle, end_radius):
    """R_e sin α must reach the flange face with R_e within roller_end_radius_mm's range
    (0, 1e5] mm: below that angle (sin α = 0 included) the angle is named with its range."""
    extra = {} if end_radius is None else {"bearing.roller_end_radius_mm": end_radius}
    with pytest.raises(SceneError) as exc:
        make_scene({"bearing.type": "NJ", "bearing.flange_angle_deg": angle, **extra})
    msg = str(exc.value)
    assert f"'bearing.flange_angle_deg' = {angle!r}" in msg and "allowed range [" in msg, msg
    # the stated lower bound, computed afresh for yang20 (D_w 4 mm: r 2, h_f 0.8, r_k 0.2 mm)
    reach = 2.0 - (0.8 if end_radius else 0.5 * (0.8 + 0.2))
    least = math.degrees(math.asin(reach / 1e5))
    assert f"[{least:.6g}, 10]" in msg, msg


def test_the_least_rib_angle_loads_and_its_stored_toml_loads_back():
    import tomllib

    from bearingdae.scene import scene_from_dict

    least = math.degrees(math.asin(1.5 / 1e5)) * (1 + 1e-9)
    s = make_scene({"bearing.type": "NJ", "bearing.flange_angle_deg": least})
    assert s.resolved["bearing"]["roller_end_radius_mm"] <= 1e5
    assert scene_from_dict(tomllib.loads(s.to_toml(complete=True))) == s
