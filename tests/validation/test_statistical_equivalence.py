"""Statistical equivalence of a long baseline run with the documented statistics.

Why statistical: the skew of the baseline is chaotic, so a change of the kernels' round-off
(e.g. the vectorised exp/log of physics/elementary.py) changes single trajectories after a few
revolutions; what must not change is their statistics. Reference: docs/performance.md,
"Same answers": the same run (baseline, IDA rtol 1e-6, 1 + 24 cage revolutions) with
the kernels before the change (commit cbeb403), as mean ± standard error. (The 40-revolution
statistics of docs/theory.md, "Newmark-β", skew RMS 0.710 mrad, were taken with
the pocket smoothing of that time, 0.1 µm; since the default became 0.01 µm the same kernels
give 0.517 mrad, so they are no reference for today's model; the 3-revolution amplitude,
2.796 ± 0.032 mrad there, barely moved: 2.843 ± 0.025.)

Tolerance: 3 combined standard errors, sqrt(se_run² + se_doc²) (a ~0.3 % false-alarm rate for
each unbiased comparison), with batch-means standard errors over revolutions (RMS) and over
3-revolution windows (amplitude, slice loads, cage speed) as in benchmarks/skew_statistics.py.

Run ``python tests/validation/test_statistical_equivalence.py [REVS]`` to print the statistics of any
checkout (the numbers behind docs/performance.md).
"""

from __future__ import annotations

import json
import sys

import numpy as np
import pytest

WARMUP_REVS = 1
REVS = 24  # 8 windows of 3 cage revolutions
PER_REV = 200  # the scene default

# docs/performance.md, "Same answers": 1 + 24 revolutions with the kernels before
# the change (commit cbeb403), mean ± standard error: skew RMS over 24 revolutions, and over
# the 8 windows of 3 revolutions the skew amplitude, each window's largest inner- and
# outer-race slice load and its mean cage speed
DOC_SKEW_RMS_MRAD = (0.5165, 0.0051)
DOC_AMPLITUDE_MRAD = (2.843, 0.025)
DOC_INNER_SLICE_MAX_N = (54.09157, 0.00045)
DOC_OUTER_SLICE_MAX_N = (54.14245, 0.00045)
DOC_CAGE_SPEED_RAD_S = (95.05240, 0.0013)


def _mean_se(x):
    """Mean and batch-means standard error, widened for a positive lag-1 correlation."""
    x = np.asarray(x, float)
    rho = np.corrcoef(x[:-1], x[1:])[0, 1] if x.size > 3 else 0.0
    rho = 0.0 if not np.isfinite(rho) else rho
    widen = np.sqrt((1 + max(rho, 0.0)) / (1 - min(max(rho, 0.0), 0.9)))
    return float(x.mean()), float(x.std(ddof=1) / np.sqrt(x.size) * widen)


def long_run_statistics(revs: int = REVS) -> dict:
    """Baseline, 1 warm-up + ``revs`` cage revolutions, IDA at the scene's rtol 1e-6."""
    from bearingdae import load_scene, simulate

    scene = load_scene("yang20_baseline", {"numerics.cage_revolutions": float(revs)})
    return run_statistics(scene, simulate(scene, progress=False))


def run_statistics(scene, ds) -> dict:
    """The statistics of the recorded window of ``ds`` (a run of the baseline ``scene``
    recorded after WARMUP_REVS, at PER_REV samples per revolution)."""
    dyn = scene.dynamics
    assert dyn.warmup_cage_revolutions == WARMUP_REVS
    assert dyn.samples_per_cage_revolution == PER_REV
    revs = round(dyn.cage_revolutions)
    assert ds.attrs["solver_status"] == "completed", ds.attrs["solver_status"]
    assert ds.sizes["time"] == revs * PER_REV + 1
    skew = np.abs(ds.skew_angle.transpose("time", "roller").values) * 1e3  # mrad
    cage = ds.cage_speed.values
    # each sample's largest slice load of each race, over rollers and slices
    loads = ds.contact_force.max(("roller", "slice")).transpose("time", "race")
    loads = loads.sel(race=["inner", "outer"]).values
    rms = [np.sqrt((skew[b * PER_REV:(b + 1) * PER_REV] ** 2).mean()) for b in range(revs)]
    n = 3 * PER_REV
    windows = range(revs // 3)
    amp = [skew[w * n:(w + 1) * n + 1].max(0).mean() for w in windows]
    inner = [loads[w * n:(w + 1) * n + 1, 0].max() for w in windows]
    outer = [loads[w * n:(w + 1) * n + 1, 1].max() for w in windows]
    speed = [cage[w * n:(w + 1) * n].mean() for w in windows]
    return {"skew_rms_mrad": _mean_se(rms), "amplitude_mrad": _mean_se(amp),
            "amplitude_sd_rel": float(np.std(amp, ddof=1) / np.mean(amp)),
            "inner_slice_max_N": _mean_se(inner), "outer_slice_max_N": _mean_se(outer),
            "cage_speed_rad_s": _mean_se(speed), "windows": len(amp),
            "steps_message": ds.attrs["solver_status"]}


def _within(run, doc, k=3.0):
    (mu, se), (mu0, se0) = run, doc
    tol = k * np.hypot(se, se0)
    return abs(mu - mu0) <= tol, f"{mu:.5g} ± {se:.2g} against {mu0:.5g} ± {se0:.2g} (tol {tol:.2g})"


@pytest.fixture(scope="module")
def stats(long_baseline):
    """The statistics of the long baseline run, shared with test_newmark.py and
    test_cage_whirl.py (computed once per session: tests/conftest.py)."""
    scene, ds = long_baseline
    assert scene.dynamics.cage_revolutions == REVS
    s = run_statistics(scene, ds)
    print(json.dumps(s))  # the numbers behind docs/performance.md (pytest -s)
    return s


@pytest.mark.slow
def test_skew_statistics_match_the_documented_long_run(stats):
    assert stats["windows"] >= 8
    ok, msg = _within(stats["skew_rms_mrad"], DOC_SKEW_RMS_MRAD)
    assert ok, "skew RMS " + msg
    ok, msg = _within(stats["amplitude_mrad"], DOC_AMPLITUDE_MRAD)
    assert ok, "3-revolution skew amplitude " + msg


@pytest.mark.slow
def test_cage_speed_and_slice_load_extremes_match_the_documented_run(stats):
    ok, msg = _within(stats["cage_speed_rad_s"], DOC_CAGE_SPEED_RAD_S)
    assert ok, "mean cage speed " + msg
    for key, doc in (("inner_slice_max_N", DOC_INNER_SLICE_MAX_N),
                     ("outer_slice_max_N", DOC_OUTER_SLICE_MAX_N)):
        ok, msg = _within(stats[key], doc)
        assert ok, key + " " + msg


if __name__ == "__main__":
    print(json.dumps(long_run_statistics(int(sys.argv[1]) if len(sys.argv) > 1 else REVS),
                     indent=1))
