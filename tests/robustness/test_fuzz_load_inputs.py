"""Property-based fuzzing of the load inputs: load files (CSV and NetCDF) and the history
tables of the load keys, on bearings with and without flanges.

* **CSV load files** built from headers (with a byte-order mark or not), rows of numbers,
  text, stray quotes and empty fields, line ends LF, CRLF, CR or mixed, then bytes mutated.
* **NetCDF load files** with units of every spelling, times and loads out of order, NaN, inf,
  huge, of another type or dimension, and valid files truncated or bit-flipped.
* **History tables** ``{times_s, values_N}`` of the radial, tangential, axial and moment keys,
  peaks up to the keys' bounds, on the flangeless, NJ and NUP bearings; solved statically
  through the program.

The contract: a file loads (times finite and increasing from at most 0 s, loads finite) or is
one :class:`SceneError` line naming the file (a CSV problem also its line); a scene loads or
is one SceneError naming the key; ``bearingdae static`` exits 0, 1 (one line ``static solver
failure``) or 2 (one line), never a traceback. Deterministic (``derandomize=True``).
"""

from __future__ import annotations

import collections
import re
import warnings

import numpy as np
import pytest
import xarray as xr
from hypothesis import given
from hypothesis import strategies as st

from bearingdae import SceneError, scene_from_dict
from bearingdae.scene.loadfile import VARIABLES, read_load_file
from fuzzing import fuzz, run_cli

COUNTS: collections.Counter = collections.Counter()


def check_file(surface: str, path) -> None:
    """read_load_file and a scene naming the file: loaded and sane, or one line naming it."""
    try:
        times, loads, names = read_load_file(path)
    except SceneError as exc:
        msg = str(exc)
        assert "\n" not in msg and len(msg) < 600, msg
        assert f"load file '{path.name}" in msg or path.name in msg, msg
        if "not readable as CSV" in msg:
            assert re.search(r"line \d+", msg), msg
        COUNTS[surface, "SceneError (one line, names the file)"] += 1
    else:
        assert times.size >= 2 and np.all(np.diff(times) > 0) and times[0] <= 0.0
        assert np.all(np.isfinite(loads)) and loads.shape == (times.size, 5) and names
        COUNTS[surface, "loaded"] += 1
    try:
        scene_from_dict({"bearing": {"preset": "yang20"},
                         "operating": {"speed_rpm": 2000.0, "load_file": str(path)}})
    except SceneError as exc:
        assert "'operating.load_file'" in str(exc), str(exc)


# --------------------------------------------------------------------------------------------
# CSV
# --------------------------------------------------------------------------------------------
FIELDS = st.one_of(st.floats(-1e9, 1e9, allow_nan=False).map(repr), st.integers(-5, 5).map(str),
                   st.sampled_from(["", " ", "nan", "inf", "1e999", '"', '"1"', "'2'", "abc",
                                    "1,5", "\x00", "0x10", "١", "\ufeff"]))
HEADERS = st.lists(st.sampled_from(["time_s", *VARIABLES, "radial_load_kN", "", "time_s "]),
                   min_size=1, max_size=4)


@st.composite
def csv_documents(draw) -> bytes:
    """A valid history (header, rows) with none to three defects, in any line-end style."""
    n = draw(st.integers(2, 6))
    header = ["time_s", "radial_load_N"] + draw(st.lists(st.sampled_from(VARIABLES[1:]),
                                                          max_size=2, unique=True))
    rows = [[repr(0.01 * i)] + [repr(800.0 + i)] * (len(header) - 1) for i in range(n)]
    for _ in range(draw(st.integers(0, 3))):
        defect = draw(st.sampled_from(["header", "field", "row length", "no rows", "bytes"]))
        if defect == "header":
            header = draw(HEADERS)
        elif defect == "field" and rows:
            row = rows[draw(st.integers(0, len(rows) - 1))]
            row[draw(st.integers(0, len(row) - 1))] = draw(FIELDS)
        elif defect == "row length" and rows:
            rows[-1] = rows[-1][:-1] if draw(st.booleans()) else rows[-1] + ["1"]
        elif defect == "no rows":
            rows = rows[:draw(st.integers(0, 1))]
    lines = (["# comment"] if draw(st.booleans()) else []) + [",".join(header)] + [
        ",".join(r) for r in rows]
    end = draw(st.sampled_from(["\n", "\r\n", "\r", "mixed"]))
    text = "".join(line + (("\n", "\r\n", "\r")[i % 3] if end == "mixed" else end)
                   for i, line in enumerate(lines))
    if draw(st.booleans()):
        text = "\ufeff" + text
    data = bytearray(text.encode("utf-8"))
    if draw(st.integers(0, 3)) == 0:  # a byte changed
        data[draw(st.integers(0, len(data) - 1))] = draw(st.sampled_from(b'",\r\n\x00\xff#'))
    return bytes(data)


@fuzz(150)
@given(doc=csv_documents())
def test_csv_load_files(tmp_path_factory, doc):
    p = tmp_path_factory.mktemp("csv") / "loads.csv"
    p.write_bytes(doc)
    check_file("CSV load files", p)


@pytest.mark.parametrize("end", ["\n", "\r\n", "\r"])
@pytest.mark.parametrize("bom", [False, True])
def test_every_line_end_and_a_bom_read_the_same_history(tmp_path, end, bom):
    rows = ["time_s,radial_load_N", "0,800", "0.01,850", "0.02,900"]
    p = tmp_path / "loads.csv"
    p.write_bytes((("\ufeff" if bom else "") + end.join(rows) + end).encode())
    t, loads, _ = read_load_file(p)
    np.testing.assert_array_equal(t, [0.0, 0.01, 0.02])
    np.testing.assert_array_equal(loads[:, 0], [800.0, 850.0, 900.0])
    COUNTS["CSV load files", "loaded"] += 1


# --------------------------------------------------------------------------------------------
# NetCDF
# --------------------------------------------------------------------------------------------
UNITS = st.sampled_from(["s", "ms", "milliseconds", "seconds", "sec", "min", "", "S", "N", "kN",
                         "lbf", "N m", "kN m", "N mm", "seconds since 2000-01-01", "  s  "])


@st.composite
def netcdf_files(draw):
    """A valid load file (time in s, radial and tangential loads in N) with none to two
    defects, then possibly truncated or bit-flipped."""
    n = draw(st.integers(2, 6))
    t = np.linspace(0.0, 0.1, n)
    t_attrs = {"units": "s"}
    data = {"radial_load_N": ["time", np.full(n, 800.0), {"units": "N"}],
            "tangential_load_N": ["time", np.full(n, 100.0), {"units": "N"}]}
    for _ in range(draw(st.integers(0, 2))):
        defect = draw(st.sampled_from(["time units", "units", "no units", "time values",
                                       "load values", "int", "text", "2-d", "other name",
                                       "one sample"]))
        var = data[draw(st.sampled_from(sorted(data)))]
        if defect == "time units":
            t_attrs = {"units": draw(UNITS)}
        elif defect == "units":
            var[2] = {"units": draw(UNITS)}
        elif defect == "no units":
            var[2] = {}
        elif defect == "time values":
            t = t.copy()
            t[draw(st.integers(0, n - 1))] = draw(st.sampled_from([np.nan, np.inf, -1.0, 0.05,
                                                                  0.2, 1e300]))
        elif defect == "load values":
            var[1] = var[1].copy()
            var[1][draw(st.integers(0, n - 1))] = draw(st.sampled_from(
                [np.nan, np.inf, -np.inf, 1e9, -1e9, 0.0, 5e-324]))
        elif defect == "int":
            var[1] = var[1].astype(np.int64)
        elif defect == "text":
            var[1] = var[1].astype(str)
        elif defect == "2-d" and var[0] == "time":
            var[0], var[1] = ("time", "x"), np.stack([var[1], var[1]], axis=1)
        elif defect == "other name" and "radial_load_N" in data:
            data["radial_load"] = data.pop("radial_load_N")
        elif defect == "one sample":
            n, t = 1, t[:1]
            for v in data.values():
                v[1] = v[1][:1] if v[0] == "time" else v[1][:1, :]
    ds = xr.Dataset({k: tuple(v) for k, v in data.items()},
                    coords={"time": ("time", t, t_attrs)})
    damage = draw(st.sampled_from(["none", "none", "none", "truncated", "bit flip"]))
    return ds, damage, draw(st.integers(0, 10**6))


@fuzz(120)
@given(case=netcdf_files())
def test_netcdf_load_files(tmp_path_factory, case):
    ds, damage, where = case
    p = tmp_path_factory.mktemp("nc") / "loads.nc"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds.to_netcdf(p)
    raw = bytearray(p.read_bytes())
    if damage == "truncated":
        raw = raw[: where % len(raw)]
    elif damage == "bit flip":
        raw[where % len(raw)] ^= 1 << (where % 8)
    p.write_bytes(bytes(raw))
    check_file("NetCDF load files", p)


# --------------------------------------------------------------------------------------------
# History tables, solved through the program
# --------------------------------------------------------------------------------------------
BEARINGS = {"flangeless": {"preset": "yang20"}, "NJ": {"preset": "yang20", "type": "NJ"},
            "NUP": {"preset": "yang20", "type": "NUP"}}
KEY_UNIT = {"radial_load_N": "values_N", "tangential_load_N": "values_N",
            "axial_load_N": "values_N", "moment_Nm": "values_Nm"}
MAGNITUDES = st.one_of(st.sampled_from([0.0, 800.0, 1e4, 1e6, 1e8, -200.0, 1e9]),
                       st.floats(0.0, 1e6, allow_nan=False))


@st.composite
def history_tables(draw):
    key = draw(st.sampled_from(sorted(KEY_UNIT)))
    n = draw(st.integers(1, 4))
    times = sorted(draw(st.lists(st.sampled_from([0.0, 0.001, 0.01, 0.02, 0.5]), min_size=n,
                                 max_size=n, unique=True)))
    if draw(st.integers(0, 5)) == 0:  # a defect: a negative time, or one value too many
        times[0] = -0.1 if draw(st.booleans()) else times[0]
        n += draw(st.integers(0, 1))
    values = draw(st.lists(MAGNITUDES, min_size=n, max_size=n))
    return key, {"times_s": times, KEY_UNIT[key]: values}


@fuzz(40)
@given(bearing=st.sampled_from(sorted(BEARINGS)), table=history_tables())
def test_history_tables_load_and_solve_or_fail_in_one_line(tmp_path_factory, bearing, table):
    key, value = table
    data = {"bearing": dict(BEARINGS[bearing]), "operating": {"speed_rpm": 2000.0, key: value}}
    if key == "moment_Nm":
        data["physics"] = {"tilt": True}
    try:
        scene_from_dict(data)
    except SceneError as exc:
        assert f"'operating.{key}" in str(exc) or "'bearing." in str(exc), str(exc)
        COUNTS["history tables", "SceneError naming the key"] += 1
        return
    d = tmp_path_factory.mktemp("hist")
    scene = d / "s.toml"
    import tomli_w

    scene.write_text(tomli_w.dumps(data))
    rc, stdout, stderr = run_cli(["static", str(scene), "-o", str(d / "s.nc")])
    assert "Traceback" not in stdout + stderr and rc in (0, 1, 2), (rc, stderr)
    errors = [ln for ln in stderr.splitlines() if not ln.startswith("bearingdae: warning")]
    if rc == 1:
        assert len(errors) == 1 and errors[0].startswith("bearingdae: static solver failure")
    elif rc == 2:
        assert len(errors) == 1 and errors[0].startswith("bearingdae: error: "), stderr
    assert (d / "s.nc").exists() == (rc == 0)
    COUNTS["history tables", f"static exit {rc}"] += 1


def test_zz_summary():
    """Cases per surface and outcome (``pytest -s``); each surface saw both of its outcomes."""
    if not COUNTS:
        pytest.skip("no load-input fuzz test ran in this session")
    per: dict[str, collections.Counter] = collections.defaultdict(collections.Counter)
    for (surface, outcome), n in COUNTS.items():
        per[surface][outcome] += n
    print("\n\nload-input fuzzing: cases per surface (outcome: count), 0 tracebacks")
    for surface, outcomes in sorted(per.items()):
        detail = ", ".join(f"{o}: {n}" for o, n in sorted(outcomes.items()))
        print(f"  {surface:24s} {sum(outcomes.values()):4d}  ({detail})")
    for surface in ("CSV load files", "NetCDF load files"):
        if sum(per[surface].values()) >= 100:  # the fuzz test ran: files loaded and refused
            assert per[surface]["loaded"] >= 5, per[surface]
            assert per[surface]["SceneError (one line, names the file)"] >= 5, per[surface]
    hist = per["history tables"]
    if sum(hist.values()) >= 40:  # refused, solved, and failed to solve in one line
        assert hist["SceneError naming the key"] >= 3 and hist["static exit 0"] >= 3, hist
