"""Cold start of ``bearingdae run`` (docs/performance.md, "Cold start"):
cost budgets in compilations, not seconds (the timings: benchmarks/cold_start.py).

A cold run (empty numba cache, as after ``pip install``) compiles every kernel entry point
once — one specialisation each — and nothing the run does not use (no flange, whirl,
rolling-resistance, mixed-lubrication or defect pass: system/optional.py); the IDA Jacobian callback
is compiled by a second process (solvers/sundials/precompile.py, aside.py), whose cache entry
the run then loads, and after it the projection of the samples, which the samples wait for; a
child that fails leaves the run to compile it itself.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from bearingdae.solvers.sundials import precompile

ROOT = Path(__file__).resolve().parents[2]
SHORT = ["--set", "numerics.cage_revolutions=0.02", "--set",
         "numerics.warmup_cage_revolutions=0", "--no-plot"]
#: compiled by a default IDA run of the CLI (analytic Jacobian, block-arrow linear solver)
NEEDED = ("callbacks._residual-", "callbacks._jacobian_analytic-", "residual.residual-",
          "residual.kinematics_pass-", "jacobian_analytic.fill_jacobian_analytic-",
          "contact_slopes.contact_slopes-", "jacobian_analytic.roller_blocks-",
          "blockarrow.factor-", "blockarrow.solve-", "projection_kernel.project_batch-",
          "projection_kernel.arrow_solve-", "film._film_loop-")
#: not used by it: the finite-difference Jacobian, Newmark, scikit-sundae's entry point, the
#: dense-solver wrappers and the compiled layers the callbacks no longer go through
NOT_NEEDED = ("jacobian.fill_jacobian-", "jacobian.jacobian_sparse-", "jacobian.jacobian_dense-",
              "newmark_kernel.", "ida_scikit_sundae.residual_flat-", "work.work_views-",
              "jacobian_analytic.jacobian_analytic_sparse-",
              "jacobian_analytic.jacobian_analytic_dense-", "callbacks._jacobian_fd-",
              # inlined into their callers (numba IR), never compiled on their own
              "residual.full_evaluate-", "residual.unpack-", "residual.pack_residual-",
              # effects the scene does not have (system/optional.py)
              "flange.", "whirl.", "rolling_resistance.", "mixed.")


@pytest.mark.slow  # a cold compile in a fresh process (≈ 16-19 s)
def test_cold_run_compiles_each_entry_point_once_and_the_jacobian_aside(tmp_path):
    cache = tmp_path / "numba"
    env = {**os.environ, "PYTHONPATH": str(ROOT), "NUMBA_CACHE_DIR": str(cache),
           "NUMBA_DEBUG_CACHE": "1", "OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg",
           "BEARINGDAE_COMPILE_ASIDE": "1"}  # whatever the load of the test machine
    r = subprocess.run([sys.executable, "-m", "bearingdae.cli", "run", "-o",
                        str(tmp_path / "r.nc"), *SHORT], capture_output=True, text=True,
                       env=env, timeout=900)
    assert r.returncode == 0, r.stderr[-3000:]
    text = r.stdout + r.stderr
    assert "compiling kernels (first run only" in text
    # the summary says how long compiling took (from the notice to the first sample)
    assert "s compiling the kernels" in r.stdout, r.stdout
    # the first progress line reports a simulated time > 0 (the integration is under way)
    progress = [ln for ln in r.stderr.splitlines() if ln.startswith("simulated time ")]
    assert progress and float(progress[0].split()[2].split("/")[0]) > 0, r.stderr[-2000:]

    data = sorted(p.name for p in cache.rglob("*.nbc"))
    # one specialisation per compiled function, in both processes (a second one would be
    # ``<name>.py311.2.nbc``)
    assert data and all(name.endswith(".1.nbc") for name in data), data
    for name in NEEDED:
        assert any(f.startswith(name) for f in data), (name, data)
    for name in NOT_NEEDED:
        assert not any(f.startswith(name) for f in data), (name, data)

    saved_here = [ln for ln in text.splitlines() if "data saved to" in ln]
    loaded_here = [ln for ln in text.splitlines() if "data loaded from" in ln]
    if len(os.sched_getaffinity(0)) >= 2:
        # the Jacobian callback was compiled by the child; this process loaded it
        assert not any("_jacobian_analytic-" in ln for ln in saved_here), saved_here
        assert any("_jacobian_analytic-" in ln for ln in loaded_here), loaded_here
        assert not any("fill_jacobian_analytic-" in ln for ln in saved_here), saved_here
        # then the projection of the samples, which the run's samples waited for
        assert not any("project_batch-" in ln for ln in saved_here), saved_here
        assert any("project_batch-" in ln for ln in loaded_here), loaded_here


#: a scene (bundled case, switches) -> its Jacobian callback's name in numba's cache (the
#: default scene's goes aside from the command line: the test above)
ASIDE = {"spall and mixed lubrication": ("defects/outer_spall",
                                         {"physics.lubrication": "mixed"},
                                         "_jacobian_analytic_defects_0001-")}


@pytest.mark.slow  # a cold compile in a fresh process (≈ 16-25 s)
@pytest.mark.parametrize("name", list(ASIDE))
def test_a_cold_run_from_python_compiles_the_jacobian_and_projection_aside(tmp_path, name):
    """``simulate`` from Python starts the second process as ``bearingdae run`` does
    (run/integrate.compile_aside), for a defect scene with a switch as well: the Jacobian
    callback and the projection of the samples come from its cache entries, and the record
    equals a warm run's, bit for bit."""
    case, sets, callback = ASIDE[name]
    cache = tmp_path / "numba"
    env = {**os.environ, "PYTHONPATH": str(ROOT), "NUMBA_CACHE_DIR": str(cache),
           "NUMBA_DEBUG_CACHE": "1", "OMP_NUM_THREADS": "1", "BEARINGDAE_COMPILE_ASIDE": "1"}
    sets = {"numerics.cage_revolutions": 0.02, "numerics.warmup_cage_revolutions": 0, **sets}
    program = ("import sys; from bearingdae import load_scene, simulate; "
               f"s = load_scene({case!r}, {sets!r}); "
               "simulate(s, progress=False).to_netcdf(sys.argv[1])")
    runs = []
    for name in ("cold.nc", "warm.nc"):
        r = subprocess.run([sys.executable, "-c", program, str(tmp_path / name)],
                           capture_output=True, text=True, env=env, timeout=900)
        assert r.returncode == 0, r.stderr[-3000:]
        runs.append(r.stdout)
    saved = [ln for ln in runs[0].splitlines() if "data saved to" in ln]
    loaded = [ln for ln in runs[0].splitlines() if "data loaded from" in ln]
    if len(os.sched_getaffinity(0)) >= 2:
        for entry in (callback, "project_batch-"):
            assert not any(entry in ln for ln in saved), (entry, saved)
            assert any(entry in ln for ln in loaded), (entry, loaded)
    import xarray as xr

    with xr.open_dataset(tmp_path / "cold.nc") as cold, \
            xr.open_dataset(tmp_path / "warm.nc") as warm:
        for v in warm.data_vars:
            assert cold[v].equals(warm[v]), v


#: a scene (bundled case, switches) -> the passes compiled apart it compiles, the tag of its
#: IDA callbacks' variant (system/optional.variant)
ALONE = {
    "rolling resistance": ([], ["physics.rolling_resistance=true"],
                           ("rolling_resistance.rolling_resistance_pass-",  # residual pass
                            "rolling_resistance.rolling_resistance_jacobian-"),  # its block
                           "apart_0010"),
    # a defect scene: the defects' passes and mixed lubrication's, not the other effects'
    "spall and mixed lubrication": (["defects/outer_spall"], ["physics.lubrication=mixed"],
                                    ("defects.defect_pass-", "mixed.mixed_tractions-",
                                     "mixed.mixed_slopes-"), "defects_0001"),
}


@pytest.mark.slow  # a cold compile in a fresh process (16-30 s)
@pytest.mark.parametrize("name", list(ALONE))
def test_a_scene_compiles_its_own_effects_passes_and_no_others(tmp_path, name):
    """Each effect compiled apart has its own entry in the marker (system/optional.py), and so
    has a defect table: a scene that switches on the rolling resistance alone compiles its
    passes, once, and not those of the flanges, the whirling cage, mixed lubrication or
    defects; an outer-race spall with mixed lubrication compiles the defects' and mixed
    lubrication's, and not the others'."""
    case, sets, passes, tag = ALONE[name]
    cache = tmp_path / "numba"
    env = {**os.environ, "PYTHONPATH": str(ROOT), "NUMBA_CACHE_DIR": str(cache),
           "OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg", "BEARINGDAE_COMPILE_ASIDE": "0"}
    r = subprocess.run([sys.executable, "-m", "bearingdae.cli", "run", *case, "-o",
                        str(tmp_path / "r.nc"), *SHORT, *(a for s in sets for a in ("--set", s))],
                       capture_output=True, text=True, env=env, timeout=900)
    assert r.returncode == 0, r.stderr[-3000:]
    data = sorted(p.name for p in cache.rglob("*.nbc"))
    # one specialisation each: the callbacks build the marker as the model holds it
    assert data and all(name.endswith(".1.nbc") for name in data), data
    for prefix in passes:
        assert any(f.startswith(prefix) for f in data), (prefix, data)
    # the callbacks of this scene's variant
    assert any(f.startswith(f"callbacks._residual_{tag}-") for f in data), data
    assert any(f.startswith(f"callbacks._jacobian_analytic_{tag}-") for f in data), data
    for prefix in ("flange.", "whirl.", "rolling_resistance.", "mixed.", "defects.",
                   "callbacks._residual-"):
        if not any(p.startswith(prefix) for p in passes):
            assert not any(f.startswith(prefix) for f in data), (prefix, data)


def test_a_failed_or_slow_child_leaves_the_compilation_to_the_run(monkeypatch):
    failing = subprocess.Popen([sys.executable, "-c", "raise SystemExit(3)"])
    monkeypatch.setitem(precompile._CHILDREN, "analytic", failing)
    assert precompile.running("analytic")
    assert precompile.wait("analytic") is False  # the caller then compiles (callbacks.compiled)
    assert not precompile.running("analytic") and precompile.wait("analytic") is False

    slow = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    monkeypatch.setitem(precompile._CHILDREN, "analytic", slow)
    monkeypatch.setattr(precompile, "WAIT_LIMIT_S", 0.2)
    assert precompile.wait("analytic") is False
    assert slow.poll() is not None  # ended, not left behind


def _child(tmp_path, code: str) -> subprocess.Popen:
    """A stand-in for the second process: ``code`` runs with ``word`` its word pipe's end."""
    word_in, word_out = os.pipe()
    child = subprocess.Popen([sys.executable, "-c", f"import os, sys, time; word = {word_out}; "
                              + code], pass_fds=(word_out,), cwd=tmp_path)
    os.close(word_out)
    child.word = word_in
    return child


def test_the_run_goes_on_at_the_childs_word_and_waits_for_the_projection_later(
        tmp_path, monkeypatch):
    """The child says that the Jacobian is in the cache (precompile.READY, a pipe of its own)
    and goes on with the projection of the samples: wait() returns at that word, with the
    child still at work; wait_projection() returns at its end. A child that ends without the
    word (it failed) leaves both to the run."""
    flag = tmp_path / "go"
    child = _child(tmp_path, f"os.write(word, {precompile.READY!r}); os.close(word); "
                   "[time.sleep(0.01) for _ in iter(lambda: os.path.exists('go'), True)]")
    monkeypatch.setitem(precompile._CHILDREN, "analytic", child)
    monkeypatch.setattr(precompile, "_PROJECTION", [child, None])
    assert precompile.wait("analytic") is True
    assert child.poll() is None  # still compiling the projection: it cannot end before "go"
    assert precompile.projection_pending() and precompile.projection_compiling()
    flag.touch()
    assert precompile.wait_projection() is True and child.returncode == 0
    assert not precompile.projection_pending() and not precompile.projection_compiling()

    failed = _child(tmp_path, "raise SystemExit(3)")
    monkeypatch.setitem(precompile._CHILDREN, "analytic", failed)
    monkeypatch.setattr(precompile, "_PROJECTION", [failed, None])
    assert precompile.wait("analytic") is False  # the run compiles the Jacobian itself
    assert not precompile.projection_pending()  # and the projection

    silent = _child(tmp_path, "time.sleep(60)")  # no word within the limit: ended
    monkeypatch.setitem(precompile._CHILDREN, "analytic", silent)
    monkeypatch.setattr(precompile, "_PROJECTION", [silent, None])
    monkeypatch.setattr(precompile, "WAIT_LIMIT_S", 0.2)
    assert precompile.wait("analytic") is False
    assert silent.poll() is not None and not precompile.projection_pending()


def test_no_child_when_switched_off_busy_or_warm(monkeypatch):
    from bearingdae.solvers.sundials import callbacks

    monkeypatch.setenv("BEARINGDAE_COMPILE_ASIDE", "0")
    assert precompile.start("analytic") is False
    # an application that embeds Python: its executable is not an interpreter to start
    monkeypatch.setenv("BEARINGDAE_COMPILE_ASIDE", "1")
    monkeypatch.setattr(precompile.sys, "executable", "/opt/blender/blender")
    assert precompile.start("analytic") is False and "analytic" not in precompile._CHILDREN
    monkeypatch.setattr(precompile.sys, "executable", "")
    assert precompile.start("analytic") is False
    monkeypatch.undo()
    monkeypatch.setenv("BEARINGDAE_COMPILE_ASIDE", "auto")
    monkeypatch.setattr(precompile, "_cpus", lambda: 2)
    monkeypatch.setattr(precompile, "_others_running", lambda: 0)
    monkeypatch.setattr(precompile.os, "getloadavg", lambda: (1.8, 1.0, 1.0))
    assert precompile._spare_cpu() is False  # both CPUs busy: the child would only take turns
    monkeypatch.setattr(precompile.os, "getloadavg", lambda: (1.1, 1.0, 1.0))
    assert precompile._spare_cpu() is True  # e.g. the run before this one
    monkeypatch.setattr(precompile, "_others_running", lambda: 1)
    assert precompile._spare_cpu() is False  # another job on the other CPU now
    monkeypatch.setattr(precompile, "_others_running", lambda: None)
    assert precompile._spare_cpu() is True
    monkeypatch.setattr(precompile, "_cpus", lambda: 1)
    monkeypatch.setenv("BEARINGDAE_COMPILE_ASIDE", "1")
    assert precompile._spare_cpu() is False  # one CPU: never
    monkeypatch.setattr(precompile, "_cpus", lambda: 2)
    monkeypatch.setattr(callbacks, "is_cold", lambda kind, optional=False: False)
    assert callbacks.compile_aside("analytic") is False  # cached: nothing to do aside
    monkeypatch.setattr(callbacks, "is_cold", lambda kind, optional=False: True)
    assert callbacks.compile_aside("residual") is False  # only Jacobian callbacks go aside
    assert not precompile._CHILDREN
