"""Compile CPU of the two DAE kernels from an empty numba cache, this checkout against another
(docs/performance.md, "Third pass").

    python benchmarks/bench_kernel_compile.py [--old /tmp/old] [--rounds 3]

Each round runs one fresh process per tree (``PYTHONPATH`` points at it) with
``NUMBA_CACHE_DIR`` set to a new empty folder, and reports the process CPU time of the first
``residual_flat`` call (IDA's residual callback) and of the first
``jacobian_analytic_sparse`` call on the baseline model, before anything else is compiled (the
static solve of the initial state would compile the residual first), i.e. their compilation
including every kernel they inline or call. The trees alternate round by round (same machine load).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHILD = r"""
import json, time
import numpy as np
from bearingdae import load_scene
from bearingdae.solvers.ida import _jacobian_work, sparsity_pattern
from bearingdae.system.jacobian_analytic import analytic_work, jacobian_analytic_sparse
from bearingdae.system.model import build_model
from bearingdae.system.residual import residual_flat
m = build_model(load_scene("yang20_baseline"))
y, yp = np.full(m.size, 0.5), np.zeros(m.size)  # any state: only the compilation counts
jd0, _ = _jacobian_work(m, sparsity_pattern(m))
jd = analytic_work(m, jd0[1], jd0[2])
JJ, res = np.zeros(jd0[1].size), np.zeros(m.size)
t0 = time.process_time()
residual_flat(0.0, y, yp, res, m.work)
t1 = time.process_time()
jacobian_analytic_sparse(0.0, y, yp, res, 1e3, JJ, m.data, jd)
t2 = time.process_time()
print(json.dumps({"residual_s": t1 - t0, "jacobian_s": t2 - t1}))
"""


def _measure(tree: Path) -> dict:
    with tempfile.TemporaryDirectory(prefix="bd_numba_cache_") as cache:
        env = {**os.environ, "PYTHONPATH": str(tree), "NUMBA_CACHE_DIR": cache,
               "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
        out = subprocess.run([sys.executable, "-c", CHILD], env=env, cwd=tree, check=True,
                             capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", help="root of another checkout to compare with")
    ap.add_argument("--rounds", type=int, default=3)
    a = ap.parse_args(argv)
    trees = ([("old", Path(a.old))] if a.old else []) + [("new", ROOT)]
    for r in range(a.rounds):
        for name, tree in trees:
            m = _measure(tree)
            print(f"round {r + 1} {name}: residual_flat {m['residual_s']:.2f} s, analytic "
                  f"Jacobian {m['jacobian_s']:.2f} s, sum {m['residual_s'] + m['jacobian_s']:.2f} "
                  "s of compile CPU", flush=True)


if __name__ == "__main__":
    main()
