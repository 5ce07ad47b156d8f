"""Every file a scene reads is part of its identity: a checkpoint written under one load
file is not resumed under another (the message names the file), and a sweep's run key
changes with the file's contents (run/checkpoint.py, studies/sweep/store.py,
``Scene.identity``).

The edits are what a user does to a load file between two runs: another value, one more
sample, the same numbers written by another tool (other bytes), or the unchanged file
written again (same bytes: the identity must not change).
"""

from __future__ import annotations

import subprocess
import sys
import warnings

import numpy as np
import pytest
import xarray as xr
from hypothesis import given
from hypothesis import strategies as st

from bearingdae import Checkpoint, load_scene, simulate
from bearingdae.run.checkpoint import CheckpointError, checkpoint_path
from bearingdae.studies.sweep import run_key
from fuzzing import fuzz

T = np.linspace(0.0, 0.1, 11)


def write_loads(path, radial_N, times=T, kind=None):
    """A load file of constant ``radial_N``: NetCDF or CSV by the suffix (``kind``: another
    writer's bytes for the same numbers)."""
    loads = np.full(times.size, float(radial_N))
    if path.suffix == ".nc":
        ds = xr.Dataset({"radial_load_N": ("time", loads, {"units": "N"})},
                        coords={"time": ("time", times, {"units": "s"})})
        if kind == "other writer":
            ds.attrs["history"] = "written again by another tool"
        ds.to_netcdf(path)
    else:
        sep = "\r\n" if kind == "other writer" else "\n"
        path.write_bytes(("time_s,radial_load_N" + sep + "".join(
            f"{float(t)!r},{float(f)!r}{sep}" for t, f in zip(times, loads))).encode())


def scene_with(tmp_path, suffix):
    loads = tmp_path / f"loads{suffix}"
    write_loads(loads, 800.0)
    s = tmp_path / "s.toml"
    s.write_text('title = "load file identity"\n[bearing]\npreset = "yang20"\n[operating]\n'
                 f'speed_rpm = 2000.0\nload_file = "{loads.name}"\n[numerics]\n'
                 'warmup_cage_revolutions = 0.0\ncage_revolutions = 0.02\n'
                 'samples_per_cage_revolution = 100\n')
    return s, loads


EDITS = {
    "another value": lambda p: write_loads(p, 850.0),
    "one more sample": lambda p: write_loads(p, 800.0, np.append(T, 0.2)),
    "the same numbers, other bytes": lambda p: write_loads(p, 800.0, kind="other writer"),
}


@fuzz(6)
@given(suffix=st.sampled_from([".nc", ".csv"]), edit=st.sampled_from(sorted(EDITS)))
def test_a_resume_after_the_load_file_changed_is_refused_naming_it(tmp_path_factory, suffix,
                                                                    edit):
    d = tmp_path_factory.mktemp("resume")
    scene_file, loads = scene_with(d, suffix)
    ck = checkpoint_path(d / "out.nc")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        simulate(load_scene(scene_file), checkpoint=Checkpoint(ck))
    before = ck.read_bytes()
    EDITS[edit](loads)
    with pytest.raises(CheckpointError) as exc:
        simulate(load_scene(scene_file), checkpoint=Checkpoint(ck, resume=True))
    msg = str(exc.value)
    assert str(loads) in msg and "operating.load_file" in msg and "\n" not in msg, msg
    assert ck.read_bytes() == before  # the refused checkpoint is kept as it was


def test_the_program_refuses_with_exit_2_and_resumes_the_unchanged_file(tmp_path):
    scene_file, loads = scene_with(tmp_path, ".nc")
    out = tmp_path / "out.nc"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        simulate(load_scene(scene_file), checkpoint=Checkpoint(checkpoint_path(out)))
    argv = [sys.executable, "-m", "bearingdae.cli", "run", str(scene_file), "-o", str(out),
            "--resume", "--no-plot", "--no-progress"]
    write_loads(loads, 850.0)
    r = subprocess.run(argv, capture_output=True, text=True)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 1, r.stderr
    assert lines[0].startswith("bearingdae: error: checkpoint") and str(loads) in lines[0]
    assert not out.exists()
    write_loads(loads, 800.0)  # the same bytes again: the same scene, resumed
    r = subprocess.run(argv, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    with xr.open_dataset(out) as ds:
        np.testing.assert_array_equal(ds.applied_load.sel(direction="radial").values, 800.0)
        assert ds.attrs["load_file_sha256"] == load_scene(scene_file).operating.load_file_sha256


@pytest.mark.parametrize("suffix", [".nc", ".csv"])
def test_a_sweep_run_key_follows_the_load_file_contents(tmp_path, suffix):
    scene_file, loads = scene_with(tmp_path, suffix)
    key = run_key(load_scene(scene_file))
    write_loads(loads, 800.0)  # rewritten, same bytes: same run
    assert run_key(load_scene(scene_file)) == key
    for edit in EDITS.values():
        edit(loads)
        assert run_key(load_scene(scene_file)) != key
        write_loads(loads, 800.0)
    # a scene without input files keeps the key of its text alone (earlier stores stay valid)
    plain = load_scene("yang20_baseline")
    assert plain.identity() == plain.to_toml() and plain.input_files() == {}


def test_resume_on_a_finished_run_whose_load_file_changed_is_refused(tmp_path, capsys):
    """--resume where the run finished (no checkpoint) under other contents of its load file:
    refused in one line naming the file, the result left byte for byte."""
    from bearingdae.cli import main

    scene, loads = scene_with(tmp_path, ".csv")
    out = tmp_path / "r.nc"
    assert main(["run", str(scene), "-o", str(out), "--no-progress", "--no-plot"]) == 0
    before = out.read_bytes()
    assert main(["run", str(scene), "-o", str(out), "--no-progress", "--no-plot",
                 "--resume"]) == 0
    capsys.readouterr()
    write_loads(loads, 850.0)
    assert main(["run", str(scene), "-o", str(out), "--no-progress", "--no-plot",
                 "--resume"]) == 2
    err = capsys.readouterr().err
    assert str(loads) in err and "operating.load_file" in err
    assert len(err.strip().splitlines()) == 1 and out.read_bytes() == before
