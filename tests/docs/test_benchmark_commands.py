"""The benchmark commands performance.md tells a user to run, run (with the least settings):
each exits 0 and prints its table. A benchmark reaches into the package's modules (the
kernels' own loops, the solvers' options), so moving a kernel could break it unnoticed: the
kernels command did, once, when IDA's flat residual callback moved beside its only user."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

pytestmark = pytest.mark.slow  # processes of their own, 2-6 s each with the kernels cached


def bench(*args: str) -> str:
    r = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "run.py"), *args],
                       capture_output=True, text=True, timeout=900, cwd=ROOT,
                       env={**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1",
                            "PYTHONPATH": str(ROOT)})
    assert r.returncode == 0, r.stderr[-3000:]
    assert "Traceback" not in r.stderr, r.stderr[-3000:]
    return r.stdout


def test_kernels_with_its_passes():
    out = bench("kernels", "--repeats", "1", "--calls", "20", "--passes")
    for label in ("residual (work tuple)", "residual_flat (IDA's callback)",
                  "analytic Jacobian", "block-arrow factorisation", "block-arrow solve",
                  "residual: contact pass", "Jacobian: contact slopes"):
        assert label in out, out


def test_dense_output_on_a_short_window():
    out = bench("dense-output", "--repeat", "1", "--revolutions", "0.05", "--warmup", "0")
    # the largest pocket force at every step does not depend on the sampling
    assert "the same at every sampling: yes" in out, out
    assert "identical to the per-sample projector: yes" in out, out


def test_switches_on_a_short_window():
    out = bench("switches", "--only", "5 slices", "--repeat", "1", "--warmup", "0",
                "--revolutions", "0.02")
    rows = [line for line in out.splitlines() if line.startswith("| 5 slices")
            or line.startswith("| default")]
    assert len(rows) == 2, out


def test_switches_modes_name_the_mode_that_sets_the_steps():
    out = bench("switches", "--only", "default", "--repeat", "1", "--warmup", "0",
                "--revolutions", "0.02", "--modes")
    line = [x for x in out.splitlines() if x.startswith("| default |")][-1]  # the modes table
    cells = [c.strip() for c in line.strip("|").split("|")]
    assert len(cells) == 6, out
    # a frequency, a damping ratio, an unknown of the scene, a step, a count (this early in the
    # run nothing rings yet: the slowest of all, the cage angle's drift, may be the one)
    assert float(cells[1].split()[0]) >= 0.0 and 0.0 <= float(cells[2].split()[0]) <= 0.2, out
    from bearingdae.system.layout import GLOBAL, LOCAL

    assert cells[3] in LOCAL + GLOBAL, out
    assert float(cells[4]) > 0.0 and float(cells[5]) > 0.0, out
    assert "IDA alone on an undamped oscillator at rtol 1e-06" in out, out


def test_static_and_stability_and_memory():
    assert "| yang20 baseline, 10 slices |" in bench("static", "--repeat", "2")
    out = bench("stability", "--cases", "preload", "--solvers", "ida", "--repeat", "1")
    assert "| preload | ida | completed |" in out, out
    out = bench("memory", "--revolutions", "0.05", "0.2")
    assert "peak RSS at 0.2 over 0.05 revolutions" in out, out


def test_skew_impact_and_workprecision(tmp_path):
    out = bench("skew-statistics", "impact", "--rates", "2", "--steps", "2e-6")
    assert "IDA 1e-6: e" in out and "NM 2 µs: e" in out, out
    out = bench("workprecision", "--quick", "--scenes", "baseline", "--repeat", "1",
                "--revolutions", "0.02", "--warmup", "0", "--solvers", "newmark", "--no-naive",
                "-o", str(tmp_path))
    assert "| ida | 1e-06 | ok |" in out and "| newmark |" in out, out


def test_cold_start_compile_per_entry_point():
    out = bench("cold-start", "--compile")  # an empty kernel cache of its own
    for entry in ("residual (initial state, from Python)", "IDA analytic Jacobian callback",
                  "projection of the samples", "sum"):
        assert entry in out, out


@pytest.mark.parametrize("solver", [[], ["--scikit-sundae"]], ids=["compiled", "scikit-sundae"])
def test_profile_by_shared_object(solver):
    import shutil

    if shutil.which("perf") is None:
        pytest.skip("Linux perf is not installed here")
    probe = subprocess.run(["perf", "stat", "-e", "task-clock", "true"], capture_output=True)
    if probe.returncode != 0:
        pytest.skip("perf cannot profile here (perf_event_paranoid)")
    out = bench("profile", "--runs", "1", *solver)
    assert "µs per step" in out and "numba kernels" in out, out


def test_versions_at_equal_error_on_one_tree(tmp_path):
    """Both curves from the same tree: the trajectories are deterministic, so every error of
    the 'old' ladder equals the 'new' one's, and each rung costs CPU in both."""
    import json

    out = bench("versions", "--old", str(ROOT), "--workprecision", "--repeat", "1",
                "--rtols", "1e-4,1e-6", "--set", "numerics.cage_revolutions=0.02",
                "-o", str(tmp_path), "--json", str(tmp_path / "v.json"))
    assert "at rtol 1e-06: new/old CPU" in out, out
    got = json.loads((tmp_path / "v.json").read_text())
    old, new = got["table"]["old"], got["table"]["new"]
    assert [r["rtol"] for r in old] == [r["rtol"] for r in new] == [1e-4, 1e-6]
    for o, n in zip(old, new):
        assert o["errors"] == n["errors"] and o["steps"] == n["steps"]
        assert set(n["errors"]) == {"cage_speed", "orbit_speed", "spin_speed", "skew_angle",
                                    "contact_force"}
        assert o["cpu_s"] > 0 and n["cpu_s"] > 0
    # the tighter rung is the more accurate against the rtol-1e-10 reference
    assert new[1]["errors"]["cage_speed"] < new[0]["errors"]["cage_speed"]
    assert (tmp_path / "workprecision_versions.png").stat().st_size > 10_000
