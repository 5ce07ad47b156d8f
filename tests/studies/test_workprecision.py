"""Work-precision study: error metrics, the nested scipy peers, the CLI output."""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest

from bearingdae import ScipyPeer, simulate
from bearingdae.studies import workprecision as wp
from bearingdae.cli import main

from conftest import make_scene

SHORT = {"numerics.warmup_cage_revolutions": 0.0, "numerics.samples_per_cage_revolution": 100}
#: the baseline scene's operating point (cases/yang20_baseline.toml)
BASELINE = {"operating": {"speed_rpm": 2000.0, "radial_load_N": 800.0, "moment_Nm": 3.0},
            "numerics": {"slices": 10}}


# ---- metrics on synthetic data (analytic answers) -------------------------------------------
def test_relative_errors_of_scaled_and_offset_signals():
    """ref = 2 + sin t over whole periods: rms(ref) = sqrt(4 + 1/2) exactly on a uniform grid;
    sol = (1 + e) ref has relative RMS and max error e; sol = ref + d has RMS error d and max
    error d / 3."""
    t = np.linspace(0.0, 4 * np.pi, 400, endpoint=False)
    ref = 2.0 + np.sin(t)
    rms, mx = wp.relative_errors(ref * (1 + 1e-3), ref)
    assert rms == pytest.approx(1e-3, rel=1e-9) and mx == pytest.approx(1e-3, rel=1e-9)
    rms, mx = wp.relative_errors(ref + 0.01, ref)
    assert rms == pytest.approx(0.01 / math.sqrt(4.5), rel=1e-9)
    assert mx == pytest.approx(0.01 / 3.0, rel=1e-6)  # max |ref| = 3 at a grid point sin = 1


def test_relative_errors_over_all_elements_of_a_field():
    """A (time, roller) field with the error on one roller only: rms over all elements."""
    ref = np.ones((10, 4))
    sol = ref.copy()
    sol[:, 2] += 0.2
    rms, mx = wp.relative_errors(sol, ref)
    assert rms == pytest.approx(math.sqrt(0.04 / 4)) and mx == pytest.approx(0.2)
    assert all(math.isnan(x) for x in wp.relative_errors(sol, np.zeros_like(ref)))


def test_mescd_analytic():
    """sol = (1 + e) ref: max e|ref| / (floor + |ref|) is reached at the largest |ref| = 3:
    mescd = -log10(3e / (floor + 3)); identical arrays give +inf."""
    ref = np.array([-1.0, 0.5, 3.0, 2.0])
    e, floor = 1e-4, 1e-2
    assert wp.mescd(ref * (1 + e), ref, floor) == pytest.approx(-math.log10(3 * e / (floor + 3)))
    assert wp.mescd(ref, ref, floor) == math.inf
    # an absolute error on a zero reference is measured against the floor
    assert wp.mescd(np.array([1e-5]), np.array([0.0]), 1e-2) == pytest.approx(3.0)


def test_interp_time_is_exact_for_linear_signals_and_identity_on_the_same_grid():
    t_ref = np.linspace(0.0, 1.0, 11)
    values = np.stack([3.0 * t_ref - 1.0, -t_ref], axis=1)
    t = np.array([0.0, 0.05, 0.333, 0.999, 1.0])
    got = wp.interp_time(t_ref, values, t)
    assert np.allclose(got, np.stack([3.0 * t - 1.0, -t], axis=1), atol=1e-14)
    assert wp.interp_time(t_ref, values, t_ref.copy()) is values


def test_time_at_error_on_a_power_law_and_its_pareto_front():
    """t = e^(-1/2): log-log interpolation is exact between rungs; a dominated run (slower and
    less accurate) is ignored; outside the ladder the kind says which bound it is."""
    errs = np.array([1e-2, 1e-4, 1e-6, 1e-8])
    times = errs ** -0.5
    t, kind = wp.time_at_error(errs, times, 1e-5)
    assert kind == "interpolated" and t == pytest.approx(10 ** 2.5, rel=1e-12)
    t, _ = wp.time_at_error(list(errs) + [1e-3], list(times) + [1e9], 1e-5)  # dominated extra run
    assert t == pytest.approx(10 ** 2.5, rel=1e-12)
    assert wp.time_at_error(errs, times, 1e-10) == (1e4, "not reached")
    assert wp.time_at_error(errs, times, 1.0) == (10.0, "below ladder")
    t, kind = wp.time_at_error([math.nan], [1.0], 1e-3)
    assert math.isnan(t) and kind == "no runs"


def _run(solver, value, err, wall, **kw):
    r = wp.Run(solver, "rtol", value, rtol=value, wall_s=wall, **kw)
    r.errors = {"cage_speed_rel_rms": err}
    return r


def test_comparison_verdicts():
    """IDA-1e-6 at error 1e-6 in 1 s. A peer whose power law passes (1e-6, 30 s) -> ratio 30
    (met); one at (1e-6, 4 s) -> 4 (not met); one that never reaches 1e-6 before its time limit
    -> lower bound = the limit. No verdict when the reference floor is within 10x of 1e-6."""
    ida = [_run("ida", 1e-6, 1e-6, 1.0), _run("ida", 1e-10, 0.0, 9.0, is_reference=True)]
    slow = [_run("scipy-BDF", 1e-4, 1e-4, 3.0), _run("scipy-BDF", 1e-8, 1e-8, 300.0)]
    st = wp.Study("t", ida + slow, ida[1], {"cage_speed_rel_rms": 1e-9}, {}, 50.0, 1, {})
    c = wp.comparison(st)
    assert c["peers"]["scipy-BDF"]["ratio"] == pytest.approx(30.0) and c["verdict"] == "met"
    fast = [_run("scipy-LSODA", 1e-4, 1e-4, 0.4), _run("scipy-LSODA", 1e-8, 1e-8, 40.0)]
    st.runs = ida + slow + fast
    c = wp.comparison(st)
    assert c["peers"]["scipy-LSODA"]["ratio"] == pytest.approx(4.0)
    assert c["verdict"] == "not met" and c["best_peer"] == "scipy-LSODA"
    capped = [_run("scipy-Radau", 1e-4, 1e-4, 20.0),
              _run("scipy-Radau", 1e-5, math.nan, math.nan, status="failed",
                   message="time limit of 50 s wall exceeded")]
    st.runs = ida + slow + capped
    c = wp.comparison(st)
    radau = c["peers"]["scipy-Radau"]
    assert radau["ratio"] == pytest.approx(50.0) and radau["bound"] == ">="
    assert radau["kind"] == "not reached within the time limit" and c["verdict"] == "met"
    # the same numbers, but the reference's own floor is close to IDA-1e-6's error: unresolved
    st.floor = {"cage_speed_rel_rms": 3e-7}
    c = wp.comparison(st)
    assert c["verdict"] == "undetermined" and "floor" in c["note"]


# ---- the nested scipy path against IDA -------------------------------------------------------
# Budgets (counts, not time): mean kernel evaluations per right-hand-side call of the inner
# Newton. Measured 2.8 / 4.5 / 4.0; without the linear predictor of z they were 3.6 / 5.7 / 4.8.
@pytest.fixture(scope="module")
def ida_tenth():
    """IDA over 0.1 cage revolution of the baseline: the reference of the three peers (one run
    for the three cases; each compares its own peer's run with it and changes nothing)."""
    scene = make_scene({**SHORT, "numerics.cage_revolutions": 0.1}, **BASELINE)
    return scene, simulate(scene)


@pytest.mark.parametrize("solver, evals_per_rhs", [("scipy-BDF", 3.3), ("scipy-Radau", 5.1),
                                                   ("scipy-LSODA", 4.5)])
def test_nested_peer_reproduces_ida(ida_tenth, solver, evals_per_rhs):
    """Reference: IDA on the same scene (an independent integrator of the full DAE, the
    algebraic unknowns inside its own Newton). The nested path (algebraic unknowns by an inner
    Newton per right-hand side) must give the same trajectory: cage speed to 1e-4 relative
    (measured ~1e-7 at rtol 1e-6), the cage's deceleration from the epicyclic start (~0.8 rad/s
    over 0.1 revolution) to 1e-3 of itself, skew to 1e-3 and slice forces to 1e-6 (rel. RMS).
    The inner Newton stays within its evaluation budget."""
    scene, ida = ida_tenth
    peer = simulate(scene, solver=solver)
    assert peer.attrs["solver"].startswith("scipy")
    np.testing.assert_array_equal(peer.time.values, ida.time.values)
    c_ref = ida.cage_speed.values
    assert wp.relative_errors(peer.cage_speed.values, c_ref)[0] < 1e-4
    change = c_ref - c_ref[0]
    assert np.abs(change).max() > 0.1  # the window does contain dynamics
    assert np.abs(peer.cage_speed.values - c_ref[0] - change).max() < 1e-3 * np.abs(change).max()
    assert wp.relative_errors(peer.skew_angle.values, ida.skew_angle.values)[0] < 1e-3
    assert wp.relative_errors(peer.contact_force.values, ida.contact_force.values)[0] < 1e-6
    stats = json.loads(peer.attrs["solver_statistics"])
    assert stats["residual_calls"] / stats["rhs_calls"] < evals_per_rhs


def test_peer_time_limit_keeps_samples_and_reports_failure():
    """A wall-time limit stops the peer cleanly: SimulationError with the message and the
    samples computed before (here none of the recorded window)."""
    from bearingdae import SimulationError

    scene = make_scene({**SHORT, "numerics.cage_revolutions": 0.05}, **BASELINE)
    with pytest.raises(SimulationError, match="time limit"):
        simulate(scene, solver=ScipyPeer("BDF", time_limit_s=1e-9))


def test_unknown_solver_is_refused():
    with pytest.raises(ValueError, match="scipy-BDF"):
        simulate(make_scene(SHORT), solver="scipy-RK45")


# ---- study, failed rows, CLI -----------------------------------------------------------------
def test_failed_and_skipped_runs_are_rows():
    """A rung that raises (bad solver option) is a failed row with its message; after a rung
    exceeds the time limit, tighter rungs are skipped rows, not dropped."""
    scene = make_scene({**SHORT, "numerics.cage_revolutions": 0.02}, **BASELINE)
    bad = wp.Ladder("scipy-BDF", "rtol", (1e-4,),
                    lambda r: (wp.tolerance_overrides(r), {"jac": "bogus"}))
    (row,) = wp.run_ladder(scene, bad, repeat=2, time_limit_s=None)
    assert row.status == "failed" and "bogus" in row.message and len(row.walls_s) == 1
    capped = wp.Ladder("scipy-LSODA", "rtol", (1e-4, 1e-5, 1e-6),
                       lambda r: (wp.tolerance_overrides(r), {}), timed_limit=True)
    rows = wp.run_ladder(scene, capped, repeat=1, time_limit_s=1e-9)
    assert [r.status for r in rows] == ["failed", "skipped", "skipped"]
    assert "time limit" in rows[0].message and "exceeded the time limit" in rows[1].message
    assert all(r.time_limit_s == 1e-9 for r in rows)


def test_cli_writes_table_and_png(tmp_path, capsys):
    """`bearingdae workprecision --quick` on a tiny window: NetCDF, CSV (one row per rung, the
    reference flagged, errors of the others finite) and PNG; with a tiny time limit the peers
    are failed rows with their message. The baseline's start-state finding (film parameter
    below 1), the same in every run of the ladder, prints once."""
    import xarray as xr

    args = ["workprecision", "yang20_baseline", "-o", str(tmp_path), "--quick", "--repeat", "1",
            "--no-progress", "--revolutions", "0.02"]
    assert main(args) == 0
    err = capsys.readouterr().err
    assert err.count("warning: film parameter") == 1, err[-2000:]
    stem = tmp_path / "yang20_baseline_workprecision"
    rows = list(csv.DictReader(open(f"{stem}.csv")))
    n_rungs = (len(wp.QUICK_IDA_RTOLS) + len(wp.QUICK_NEWMARK_STEPS_S)
               + len(wp.PEERS) * len(wp.QUICK_PEER_RTOLS))
    assert len(rows) == n_rungs
    assert all(r["status"] == "ok" for r in rows)
    ref = [r for r in rows if r["is_reference"] == "1"]
    assert len(ref) == 1 and ref[0]["solver"] == "ida"
    assert float(ref[0]["rtol"]) == min(wp.QUICK_IDA_RTOLS)
    others = [r for r in rows if r["is_reference"] == "0"]
    assert all(float(r["cage_speed_rel_rms"]) > 0 and float(r["wall_s"]) > 0 for r in others)
    assert stem.with_suffix(".png").stat().st_size > 10_000
    ds = xr.open_dataset(f"{stem}.nc")
    assert ds.sizes["run"] == n_rungs and "reference" in ds.attrs
    window = json.loads(ds.attrs["scene_overrides"])
    assert window["numerics.cage_revolutions"] == 0.02
    assert window["numerics.warmup_cage_revolutions"] == 0.0
    ds.close()

    assert main(args + ["--time-limit-factor", "1e-9", "--solvers", "scipy-LSODA"]) == 0
    rows = list(csv.DictReader(open(f"{stem}.csv")))
    assert len(rows) == len(wp.QUICK_IDA_RTOLS) + len(wp.QUICK_PEER_RTOLS)
    peers = [r for r in rows if r["solver"].startswith("scipy")]
    assert peers and all(r["status"] == "failed" and "time limit" in r["message"] for r in peers)
    assert all(r["cage_speed_rel_rms"] in ("", "nan") for r in peers)


def test_cli_rejects_bad_repeat(capsys):
    assert main(["workprecision", "--repeat", "0"]) == 2
    assert "--repeat" in capsys.readouterr().err


def test_naive_nested_path_matches_the_lean_one():
    """Reference: the lean nested path (numba chord Newton, Schur Jacobian), itself checked
    against IDA above. The straightforward one (static solver's Newton per right-hand side,
    scipy's finite-difference Jacobian) integrates the same reduced ODE: cage speed and slice
    forces agree to 1e-9 relative over a short window."""
    scene = make_scene({**SHORT, "numerics.cage_revolutions": 0.02}, **BASELINE)
    lean = simulate(scene, solver="scipy-BDF")
    naive = simulate(scene, solver=ScipyPeer("BDF", inner="static", jac="fd"))
    assert "(static)" in naive.attrs["solver"]
    assert wp.relative_errors(naive.cage_speed.values, lean.cage_speed.values)[0] < 1e-9
    assert wp.relative_errors(naive.contact_force.values, lean.contact_force.values)[0] < 1e-9



def test_an_undetermined_verdict_says_what_to_change():
    """Each way the verdict stays open names its cause and the change that settles it: a
    window too long for the reference to resolve IDA-1e-6's error (shorten --revolutions), a
    peer stopped at a time limit below 10x IDA's time (raise --time-limit-factor), a one-rung
    --quick ladder that does not reach IDA-1e-6's error (run without --quick)."""
    ida = [_run("ida", 1e-6, 1e-6, 1.0), _run("ida", 1e-10, 0.0, 9.0, is_reference=True)]
    slow = [_run("scipy-BDF", 1e-4, 1e-4, 3.0), _run("scipy-BDF", 1e-8, 1e-8, 300.0)]
    floor = {"run": "ida rtol=1e-09", "cage_speed_rel_rms": 3e-7}
    st = wp.Study("t", ida + slow, ida[1], floor, {}, 50.0, 1,
                  {"numerics.cage_revolutions": 0.2})
    c = wp.comparison(st)
    assert c["verdict"] == "undetermined"
    assert "errors not resolved" in c["note"] and "ida rtol=1e-09" in c["note"]
    assert "--revolutions 0.1 (now 0.2)" in c["note"]
    # --quick: the next-tightest IDA rung is IDA-1e-6 itself; and a window so short that the
    # runs agree to round-off
    tiny = [_run("ida", 1e-6, 2e-14, 1.0), _run("ida", 1e-8, 0.0, 3.0, is_reference=True)]
    st.runs, st.reference = tiny + slow, tiny[1]
    st.floor = {"run": "ida rtol=1e-06", "cage_speed_rel_rms": 2e-14}
    c = wp.comparison(st)
    assert "that run is IDA-1e-6 itself" in c["note"] and "run without --quick" in c["note"]
    assert "lengthen it, e.g. --revolutions 0.4 (now 0.2)" in c["note"]
    st.reference = ida[1]

    st.floor = {"cage_speed_rel_rms": 1e-9}
    st.time_limit_s = 5.0  # a factor of 5: the peer stopped before reaching 1e-6
    stopped = [_run("scipy-Radau", 1e-4, 1e-4, 2.0),
               _run("scipy-Radau", 1e-5, math.nan, math.nan, status="failed",
                    message="time limit of 5 s wall exceeded")]
    st.runs = ida + stopped
    c = wp.comparison(st)
    assert c["verdict"] == "undetermined"
    assert "scipy-Radau was stopped at the time limit" in c["note"]
    assert "raise --time-limit-factor to at least 10" in c["note"]

    st.time_limit_s = 50.0
    st.runs = ida + [_run("scipy-LSODA", 1e-4, 1e-4, 2.0)]  # --quick: one rung, 1e-4 > 1e-6
    c = wp.comparison(st)
    assert c["verdict"] == "undetermined"
    assert "scipy-LSODA's tightest rung is still less accurate" in c["note"]
    assert "run without --quick" in c["note"]
    st.runs = ida + slow  # resolved, every peer bounded: a verdict and no note
    c = wp.comparison(st)
    assert c["verdict"] == "met" and c["note"] == ""


def test_cli_progress_in_a_log_is_one_line_per_run(tmp_path, capsys):
    """Without a terminal (pytest captures stderr) the study's progress is one line per run,
    never a carriage return; an undetermined verdict comes with what to change."""
    args = ["workprecision", "yang20_baseline", "-o", str(tmp_path), "--quick", "--repeat", "1",
            "--revolutions", "0.02", "--solvers", "scipy-LSODA"]
    assert main(args) == 0
    out, err = capsys.readouterr()
    assert "\r" not in err
    lines = [ln for ln in err.splitlines() if ln.startswith("work-precision: ")]
    n_runs = len(wp.QUICK_IDA_RTOLS) + len(wp.QUICK_PEER_RTOLS)
    assert [ln.split()[1] for ln in lines] == [f"{i}/{n_runs}" for i in range(1, n_runs + 1)]
    if "10x faster than every scipy solver at the same error: cannot tell" in out:
        warning = [ln for ln in err.splitlines() if ln.startswith("bearingdae: warning: is IDA")]
        assert warning and ("--" in warning[0]), err
