"""A result's numbers as variables (bearingdae/analysis/result_variables.py): the table, the
error links, a new statistic as one entry, and files of the older format (results as global
attributes, power loss over ``source``).

``data/old_format_run.nc`` was written by bearingdae before results were variables (commit
1e31073): ``bearingdae run cases/yang20_baseline.toml`` with
``numerics.warmup_cage_revolutions=0.05 numerics.cage_revolutions=0.2
numerics.samples_per_cage_revolution=100`` and ``output.variables=["cage_speed",
"power_loss_W", "skew_angle"]``; its numbers are read here with the netCDF4 library directly,
not through the code under test.
"""

from __future__ import annotations

import json
from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr

from bearingdae.analysis import result_variables as rv
from bearingdae.results.dataset import DYNAMIC_VARIABLES
from bearingdae.results.readers import open_result

OLD = Path(__file__).parent / "data" / "old_format_run.nc"


def test_every_entry_has_units_a_long_name_and_a_distinct_error():
    errors = [q.error for q in rv.RESULT_VARIABLES.values() if q.error]
    assert len(errors) == len(set(errors)) and not set(errors) & set(rv.RESULT_VARIABLES)
    for name, q in rv.RESULT_VARIABLES.items():
        assert q.units.strip() and q.long_name.strip(), name
        assert q.error_kind in ("standard_error", "discretisation"), name
    # no result shadows a per-sample variable
    assert not rv.result_names() & set(DYNAMIC_VARIABLES)


def test_a_new_statistic_is_one_entry(monkeypatch):
    """One line in the table: the producer's number and its error become two variables,
    linked; a standard name gives the error CF's modifier form, none a long name."""
    table = dict(rv.RESULT_VARIABLES)
    table["rolling_resistance_power_W"] = rv.Quantity(
        "W", "mean rolling-resistance power loss", None, "rolling_resistance_power_stderr_W")
    table["toy_speed"] = rv.Quantity("m s-1", "toy speed", "platform_speed_wrt_ground",
                                     "toy_speed_stderr")
    monkeypatch.setattr(rv, "RESULT_VARIABLES", table)
    variables, rest = rv.split_results({
        "rolling_resistance_power_W": 0.25, "rolling_resistance_power_stderr_W": 0.01,
        "toy_speed": 3.0, "toy_speed_stderr": 0.1, "title": "x"})
    assert rest == {"title": "x"}
    p, e = variables["rolling_resistance_power_W"], variables["rolling_resistance_power_stderr_W"]
    assert p.ndim == 0 and float(p) == 0.25 and p.attrs["units"] == "W"
    assert p.attrs["ancillary_variables"] == "rolling_resistance_power_stderr_W"
    assert float(e) == 0.01 and e.attrs["units"] == "W" and "standard_name" not in e.attrs
    assert e.attrs["long_name"] == "standard error of the mean rolling-resistance power loss"
    s, se = variables["toy_speed"], variables["toy_speed_stderr"]
    assert s.attrs["standard_name"] == "platform_speed_wrt_ground"
    assert se.attrs["standard_name"] == "platform_speed_wrt_ground standard_error"


def test_an_error_without_its_statistic_is_no_dangling_link():
    variables, _ = rv.split_results({"cage_slip_ratio": 0.01})
    assert "ancillary_variables" not in variables["cage_slip_ratio"].attrs


def _old_numbers() -> tuple[dict, list]:
    """The old file's global attributes and its power-loss dimensions, as netCDF4 reads them."""
    with netCDF4.Dataset(OLD) as nc:
        return ({k: nc.getncattr(k) for k in nc.ncattrs()},
                list(nc.variables["power_loss_W"].dimensions))


def test_a_file_of_the_older_format_reads_as_the_current_one():
    attrs, dims = _old_numbers()
    assert dims == ["time", "source"] and "mean_cage_speed_rad_s" in attrs  # really old
    kind, ds = open_result(OLD)
    assert kind == "run" and ds.power_loss_W.dims == ("time", "loss_source")
    for name in ("mean_cage_speed_rad_s", "cage_slip_ratio", "skew_rms_rad",
                 "reference_rating_life_L10r_Mrev", "radial_load_N", "record_start_s"):
        assert ds[name].ndim == 0 and ds[name].attrs["units"], name
        assert ds[name].item() == attrs[name], name
        assert name not in ds.attrs
    se = ds[ds.mean_cage_speed_rad_s.attrs["ancillary_variables"]]
    assert se.item() == attrs["mean_cage_speed_stderr_rad_s"]
    f = json.loads(attrs["characteristic_frequencies_Hz"])
    got = ds.characteristic_frequencies_Hz
    assert got.dims == ("frequency_name",) and list(got.frequency_name.values) == list(f)
    assert np.array_equal(got.values, list(f.values()))
    assert not rv.result_names() & set(ds.attrs)


def test_the_summary_reads_an_old_file():
    """The summary lines (rating life, power loss) read the variables an old file becomes."""
    from bearingdae.analysis.engineering import summary_lines

    attrs, _ = _old_numbers()
    _, ds = open_result(OLD)
    lines = summary_lines(ds)
    life = attrs["reference_rating_life_L10r_Mrev"]
    assert any(line.startswith("rating life L10r") and f"{life:.4g}" in line for line in lines)
    with netCDF4.Dataset(OLD) as nc:
        total = float(np.mean(np.sum(nc.variables["power_loss_W"][:], axis=1)))
    assert any(line.startswith("power loss (mean)") and f"{total:.4g} W" in line
               for line in lines)


def test_an_old_file_that_cannot_be_converted_says_so_in_one_line(tmp_path):
    bad = tmp_path / "bad.nc"
    import shutil

    shutil.copyfile(OLD, bad)
    with netCDF4.Dataset(bad, "a") as nc:
        nc.setncattr("characteristic_frequencies_Hz", "{not json")
    with pytest.raises(ValueError) as err:
        open_result(bad)
    message = str(err.value)
    assert "\n" not in message and "older bearingdae format" in message


@pytest.mark.parametrize("value", ["not a number", "1.5"])
def test_a_current_file_with_one_stray_result_attribute_is_damaged_not_old(tmp_path, value):
    """A file whose results are variables is of the current format: a result-named global
    attribute beside them (a damaged or hand-edited file) is named as such, not called "an
    older bearingdae format"; the old file itself still reads."""
    from bearingdae.results.readers import ResultFileError

    _, ds = open_result(OLD)
    current = tmp_path / "current.nc"
    ds.to_netcdf(current)
    assert open_result(current)[0] == "run"
    with netCDF4.Dataset(current, "a") as nc:
        nc.setncattr("mean_cage_speed_rad_s", value)
    with pytest.raises(ResultFileError) as info:
        open_result(current)
    msg = str(info.value)
    assert "older" not in msg and "is damaged" in msg and "mean_cage_speed_rad_s" in msg
    assert len(msg.splitlines()) == 1
    assert rv.is_old_format(xr.open_dataset(OLD))
