"""Scene loading and validation: every documented key, its unit, default and range."""

from __future__ import annotations

import dataclasses
import math

import pytest

from bearingdae import SceneError, load_scene, scene_from_dict
from bearingdae.scene import bundled_case_dirs, valid_keys
from bearingdae.studies.sweep import is_sweep_file
from conftest import make_scene


def bundled_cases():
    return sorted({p for d in bundled_case_dirs() for p in d.rglob("*.toml")
                   if not is_sweep_file(p)})


@pytest.mark.parametrize("path", bundled_cases(), ids=lambda p: p.stem)
def test_every_bundled_case_loads(path):
    scene = load_scene(path)
    assert scene.bearing.rollers >= 3


def test_case_by_name_and_si_conversion():
    s = load_scene("yang20_baseline")
    b = s.bearing
    # Table 2 of the paper, converted to SI once: mm -> m, GPa -> Pa.
    assert b.rollers == 20
    assert b.roller_diameter_m == pytest.approx(4e-3, rel=1e-15)
    assert b.pitch_diameter_m == pytest.approx(45e-3, rel=1e-15)  # (D + d)/2, theory.md §2
    assert b.clearance_m == pytest.approx(10e-6, rel=1e-12)
    assert s.materials.youngs_modulus_Pa == pytest.approx(207e9)
    assert s.operating.radial_load_N == 800.0 and s.operating.moment_Nm == 3.0
    assert s.numerics.slices == 10
    assert "Lubricants 2024" in s.preset_citation


def test_scene_is_frozen():
    s = make_scene()
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.bearing.rollers = 3


def test_overrides_with_dotted_keys():
    s = load_scene("yang20_baseline", {"operating.radial_load_N": 400, "numerics.slices": 30})
    assert s.operating.radial_load_N == 400.0 and s.numerics.slices == 30


def test_explicit_keys_override_preset():
    s = make_scene(bearing={"rollers": 18})
    assert s.bearing.rollers == 18 and s.bearing.roller_diameter_m == pytest.approx(4e-3)


def test_toml_round_trip_of_the_scene():
    import tomllib

    s = load_scene("yang20_baseline")
    again = scene_from_dict(tomllib.loads(s.to_toml()))
    assert again.bearing == s.bearing and again.operating == s.operating


@pytest.mark.parametrize(
    "data, key, suggestion",
    [
        ({"operating": {"radial_load": 3}}, "operating.radial_load", "operating.radial_load_N"),
        ({"bearing": {"rolers": 3}}, "bearing.rolers", "bearing.rollers"),
        ({"numerics": {"slice": 3}}, "numerics.slice", "numerics.slices"),
        ({"operation": {}}, "operation", "operating"),
        ({"radial_load_N": 3}, "radial_load_N", "operating.radial_load_N"),
    ],
)
def test_unknown_keys_rejected_with_closest_valid_key(data, key, suggestion):
    data = {"bearing": {"preset": "yang20", **data.pop("bearing", {})}, **data}
    with pytest.raises(SceneError) as e:
        scene_from_dict(data)
    assert f"'{key}'" in str(e.value) and f"'{suggestion}'" in str(e.value)


def test_unknown_override_rejected():
    with pytest.raises(SceneError, match="operating.speed_rpm"):
        make_scene({"operating.speed_rmp": 10})


# Each impossible value: (override, key named, value shown, range text shown)
BAD = [
    ({"bearing.rollers": 60}, "bearing.rollers", "60", "3..35"),
    ({"bearing.radial_clearance_mm": 4.0}, "bearing.radial_clearance_mm", "4.0", "(-4, 4)"),
    ({"bearing.roller_length_mm": -3.0}, "bearing.roller_length_mm", "-3.0", "[0.5, 1000]"),
    ({"bearing.effective_length_mm": 30.0}, "bearing.effective_length_mm", "30.0", "25.5"),
    ({"numerics.slices": 0}, "numerics.slices", "0", "[1, 1000]"),
    ({"operating.radial_load_N": math.nan}, "operating.radial_load_N", "nan", "[0, 1e+08]"),
    ({"operating.moment_Nm": math.inf}, "operating.moment_Nm", "inf", "finite"),
    ({"operating.radial_load_N": -5.0}, "operating.radial_load_N", "-5.0", "[0, 1e+08]"),
    ({"operating.speed_rpm": -1.0}, "operating.speed_rpm", "-1.0", "[0, 200000]"),
    ({"materials.poisson_ratio": 0.7}, "materials.poisson_ratio", "0.7", "[0, 0.5)"),
    ({"bearing.rollers": "20"}, "bearing.rollers", "'20'", "integer"),
    ({"bearing.profile": "crowned"}, "bearing.profile", "'crowned'", "end-crown"),
    ({"bearing.preset": "yang21"}, "bearing.preset", "'yang21'", "yang20"),
    ({"bearing.crown_radius_mm": 1.0}, "bearing.crown_radius_mm", "1.0", "1.275"),
    ({"bearing.bore_mm": 70.0}, "bearing.bore_mm", "70.0", "outer_diameter_mm"),
]


@pytest.mark.parametrize("override, key, value, allowed", BAD, ids=[b[1] + "=" + b[2] for b in BAD])
def test_bad_values_name_key_value_and_range(override, key, value, allowed):
    with pytest.raises(SceneError) as e:
        make_scene(override)
    msg = str(e.value)
    assert f"'{key}'" in msg and value in msg and allowed in msg, msg


def test_missing_geometry_without_preset_names_the_keys():
    with pytest.raises(SceneError, match="bearing.roller_diameter_mm"):
        scene_from_dict({"bearing": {"rollers": 20, "outer_diameter_mm": 60.0}})


def test_file_errors_are_scene_errors(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_bytes(b"\xff\xfe[bearing]")
    with pytest.raises(SceneError, match="UTF-8"):
        load_scene(bad)
    bad.write_text("[bearing\npreset = 'yang20'")
    with pytest.raises(SceneError, match="not valid TOML"):
        load_scene(bad)
    with pytest.raises(SceneError, match="does not exist"):
        load_scene(tmp_path / "nope.toml")


def test_empty_file_asks_for_geometry(tmp_path):
    p = tmp_path / "empty.toml"
    p.write_text("")
    with pytest.raises(SceneError, match="bearing.preset"):
        load_scene(p)


def test_speed_ramp():
    s = make_scene(operating={"speed_rpm": {"times_s": [0.0, 0.02], "values_rpm": [0.0, 14000.0]}})
    assert s.operating.speed_at(0.01) == pytest.approx(7000.0)
    assert s.operating.speed_at(1.0) == pytest.approx(14000.0)


def test_valid_keys_cover_issue_list():
    keys = set(valid_keys())
    for k in ["bearing.preset", "bearing.rollers", "bearing.outer_diameter_mm", "bearing.bore_mm",
              "bearing.pitch_diameter_mm", "bearing.roller_diameter_mm",
              "bearing.roller_length_mm", "bearing.effective_length_mm",
              "bearing.crown_radius_mm", "bearing.profile", "bearing.radial_clearance_mm",
              "materials.youngs_modulus_GPa", "materials.poisson_ratio",
              "materials.density_kg_m3", "operating.speed_rpm", "operating.radial_load_N",
              "operating.moment_Nm", "operating.tangential_load_N",
              "operating.tangential_moment_Nm", "numerics.slices"]:
        assert k in keys
