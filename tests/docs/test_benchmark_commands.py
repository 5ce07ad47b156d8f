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
