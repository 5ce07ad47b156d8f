"""The default run of this checkout against another git revision, side by side.

    python benchmarks/run.py versions --old REV [--repeat 3] [--set KEY=VALUE ...] [--json F]

REV is a git revision of this repository (exported once with ``git archive`` to a folder in the
temp directory, whose numba cache then stays warm) or a folder holding ``bearingdae/``. Each
repeat runs ``simulate(load_scene(CASE))`` (by default the README's main job without writing
files: yang20_baseline, 1 warm-up + 3 recorded cage revolutions, rtol 1e-6) once with each
tree, alternating, each in a fresh process with ``PYTHONPATH`` pointing at the tree, after one
untimed process per tree that loads (or compiles) its kernels. Reported per run: process wall
time from start to the returned Dataset (imports, model, initial state, integration,
projection), process CPU time, the integration's wall time, IDA's steps and the mean cage
speed; then the medians and the median of the per-repeat ratios new/old (same machine load).
Equal steps and mean cage speed mean the same trajectory (the default run is deterministic).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

from run import ROOT, header, median, overrides, tree, write_json

CHILD = r"""
import json, sys, time
t0, c0 = time.perf_counter(), time.process_time()
from bearingdae import load_scene, simulate
ds = simulate(load_scene(sys.argv[1], json.loads(sys.argv[2])))
stats = json.loads(ds.attrs.get("solver_statistics", "{}"))  # older trees: absent
print(json.dumps({"process_wall_s": time.perf_counter() - t0,
                  "process_cpu_s": time.process_time() - c0,
                  "integration_wall_s": stats.get("wall_time_s"),
                  "steps": stats.get("steps"), "residual_calls": stats.get("residual_calls"),
                  "cage_speed_mean_rad_s": float(ds.cage_speed.mean())}))
"""
QUANTITIES = ("process_wall_s", "process_cpu_s", "integration_wall_s")


def run_tree(path, case: str, over: dict) -> dict:
    env = {**os.environ, "PYTHONPATH": str(path), "PYTHONWARNINGS": "ignore"}
    out = subprocess.run([sys.executable, "-c", CHILD, case, json.dumps(over)], env=env,
                         cwd=path, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main(argv=None, name="versions") -> None:
    ap = argparse.ArgumentParser(prog=f"run.py {name}", description=__doc__.splitlines()[0])
    ap.add_argument("--old", required=True, help="git revision or folder of the other version")
    ap.add_argument("--new", default=str(ROOT), help="the version to compare (default: this "
                    "checkout)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--case", default="yang20_baseline")
    ap.add_argument("--set", action="append", metavar="KEY=VALUE",
                    help="scene override for both trees, e.g. numerics.cage_revolutions=0.5")
    ap.add_argument("--json", help="write the rows, medians and ratios here")
    a = ap.parse_args(argv)
    over = overrides(a.set)
    trees = {"old": tree(a.old), "new": tree(a.new)}
    header(f"{a.case}{f' {over}' if over else ''}: old = {trees['old']}, new = {trees['new']}")
    for label, path in trees.items():  # load (or compile) each tree's kernels, untimed
        t = time.perf_counter()
        run_tree(path, a.case, over)
        print(f"warm-up {label}: {time.perf_counter() - t:.1f} s", flush=True)
    rows = {"old": [], "new": []}
    for k in range(a.repeat):
        for label in ("old", "new"):
            r = run_tree(trees[label], a.case, over)
            rows[label].append(r)
            print(f"repeat {k + 1} {label}: process {r['process_wall_s']:.2f} s wall, "
                  f"{r['process_cpu_s']:.2f} s CPU; integration "
                  f"{r['integration_wall_s'] or 0:.2f} s; steps {r['steps']}; mean cage speed "
                  f"{r['cage_speed_mean_rad_s']:.6f} rad/s", flush=True)
    known = [q for q in QUANTITIES if all(r[q] is not None for n in rows for r in rows[n])]
    med = {n: {q: median(r[q] for r in rows[n]) for q in known} for n in rows}
    ratios = {q: median(n[q] / o[q] for n, o in zip(rows["new"], rows["old"])) for q in known}
    same = all(n["steps"] == o["steps"] and n["cage_speed_mean_rad_s"]
               == o["cage_speed_mean_rad_s"] for n, o in zip(rows["new"], rows["old"]))
    for q in known:
        print(f"{q:20s} old {med['old'][q]:7.2f}  new {med['new'][q]:7.2f}  ratio new/old "
              f"(median per repeat) {ratios[q]:.3f}")
    print(f"same steps and mean cage speed in both: {'yes' if same else 'no'}")
    write_json(a.json, {"benchmark": name, "case": a.case, "overrides": over,
                        "old": str(trees["old"]), "new": str(trees["new"]), "rows": rows,
                        "median": med, "ratio_new_over_old": ratios, "same_trajectory": same})
