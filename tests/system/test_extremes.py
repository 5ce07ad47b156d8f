"""Running extremes at every accepted step (system/extremes.py; IDA's root-function hook,
Newmark's step loop; results/extremes.py).

References: the 1-DOF skew equation of one pocket impact (DOP853 at rtol 1e-12, the same
reference tests/solvers/test_newmark.py checks against the analytic Kelvin-Voigt law) for the
peak force and skew; the same run without the hook for the steps; the same run at another
sample density for independence of the sampling.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import solve_ivp

from bearingdae import load_scene, save, simulate
from bearingdae.cli import main
from bearingdae.physics.cage import pocket_force
from bearingdae.solvers.algebraic import initial_state
from bearingdae.solvers.ida import IDA
from bearingdae.solvers.newmark import Newmark, NewmarkOptions
from bearingdae.system.model import build_model
from bearingdae.system.residual import PARAM_NAMES

IMPACT_ROLLER = 10  # index (roller 11), azimuth π: no race load; a pure skew impact
#                   (tests/solvers/test_newmark.py)
IMPACT_GAP_RAD = 2e-4
RATE_RAD_S = 2.0


def impact():
    """The baseline bearing at rest, roller IMPACT_ROLLER skewed IMPACT_GAP_RAD short of its
    pocket bars and turning towards them: (model, y0, yp0, t_end, reference peaks)."""
    m = build_model(load_scene("yang20_baseline", {"operating.speed_rpm": 0.0,
                                                   "operating.moment_Nm": 0.0}))
    P = dict(zip(PARAM_NAMES, m.data[0]))
    L, It = P["L"], P["It"]
    law = (P["cp"], P["Kp"], P["cdamp"], P["eps_p"], P["f_p"])
    th0 = P["cp"] / L - IMPACT_GAP_RAD
    y0, yp0 = initial_state(m)
    y0 = y0.copy()
    for q, v in (("skew_angle", th0), ("skew_rate", RATE_RAD_S)):
        i = m.layout.index(q, IMPACT_ROLLER)
        y0[i] = v / m.scale[i]
    t_end = 2 * IMPACT_GAP_RAD / RATE_RAD_S + 2e-4

    def ends(z):
        return (pocket_force(-0.5 * L * z[0], -0.5 * L * z[1], *law)[0],
                pocket_force(0.5 * L * z[0], 0.5 * L * z[1], *law)[0])

    def rhs(t, z):
        f_a, f_b = ends(z)
        return [z[1], 0.5 * L * (f_b - f_a) / It]

    t = np.linspace(0.0, t_end, 200001)  # 1.5 ns apart: the peak to ~1e-7
    r = solve_ivp(rhs, (0.0, t_end), [th0, RATE_RAD_S], method="DOP853", rtol=1e-12,
                  atol=1e-15, t_eval=t, max_step=1e-7)
    assert r.success
    force = np.abs(np.array([ends(z) for z in r.y.T]))
    peak = {"force": force.max(), "time": t[np.argmax(force.max(axis=1))],
            "skew": np.abs(r.y[0]).max()}
    return m, y0, yp0, t_end, peak


@pytest.fixture(scope="module")
def impact_case():
    return impact()


def test_ida_extremes_find_the_impact_peak_that_samples_miss(impact_case):
    """Outputs only at the start and the end: the samples see no impact at all, the per-step
    extremes see its peak pocket force within 0.5 % of the reference (IDA at rtol 1e-6, the
    peak read at step ends, ~0.1 µs apart during the impact), at its time, on both ends (the
    impact is a pure rotation: both ends meet a bar at once), and the peak |skew|."""
    m, y0, yp0, t_end, peak = impact_case
    sol = IDA().integrate(m, y0, yp0, np.array([0.0, t_end]), extremes_from=0.0)
    assert sol.success
    fmax, tmax = sol.extremes.result()["cage_force"]
    assert np.abs(m.diagnostics(sol.t[-1], sol.y[-1])["cage_force"]).max() < 1e-3 * peak["force"]
    assert fmax[IMPACT_ROLLER] == pytest.approx([peak["force"]] * 2, rel=5e-3)
    assert tmax[IMPACT_ROLLER] == pytest.approx([peak["time"]] * 2, abs=0.5e-6)
    others = np.delete(fmax, IMPACT_ROLLER, axis=0)
    assert np.nanmax(others) < 1e-6 * peak["force"]
    skew = sol.extremes.result()["skew_angle"][0]
    assert skew[IMPACT_ROLLER] == pytest.approx(peak["skew"], rel=1e-5)


def test_newmark_extremes_from_its_steps(impact_case):
    """Newmark-β keeps the same extremes from its own steps (1 µs: the impact lasts ~10 µs);
    its peak is within 5 % of the reference (tests/solvers/test_newmark.py: its peak
    penetration is within 5 % at 4 µs and better below)."""
    m, y0, yp0, t_end, peak = impact_case
    t_out = 4e-6 * np.arange(int(round(t_end / 4e-6)) + 1)
    sol = Newmark(NewmarkOptions(step_s=1e-6)).integrate(m, y0, yp0, t_out, extremes_from=0.0)
    assert sol.success and sol.extremes is not None
    fmax, _ = sol.extremes.result()["cage_force"]
    assert fmax[IMPACT_ROLLER] == pytest.approx([peak["force"]] * 2, rel=0.05)
    assert sol.stats["extremes_steps"] == sol.stats["steps"]


@pytest.fixture(scope="module")
def baseline():
    m = build_model(load_scene("yang20_baseline"))
    y0, yp0 = initial_state(m)
    return m, y0, yp0


def test_extremes_do_not_change_the_steps_nor_depend_on_sampling(baseline):
    """The hook returns g = 1 (never a root): IDA takes the same steps with and without it
    (same counts, same samples bit for bit), and the extremes at 50 and 1000 output samples are
    identical (evaluations at output times do not count); steps before ``extremes_from`` do
    not count."""
    m, y0, yp0 = baseline
    runs = {}
    for n in (50, 1000):
        t_out = np.linspace(0.0, 0.008, n + 1)
        runs[n] = IDA().integrate(m, y0, yp0, t_out, extremes_from=0.004)
        if n == 50:
            plain = IDA().integrate(m, y0, yp0, t_out)
            for key in ("steps", "residual_calls", "jacobian_calls"):
                assert plain.stats[key] == runs[n].stats[key], key
            assert np.array_equal(plain.y, runs[n].y) and plain.extremes is None
    a, b = (runs[n].extremes.result() for n in (50, 1000))
    for name in a:
        for k in range(2):
            assert np.array_equal(a[name][k], b[name][k], equal_nan=True), name
    assert np.nanmin(a["contact_force"][1]) >= 0.004
    assert 0 < runs[50].stats["extremes_steps"] < runs[50].stats["steps"]


def test_interval_peaks_partition_the_steps(impact_case):
    """The peak trace (system/extremes.py): each sample closes an interval. The intervals hold
    every counted step once, so their largest value is the window's (bit for bit), and the
    impact's peak is in the interval that contains its time (within the one step IDA's hook
    lags behind a sample time); samples before the impact see no pocket force."""
    from bearingdae.system.extremes import PEAKS

    m, y0, yp0, t_end, peak = impact_case
    t_out = np.linspace(0.0, t_end, 41)
    for solver in (IDA(), Newmark(NewmarkOptions(step_s=1e-6))):
        if isinstance(solver, Newmark):
            t_out = 4e-6 * np.arange(int(round(t_end / 4e-6)) + 1)
        sol = solver.integrate(m, y0, yp0, t_out, extremes_from=0.0)
        tp, P = sol.extremes.interval_peaks()
        assert np.array_equal(tp, sol.t)
        res = sol.extremes.result()
        f = P[:, PEAKS.index("cage_force")]
        assert np.nanmax(f) == np.nanmax(res["cage_force"][0])
        assert np.nanmax(P[:, PEAKS.index("skew_angle")]) == np.nanmax(res["skew_angle"][0])
        q = res["contact_force"][0]
        assert np.nanmax(P[:, PEAKS.index("contact_force_inner")]) == np.nanmax(q[..., 0])
        assert np.nanmax(P[:, PEAKS.index("contact_force_outer")]) == np.nanmax(q[..., 1])
        i = int(np.nanargmax(f))
        assert tp[i - 1] - 1e-6 <= peak["time"] <= tp[i] + 1e-6, type(solver).__name__
        assert np.nanmax(f[tp < 0.5 * peak["time"]], initial=0.0) < 1e-6 * peak["force"]


def test_interval_peaks_do_not_depend_on_the_sampling_between_their_samples(baseline):
    """The 1000-sample trace, grouped by 20, is the 50-sample trace bit for bit: IDA takes the
    same steps at any sampling (the test above), and a step is counted in the interval of the
    sample at or after which the hook sees it, at either density."""
    from bearingdae.system.extremes import PEAKS

    m, y0, yp0 = baseline
    traces = {}
    fine = np.linspace(0.0, 0.008, 1001)
    for n, t_out in ((50, fine[::20]), (1000, fine)):
        sol = IDA().integrate(m, y0, yp0, t_out, extremes_from=0.004)
        traces[n] = sol.extremes.interval_peaks()
    t50, P50 = traces[50]
    t1k, P1k = traces[1000]
    assert np.array_equal(t50, t1k[::20])
    grouped = np.array([np.nanmax(P1k[max(0, 20 * g - 19):20 * g + 1], axis=0)
                        if g else P1k[0] for g in range(t50.size)])
    for c, name in enumerate(PEAKS):
        assert np.array_equal(grouped[:, c], P50[:, c], equal_nan=True), name


def short(**over):
    return load_scene("yang20_baseline", {"numerics.warmup_cage_revolutions": 0.02,
                                          "numerics.cage_revolutions": 0.05, **over})


def test_dataset_variables_round_trip_and_bound_the_samples(tmp_path):
    """Every extreme and its time in the Dataset, with units and long names; each at least
    the largest sampled magnitude it stands for (pocket force and skew are evaluated at the
    accepted states; slice loads and slips at the last corrector iterate, so within the
    Newton tolerance); times inside the recorded window; the file round-trips exactly."""
    ds = simulate(short())
    names = ("cage_force_max", "contact_force_max", "contact_pressure_max", "slip_velocity_max",
             "skew_angle_max")
    for name in names:
        for v in (name, name + "_time"):
            assert {"units", "long_name"} <= set(ds[v].attrs), v
        t = ds[name + "_time"]
        assert float(t.min()) >= ds["record_start_s"].item() - 1e-12
        assert float(t.max()) <= float(ds.time[-1]) + 1e-12
    assert float(ds.cage_force_max.max()) >= float(np.abs(ds.cage_force).max())
    assert (ds.skew_angle_max >= np.abs(ds.skew_angle).max("time")).all()
    assert (ds.contact_force_max >= ds.contact_force.max("time") * (1 - 1e-6)).all()
    assert float(ds.contact_pressure_max.max()) == pytest.approx(
        float(ds.contact_pressure.max()), rel=1e-3)
    assert ds.attrs["extremes_source"] == ("every accepted solver step in the recorded window and "
                                          "its first and last samples")
    path = save(ds, tmp_path / "x.nc")
    with xr.open_dataset(path) as back:
        for name in names:
            for v in (name, name + "_time"):
                assert np.array_equal(back[v].values, ds[v].values, equal_nan=True)
                assert back[v].attrs == ds[v].attrs


def test_output_selection_switches_the_hook(monkeypatch):
    """A scene whose ``output.variables`` names no extreme runs without the hook (no
    per-step cost); naming one keeps that one (and its time) only."""
    none = simulate(short(**{"output.variables": ["cage_speed"]}))
    assert not [v for v in none.data_vars if v.endswith("_max") or v.endswith("_max_time")]
    assert "extremes_steps" not in json.loads(none.attrs["solver_statistics"])
    one = simulate(short(**{"output.variables": ["cage_speed", "cage_force_max"]}))
    assert {v for v in one.data_vars if "_max" in v} == {"cage_force_max",
                                                        "cage_force_max_time"}


def test_solver_without_extremes_falls_back_to_samples():
    """A scipy peer keeps no per-step extremes: the variables come from the samples, and the
    attribute says so; so does the peak trace."""
    ds = simulate(load_scene("yang20_baseline", {"numerics.warmup_cage_revolutions": 0.0,
                                                 "numerics.cage_revolutions": 0.002,
                                                 "numerics.samples_per_cage_revolution": 2000}),
                  solver="scipy-BDF")
    assert ds.attrs["extremes_source"] == "the output samples of the recorded window"
    assert float(ds.cage_force_max.max()) == float(np.abs(ds.cage_force).max())
    # the peak trace is then each sample's own largest value over the bearing
    assert np.array_equal(ds.cage_force_peak.values, np.abs(ds.cage_force).max(("roller", "end")))
    assert np.array_equal(ds.skew_angle_peak.values, np.abs(ds.skew_angle).max("roller"))


def test_run_summary_prints_the_peaks(tmp_path, capsys):
    out = tmp_path / "r.nc"
    assert main(["run", "yang20_baseline", "-o", str(out), "--no-plot", "--set",
                 "numerics.warmup_cage_revolutions=0.02", "--set",
                 "numerics.cage_revolutions=0.05"]) == 0
    text = capsys.readouterr().out
    with xr.open_dataset(out) as ds:
        peak = float(ds.cage_force_max.max())
    line = next(ln for ln in text.splitlines() if "peak pocket force" in ln)
    assert f"{peak:.3f} N" in line and "roller" in line and "t = " in line
    assert "peak slice pressure" in text and "every accepted solver step" in text


def test_resumed_run_takes_the_part_before_the_resume_from_its_samples():
    """A checkpointed run resumed at t_r kept per-step extremes only from t_r on: the samples
    before t_r are folded in (a larger one wins, with its time), and ``extremes_source`` says
    so. Without per-step extremes every sample counts."""
    from bearingdae.results.extremes import extreme_variables
    from bearingdae.system.extremes import H_SIZE, Extremes

    m = build_model(load_scene("yang20_baseline"))
    Z, k = m.layout.rollers, m.geometry.slices
    t = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    diag = {"cage_force": np.zeros((5, Z, 2)), "contact_force": np.ones((5, Z, k, 2)),
            "slip_velocity": np.zeros((5, Z, k, 2))}
    diag["cage_force"][1, 3, 0] = -7.0  # before the resume: larger than any step's
    diag["cage_force"][3, 4, 1] = 9.0  # after it: covered by the steps, not folded in
    diag["cage_force"][4, 5, 0] = 8.0  # the window's last sample: always folded in
    skew = np.zeros((5, Z))
    ext = Extremes(Z, k, 0.0)
    ext.steps_from = 2.5
    E = ext.buffer
    o = H_SIZE  # the cage_force block (system/extremes.py): max, then times
    E[o:o + 2 * Z] = 2.0
    E[o + 2 * Z:o + 4 * Z] = 3.5
    wanted = ("cage_force_max",)
    out, attrs = extreme_variables(m, t, skew, diag, ext, wanted)
    f, ft = out["cage_force_max"].values, out["cage_force_max_time"].values
    assert f[3, 0] == 7.0 and ft[3, 0] == 1.0
    assert f[4, 1] == 2.0 and ft[4, 1] == 3.5
    assert f[5, 0] == 8.0 and ft[5, 0] == 4.0
    assert f[0, 0] == 2.0 and ft[0, 0] == 3.5
    assert "resumed" in attrs["extremes_source"]
    out, attrs = extreme_variables(m, t, skew, diag, None, wanted)
    assert out["cage_force_max"].values[4, 1] == 9.0
    assert attrs["extremes_source"] == "the output samples of the recorded window"
