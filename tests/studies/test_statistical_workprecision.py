"""Statistical work-precision (studies/workprecision/statistical.py): the adequacy rule on
numbers whose answer is known, and the study end to end on a short run through the CLI."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from bearingdae import load_scene, simulate
from bearingdae.studies.workprecision import statistical as sw
from fuzzing import run_cli


def _table(values, errors, se_default, rtols=(1e-4, 1e-5, 1e-6, 1e-7, 1e-8)):
    values = np.asarray(values, float)[:, None]
    errors = np.asarray(errors, float)[:, None]
    n = len(rtols)
    nan = np.full(n, np.nan)
    scene = load_scene("yang20_baseline")
    return sw._table(scene, list(rtols), ["mean_cage_speed_rad_s"], values, errors,
                     np.array([se_default]), nan, nan, nan, nan, ["ok"] * n, 1e-6, 3.0)


def test_rule_rejects_a_bias_beyond_the_default_error_and_picks_the_loosest_adequate_rung():
    # the default run's SE is 0.02: 0.05 at 1e-4 exceeds it, 0.015 at 1e-5 does not
    ds = _table([95.05, 95.015, 95.0, 95.0, 95.0], [0.01] * 5, 0.02)
    assert ds.adequate.values.tolist() == [0, 1, 1, 1, 1]
    assert ds.attrs["chosen_rtol"] == 1e-5
    assert ds.difference.sel(rtol=1e-4).item() == pytest.approx(0.05)
    assert ds.difference_standard_error.sel(rtol=1e-4).item() == pytest.approx(0.01 * 2**0.5)


def test_an_inadequate_tighter_rung_blocks_the_looser_ones():
    # 1e-4 agrees by chance, 1e-6 carries a resolved bias: nothing looser than 1e-7 is chosen
    ds = _table([95.0, 95.0, 95.06, 95.0, 95.0], [0.01] * 5, 0.02)
    assert ds.adequate.values.tolist() == [1, 1, 0, 1, 1]
    assert ds.attrs["chosen_rtol"] == 1e-7


def test_labels_say_reference_and_not_judged_when_the_record_has_no_error_bar():
    """A record too short for a standard error of the default run judges no rung: the
    tightest is labelled the reference, the others 'not judged' (never 'biased'), and the
    chosen line says what to raise."""
    ds = _table([95.05, 95.015, 95.0, 95.0, 95.0], [np.nan] * 5, np.nan)
    lines = sw.summary_lines(ds)
    labels = [line.split()[4] for line in lines[:5]]
    assert labels == ["not", "not", "not", "not", "reference"]
    assert all("not judged" in line for line in lines[:4])
    assert "too short" in lines[-1] and "--revolutions" in lines[-1]
    judged = sw.summary_lines(_table([95.05, 95.015, 95.0, 95.0, 95.0], [0.01] * 5, 0.02))
    assert [line.split()[4] for line in judged[:5]] == ["biased", "adequate", "adequate",
                                                        "adequate", "reference"]


def test_study_end_to_end_through_the_cli(tmp_path):
    rc, out, err = run_cli(["workprecision", "--statistics", "--set",
                            "numerics.cage_revolutions=0.05", "--set",
                            "numerics.warmup_cage_revolutions=0", "--no-progress",
                            "-o", str(tmp_path)])
    assert rc == 0, err
    assert "chosen rtol:" in out
    ds = xr.open_dataset(tmp_path / "yang20_baseline_statistics.nc")
    assert list(ds.rtol.values) == list(sw.STATISTICS_RTOLS)
    assert (ds.steps.diff("rtol") > 0).all()  # tighter tolerance, more steps
    assert np.isfinite(ds.value).all() and (ds.difference.sel(rtol=1e-8) == 0).all()
    # the yardstick is the default run's own error bar: the default-rtol run's first record
    # takes the same steps as the default run (samples do not change IDA's steps)
    assert ds.attrs["cage_revolutions"] == 4 * 0.05
    default = simulate(load_scene("yang20_baseline", {"numerics.cage_revolutions": 0.05,
                                                      "numerics.warmup_cage_revolutions": 0}),
                       progress=False)
    se = ds.default_run_standard_error
    assert se.sel(statistic="mean_cage_speed_rad_s").item() == \
        default["mean_cage_speed_stderr_rad_s"].item()
    assert se.sel(statistic="skew_rms_rad").item() == default["skew_rms_stderr_rad"].item()
    assert (tmp_path / "yang20_baseline_statistics.png").stat().st_size > 0
    rows = len(sw.STATISTICS_RTOLS) * len(sw.STATISTICS)
    assert (tmp_path / "yang20_baseline_statistics.csv").read_text().count("\n") == 1 + rows


def test_a_statistic_at_the_integration_floor_is_not_a_bias():
    # the skew RMS of a bearing without moment is ~1e-13 rad: differences at that level are
    # integration noise below the default run's atol in radians (1e-11), not a bias
    rtols = (1e-5, 1e-6, 1e-7)
    scene = load_scene("yang20_baseline")
    values = np.array([[7e-14], [5e-14], [2e-14]])
    errors = np.full((3, 1), 1e-15)
    nan = np.full(3, np.nan)
    args = (scene, list(rtols), ["skew_rms_rad"], values, errors, np.array([1e-15]), nan, nan,
            nan, nan, ["ok"] * 3, 1e-6, 3.0)
    assert sw._table(*args).adequate.values.tolist() == [0, 0, 1]  # without a floor
    ds = sw._table(*args, floor=[1e-11])
    assert ds.adequate.values.tolist() == [1, 1, 1] and ds.attrs["chosen_rtol"] == 1e-5
