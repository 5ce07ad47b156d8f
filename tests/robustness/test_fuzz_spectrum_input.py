"""``plot RUN.nc --spectrum`` on damaged run files: the characteristic frequencies of a file of
the older format (a JSON attribute) any JSON (or none), a time axis with a stray sample far away, non-finite values. The contract:
exit 0, or exit 2 with one line ``bearingdae: error:``; never a traceback or a NumPy warning;
memory bounded (the equal-step resampling is refused before it allocates); and a figure that
fails to draw is closed (pyplot holds no figure after the command).
"""

from __future__ import annotations

import collections
import json
import tracemalloc
import warnings

import numpy as np
import pytest
import xarray as xr
from hypothesis import given
from hypothesis import strategies as st

from bearingdae import load_scene, save, simulate
from fuzzing import fuzz, run_cli

COUNTS: collections.Counter = collections.Counter()
#: the most a spectrum of this small file may allocate (it is 61 samples; the stray sample of
#: the unchecked resampling asked for 7.3 GB)
PEAK_BYTES = 64 << 20


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    d = tmp_path_factory.mktemp("spectrum")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = simulate(load_scene("yang20_baseline", {
            "physics.ring": "dynamic", "numerics.warmup_cage_revolutions": 0.0,
            "numerics.cage_revolutions": 0.3}))
    return save(ds, d / "run.nc")


def spectrum_case(run_file, surface: str, edit, traced: bool = False) -> tuple[int, str]:
    """The command on the edited file, checked against the contract (module docstring);
    ``traced``: its peak memory too (tracemalloc slows drawing several times)."""
    import matplotlib.pyplot as plt

    ds = xr.load_dataset(run_file)
    ds = edit(ds) or ds  # (an edit that makes another Dataset returns it)
    p = run_file.with_name("edited.nc")
    ds.to_netcdf(p)
    figures = set(plt.get_fignums())
    if traced:
        tracemalloc.start()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # a NumPy warning would be a failure
            rc, stdout, stderr = run_cli(["plot", str(p), "--spectrum"])
        peak = tracemalloc.get_traced_memory()[1] if traced else 0
    finally:
        if traced:
            tracemalloc.stop()
    assert "Traceback" not in stdout + stderr
    assert peak < PEAK_BYTES, peak
    assert set(plt.get_fignums()) == figures  # drawn and closed, or failed and closed
    assert rc in (0, 2), (rc, stderr)
    if rc == 2:
        lines = stderr.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("bearingdae: error: "), stderr
    COUNTS[surface, f"exit {rc}"] += 1
    return rc, stderr


json_values = st.recursive(
    st.one_of(st.none(), st.booleans(), st.integers(-10**6, 10**6), st.text(max_size=5),
              st.floats(allow_nan=False, allow_infinity=False)),
    lambda inner: st.one_of(st.lists(inner, max_size=3),
                            st.dictionaries(st.text(max_size=8), inner, max_size=4)),
    max_leaves=6)


@fuzz(12)
@given(value=st.one_of(json_values.map(json.dumps),
                       st.sampled_from(["", "{", "NaN", '{"cage": NaN}', '{"cage": Infinity}',
                                        "[" * 5000 + "]" * 5000, '{"cage": 1e400}'])))
def test_characteristic_frequencies_of_any_json(run_file, value):
    # as a file of the older format held them (a JSON attribute; analysis/result_variables.py):
    # no result variable at all (a current file with a result attribute is damaged)
    from bearingdae.analysis.result_variables import result_names

    rc, _ = spectrum_case(run_file, "characteristic_frequencies_Hz",
                          lambda ds: ds.drop_vars([n for n in result_names() | {"frequency_name"}
                                                   if n in ds.variables]).assign_attrs(
                              characteristic_frequencies_Hz=value))
    parsed = None
    try:
        parsed = json.loads(value)
    except (ValueError, RecursionError):
        pass
    good = isinstance(parsed, dict) and all(
        isinstance(v, (int, float)) and not isinstance(v, bool) and np.isfinite(v)
        for v in parsed.values())
    assert rc == (0 if good else 2), (value, rc)


@fuzz(8)
@given(sample=st.integers(0, 60), shift_s=st.sampled_from([1e5, 1.0, -1.0, 0.0, np.nan, 1e-9]))
def test_time_axis_with_a_stray_sample(run_file, sample, shift_s):
    def edit(ds):
        t = ds.time.values.copy()
        t[sample] = t[sample] + shift_s if np.isfinite(shift_s) else shift_s
        ds["time"] = t
    spectrum_case(run_file, "time axis", edit, traced=shift_s == 1e5)


def test_one_sample_far_away_is_refused_in_bounded_memory(run_file):
    def edit(ds):
        t = ds.time.values.copy()
        t[-1] = t[-2] + 1e5  # the resampling onto equal steps would need 7.3 GB
        ds["time"] = t
    rc, stderr = spectrum_case(run_file, "time axis", edit, traced=True)
    assert rc == 2 and "equal steps" in stderr, stderr


@fuzz(4)
@given(value=st.sampled_from([np.inf, -np.inf, np.nan]), sample=st.integers(0, 60),
       name=st.sampled_from(["ring_displacement", "ring_acceleration"]))
def test_non_finite_values(run_file, value, sample, name):
    def edit(ds):
        v = ds[name].values.copy()
        v[sample, 0] = value
        ds[name] = (ds[name].dims, v, ds[name].attrs)
    rc, stderr = spectrum_case(run_file, "non-finite values", edit)
    assert rc == 2 and "finite values" in stderr, stderr


def test_zz_summary():
    """Cases per surface and outcome (``pytest -s``): each surface ran, both outcomes seen."""
    if not COUNTS:
        pytest.skip("no spectrum test ran in this session")
    print("\n\nspectrum input fuzzing:", dict(COUNTS))
    surfaces = {s for s, _ in COUNTS}
    if surfaces == {"characteristic_frequencies_Hz", "time axis", "non-finite values"}:
        assert COUNTS["characteristic_frequencies_Hz", "exit 0"] >= 1
        assert COUNTS["characteristic_frequencies_Hz", "exit 2"] >= 3
        assert COUNTS["time axis", "exit 2"] >= 1
        assert COUNTS["non-finite values", "exit 2"] == 4
