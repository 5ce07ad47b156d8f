"""Benchmark: the default run of this checkout against an earlier version, side by side.

Run on demand:
    git archive 926583b | (mkdir -p /tmp/bd_old && tar -x -C /tmp/bd_old)
    python benchmarks/bench_versions.py --old /tmp/bd_old [--repeat 3] [--json out.json]

Each repeat runs ``simulate(load_scene("yang20_baseline"))`` (1 warm-up + 3 cage revolutions,
rtol 1e-6: the README's main job without writing files) once with the old tree and once with
this one, alternating, each in a fresh process (``PYTHONPATH`` points at the tree), after one
untimed warm-up process per tree so that both load their kernels from numba's cache. Reported
per tree: the process wall time from start to the returned Dataset (imports, model, initial
state, integration, projection), the integration's own wall and CPU time and IDA's step count
where the version records them, and the medians; the ratio new/old is formed per repeat
(same machine load) and its median quoted. The machine is shared: quote the ratios.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHILD = r"""
import json, os, sys, time
t0 = time.perf_counter()
c0 = time.process_time()
from bearingdae import load_scene, simulate
ds = simulate(load_scene("yang20_baseline"))
stats = json.loads(ds.attrs["solver_statistics"])
print(json.dumps({"process_wall_s": time.perf_counter() - t0,
                  "process_cpu_s": time.process_time() - c0,
                  "integration_wall_s": stats.get("wall_time_s"),
                  "steps": stats.get("steps"),
                  "residual_calls": stats.get("residual_calls"),
                  "cage_speed_mean_rad_s": float(ds.cage_speed.mean()),
                  "solver": ds.attrs.get("solver")}))
"""


def run(tree: Path) -> dict:
    env = {**os.environ, "PYTHONPATH": str(tree), "OMP_NUM_THREADS": "1",
           "OPENBLAS_NUM_THREADS": "1", "PYTHONWARNINGS": "ignore"}
    out = subprocess.run([sys.executable, "-c", CHILD], env=env, cwd=tree, check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", required=True, type=Path, help="tree of the earlier version")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--json", type=Path)
    a = ap.parse_args()
    trees = {"old": a.old.resolve(), "new": ROOT}
    for name, tree in trees.items():  # warm numba's cache of each tree, untimed
        t = time.perf_counter()
        run(tree)
        print(f"warm-up {name}: {time.perf_counter() - t:.1f} s", flush=True)
    rows = {"old": [], "new": []}
    for k in range(a.repeat):
        for name in ("old", "new"):
            r = run(trees[name])
            rows[name].append(r)
            print(f"repeat {k + 1} {name}: process {r['process_wall_s']:.2f} s, integration "
                  f"{r['integration_wall_s']:.2f} s, cpu {r['process_cpu_s']:.2f} s, "
                  f"steps {r['steps']}, mean cage speed {r['cage_speed_mean_rad_s']:.4f} rad/s",
                  flush=True)
    med = {n: {q: statistics.median(r[q] for r in rows[n])
               for q in ("process_wall_s", "integration_wall_s", "process_cpu_s")}
           for n in rows}
    ratios = {q: statistics.median(n[q] / o[q] for n, o in zip(rows["new"], rows["old"]))
              for q in ("process_wall_s", "integration_wall_s", "process_cpu_s")}
    print(json.dumps({"median": med, "ratio_new_over_old_median": ratios}, indent=1))
    if a.json:
        a.json.write_text(json.dumps({"rows": rows, "median": med, "ratios": ratios}, indent=1))


if __name__ == "__main__":
    main()
