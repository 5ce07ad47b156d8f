"""Loads that change in time as scene input (theory.md §14): history tables of the load
keys, the unbalance keys and load files (.nc, .csv). Every malformed load file gives one
SceneError line naming the file and the variable, and exit status 2 from the program."""

from __future__ import annotations

import os
from pathlib import Path
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from bearingdae import SceneError, load_scene
from bearingdae.scene.loadfile import read_load_file
from tests.conftest import make_scene


def test_tables_merge_on_one_time_grid():
    sc = make_scene(operating={
        "speed_rpm": 2000.0,
        "radial_load_N": {"times_s": [0.0, 0.01], "values_N": [0.0, 800.0]},
        "moment_Nm": {"times_s": [0.005, 0.02], "values_Nm": [1.0, 3.0]},
        "tangential_load_N": 20.0})
    rows = np.array(sc.operating.load_history)
    np.testing.assert_array_equal(rows[:, 0], [0.0, 0.005, 0.01, 0.02])
    np.testing.assert_allclose(rows[:, 1], [0.0, 400.0, 800.0, 800.0], rtol=1e-15)
    np.testing.assert_allclose(rows[:, 3], [1.0, 1.0, 1.0 + 2.0 / 3.0, 3.0], rtol=1e-15)
    np.testing.assert_array_equal(rows[:, 2], 20.0)
    np.testing.assert_array_equal(rows[:, 5], 0.0)  # no axial load (no flanges)
    assert sc.operating.loads == (0.0, 20.0, 1.0, 0.0)  # the loads at t = 0
    assert make_scene(operating={"radial_load_N": 800.0}).operating.load_history is None


@pytest.mark.parametrize("value, fragment", [
    ({"times_s": [0.0, 0.01, 0.02], "values_N": [1.0, 2.0]}, "same length"),
    ({"times_s": [0.0, 0.0], "values_N": [1.0, 2.0]}, "strictly increasing"),
    ({"times_s": [-1.0, 0.0], "values_N": [1.0, 2.0]}, "must not be negative"),
    ({"times_s": [0.0, 1.0], "values_N": [1.0, 2e9]}, "every force must lie"),
    ({"times_s": [0.0, 1.0], "values_Nm": [1.0, 2.0]}, "values_N"),
    (-5.0, "outside the allowed range [0, 1e+08]"),
])
def test_bad_tables_name_the_key(value, fragment):
    with pytest.raises(SceneError) as exc:
        make_scene(operating={"radial_load_N": value})
    assert "operating.radial_load_N" in str(exc.value) and fragment in str(exc.value)


def test_a_moment_history_needs_tilt():
    with pytest.raises(SceneError, match="physics.tilt"):
        make_scene(operating={"moment_Nm": {"times_s": [0.0, 1.0], "values_Nm": [0.0, 2.0]}},
                   physics={"tilt": False})


def _write_nc(path, t, loads, t_units="s", units=None):
    units = units or {}
    data = {name: ("time", np.asarray(v, float), {"units": units.get(name, "N" if
                                                  name.endswith("_N") else "N m")})
            for name, v in loads.items()}
    xr.Dataset(data, coords={"time": ("time", np.asarray(t, float), {"units": t_units})}
               ).to_netcdf(path)
    return path


def test_a_file_written_by_plain_xarray_is_read_in_si(tmp_path):
    t = np.linspace(0.0, 0.1, 11)
    p = _write_nc(tmp_path / "loads.nc", t, {"radial_load_N": 0.8 + 0 * t, "moment_Nm": 3 + t},
                  units={"radial_load_N": "kN"})
    times, loads, names = read_load_file(p)
    assert names == ("radial_load_N", "moment_Nm")
    np.testing.assert_array_equal(times, t)
    np.testing.assert_allclose(loads[:, 0], 800.0, rtol=1e-15)
    np.testing.assert_array_equal(loads[:, 1], 0.0)
    np.testing.assert_allclose(loads[:, 2], 3 + t, rtol=1e-15)
    # named relative to the scene file
    scene = tmp_path / "s.toml"
    scene.write_text('[bearing]\npreset = "yang20"\n[operating]\nspeed_rpm = 2000.0\n'
                     'load_file = "loads.nc"\nunbalance_N = 50.0\n')
    sc = load_scene(scene)
    assert sc.operating.load_file == str(p)
    assert np.array(sc.operating.load_history).shape == (11, 6)  # t and the five loads
    assert sc.operating.unbalance_N == 50.0
    # the same history as CSV
    csv = tmp_path / "loads.csv"
    csv.write_text("# from a shaft model\ntime_s,radial_load_N,moment_Nm\n"
                   + "".join(f"{float(a)!r},800,{float(3 + a)!r}\n" for a in t))
    t2, l2, _ = read_load_file(csv)
    np.testing.assert_array_equal(t2, times)
    np.testing.assert_array_equal(l2, loads)


def _bad_files(d):
    """(name, writer, the variable the message must name, a fragment of the expectation)."""
    t = np.linspace(0.0, 0.1, 5)
    F = {"radial_load_N": np.full(5, 800.0)}
    nan = {"radial_load_N": np.array([800.0, np.nan, 800.0, 800.0, 800.0])}
    return [
        ("units.nc", lambda p: _write_nc(p, t, F, units={"radial_load_N": "lbf"}),
         "radial_load_N", "expected one of 'N'"),
        ("notime.nc", lambda p: xr.Dataset({"radial_load_N": ("x", F["radial_load_N"],
                                                              {"units": "N"})}).to_netcdf(p),
         "time", "expected a coordinate 'time'"),
        ("nan.nc", lambda p: _write_nc(p, t, nan), "radial_load_N", "expected finite loads"),
        ("decreasing.nc", lambda p: _write_nc(p, t[::-1], F), "time", "strictly increasing"),
        ("short.nc", lambda p: _write_nc(p, t[:1], {"radial_load_N": [800.0]}), "time",
         "at least 2"),
        ("late.nc", lambda p: _write_nc(p, t + 0.5, F), "time", "at or before 0 s"),
        ("tunits.nc", lambda p: _write_nc(p, t, F, t_units="seconds since 2000-01-01"), "time",
         "not a duration"),
        ("nounits.nc", lambda p: xr.Dataset({"radial_load_N": ("time", F["radial_load_N"])},
                                            coords={"time": ("time", t, {"units": "s"})}
                                            ).to_netcdf(p), "radial_load_N", "'units'"),
        ("misspelt.nc", lambda p: _write_nc(p, t, {"radial_load": F["radial_load_N"]},
                                            units={"radial_load": "N"}),
         "radial_load", "expected only"),
        ("garbage.nc", lambda p: p.write_bytes(b"\x89HDF\r\n garbage" * 10), "NetCDF",
         "NetCDF file"),
        ("nan_time.nc", lambda p: _write_nc(p, [0.0, np.nan, 0.2, 0.3, 0.4], F), "time",
         "finite times"),
        ("header.csv", lambda p: p.write_text("t,radial_load_N\n0,1\n1,2\n"), "time_s",
         "column 'time_s'"),
        ("text.csv", lambda p: p.write_text("time_s,radial_load_N\n0,1\n1,heavy\n"),
         "radial_load_N", "is not a number"),
        ("fields.csv", lambda p: p.write_text("time_s,radial_load_N\n0,1\n1\n"), "line 3",
         "expected 2"),
        ("empty.csv", lambda p: p.write_text(""), "empty", "header line"),
        ("loads.txt", lambda p: p.write_text("0 1\n"), "'.txt'", ".nc or a CSV"),
        ("missing.nc", lambda p: None, "missing.nc", "cannot be read"),
        # the axial load (a bearing with flanges, theory.md §16): units and values as the others
        ("axial_units.nc", lambda p: _write_nc(p, t, {"axial_load_N": np.full(5, 200.0)},
                                               units={"axial_load_N": "N m"}),
         "axial_load_N", "expected one of 'N'"),
        ("axial_nan.nc", lambda p: _write_nc(p, t, {"axial_load_N": [200.0, np.nan, 1, 1, 1]}),
         "axial_load_N", "expected finite loads"),
        ("axial_big.csv", lambda p: p.write_text("time_s,axial_load_N\n0,1\n1,2e9\n"),
         "axial_load_N", "expected values in [-1e+08, 1e+08]"),
        ("axial_text.csv", lambda p: p.write_text("time_s,axial_load_N\n0,1\n1,push\n"),
         "axial_load_N", "is not a number"),
    ]


@pytest.mark.parametrize("case", range(21))
def test_each_malformed_load_file_gives_one_line(tmp_path, case):
    name, write, variable, expected = _bad_files(tmp_path)[case]
    p = tmp_path / name
    write(p)
    with pytest.raises(SceneError) as exc:
        make_scene(operating={"speed_rpm": 2000.0, "load_file": str(p)})
    msg = str(exc.value)
    assert "\n" not in msg and len(msg) < 400, msg
    assert "'operating.load_file': load file '" in msg and name in msg, msg
    assert variable in msg and expected in msg, msg


def test_load_file_and_load_keys_exclude_each_other(tmp_path):
    p = _write_nc(tmp_path / "l.nc", [0.0, 1.0], {"radial_load_N": [1.0, 2.0]})
    with pytest.raises(SceneError, match="operating.radial_load_N is given too"):
        make_scene(operating={"radial_load_N": 5.0, "load_file": str(p)})


@pytest.mark.parametrize("path", ["loads\x00.nc", "yang20\x00"])
def test_a_nul_in_the_load_file_path_is_one_line(path):
    # open() raises ValueError, not OSError, for an embedded NUL
    with pytest.raises(SceneError) as exc:
        make_scene(operating={"radial_load_N": 0.0, "load_file": path})
    msg = str(exc.value)
    assert "\n" not in msg and "'operating.load_file'" in msg, msg


def test_program_exits_2_with_one_line(tmp_path):
    """As a program: a malformed file, and a file too short for the run (checked once the run's
    end is known), each give exit status 2 and one line on stderr."""
    t = np.linspace(0.0, 0.1, 5)
    _write_nc(tmp_path / "nan.nc", t, {"radial_load_N": [1.0, np.nan, 1.0, 1.0, 1.0]})
    _write_nc(tmp_path / "brief.nc", t * 0.01, {"radial_load_N": np.full(5, 800.0)})
    env = {**os.environ, "OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    for name, fragment in (("nan.nc", "expected finite loads"),
                           ("brief.nc", "expected to cover the run")):
        scene = tmp_path / f"{name}.toml"
        scene.write_text(f'[bearing]\npreset = "yang20"\n[operating]\nspeed_rpm = 2000.0\n'
                         f'load_file = "{name}"\n')
        r = subprocess.run([sys.executable, "-m", "bearingdae.cli", "run", str(scene), "--no-plot",
                            "--no-progress", "-o", str(tmp_path / "out.nc")],
                           capture_output=True, text=True, env=env, cwd=tmp_path)
        assert r.returncode == 2, r.stderr
        # a first run on a machine announces the compile before the scene is checked against
        # the run's end; the refusal itself is one line
        lines = [line for line in r.stderr.strip().splitlines()
                 if not line.startswith("compiling kernels (first run only")]
        assert len(lines) == 1 and fragment in lines[0] and name in lines[0], r.stderr
        assert not (tmp_path / "out.nc").exists()


ROWS = ["time_s,radial_load_N,moment_Nm"] + [f"{0.01 * i!r},{800.0 + i!r},{0.5 * i!r}"
                                              for i in range(6)]


@pytest.mark.parametrize("how", ["LF", "CRLF", "CR (Excel's CSV (Macintosh))",
                                 "BOM (Excel's CSV UTF-8)", "BOM and CRLF"])
def test_csv_line_ends_and_a_byte_order_mark_read_as_plain_lines(tmp_path, how):
    end = {"LF": "\n", "CR": "\r", "CRLF": "\r\n", "BOM": "\n"}[how.split(" ")[0]]
    end = "\r\n" if how == "BOM and CRLF" else end
    text = ("\ufeff" if how.startswith("BOM") else "") + end.join(ROWS) + end
    p = tmp_path / "loads.csv"
    p.write_bytes(text.encode("utf-8"))
    t, loads, names = read_load_file(p)
    assert names == ("radial_load_N", "moment_Nm")
    # the reference: the numbers as typed above, parsed afresh
    want = np.array([[float(x) for x in r.split(",")] for r in ROWS[1:]])
    np.testing.assert_array_equal(t, want[:, 0])
    np.testing.assert_array_equal(loads[:, 0], want[:, 1])
    np.testing.assert_array_equal(loads[:, 2], want[:, 2])


@pytest.mark.parametrize("rows, line", [
    (40_000, 4),  # the quoted field runs past the csv module's field limit (131072)
    (3, 4),       # ... or to the end of a short file: then its text is not a number
])
def test_a_stray_double_quote_names_the_file_and_its_line(tmp_path, rows, line):
    p = tmp_path / "quoted.csv"
    p.write_text("\n".join(ROWS[:3] + ['0.03,"803,1.5'] + [f"{1 + i},{i},0" for i in range(rows)]))
    with pytest.raises(SceneError) as exc:
        read_load_file(p)
    msg = str(exc.value)
    assert "\n" not in msg and len(msg) < 400, msg
    assert "quoted.csv" in msg and f"line {line}" in msg, msg


def test_millisecond_times_and_messages_that_quote_once(tmp_path):
    t = np.linspace(0.0, 100.0, 5)  # in ms
    for units in ("ms", "millisecond", "milliseconds", "msec"):
        p = _write_nc(tmp_path / f"{units}.nc", t, {"radial_load_N": np.full(5, 800.0)},
                      t_units=units)
        np.testing.assert_allclose(read_load_file(p)[0], t * 1e-3, rtol=1e-15)
    p = _write_nc(tmp_path / "lbf.nc", t * 1e-3, {"radial_load_N": np.full(5, 180.0)},
                  units={"radial_load_N": "lbf"})
    with pytest.raises(SceneError) as exc:
        read_load_file(p)
    assert "units 'lbf';" in str(exc.value) and "''" not in str(exc.value), str(exc.value)


def test_a_load_history_is_one_float_array_that_compares_and_hashes_by_value(tmp_path):
    """A load file's history is held as one read-only (n, 6) float array (48 bytes a row,
    not a tuple of Python tuples): rows, columns and np.asarray as before; equal and hashed
    by value (scenes compare, frozen)."""
    import pickle

    from bearingdae.scene.si import LoadHistory

    t = np.linspace(0.0, 0.1, 100_001)
    p = _write_nc(tmp_path / "long.nc", t, {"radial_load_N": 800.0 + 100.0 * np.sin(40 * t)})
    sc = make_scene(operating={"speed_rpm": 2000.0, "load_file": str(p)})
    h = sc.operating.load_history
    rows = np.asarray(h)
    assert isinstance(h, LoadHistory) and rows.shape == (t.size, 6) and rows.dtype == float
    assert not rows.flags.writeable and rows.nbytes == 48 * t.size
    np.testing.assert_array_equal(rows[:, 0], t)
    np.testing.assert_array_equal(h[0][1:], [800.0, 0.0, 0.0, 0.0, 0.0])
    assert sc.operating.radial_load_N == 800.0 and type(sc.operating.radial_load_N) is float
    again = pickle.loads(pickle.dumps(sc))
    assert again == sc and hash(again.operating) == hash(sc.operating)
    other = make_scene(operating={"speed_rpm": 2000.0, "load_file": str(_write_nc(
        tmp_path / "other.nc", t, {"radial_load_N": 800.0 + 100.0 * np.cos(40 * t)}))})
    assert other.operating.load_history != h


@pytest.mark.parametrize("kind", ["fifo", "dev_zero_link"])
def test_a_load_file_that_is_not_a_regular_file_is_refused_before_it_is_hashed(tmp_path, kind):
    """A FIFO blocks a reader until a writer comes and /dev/zero never ends: the scene's
    identity (the file's digest) must not read either before the regular-file check. Run as
    a process, as a user meets it: one line, exit status 2 (the timeout only guards the test
    run against the hang; it asserts no speed)."""
    path = tmp_path / "loads.csv"
    if kind == "fifo":
        os.mkfifo(path)
    else:
        os.symlink("/dev/zero", path)
    scene = tmp_path / "scene.toml"
    text = (Path(__file__).resolve().parents[2] / "cases" / "shaft_load_history.toml").read_text()
    scene.write_text(text.replace("shaft_load_history.nc", str(path)))
    from bearingdae.scene.loadfile import file_sha256

    with pytest.raises(SceneError, match="is not a regular file"):
        file_sha256(path)
    done = subprocess.run([sys.executable, "-m", "bearingdae.cli", "static", str(scene), "-o",
                           str(tmp_path / "s.nc")], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and "operating.load_file" in lines[0], done.stderr
    assert "is not a regular file" in lines[0]
