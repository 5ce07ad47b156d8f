"""``bearingdae spectrum RUN.nc`` under any option value and on damaged files: exit 0 with a
table, or exit 2 with one line ``bearingdae: error:``; never a traceback or a NumPy warning.
The run file is a synthetic one (tests/analysis/test_spectrum_peaks.py) so that the cases stay
fast."""

from __future__ import annotations

import collections
import warnings

import numpy as np
import pytest
import xarray as xr
from hypothesis import given
from hypothesis import strategies as st

from fuzzing import fuzz, run_cli
from tests.analysis.test_spectrum_peaks import BPFO, synthetic

COUNTS: collections.Counter = collections.Counter()


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("table") / "run.nc"
    synthetic(BPFO).isel(time=slice(0, 4000)).assign_attrs(
        Conventions="CF-1.10", bearingdae_version="test").to_netcdf(path)
    return path


def table_case(path, surface: str, argv: list[str]) -> tuple[int, str, str]:
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a NumPy warning would be a failure
        rc, out, err = run_cli(["spectrum", str(path), *argv])
    assert "Traceback" not in out + err
    assert rc in (0, 2), (rc, err)
    if rc == 2:
        lines = err.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("bearingdae: error: ") and out == "", err
    else:
        assert "frequency [Hz]" in out or "no peak" in out, out
    COUNTS[surface, f"exit {rc}"] += 1
    return rc, out, err


numbers = st.one_of(st.integers(-5, 50).map(str), st.sampled_from(
    ["0", "1e3", "nan", "inf", "-inf", "", "2.5", "x", "1e400", "3,4", " 7"]))


@fuzz(16)
@given(peaks=numbers, fmax=st.one_of(st.none(), st.sampled_from(
    ["50", "0", "-1", "nan", "inf", "1e9", "400"])), envelope=st.booleans(),
    band=st.one_of(st.none(), st.sampled_from(["2000,4000", "4000,2000", "1,2", "a,b", "5",
                                               "0,1e9", "nan,3"])))
def test_any_option_values(run_file, peaks, fmax, envelope, band):
    argv = ["--peaks", peaks] + (["--fmax", fmax] if fmax is not None else [])
    argv += (["--envelope"] if envelope else []) + (["--band", band] if band else [])
    try:
        rc, _, _ = table_case(run_file, "options", argv)
    except SystemExit as exc:  # argparse: --fmax is a float option
        assert exc.code == 2
        COUNTS["options", "argparse"] += 1
        return
    ok_peaks = peaks.strip().lstrip("-").isdigit() and int(peaks) >= 1
    if not ok_peaks:
        assert rc == 2


@fuzz(6)
@given(edit=st.sampled_from(["no frequencies", "nan value", "one sample", "reversed time",
                             "no ring", "text frequencies"]))
def test_damaged_files(run_file, tmp_path_factory, edit):
    ds = xr.load_dataset(run_file)
    if edit == "no frequencies":
        ds = ds.drop_vars(["characteristic_frequencies_Hz", "frequency_name"])
    elif edit == "nan value":
        v = ds.ring_acceleration.values.copy()
        v[10, 1] = np.nan
        ds["ring_acceleration"] = (ds.ring_acceleration.dims, v, ds.ring_acceleration.attrs)
    elif edit == "one sample":
        ds = ds.isel(time=slice(0, 1))
    elif edit == "reversed time":
        ds["time"] = ds.time.values[::-1].copy()
    elif edit == "no ring":
        ds = ds.drop_vars("ring_acceleration")
    else:
        ds["characteristic_frequencies_Hz"] = ("frequency_name",
                                               np.array(["a"] * ds.sizes["frequency_name"]))
    path = tmp_path_factory.mktemp("damaged") / "edited.nc"
    ds.to_netcdf(path)
    rc, out, _ = table_case(path, "damaged file", ["--envelope", "--peaks", "3"])
    if edit == "no frequencies":
        rows = [line for line in out.splitlines()
                if line.split()[0].isdigit() and line.split()[-1] == "unmatched"]
        assert rc == 0 and len(rows) == 3, out
    else:
        assert rc == 2, edit


def test_zz_summary():
    """Both outcomes were seen on the option surface, and every damaged file was refused or
    read without its orders."""
    if not COUNTS:
        pytest.skip("no spectrum-table case ran in this session")
    print("\n\nspectrum table fuzzing:", dict(COUNTS))
    assert COUNTS["options", "exit 0"] >= 1 and COUNTS["options", "exit 2"] >= 1
    assert sum(v for (s, _), v in COUNTS.items() if s == "damaged file") >= 4
