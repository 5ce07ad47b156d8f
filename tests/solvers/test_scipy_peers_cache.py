"""The scipy peers' compiled kernels (solvers/scipy_peers.py) are cached: a second process
loads them from numba's cache instead of compiling them again (they once took the Jacobian
filler as an argument, which numba cannot cache: ~26 s of CPU in every process)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PROGRAM = r"""
import json, sys
import numpy as np
from bearingdae import load_scene
from bearingdae.solvers import scipy_peers as sp
from bearingdae.solvers.algebraic import initial_state
from bearingdae.system.model import build_model

m = build_model(load_scene("yang20_baseline"))
y0, _ = initial_state(m)
out = {}
for kind in sys.argv[1:]:
    ode = sp.ReducedODE(m, y0, 1e-6, dae_jacobian=kind)
    yd = y0[ode.diff].copy()
    f, J = ode.fun(0.0, yd), ode.jac(0.0, yd)
    out[kind] = [float(np.abs(f).sum()), float(np.abs(J).sum())]
out["stats"] = {name: [sum(k.stats.cache_hits.values()), sum(k.stats.cache_misses.values())]
                for name, k in (("rhs", sp.reduced_rhs), ("jac", sp.reduced_jacobian))}
print(json.dumps(out))
"""


@pytest.mark.slow  # two fresh processes, the first compiling on an empty cache
def test_a_second_process_loads_the_scipy_peers_kernels_from_the_cache(tmp_path):
    env = {**os.environ, "PYTHONPATH": str(ROOT), "NUMBA_CACHE_DIR": str(tmp_path / "numba"),
           "OMP_NUM_THREADS": "1"}

    def run():
        r = subprocess.run([sys.executable, "-c", PROGRAM, "analytic", "fd"],
                           capture_output=True, text=True, env=env)
        assert r.returncode == 0, r.stderr[-3000:]
        return json.loads(r.stdout.strip().splitlines()[-1])

    first, second = run(), run()
    # both Jacobian kinds: one specialisation each, compiled by the first process ...
    assert first["stats"] == {"rhs": [0, 2], "jac": [0, 2]}, first["stats"]
    # ... and loaded, not compiled, by the second, which computes the same numbers
    assert second["stats"] == {"rhs": [2, 0], "jac": [2, 0]}, second["stats"]
    for kind in ("analytic", "fd"):
        assert second[kind] == first[kind]
        assert all(v > 0.0 for v in first[kind])
