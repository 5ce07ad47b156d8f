"""Sweeps: sweep-file validation, dask execution, resume, failure recording, figures.

Every run here is tiny (a few hundredths of a cage revolution), so these tests check the
machinery, not the physics; the physics trends are in test_paper_trends.py (slow).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from bearingdae import SceneError, load_scene, scene_from_dict
from bearingdae.studies.sweep import cluster as sweep_mod  # _execute looks execute_run up there
from bearingdae.analysis.summary import one_orbit
from bearingdae.cli import main
from bearingdae.scene import bundled_case_dirs
from bearingdae.studies.sweep import is_sweep_file, load_sweep, run_key, run_sweep

TINY = """
title = "tiny"
base = "yang20_baseline"
[overrides]
"numerics.warmup_cage_revolutions" = 0.02
"numerics.cage_revolutions" = 0.05
"numerics.samples_per_cage_revolution" = 100
[axes]
"operating.speed_rpm" = {speeds}
"operating.radial_load_N" = [800]
"""


def write(tmp_path: Path, text: str, name: str = "s.toml") -> Path:
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def tiny(tmp_path: Path, speeds=(14000, 2000)) -> Path:
    return write(tmp_path, TINY.format(speeds=list(speeds)))


def comparable(ds: xr.Dataset) -> xr.Dataset:
    """A sweep Dataset without what legitimately differs between two executions."""
    return ds.drop_vars(["run_wall_time_s", "run_cpu_time_s"])


# ------------------------------------------------------------------------------------------
# Sweep files
# ------------------------------------------------------------------------------------------
def bundled_sweeps():
    return sorted({p for d in bundled_case_dirs() for p in d.rglob("*.toml") if is_sweep_file(p)})


@pytest.mark.parametrize("path", bundled_sweeps(), ids=lambda p: p.stem)
def test_every_bundled_sweep_loads(path):
    sw = load_sweep(path)
    assert len(sw.points) == int(np.prod(sw.shape))
    assert len({pt.key for pt in sw.points}) == len(sw.points)


def test_paper_cases_match_the_paper():
    """The paper's sweep scenes (docs/theory.md §13): the scenes of Yang et al. (2024)."""
    h = load_sweep("harris36_cage_speed")
    (ax,) = h.axes
    assert ax.key == "operating.radial_load_N" and len(ax.values) >= 13
    assert min(ax.values) == 0 and max(ax.values) == 12000
    assert {pt.scene.operating.speed_rpm for pt in h.points} == {5000.0}
    assert {pt.scene.bearing.rollers for pt in h.points} == {36}
    sp = load_sweep("yang20_speed_sweep")
    assert sp.axes[0].values == (2000.0, 6000.0, 10000.0, 14000.0)
    assert {(p.scene.operating.radial_load_N, p.scene.operating.moment_Nm)
            for p in sp.points} == {(800.0, 3.0)}
    mo = load_sweep("yang20_moment_sweep")
    assert mo.axes[0].values == (0.0, 3.0, 5.0, 10.0)
    assert {(p.scene.operating.speed_rpm, p.scene.operating.radial_load_N)
            for p in mo.points} == {(6000.0, 400.0)}
    ra = load_sweep("yang20_radial_load_sweep")
    loads = ra.axes[0].values
    assert len(loads) >= 4 and min(loads) == 200.0 and max(loads) == 1600.0
    assert {(p.scene.operating.speed_rpm, p.scene.operating.moment_Nm)
            for p in ra.points} == {(6000.0, 3.0)}
    base = load_sweep("yang20_baseline_figs12_17")
    (pt,) = base.points
    assert pt.key == sp.points[0].key  # shared with the 2000 r/min run: computed once


@pytest.mark.parametrize("body, fragments", [
    ('base = "yang20_baseline"\naxis = {}', ["unknown key 'axis'", "Did you mean 'axes'"]),
    ('[axes]\n"operating.speed_rpm" = [1.0]', ["'base' is required"]),
    ('base = "no_such_case"', ["'base' = 'no_such_case'", "does not exist"]),
    ('base = "yang20_baseline"\n[axes]\n"operating.speed" = [1.0]',
     ["[axes]", "'operating.speed'", "operating.speed_rpm"]),
    ('base = "yang20_baseline"\n[axes]\n"operating.speed_rpm" = [2000.0, -5.0]',
     ["axes.'operating.speed_rpm'[1] = -5.0", "[0, 200000]"]),
    ('base = "yang20_baseline"\n[axes]\n"operating.speed_rpm" = []', ["non-empty list"]),
    ('base = "yang20_baseline"\n[axes]\n"operating.speed_rpm" = [1.0, 1.0]',
     ["more than once"]),
    ('base = "yang20_baseline"\n[axes]\n"operating.speed_rpm" = [1.0, "fast"]', ["mixes"]),
    ('base = "yang20_baseline"\n[axes]\noperating.moment_Nm = [1.0, 2.0]\n'
     '[overrides]\n"operating.moment_Nm" = 3.0', ["both an axis and an override"]),
    ('base = "yang20_baseline"\n[overrides]\n"numerics.slices" = 0',
     ["[overrides]", "'numerics.slices' = 0", "[1, 1000]"]),
    ('base = "yang20_baseline"\n[axes]\n"numerics.slices" = [10, 1]',
     ["axes.'numerics.slices'[1] = 1", "moment"]),
    ('base = "yang20_baseline"\n[sweep]\nworkers = 0', ["'sweep.workers' = 0", "[1, 4096]"]),
    ('base = "yang20_baseline"\n[sweep]\nfigres = [11]', ["'sweep.figres'", "sweep.figures"]),
    ('base = "yang20_baseline"\n[sweep]\nfigures = [5]', ["'sweep.figures'", "11..24"]),
    ('base = "yang20_baseline"\naxes = 3', ["[axes] must be a table"]),
])
def test_bad_sweep_files_name_the_key(tmp_path, body, fragments):
    path = write(tmp_path, body)
    with pytest.raises(SceneError) as err:
        load_sweep(path)
    for f in fragments:
        assert f in str(err.value), (f, str(err.value))


def test_bad_sweep_file_exits_2_on_the_command_line(tmp_path, capsys):
    path = write(tmp_path, 'base = "yang20_baseline"\n[axes]\n"operating.speed_rpm" = [-1.0]')
    assert main(["sweep", str(path), "-o", str(tmp_path / "o.nc")]) == 2
    err = capsys.readouterr().err
    assert "operating.speed_rpm" in err and "Traceback" not in err
    assert not (tmp_path / "o.nc").exists()


def test_nested_tables_equal_dotted_keys(tmp_path):
    a = load_sweep(write(tmp_path, 'base = "yang20_baseline"\n[axes.operating]\n'
                         'speed_rpm = [1000.0, 3000.0]\n[overrides.numerics]\nslices = 12',
                         "a.toml"))
    b = load_sweep(write(tmp_path, 'base = "yang20_baseline"\n[axes]\n'
                         '"operating.speed_rpm" = [1000.0, 3000.0]\n[overrides]\n'
                         '"numerics.slices" = 12', "b.toml"))
    assert [p.key for p in a.points] == [p.key for p in b.points]
    assert a.points[1].scene.numerics.slices == 12


def test_run_key_is_the_scene_without_title():
    s = load_scene("yang20_baseline")
    again = scene_from_dict(__import__("tomllib").loads(s.to_toml()))
    assert run_key(again) == run_key(s)
    assert run_key(load_scene("yang20_baseline", {"title": "other"})) == run_key(s)
    assert run_key(load_scene("yang20_baseline", {"operating.radial_load_N": 801})) != run_key(s)


# ------------------------------------------------------------------------------------------
# Running
# ------------------------------------------------------------------------------------------
def test_tiny_sweep_on_a_local_cluster(tmp_path):
    """Two runs on a LocalCluster of 2 pinned processes -> one Dataset with the axes as dims;
    each run's file is kept and referenced, and equals an in-process (synchronous) run."""
    out = tmp_path / "cl.nc"
    ds = run_sweep(tiny(tmp_path), out, workers=2, progress=False)
    assert ds.status.dims == ("speed_rpm", "radial_load_N")
    assert ds.sizes == {"speed_rpm": 2, "radial_load_N": 1}
    assert (ds.status == "completed").all()
    assert ds.speed_rpm.attrs["scene_key"] == "operating.speed_rpm"
    back = xr.open_dataset(out)
    assert back.attrs["runs_completed"] == 2
    for f in back.run_file.values.ravel():
        with xr.open_dataset(out.parent / f) as run:
            assert run.sizes["time"] > 2 and "contact_force" in run
    # same physics in this process
    sync = run_sweep(tiny(tmp_path), tmp_path / "sync.nc", scheduler="synchronous",
                     progress=False)
    for name in ("mean_cage_speed_rad_s", "peak_slice_load_N", "max_abs_slip_m_s"):
        np.testing.assert_allclose(sync[name], ds[name], rtol=1e-9)
    back.close()


def _wait_for(pred, timeout_s):
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout_s:
        if pred():
            return True
        time.sleep(0.02)
    return False


def test_interrupted_sweep_resumes_without_recomputing(tmp_path, monkeypatch):
    """Kill a sweep (SIGKILL) after its first run is written; the restart computes only the
    missing run (counted), leaves the finished file untouched (mtime) and gives the same file
    as an uninterrupted sweep."""
    src = tiny(tmp_path)  # 14 000 r/min first (quick), then 2000 r/min (slower)
    work = tmp_path / "interrupted"
    work.mkdir()
    runs = work / "out_runs"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(Path(__file__).resolve().parents[2]), os.environ.get("PYTHONPATH", "")])}
    proc = subprocess.Popen([sys.executable, "-m", "bearingdae.cli", "sweep", str(src), "-o",
                             str(work / "out.nc"), "--scheduler", "synchronous",
                             "--no-progress"], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    try:
        assert _wait_for(lambda: len(list(runs.glob("*.nc"))) >= 1, 300), "no run finished"
        proc.send_signal(signal.SIGKILL)
    finally:
        proc.wait()
    finished = list(runs.glob("*.nc"))
    assert len(finished) == 1, "the kill came too late to interrupt the sweep"
    assert not (work / "out.nc").exists()
    mtime = finished[0].stat().st_mtime_ns

    calls = []
    real = sweep_mod.execute_run

    def counting(text):
        calls.append(text)
        return real(text)

    monkeypatch.setattr(sweep_mod, "execute_run", counting)
    resumed = run_sweep(src, work / "out.nc", scheduler="synchronous", progress=False)
    assert len(calls) == 1 and "speed_rpm = 2000.0" in calls[0]
    assert finished[0].stat().st_mtime_ns == mtime
    assert (resumed.status == "completed").all()

    fresh_dir = tmp_path / "fresh"
    fresh = run_sweep(src, fresh_dir / "out.nc", scheduler="synchronous", progress=False)
    assert len(calls) == 3
    a = xr.open_dataset(work / "out.nc").load()
    b = xr.open_dataset(fresh_dir / "out.nc").load()
    xr.testing.assert_identical(comparable(a), comparable(b).assign_attrs(a.attrs))
    xr.testing.assert_identical(comparable(resumed), comparable(fresh).assign_attrs(
        resumed.attrs))


def test_failed_run_is_recorded_and_the_others_finish(tmp_path, monkeypatch):
    """numerics.max_steps = 100 cannot reach the end of the window: that run fails with IDA's
    message, its error is kept in a small file and in the Dataset, the other run completes; a
    restart does not retry it unless asked."""
    path = write(tmp_path, """
base = "yang20_baseline"
[overrides]
"numerics.warmup_cage_revolutions" = 0.02
"numerics.cage_revolutions" = 0.05
[axes]
"numerics.max_steps" = [100, 500000]
""")
    out = tmp_path / "f.nc"
    assert main(["sweep", str(path), "-o", str(out), "--scheduler", "synchronous",
                 "--no-progress"]) == 1
    ds = xr.open_dataset(out).load()
    assert list(ds.status.values) == ["failed", "completed"]
    assert "SimulationError" in ds.error.values[0] and ds.error.values[1] == ""
    assert np.isnan(ds.mean_cage_speed_rad_s.values[0])
    assert np.isfinite(ds.mean_cage_speed_rad_s.values[1])
    failed = list((tmp_path / "f_runs").glob("*.failed.json"))
    assert len(failed) == 1 and failed[0].stat().st_size < 20_000
    calls = []
    real = sweep_mod.execute_run
    monkeypatch.setattr(sweep_mod, "execute_run", lambda t: calls.append(t) or real(t))
    run_sweep(path, out, scheduler="synchronous", progress=False)
    assert calls == []
    again = run_sweep(path, out, scheduler="synchronous", progress=False, retry_failed=True)
    assert len(calls) == 1 and list(again.status.values) == ["failed", "completed"]


def test_a_crashing_run_is_recorded(tmp_path, monkeypatch):
    """Any exception inside a run (not only solver failures) is recorded with its type."""
    real_simulate = __import__("bearingdae.api", fromlist=["simulate"]).simulate

    def boom(scene, **kw):
        if scene.operating.speed_rpm == 2000.0:
            raise ZeroDivisionError("synthetic")
        return real_simulate(scene, **kw)

    monkeypatch.setattr("bearingdae.api.simulate", boom)
    ds = run_sweep(tiny(tmp_path), tmp_path / "c.nc", scheduler="synchronous", progress=False)
    assert list(ds.status.values.ravel()) == ["completed", "failed"]
    assert "ZeroDivisionError: synthetic" in str(ds.error.values.ravel()[1])


# ------------------------------------------------------------------------------------------
# Orbits and figures
# ------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def orbit_sweep(tmp_path_factory):
    """Two speeds with a window of 1.3 cage revolutions (one full orbit of some roller)."""
    tmp = tmp_path_factory.mktemp("orbit")
    path = write(tmp, """
title = "orbit test"
base = "yang20_baseline"
[overrides]
"numerics.warmup_cage_revolutions" = 0.0
"numerics.cage_revolutions" = 1.3
"numerics.samples_per_cage_revolution" = 60
"numerics.rtol" = 1e-4
[axes]
"operating.speed_rpm" = [10000.0, 14000.0]
[sweep]
figures = [18, 19, 20, 21]
orbit_points = 90
""")
    out = tmp / "orbit.nc"
    run_sweep(path, out, scheduler="synchronous", progress=False)
    return out


def test_one_orbit_is_the_roller_at_its_own_azimuth(orbit_sweep):
    """Phase folding (reference: the raw samples): at each grid azimuth the stored value is
    the run's value at the time the chosen roller passes that azimuth."""
    ds = xr.open_dataset(orbit_sweep).load()
    sel = ds.isel(speed_rpm=1)
    with xr.open_dataset(orbit_sweep.parent / str(sel.run_file.values)) as run:
        run = run.load()
    o = one_orbit(run, points=90)
    j = int(sel.orbit_roller)
    assert j == o.attrs["roller"] >= 1
    az = run.roller_azimuth.sel(roller=j).interp(time=o.time_at_azimuth.values).values
    np.testing.assert_allclose(np.degrees(az) - 360 * o.attrs["orbit_index"], o.azimuth,
                               atol=1e-6)
    skew = run.skew_angle.sel(roller=j).interp(time=o.time_at_azimuth.values).values
    np.testing.assert_allclose(sel.skew_angle.values, skew, rtol=1e-12)


def test_plot_command_draws_the_sweep_figures(orbit_sweep, tmp_path, capsys):
    out = tmp_path / "fig.png"
    assert main(["plot", str(orbit_sweep), "-o", str(out)]) == 0
    made = sorted(p.name for p in tmp_path.glob("*.png"))
    assert made == ["fig_fig18.png", "fig_fig19.png", "fig_fig20.png", "fig_fig21.png",
                    "fig_trends.png"]
    assert all((tmp_path / m).stat().st_size > 10_000 for m in made)
    assert main(["plot", str(orbit_sweep), "--figure", "11", "-o",
                 str(tmp_path / "cage.png")]) == 0
    assert main(["plot", str(orbit_sweep), "--select", "speed_rpm=14000", "--figure", "12",
                 "-o", str(tmp_path / "f12.png")]) == 0
    assert (tmp_path / "f12.png").stat().st_size > 10_000
    capsys.readouterr()
    assert main(["plot", str(orbit_sweep), "--figure", "12"]) == 2
    assert "--select" in capsys.readouterr().err
    assert main(["plot", str(orbit_sweep), "--figure", "7"]) == 2


def test_paper_sweeps_ship_in_the_package(tmp_path):
    """pyproject.toml ships cases/paper as bearingdae/cases/paper: build the package files
    with setuptools' build_py and load every paper sweep from that copy, from another cwd."""
    pytest.importorskip("setuptools")
    root = Path(__file__).resolve().parents[2]
    lib = tmp_path / "lib"
    r = subprocess.run([sys.executable, "-c", "from setuptools import setup; setup()", "-q",
                        "build_py", "-d", str(lib)], cwd=root, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    code = ("import bearingdae; from bearingdae.studies.sweep import load_sweep; "
            "from bearingdae.studies.paper import PAPER_SWEEPS; print(bearingdae.__file__); "
            "[print(load_sweep('paper/' + n).origin) for n in PAPER_SWEEPS]")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       cwd=tmp_path, env={**os.environ, "PYTHONPATH": str(lib)})
    assert r.returncode == 0, r.stderr
    lines = r.stdout.split()
    assert lines[0].startswith(str(lib)) and len(lines) == 6
    assert all(line.startswith(str(lib / "bearingdae" / "cases" / "paper")) for line in lines[1:])


def test_runs_lost_by_the_cluster_are_missing_not_failed(tmp_path, monkeypatch):
    """A run whose future errs with a communication error (here raised on purpose inside an
    in-process dask cluster) is a failure of the cluster: no failure record, status 'missing',
    SweepIncomplete raised after the file is written, and the restart computes it."""
    from distributed import LocalCluster

    from bearingdae.studies.sweep import SweepIncomplete

    real = sweep_mod.execute_run

    def flaky(text):
        if "speed_rpm = 2000.0" in text:
            raise ConnectionError("synthetic: connection to the scheduler lost")
        return real(text)

    monkeypatch.setattr(sweep_mod, "execute_run", flaky)
    src, out = tiny(tmp_path), tmp_path / "lost.nc"
    with LocalCluster(n_workers=1, processes=False, threads_per_worker=1,
                      dashboard_address=None) as cluster:
        with pytest.raises(SweepIncomplete, match="run the same command again") as err:
            run_sweep(src, out, scheduler=cluster.scheduler_address, progress=False)
    assert list(err.value.datasets[0].status.values.ravel()) == ["completed", "missing"]
    assert xr.open_dataset(out).status.values.ravel().tolist() == ["completed", "missing"]
    assert not list((tmp_path / "lost_runs").glob("*.failed.json"))
    monkeypatch.setattr(sweep_mod, "execute_run", real)
    ds = run_sweep(src, out, scheduler="synchronous", progress=False)
    assert (ds.status == "completed").all()


def test_sweep_file_meets_the_output_contract(orbit_sweep, tmp_path):
    """The sweep file passes the same CF checkers and units contract as run files
    (test_output_contract.py: cfchecks, compliance-checker with its stated exemptions, every
    variable with units and long_name)."""
    contract = pytest.importorskip("test_output_contract")
    found, errors = contract.cf_findings(orbit_sweep)
    left = [f for f in found if not any(sec in f and msg in f for sec, msg in contract.EXEMPT)]
    assert errors == {} and left == [], left
    h = contract.assert_units_contract(orbit_sweep)
    assert {"status", "mean_cage_speed_rad_s", "skew_angle", "azimuth",
            "slice_position"} <= set(h)
    r = contract.cfchecks(orbit_sweep, tmp_path)  # skips without libudunits2
    assert r["counts"]["ERRORS detected"] == 0 and r["counts"]["WARNINGS given"] == 0 \
        and r["counts"].get("FATAL ERRORS", 0) == 0, r["output"]


def test_a_runs_warnings_print_as_one_line_naming_the_run(tmp_path, capsys):
    """A warm-up that does not settle within its cap warns (run/steady.py): in a sweep each
    run's warning is one 'bearingdae: warning: run <values set>: ...' line, never Python's
    file name, line number and source line (util/warning_lines.py)."""
    path = write(tmp_path, """
title = "unsettled"
base = "paper/harris36_5000rpm"
[overrides]
"operating.radial_load_N" = 250.0
"numerics.until_steady" = true
"numerics.initial_speeds" = "epicyclic"
"numerics.warmup_cage_revolutions" = 0.0
"numerics.steady_block_cage_revolutions" = 0.25
"numerics.max_warmup_cage_revolutions" = 1.0
"numerics.cage_revolutions" = 0.05
"numerics.samples_per_cage_revolution" = 40
"output.variables" = ["cage_speed"]
[axes]
"operating.speed_rpm" = [4000, 5000]
""")
    assert main(["sweep", str(path), "-o", str(tmp_path / "u.nc"), "--scheduler",
                 "synchronous", "--no-progress"]) == 0
    err = capsys.readouterr().err
    lines = [x for x in err.splitlines() if "until_steady" in x]
    assert len(lines) == 2, err
    for rpm, line in zip(("4000", "5000"), sorted(lines)):
        assert line.startswith(f"bearingdae: warning: run 'unsettled: speed_rpm = {rpm}': "), \
            line
    assert "NotSteadyWarning" not in err and ".py:" not in err and "warnings.warn" not in err
