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

With ``--cli`` each run is the command ``bearingdae run CASE -o FILE --no-progress`` instead
(overview PNG included; ``--no-plot`` leaves it out), its process wall and CPU time (user +
system, from ``wait4``) measured from outside; and the data variables of the two trees' files
of the last repeat are compared with ``np.array_equal`` (NaN equal to NaN), each.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

from run import ROOT, header, median, overrides, run_process, summary, tree, write_json

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


def run_cli(path, case: str, over: dict, out: str, plot: bool) -> dict:
    """``bearingdae run`` of the tree at ``path`` in a process of its own: its wall and CPU
    time, and the steps and mean cage speed of the file it wrote."""
    import numpy as np
    import xarray as xr

    ru, wall = run_process(path, case, over, out, plot)
    with xr.open_dataset(out, decode_timedelta=False) as ds:
        stats = json.loads(ds.attrs.get("solver_statistics", "{}"))
        return {"process_wall_s": wall, "process_cpu_s": ru.ru_utime + ru.ru_stime,
                "integration_wall_s": stats.get("wall_time_s"), "steps": stats.get("steps"),
                "residual_calls": stats.get("residual_calls"),
                "cage_speed_mean_rad_s": float(np.mean(ds.cage_speed.values)),
                "max_rss_MB": ru.ru_maxrss / 1024, "file_MB": os.path.getsize(out) / 2**20}


def same_data(a: str, b: str) -> tuple[bool, list[str]]:
    """(every data variable of the two files equal bit for bit, those that are not)."""
    import numpy as np
    import xarray as xr

    with xr.open_dataset(a, decode_timedelta=False) as x, \
            xr.open_dataset(b, decode_timedelta=False) as y:
        names = set(x.data_vars) | set(y.data_vars)
        differ = sorted(n for n in names if n not in x or n not in y or not np.array_equal(
            x[n].values, y[n].values, equal_nan=x[n].dtype.kind == "f"))
        return not differ, differ


def run_tree(path, case: str, over: dict) -> dict:
    env = {**os.environ, "PYTHONPATH": str(path), "PYTHONWARNINGS": "ignore"}
    out = subprocess.run([sys.executable, "-c", CHILD, case, json.dumps(over)], env=env,
                         cwd=path, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main(argv=None, name="versions") -> None:
    ap = argparse.ArgumentParser(prog=f"run.py {name}", description=summary(__doc__))
    ap.add_argument("--old", required=True, help="git revision or folder of the other version")
    ap.add_argument("--new", default=str(ROOT), help="the version to compare (default: this "
                    "checkout)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--case", default="yang20_baseline")
    ap.add_argument("--set", action="append", metavar="KEY=VALUE",
                    help="scene override for both trees, e.g. numerics.cage_revolutions=0.5")
    ap.add_argument("--json", help="write the rows, medians and ratios here")
    ap.add_argument("--cli", action="store_true", help="time the command `bearingdae run` "
                    "(writing its file) instead of simulate() in a script")
    ap.add_argument("--no-plot", action="store_true", help="with --cli: no overview PNG")
    a = ap.parse_args(argv)
    import tempfile

    scratch = tempfile.mkdtemp(prefix="bearingdae-versions-")

    def run_one(label, path):
        if not a.cli:
            return run_tree(path, a.case, over)
        return run_cli(path, a.case, over, os.path.join(scratch, f"{label}.nc"),
                       not a.no_plot)

    over = overrides(a.set)
    trees = {"old": tree(a.old), "new": tree(a.new)}
    header(f"{a.case}{f' {over}' if over else ''}: old = {trees['old']}, new = {trees['new']}")
    for label, path in trees.items():  # load (or compile) each tree's kernels, untimed
        t = time.perf_counter()
        run_one(label, path)
        print(f"warm-up {label}: {time.perf_counter() - t:.1f} s", flush=True)
    rows = {"old": [], "new": []}
    for k in range(a.repeat):
        for label in ("old", "new"):
            r = run_one(label, trees[label])
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
    identical = differ = None
    if a.cli:
        identical, differ = same_data(os.path.join(scratch, "old.nc"),
                                      os.path.join(scratch, "new.nc"))
        print(f"data variables of the two files equal bit for bit: "
              f"{'yes' if identical else 'no: ' + ', '.join(differ)}")
        for q in ("max_rss_MB", "file_MB"):
            print(f"{q:20s} old {med_of(rows, 'old', q):7.1f}  new {med_of(rows, 'new', q):7.1f}")
    write_json(a.json, {"benchmark": name, "case": a.case, "overrides": over, "cli": a.cli,
                        "data_variables_identical": identical, "differing": differ,
                        "old": str(trees["old"]), "new": str(trees["new"]), "rows": rows,
                        "median": med, "ratio_new_over_old": ratios, "same_trajectory": same})


def med_of(rows, label, q):
    return median(r[q] for r in rows[label])
