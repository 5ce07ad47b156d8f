"""A sweep's first run after installation compiles the kernels once, in its client, before
the worker processes start (studies/sweep/cluster.py ``_compile_before_workers``; the paper
set cold: 66 -> 54 s, CHANGELOG.md 2026-11-23). Cost budgets and decisions, no
timing."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from bearingdae.run import progress
from bearingdae.solvers.ida import IDA
from bearingdae.studies.sweep import cluster

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("scheduler, workers, cold, compiles", [
    (None, 2, True, True),           # a LocalCluster on a fresh install: once, here
    (None, 2, False, False),         # the cache holds the kernels: the workers load them
    (None, 1, True, False),          # one worker compiles them once anyway
    ("synchronous", 2, True, False),  # no workers: the first run compiles them
    ("tcp://127.0.0.1:8786", 2, True, False),  # a remote cluster's workers: their own cache
])
def test_kernels_compile_once_before_a_local_cluster_starts(monkeypatch, scheduler, workers,
                                                            cold, compiles):
    calls = []
    monkeypatch.setattr(progress, "kernels_cold", lambda: cold)
    monkeypatch.setattr(IDA, "compile_kernels", lambda self, busy_ok=False: calls.append(busy_ok))
    assert cluster._compile_before_workers(scheduler, workers) is compiles
    # both CPUs whatever the load: the workers are about to take them anyway
    assert calls == ([True] if compiles else [])


def test_a_failed_compilation_leaves_it_to_the_workers(monkeypatch):
    def fail(self, busy_ok=False):
        raise RuntimeError("numba failed")

    monkeypatch.setattr(progress, "kernels_cold", lambda: True)
    monkeypatch.setattr(IDA, "compile_kernels", fail)
    assert cluster._compile_before_workers(None, 2) is False


@pytest.mark.slow  # cold compiles in fresh processes (≈ 15-18 s)
def test_compile_kernels_leaves_every_kernel_of_a_run_in_the_cache(tmp_path):
    cache = tmp_path / "numba"
    code = ("from bearingdae.run.progress import kernels_cold\n"
            "assert kernels_cold()\n"
            "from bearingdae.solvers.ida import IDA\n"
            "IDA().compile_kernels(busy_ok=True)\n"
            "assert not kernels_cold()\n")
    env = {**os.environ, "PYTHONPATH": str(ROOT), "NUMBA_CACHE_DIR": str(cache),
           "OMP_NUM_THREADS": "1"}
    r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                       timeout=900)
    assert r.returncode == 0, r.stderr[-3000:]
    data = [p.name for p in cache.rglob("*.nbc")]
    for name in ("callbacks._residual-", "callbacks._jacobian_analytic-", "linsol._setup-",
                 "linsol._solve-", "residual.residual-",
                 "jacobian_analytic.fill_jacobian_analytic-"):
        assert any(f.startswith(name) for f in data), (name, data)
