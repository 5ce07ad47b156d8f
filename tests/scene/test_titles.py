"""Scene titles that follow the scene's values (scene/titles.py)."""

from __future__ import annotations

from bearingdae import load_scene
from bearingdae.scene import scene_from_dict


def _write(path, body):
    path.write_text(body, encoding="utf-8")
    return path


def test_a_title_written_by_the_user_is_kept(tmp_path):
    p = _write(tmp_path / "a.toml", 'title = "my rig {speed}"\n[bearing]\npreset = "yang20"\n')
    assert load_scene(p).title == "my rig {speed}"  # other braces are the user's text


def test_a_file_without_a_title_is_named_with_its_operating_point(tmp_path):
    p = _write(tmp_path / "spindle_7.toml", '[bearing]\npreset = "yang20"\n[operating]\n'
               'speed_rpm = 3500.0\nradial_load_N = 1250.0\nmoment_Nm = 0.5\n')
    assert load_scene(p).title == "spindle_7: 1250 N, 0.5 N·m, 3500 r/min"


def test_the_placeholder_states_every_load_that_is_set():
    sc = scene_from_dict({"title": "rig: {operating}", "bearing": {"preset": "yang20"},
                          "operating": {"speed_rpm": 6000.0, "radial_load_N": 400.0,
                                        "tangential_load_N": -50.0, "unbalance_N": 30.0}})
    assert sc.title == "rig: 400 N, -50 N tangential, unbalance 30 N, 6000 r/min"
    ramp = scene_from_dict({"bearing": {"preset": "yang20"}, "operating": {
        "speed_rpm": {"times_s": [0.0, 0.02], "values_rpm": [0.0, 14000.0]}}})
    assert ramp.title.startswith("bearingdae scene: ") and "0 -> 14000 r/min" in ramp.title


def test_overrides_change_the_generated_values_and_are_listed():
    sc = load_scene("yang20_baseline", {"operating.radial_load_N": 1500.0})
    assert sc.title.startswith("yang20 baseline: 1500 N, 3 N·m, 2000 r/min")
    assert sc.title.endswith("[set: operating.radial_load_N = 1500]")


def test_the_stored_scene_loads_back_with_the_same_title(tmp_path):
    sc = load_scene("yang20_nj_axial")
    assert sc.title == "yang20 NJ: 800 N, 3 N·m, 200 N axial, 2000 r/min"
    p = _write(tmp_path / "stored.toml", sc.to_toml(complete=True))
    assert load_scene(p).title == sc.title
