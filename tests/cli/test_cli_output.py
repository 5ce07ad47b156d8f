"""CLI and NetCDF output contract of the static solve."""

from __future__ import annotations

import subprocess
import tomllib
import sys

import numpy as np
import pytest
import xarray as xr

from bearingdae import load_scene, save, solve_static
from bearingdae.cli import main


def test_static_cli_writes_netcdf_with_units(tmp_path, capsys):
    out = tmp_path / "s.nc"
    assert main(["static", "yang20_baseline", "-o", str(out), "--set",
                 "operating.radial_load_N=400"]) == 0
    ds = xr.open_dataset(out)
    assert set(ds.dims) == {"roller", "slice", "race", "direction", "bounds"}
    for name, var in ds.variables.items():
        if name in ("race", "direction", "roller", "slice"):  # labels and index numbers
            assert "units" not in var.attrs and "long_name" in var.attrs, name
        elif "flag_values" in var.attrs:  # CF flags: meanings instead of a unit
            assert "flag_meanings" in var.attrs and "units" not in var.attrs, name
        elif name != "slice_position_bounds":  # CF 7.1: shares slice_position's attributes
            assert "units" in var.attrs and "long_name" in var.attrs, name
    assert ds.attrs["Conventions"] == "CF-1.10"
    assert 'radial_load_N = 400.0' in ds.attrs["scene_toml"]
    assert ds.contact_force.sel(race="inner").sum().item() > 400.0
    ds.close()


def test_netcdf_round_trip_is_exact(tmp_path):
    ds = solve_static(load_scene("yang20_baseline"))
    path = save(ds, tmp_path / "rt.nc")
    back = xr.open_dataset(path)
    xr.testing.assert_identical(back.load(), ds)
    back.close()


def test_failed_write_leaves_no_file(tmp_path, monkeypatch):
    ds = solve_static(load_scene("yang20_baseline"))
    target = tmp_path / "x.nc"

    def boom(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(xr.Dataset, "to_netcdf", boom)
    with pytest.raises(KeyboardInterrupt):
        save(ds, target)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["static", "no_such_case"], "does not exist"),
        (["static", "yang20_baseline", "--set", "bearing.rolers=3"], "bearing.rollers"),
        (["static", "yang20_baseline", "--set", "operating.radial_load_N=nan"], "finite"),
        (["static", "yang20_baseline", "--set", "numerics.slices=0"], "[1, 1000]"),
    ],
)
def test_bad_input_exits_2_with_one_message_and_no_traceback(args, fragment):
    r = subprocess.run([sys.executable, "-m", "bearingdae.cli", *args], capture_output=True,
                       text=True)
    assert r.returncode == 2
    assert fragment in r.stderr and "Traceback" not in r.stderr


def test_keys_and_cases_commands(capsys):
    assert main(["keys"]) == 0
    out = capsys.readouterr().out
    assert "operating.radial_load_N" in out
    assert out.splitlines()[0].split() == ["key", "default", "allowed", "meaning"]  # a header
    assert main(["cases"]) == 0
    lines = capsys.readouterr().out.splitlines()
    # one line per case, each saying what it is (the first sentence of the case's comment)
    base = [ln for ln in lines if ln.split()[0] == "yang20_baseline"]
    assert len(base) == 1 and "Yang et al. 2024" in base[0], lines
    assert all(len(ln.split()) >= 3 for ln in lines), lines
    assert not any("issue" in ln for ln in lines)


def test_an_unknown_key_points_at_the_keys_command():
    from bearingdae import SceneError, load_scene

    with pytest.raises(SceneError, match="bearingdae keys"):
        load_scene("yang20_baseline", {"operating.radial_lod_N": 1.0})


def test_bundled_cases_found_from_an_installed_wheel(tmp_path):
    """Regression: after a non-editable `pip install .` the bundled cases live in
    site-packages/bearingdae/cases, which is a data folder, not a module; `bearingdae run` with
    no CASE must find yang20_baseline there (README's first command)."""
    import shutil

    import bearingdae
    from bearingdae.scene import bundled_case_dirs

    fake = tmp_path / "site" / "bearingdae"
    shutil.copytree(__import__("pathlib").Path(bearingdae.__file__).parent, fake,
                    ignore=shutil.ignore_patterns("__pycache__", "cases"))
    (fake / "cases").mkdir()
    for d in bundled_case_dirs():
        for p in d.glob("*.toml"):
            shutil.copy(p, fake / "cases" / p.name)
    code = ("import bearingdae, sys; from bearingdae.scene import resolve_case; "
            "print(bearingdae.__file__); print(resolve_case('yang20_baseline'))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       cwd=tmp_path, env={**__import__("os").environ,
                                          "PYTHONPATH": str(tmp_path / "site")})
    assert r.returncode == 0, r.stderr
    lines = r.stdout.split()
    assert lines[0].startswith(str(fake)) and lines[1].startswith(str(fake / "cases"))


def test_summary_notes_for_a_negative_slip_and_a_skew_at_the_pocket_limit():
    """The run summary explains a negative cage slip (resolved or not) and flags a largest
    skew at the angle where a roller end meets its pocket bar: |θ| L/2 = c_p/2."""
    from bearingdae.cli.run import negative_slip_note, pocket_limit_note

    assert "faster than the rigid-body epicyclic" in negative_slip_note(-0.004, 0.001)
    assert "not resolved" in negative_slip_note(-0.001, 0.001)
    assert "not resolved" in negative_slip_note(-0.001, float("nan"))
    scene = load_scene("yang20_baseline")
    src = tomllib.loads(scene.to_toml(complete=True))
    limit = src["cage"]["pocket_clearance_mm"] / scene.bearing.roller_length_m / 1e3  # rad
    assert "pocket limit" in pocket_limit_note(limit, scene, 1e3, "mrad")
    assert f"{limit * 1e3:.3f} mrad" in pocket_limit_note(limit * 1.01, scene, 1e3, "mrad")
    assert pocket_limit_note(0.9 * limit, scene, 1e3, "mrad") == ""
