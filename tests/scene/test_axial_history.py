"""The axial load as a history (theory.md §14, §16): ``operating.axial_load_N`` as a table, a
load file's ``axial_load_N`` variable, and the bearing type's sign rule on every value of the
history. Every refusal is one SceneError line naming the field, the value and the rule."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from bearingdae.scene import SceneError
from conftest import make_scene

RAMP = {"times_s": [0.0, 0.01, 0.02], "values_N": [200.0, 1000.0, 1000.0]}


def _nc(path, t, loads, units=None):
    units = units or {}
    data = {k: ("time", np.asarray(v, float), {"units": units.get(k, "N" if k.endswith("_N")
                                                                   else "N m")})
            for k, v in loads.items()}
    xr.Dataset(data, coords={"time": ("time", np.asarray(t, float), {"units": "s"})}
               ).to_netcdf(path)
    return str(path)


def _one_line(over=None, **sections):
    with pytest.raises(SceneError) as exc:
        make_scene(over, **sections)
    msg = str(exc.value)
    assert "\n" not in msg and len(msg) < 400, msg
    return msg


def test_an_axial_table_is_the_sixth_column_of_the_load_history():
    sc = make_scene({"bearing.type": "NJ"}, operating={
        "radial_load_N": 800.0, "axial_load_N": RAMP,
        "moment_Nm": {"times_s": [0.005, 0.03], "values_Nm": [1.0, 3.0]}})
    rows = np.array(sc.operating.load_history)
    np.testing.assert_array_equal(rows[:, 0], [0.0, 0.005, 0.01, 0.02, 0.03])
    np.testing.assert_allclose(rows[:, 5], [200.0, 600.0, 1000.0, 1000.0, 1000.0], rtol=1e-15)
    np.testing.assert_array_equal(rows[:, 1], 800.0)
    assert sc.operating.axial_load_N == 200.0  # at t = 0, as the other keys
    assert sc.operating.axial_load_max_N == 1000.0


def test_a_constant_axial_load_makes_no_history():
    sc = make_scene({"bearing.type": "NJ", "operating.axial_load_N": 200.0})
    assert sc.operating.load_history is None and sc.operating.axial_load_max_N == 200.0


@pytest.mark.parametrize("kind, values, words", [
    ("NJ", [200.0, -5.0], ["'operating.axial_load_N' = -5.0 at t = 0.01 s", "[0, 1e8]", "NUP"]),
    ("NU", [0.0, 5.0], ["'operating.axial_load_N' = 5.0 at t = 0.01 s", "allowed: 0"]),
    (None, [0.0, 5.0], ["'operating.axial_load_N' = 5.0 at t = 0.01 s", "flangeless"]),
])
def test_the_sign_rule_holds_for_every_value_of_the_history(kind, values, words):
    over = {"bearing.type": kind} if kind else {}
    msg = _one_line(over, operating={"axial_load_N": {"times_s": [0.0, 0.01],
                                                      "values_N": values}})
    for w in words:
        assert w in msg, (w, msg)


def test_a_zero_history_needs_no_flanges_and_a_negative_one_is_fine_on_nup():
    assert make_scene(operating={"axial_load_N": {"times_s": [0.0, 1.0],
                                                  "values_N": [0.0, 0.0]}}).bearing.flanges is None
    sc = make_scene({"bearing.type": "NUP"}, operating={
        "axial_load_N": {"times_s": [0.0, 1.0], "values_N": [300.0, -300.0]}})
    assert sc.operating.axial_load_max_N == 300.0


@pytest.mark.parametrize("value, fragment", [
    ({"times_s": [0.0, 0.01, 0.02], "values_N": [1.0, 2.0]}, "same length"),
    ({"times_s": [0.0, 0.0], "values_N": [1.0, 2.0]}, "strictly increasing"),
    ({"times_s": [0.0, 1.0], "values_N": [1.0, 2e9]}, "every force must lie"),
    ({"times_s": [0.0, 1.0], "values_Nm": [1.0, 2.0]}, "values_N"),
    (2e9, "outside the allowed range [-1e+08, 1e+08]"),
])
def test_bad_axial_tables_name_the_key(value, fragment):
    """The schema's checks, worded as for the other load keys."""
    with pytest.raises(SceneError) as exc:
        make_scene({"bearing.type": "NUP"}, operating={"axial_load_N": value})
    msg = str(exc.value)
    assert "operating.axial_load_N" in msg and fragment in msg, msg


def test_a_load_file_may_carry_the_axial_load_in_kN(tmp_path):
    t = np.linspace(0.0, 0.02, 5)
    p = _nc(tmp_path / "l.nc", t, {"radial_load_N": np.full(5, 800.0),
                                   "axial_load_N": 0.2 + 40.0 * t},
            units={"axial_load_N": "kN"})
    sc = make_scene({"bearing.type": "NJ"}, operating={"load_file": p})
    rows = np.array(sc.operating.load_history)
    np.testing.assert_allclose(rows[:, 5], 200.0 + 40e3 * t, rtol=1e-15)
    # the same history as CSV
    csv = tmp_path / "l.csv"
    csv.write_text("time_s,radial_load_N,axial_load_N\n"
                   + "".join(f"{float(a)!r},800,{200.0 + 40e3 * float(a)!r}\n" for a in t))
    rows2 = np.array(make_scene({"bearing.type": "NJ"},
                                operating={"load_file": str(csv)}).operating.load_history)
    np.testing.assert_allclose(rows2, rows, rtol=1e-15)


def test_a_load_file_without_axial_load_takes_the_scene_key(tmp_path):
    t = np.linspace(0.0, 0.02, 5)
    p = _nc(tmp_path / "l.nc", t, {"radial_load_N": 800.0 + 1e4 * t})
    const = make_scene({"bearing.type": "NJ"}, operating={"load_file": p, "axial_load_N": 250.0})
    np.testing.assert_array_equal(np.array(const.operating.load_history)[:, 5], 250.0)
    table = make_scene({"bearing.type": "NJ"}, operating={
        "load_file": p, "axial_load_N": {"times_s": [0.0, 0.012], "values_N": [0.0, 1200.0]}})
    rows = np.array(table.operating.load_history)
    np.testing.assert_allclose(rows[:, 0], [0.0, 0.005, 0.01, 0.012, 0.015, 0.02], rtol=1e-15)
    np.testing.assert_allclose(rows[:, 1], 800.0 + 1e4 * rows[:, 0], rtol=1e-15)
    np.testing.assert_allclose(rows[:, 5], [0.0, 500.0, 1000.0, 1200.0, 1200.0, 1200.0],
                               rtol=1e-14)


def test_load_file_axial_load_and_scene_key_exclude_each_other(tmp_path):
    p = _nc(tmp_path / "l.nc", [0.0, 1.0], {"axial_load_N": [1.0, 2.0]})
    msg = _one_line({"bearing.type": "NJ"}, operating={"load_file": p, "axial_load_N": 5.0})
    assert "gives axial_load_N" in msg and "'operating.axial_load_N' is given too" in msg, msg


def test_a_load_file_axial_load_follows_the_sign_rule(tmp_path):
    p = _nc(tmp_path / "l.nc", [0.0, 0.01, 0.02], {"axial_load_N": [100.0, 0.0, -50.0]})
    msg = _one_line({"bearing.type": "NJ"}, operating={"load_file": p})
    assert "'operating.load_file' variable 'axial_load_N' = -50.0 at t = 0.02 s" in msg, msg
    assert "[0, 1e8]" in msg, msg
    msg = _one_line(operating={"load_file": p})  # no flanges
    assert "variable 'axial_load_N' = 100.0 at t = 0 s" in msg and "flangeless" in msg, msg
