"""``[[defects]]`` and ``[[waviness]]`` (scene/sections/defects.py, scene/defects.py): every
key refused out of its range or of the wrong type in one line naming the key and the value,
the cross-field rules (wider than the roller, off the race, ramps longer than the defect, a
roller index out of range or on a race), the CLI's exit status 2, the complete TOML's round
trip, and a default scene's text without either table."""

from __future__ import annotations

import subprocess
import sys
import tomllib

import pytest

from bearingdae.scene import load_scene, scene_from_dict
from bearingdae.scene.errors import SceneError

GOOD_DEFECT = {"on": "outer", "angle_deg": 10.0, "length_mm": 1.0, "width_mm": 6.0,
               "depth_um": 20.0, "edge_mm": 0.1}
GOOD_WAVES = {"on": "inner", "order": 21, "amplitude_um": 0.5, "phase_deg": 30.0}

#: (table, key, bad value, fragment the message must hold): every key, a value off its range
#: or of the wrong type, and each cross-field rule (yang20: 20 rollers, roller length
#: 25.5 mm, outer raceway 49 mm)
CASES = [
    ("defects", "on", "outr", "input should be 'outer', 'inner' or 'roller'"),
    ("defects", "on", 3, "wrong type"),
    ("defects", "angle_deg", 400.0, "[-360, 360]"),
    ("defects", "angle_deg", "ten", "wrong type"),
    ("defects", "roller", -1, "applies to a defect on a roller only"),
    ("defects", "roller", 2.5, "wrong type"),
    ("defects", "roller", 2, "applies to a defect on a roller only"),
    ("defects", "length_mm", 0.0, "(0, 100]"),
    ("defects", "length_mm", float("nan"), "finite"),
    ("defects", "width_mm", 30.0, "wider than the roller; allowed range (0, 25.5]"),
    ("defects", "width_mm", -1.0, "(0, 100]"),
    ("defects", "depth_um", 0.0, "(0, 1000]"),
    ("defects", "depth_um", 5000.0, "(0, 1000]"),
    ("defects", "edge_mm", -0.1, "[0, 50]"),
    ("defects", "edge_mm", 0.6, "the two ramps exceed the length; allowed range [0, 0.5]"),
    ("defects", "depth_nm", 3.0, "unknown key 'defects[0].depth_nm'"),
    ("waviness", "on", "ring", "input should be 'outer', 'inner' or 'roller'"),
    ("waviness", "order", 0, "[1, 1000]"),
    ("waviness", "order", 2.5, "wrong type"),
    ("waviness", "amplitude_um", -1.0, "[0, 100]"),
    ("waviness", "amplitude_um", float("inf"), "finite"),
    ("waviness", "phase_deg", 720.0, "[-360, 360]"),
    ("waviness", "amplitude", 1.0, "unknown key 'waviness[0].amplitude'"),
]


def _scene(defects=(), waviness=()):
    return {"bearing": {"preset": "yang20"}, "defects": list(defects),
            "waviness": list(waviness)}


def _message(table, key, value):
    entry = dict(GOOD_DEFECT if table == "defects" else GOOD_WAVES, **{key: value})
    with pytest.raises(SceneError) as err:
        scene_from_dict(_scene(**{table: [entry]}))
    return str(err.value)


@pytest.mark.parametrize("table, key, value, fragment", CASES,
                         ids=[f"{c[0]}.{c[1]}={c[2]!r}" for c in CASES])
def test_each_bad_key_gives_one_line(table, key, value, fragment):
    text = _message(table, key, value)
    problems = [line for line in text.splitlines() if not line.endswith(":")]
    assert len(problems) == 1, text  # one line (after a header naming the file, if any)
    assert f"{table}[0]." in problems[0] and fragment in problems[0], text
    if not fragment.startswith("unknown key"):  # (an unknown key's line names the key)
        assert repr(value) in problems[0] or str(value) in problems[0], text


def test_every_key_is_fuzzed():
    from bearingdae.scene.sections.defects import ARRAY_SECTIONS

    covered = {(c[0], c[1]) for c in CASES}
    for table, model in ARRAY_SECTIONS.items():
        for name in model.model_fields:
            assert (table, name) in covered, (table, name)


#: a defect on roller 3 (yang20: roller diameter 4 mm, circumference 12.57 mm)
GOOD_ROLLER = dict(GOOD_DEFECT, on="roller", roller=3, angle_deg=90.0)
#: (key, bad value, fragment): the roller's own rules, each in one line
ROLLER_CASES = [
    ("roller", 20, "outside the allowed range [0, 19] for the bearing's 20 rollers"),
    ("roller", -1, "outside the allowed range [0, 19] for the bearing's 20 rollers"),
    ("roller", 1001, "outside the allowed range [0, 19] for the bearing's 20 rollers"),
    ("roller", 2.5, "wrong type or value; input should be a valid integer (allowed range "
                    "[0, 19] for the bearing's 20 rollers)"),
    ("width_mm", 26.0, "wider than the roller; allowed range (0, 25.5]"),
    ("length_mm", 13.0, "longer than the roller surface's circumference, off the roller; "
                        "allowed range (0, 12.57)"),
    ("edge_mm", 0.7, "the two ramps exceed the length; allowed range [0, 0.5]"),
    ("angle_deg", -361.0, "[-360, 360]"),
]


@pytest.mark.parametrize("key, value, fragment", ROLLER_CASES,
                         ids=[f"roller.{c[0]}={c[1]!r}" for c in ROLLER_CASES])
def test_each_bad_roller_key_gives_one_line(key, value, fragment):
    with pytest.raises(SceneError) as err:
        scene_from_dict(_scene([dict(GOOD_ROLLER, **{key: value})]))
    problems = [line for line in str(err.value).splitlines() if not line.endswith(":")]
    assert len(problems) == 1, str(err.value)
    assert f"defects[0].{key}" in problems[0] and fragment in problems[0], problems[0]
    assert repr(value) in problems[0] or str(value) in problems[0], problems[0]


def test_roller_range_is_the_bearings():
    """-1 and Z name the same range, the bearing's [0, Z - 1] (a 12-roller bearing: [0, 11]);
    where bearing.rollers is itself refused, the range is written in terms of Z, and the key
    reference writes it so."""
    from bearingdae.scene.keydoc import key_reference

    for value in (-1, 12):
        with pytest.raises(SceneError) as err:
            scene_from_dict({"bearing": {"preset": "yang20", "rollers": 12},
                             "defects": [dict(GOOD_ROLLER, roller=value)]})
        assert (f"'defects[0].roller' = {value}: outside the allowed range [0, 11] for the "
                f"bearing's 12 rollers." in str(err.value)), str(err.value)
    with pytest.raises(SceneError) as err:
        scene_from_dict({"bearing": {"preset": "yang20", "rollers": 2},
                         "defects": [dict(GOOD_ROLLER, roller="one")]})
    assert "'bearing.rollers' = 2: outside the allowed range [3, 500]" in str(err.value)
    assert ("'defects[0].roller' = 'one': wrong type or value; input should be a valid integer "
            "(allowed range [0, Z - 1] for Z = bearing.rollers)" in str(err.value))
    assert "| [0, Z - 1] for Z = bearing.rollers |" in key_reference()


#: (table, entry without the key, the one line): a missing key names itself and what it
#: allows
MISSING = [
    ("defects", {k: v for k, v in GOOD_ROLLER.items() if k != "roller"},
     "'defects[0].roller' is required for on = \"roller\" but missing (allowed range [0, 19] "
     "for the bearing's 20 rollers)."),
    ("defects", {k: v for k, v in GOOD_DEFECT.items() if k != "length_mm"},
     "'defects[0].length_mm' is required but missing (allowed range (0, 100])."),
    ("defects", {k: v for k, v in GOOD_DEFECT.items() if k != "on"},
     "'defects[0].on' is required but missing (allowed: 'outer', 'inner' or 'roller')."),
    ("waviness", {k: v for k, v in GOOD_WAVES.items() if k != "order"},
     "'waviness[0].order' is required but missing (allowed range [1, 1000])."),
]


@pytest.mark.parametrize("table, entry, line", MISSING, ids=[m[2].split("'")[1] for m in MISSING])
def test_missing_key_names_its_range(table, entry, line):
    with pytest.raises(SceneError) as err:
        scene_from_dict(_scene(**{table: [entry]}))
    problems = [ln.strip(" -") for ln in str(err.value).splitlines() if not ln.endswith(":")]
    assert len(problems) == 1, str(err.value)
    assert problems[0].endswith(line), problems[0]


def test_angle_is_optional():
    """angle_deg is not required: a defect without it sits at 0° (the load direction)."""
    entry = {k: v for k, v in GOOD_DEFECT.items() if k != "angle_deg"}
    assert scene_from_dict(_scene([entry])).defects[0].angle_rad == 0.0


def test_roller_defects_and_waviness_are_taken():
    """A defect on a roller and waviness on the rollers load (the model carries the rollers'
    spin angles for them): SI values, the roller index kept."""
    s = scene_from_dict(_scene([GOOD_ROLLER], [dict(GOOD_WAVES, on="roller", order=2)]))
    assert len(ROLLER_CASES) == 8
    (d,), (w,) = s.defects, s.waviness
    assert (d.surface, d.roller, d.length_m, d.width_m) == ("roller", 3, 1e-3, 6e-3)
    assert d.angle_rad == pytest.approx(0.5 * 3.141592653589793)
    assert (w.surface, w.order, w.amplitude_m) == ("roller", 2, 0.5e-6)


def test_off_the_race_and_not_a_table():
    with pytest.raises(SceneError, match="off the race"):
        scene_from_dict({"bearing": {"preset": "yang20", "outer_diameter_mm": 30.0,
                                     "bore_mm": 10.0, "roller_diameter_mm": 4.0,
                                     "roller_length_mm": 4.0, "effective_length_mm": 4.0,
                                     "rollers": 8, "pitch_diameter_mm": 20.0},
                         "defects": [dict(GOOD_DEFECT, on="inner", length_mm=60.0,
                                          width_mm=2.0)]})
    with pytest.raises(SceneError, match=r"must be an array of tables"):
        scene_from_dict({"bearing": {"preset": "yang20"}, "defects": GOOD_DEFECT})


def test_complete_toml_round_trip():
    s = scene_from_dict(_scene([GOOD_DEFECT, dict(GOOD_DEFECT, on="inner", angle_deg=-5.0)],
                               [GOOD_WAVES]))
    assert len(s.defects) == 2 and s.defects[1].surface == "inner"
    assert s.defects[0].depth_m == 20e-6 and s.defects[0].roller == -1
    assert s.waviness[0].order == 21
    again = scene_from_dict(tomllib.loads(s.to_toml(complete=True)))
    assert again.defects == s.defects and again.waviness == s.waviness
    for table in ("defects", "waviness"):
        assert (tomllib.loads(again.to_toml(complete=True))[table]
                == tomllib.loads(s.to_toml(complete=True))[table])


def test_default_scene_has_neither_table():
    s = load_scene("yang20_baseline")
    assert s.defects == () and s.waviness == ()
    for text in (s.to_toml(), s.to_toml(complete=True)):
        assert "defects" not in text and "waviness" not in text


def test_cli_exit_status_two(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text('[bearing]\npreset = "yang20"\n\n[[defects]]\non = "outer"\nlength_mm = 1.0\n'
                 'width_mm = 40.0\ndepth_um = 20.0\n')
    p = subprocess.run([sys.executable, "-m", "bearingdae.cli", "run", str(f), "--no-plot",
                        "--no-progress", "-o", str(tmp_path / "x.nc")],
                       capture_output=True, text=True)
    assert p.returncode == 2, p.stderr
    assert "Traceback" not in p.stderr
    assert "'defects[0].width_mm' = 40.0: wider than the roller" in p.stderr
    assert len(p.stderr.strip().splitlines()) == 1, p.stderr
