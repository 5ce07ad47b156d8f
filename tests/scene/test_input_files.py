"""Scene and sweep files as inputs: only regular files up to the size cap are read; names the
user typed are echoed cut; "did you mean" ignores case; API arguments that stand for scene keys
share their ranges."""

from __future__ import annotations

import os

import pytest

from bearingdae import SceneError, load_scene
from bearingdae.scene.files import MAX_INPUT_BYTES, read_input
from bearingdae.scene.arguments import check_argument
from bearingdae.scene.schema import allowed_range


@pytest.mark.parametrize("kind, fragment", [("fifo", "FIFO"), ("dir", "directory"),
                                             ("big", "1 MiB"), ("dev", "character device")])
def test_only_regular_files_up_to_the_cap_are_read(tmp_path, kind, fragment):
    p = tmp_path / "s.toml"
    if kind == "fifo":
        os.mkfifo(p)  # reading it would block until a writer came
    elif kind == "dir":
        p.mkdir()
    elif kind == "big":
        with open(p, "wb") as fh:
            fh.truncate(MAX_INPUT_BYTES + 1)
    else:
        p = "/dev/zero"  # reading it would never end
    with pytest.raises(SceneError, match=fragment):
        load_scene(p)
    with pytest.raises(SceneError, match=fragment):
        read_input(p, "sweep file")


def test_a_file_at_the_cap_is_read(tmp_path):
    p = tmp_path / "s.toml"
    p.write_bytes(b"#" * (MAX_INPUT_BYTES - 1) + b"\n")
    assert len(read_input(p)) == MAX_INPUT_BYTES


@pytest.mark.parametrize("key, suggestion", [("numerics.Atol", "numerics.atol"),
                                             ("bearing.OUTER_DIAMETER_MM",
                                              "bearing.outer_diameter_mm"),
                                             ("Numerics.Slices", "numerics.slices")])
def test_did_you_mean_ignores_case(key, suggestion):
    with pytest.raises(SceneError, match=f"Did you mean '{suggestion}'"):
        load_scene("yang20_baseline", {key: 1})


def test_long_names_and_values_are_echoed_cut():
    for overrides in ({"numerics." + "k" * 5000: 1}, {"numerics.slices": "9" * 100_000}):
        with pytest.raises(SceneError) as e:
            load_scene("yang20_baseline", overrides)
        assert len(str(e.value)) < 1000, len(str(e.value))


def test_check_argument_uses_the_scene_keys_range():
    key = "numerics.newmark_step_s"
    assert check_argument(key, 1e-6, "h") == 1e-6
    with pytest.raises(ValueError) as e:
        check_argument(key, -1.0, "h")
    assert f"h = -1.0: outside the allowed range {allowed_range(key)}" in str(e.value)
    with pytest.raises(TypeError, match="h = '1e-6': expected a number"):
        check_argument(key, "1e-6", "h")
    with pytest.raises(ValueError, match="must be a finite number"):
        check_argument(key, float("nan"), "h")
    with pytest.raises(TypeError, match="expected True or False"):
        check_argument("numerics.newmark_error_estimate", 1, "flag")


def test_a_nested_override_names_the_sections_keys_not_itself(tmp_path):
    """``--set cage={friction=0.1}`` (or ``{"cage": {...}}`` through the API) answered "Did you
    mean 'cage'?", the very key given. Now the message says it is a section and lists its
    keys; as a process: one line, status 2."""
    import subprocess
    import sys

    with pytest.raises(SceneError) as info:
        load_scene("yang20_baseline", {"cage": {"friction": 0.1}})
    msg = str(info.value)
    assert "Did you mean 'cage'" not in msg and "[cage] is a section" in msg
    assert "cage.friction" in msg
    done = subprocess.run([sys.executable, "-m", "bearingdae.cli", "static", "yang20_baseline",
                           "-o", str(tmp_path / "s.nc"), "--set", "lubricant={viscosity_Pa_s=1}"],
                          capture_output=True, text=True)
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 2 and len(lines) == 1, done.stderr
    assert "[lubricant] is a section" in lines[0] and "lubricant.viscosity_Pa_s" in lines[0]
