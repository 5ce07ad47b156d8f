"""The default run of this checkout against another git revision, side by side.

    python benchmarks/run.py versions --old REV [--repeat 3] [--set KEY=VALUE ...]
        [--old-env NAME=VALUE ...] [--json F]

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
``--old-env NAME=VALUE`` sets an environment variable in the old side's processes only: with
``--old .`` it compares one tree under two settings (``BEARINGDAE_VECTOR_BITS=256``: the
kernels compiled for 256-bit vectors, util/vector_width.py).

With ``--cli`` each run is the command ``bearingdae run CASE -o FILE --no-progress`` instead
(overview PNG included; ``--no-plot`` leaves it out), its process wall and CPU time (user +
system, from ``wait4``) measured from outside; and the data variables of the two trees' files
of the last repeat are compared with ``np.array_equal`` (NaN equal to NaN), each.

With ``--workprecision`` the two trees are compared at equal error instead, as the work-precision
study does (docs/performance.md, "Work-precision"): IDA over the study's window (the first 0.2
cage revolution from t = 0) at each rtol of ``--rtols`` (atol = rtol / 100), every rung of a tree
in one process after an untimed run that loads its kernels, the trees alternating per repeat;
CPU of ``simulate`` per run (``time.process_time``, median over repeats); errors of both trees
against one reference, this tree's IDA at rtol 1e-10 (relative RMS, as the study). It prints
the table, the old tree's CPU at the error of this tree's rtol-1e-6 run (log-log along the
old tree's Pareto front, studies/workprecision ``time_at_error``) as a ratio, and writes the
figure and CSV (``-o DIR``) and ``--json``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

from run import ROOT, header, load, median, overrides, run_process, summary, tree, write_json

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

#: one tree's work-precision ladder in one process (``--workprecision``): argv = case, base
#: overrides, rtols (JSON), output folder, label; one JSON line per rung
WP_CHILD = r"""
import json, sys, time
import numpy as np
from bearingdae import load_scene, simulate
case, base, rtols, out, label = (sys.argv[1], json.loads(sys.argv[2]), json.loads(sys.argv[3]),
                                 sys.argv[4], sys.argv[5])
simulate(load_scene(case, {**base, "numerics.cage_revolutions": 0.01}))  # kernels, untimed
for rtol in rtols:
    scene = load_scene(case, {**base, "numerics.rtol": rtol,
                              "numerics.atol": min(1e-2 * rtol, 1e-4)})
    c0 = time.process_time()
    ds = simulate(scene)
    cpu = time.process_time() - c0
    t = ds.time.values
    t = t / np.timedelta64(1, "s") if t.dtype.kind == "m" else np.asarray(t, float)
    path = f"{out}/{label}-{rtol:.0e}.npz"
    np.savez(path, time=t, **{q: ds[q].values for q in
                              ("cage_speed", "orbit_speed", "spin_speed", "skew_angle",
                               "contact_force") if q in ds})
    stats = json.loads(ds.attrs.get("solver_statistics", "{}"))
    print(json.dumps({"rtol": rtol, "cpu_s": cpu, "steps": stats.get("steps"),
                      "residual_calls": stats.get("residual_calls"), "file": path}), flush=True)
"""
#: the quantities of the work-precision comparison, and those of its figure
WP_QUANTITIES = ("cage_speed", "orbit_speed", "spin_speed", "skew_angle", "contact_force")
WP_PANELS = ("cage_speed", "skew_angle", "contact_force")
WP_REFERENCE_RTOL = 1e-10
WP_TARGET_RTOL = 1e-6


def run_cli(path, case: str, over: dict, out: str, plot: bool,
            extra_env: dict | None = None) -> dict:
    """``bearingdae run`` of the tree at ``path`` in a process of its own: its wall and CPU
    time, and the steps and mean cage speed of the file it wrote."""
    import numpy as np
    import xarray as xr

    ru, wall = run_process(path, case, over, out, plot, extra_env)
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


def run_tree(path, case: str, over: dict, extra_env: dict | None = None) -> dict:
    env = {**os.environ, "PYTHONPATH": str(path), "PYTHONWARNINGS": "ignore",
           **(extra_env or {})}
    out = subprocess.run([sys.executable, "-c", CHILD, case, json.dumps(over)], env=env,
                         cwd=path, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def wp_tree(path, case: str, base: dict, rtols, out: str, label: str) -> list[dict]:
    """One tree's ladder (``WP_CHILD``) in a process of its own: a row per rung."""
    env = {**os.environ, "PYTHONPATH": str(path), "PYTHONWARNINGS": "ignore"}
    text = subprocess.run([sys.executable, "-c", WP_CHILD, case, json.dumps(base),
                           json.dumps(list(rtols)), out, label], env=env, cwd=path, check=True,
                          capture_output=True, text=True).stdout
    return [json.loads(line) for line in text.splitlines() if line.startswith("{")]


def wp_errors(file: str, ref: dict) -> dict:
    """Relative RMS error of each quantity of a run's file against the reference arrays,
    over the run's times inside the reference's window (as the work-precision study)."""
    import numpy as np

    from bearingdae.studies.workprecision.errors import relative_rms_errors

    with np.load(file) as z:
        return relative_rms_errors(z["time"], {k: z[k] for k in z.files}, ref["time"], ref,
                                   WP_QUANTITIES)


def wp_figure(table: dict, labels: dict, title: str, png: str) -> None:
    """CPU against each panel quantity's error, one curve per tree, rungs labelled."""
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(WP_PANELS), figsize=(4.2 * len(WP_PANELS), 3.9),
                             constrained_layout=True)
    for ax, q in zip(axes, WP_PANELS):
        for tree_, style in (("old", dict(color="0.45", marker="s", ls="--")),
                             ("new", dict(color="tab:blue", marker="o", ls="-"))):
            rows = table[tree_]
            ax.loglog([r["errors"][q] for r in rows], [r["cpu_s"] for r in rows],
                      label=labels[tree_], **style)
            for r in rows:
                ax.annotate(f"{r['rtol']:.0e}", (r["errors"][q], r["cpu_s"]), fontsize=7,
                            xytext=(3, 3), textcoords="offset points", color=style["color"])
        ax.set_xlabel(f"{q.replace('_', ' ')}: relative RMS error")
        ax.set_ylabel("CPU of simulate [s]")
        ax.yaxis.set_major_formatter(plt.FormatStrFormatter("%g"))
        ax.yaxis.set_minor_formatter(plt.FormatStrFormatter("%g"))
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.savefig(png, dpi=110)
    plt.close(fig)


def revision(spec: str) -> str:
    """A tree's name for a legend: the commit of a checkout or a revision, else the folder."""
    path = Path(spec)
    cmd = (["git", "-C", str(path), "rev-parse", "--short=7", "HEAD"]
           if (path / "bearingdae").is_dir()
           else ["git", "-C", str(ROOT), "rev-parse", "--short=7", f"{spec}^{{commit}}"])
    return subprocess.run(cmd, capture_output=True, text=True).stdout.strip() or path.name


def workprecision(a, trees: dict, over: dict) -> None:
    """``--workprecision``: the two trees' IDA ladders at equal error (module docstring)."""
    import csv
    import tempfile

    import numpy as np

    from bearingdae.studies.workprecision.errors import time_at_error

    rtols = [float(v) for v in a.rtols.split(",")]
    if WP_TARGET_RTOL not in rtols:
        raise SystemExit(f"--rtols {a.rtols!r}: must include {WP_TARGET_RTOL:g}, the default")
    base = {"numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 0.2, **over}
    scratch = tempfile.mkdtemp(prefix="bearingdae-versions-wp-")
    loads = [load()]
    ref_row = wp_tree(trees["new"], a.case, base, [WP_REFERENCE_RTOL], scratch, "reference")[0]
    with np.load(ref_row["file"]) as z:
        ref = {k: z[k] for k in z.files}
    cpu = {"old": [], "new": []}
    rows = {}
    for k in range(a.repeat):
        for label in ("old", "new"):
            got = wp_tree(trees[label], a.case, base, rtols, scratch, label)
            cpu[label].append([r["cpu_s"] for r in got])
            rows[label] = got
            print(f"repeat {k + 1} {label}: " + ", ".join(
                f"{r['rtol']:.0e} {r['cpu_s']:.2f} s" for r in got), flush=True)
        loads.append(load())
    table = {label: [{"rtol": r["rtol"], "steps": r["steps"],
                      "residual_calls": r.get("residual_calls"),
                      "cpu_s": median(c[i] for c in cpu[label]),
                      "cpu_range_s": [min(c[i] for c in cpu[label]),
                                      max(c[i] for c in cpu[label])],
                      "errors": wp_errors(r["file"], ref)}
                     for i, r in enumerate(rows[label])] for label in rows}
    i6 = rtols.index(WP_TARGET_RTOL)
    ratio_default = median(n[i6] / o[i6] for n, o in zip(cpu["new"], cpu["old"]))
    at_equal = {}
    for q in WP_QUANTITIES:
        target = table["new"][i6]["errors"].get(q)
        if target is None:
            continue
        t_old, kind = time_at_error([r["errors"][q] for r in table["old"]],
                                    [r["cpu_s"] for r in table["old"]], target)
        at_equal[q] = {"new_error": target, "old_cpu_s": t_old, "kind": kind,
                       "new_over_old": table["new"][i6]["cpu_s"] / t_old}
    print(f"\n| tree | rtol | CPU [s] (range) | steps | residual calls | "
          + " | ".join(q.replace("_", " ") for q in WP_QUANTITIES) + " |")
    print("|---|---|---|---|---|" + "---|" * len(WP_QUANTITIES))
    for label in ("old", "new"):
        for r in table[label]:
            print(f"| {label} | {r['rtol']:.0e} | {r['cpu_s']:.2f} ({r['cpu_range_s'][0]:.2f}"
                  f"–{r['cpu_range_s'][1]:.2f}) | {r['steps'] or '–'} | "
                  f"{r['residual_calls'] or '–'} | "
                  + " | ".join(f"{r['errors'].get(q, float('nan')):.1e}"
                               for q in WP_QUANTITIES) + " |")
    print(f"\nat rtol {WP_TARGET_RTOL:g}: new/old CPU {ratio_default:.3f} (median per repeat)")
    for q, e in at_equal.items():
        print(f"at the new rtol-{WP_TARGET_RTOL:g} {q} error {e['new_error']:.2e}: old "
              f"{e['old_cpu_s']:.2f} s ({e['kind']}), new/old {e['new_over_old']:.3f}")
    labels = {label: f"{label}: {revision(spec)}" for label, spec in (("old", a.old),
                                                                      ("new", a.new))}
    if a.output:
        out = Path(a.output)
        out.mkdir(parents=True, exist_ok=True)
        with open(out / "workprecision_versions.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["tree", "rtol", "cpu_s", "steps", "residual_calls"]
                       + [f"{q}_rel_rms" for q in WP_QUANTITIES])
            for label in ("old", "new"):
                for r in table[label]:
                    w.writerow([label, f"{r['rtol']:.0e}", f"{r['cpu_s']:.3f}", r["steps"],
                                r["residual_calls"]]
                               + [f"{r['errors'].get(q, float('nan')):.3e}"
                                  for q in WP_QUANTITIES])
        wp_figure(table, labels, f"{a.case}, first 0.2 cage revolution: IDA, old against new "
                  f"(reference: new at rtol {WP_REFERENCE_RTOL:g})",
                  str(out / "workprecision_versions.png"))
        print(f"wrote {out / 'workprecision_versions.csv'}, {out / 'workprecision_versions.png'}")
    write_json(a.json, {"benchmark": "versions --workprecision", "case": a.case,
                        "overrides": base, "old": str(trees["old"]), "new": str(trees["new"]),
                        "repeat": a.repeat, "load_1min": loads, "rtols": rtols,
                        "reference_rtol": WP_REFERENCE_RTOL, "table": table,
                        "cpu_per_repeat": cpu, "new_over_old_at_default_rtol": ratio_default,
                        "at_equal_error": at_equal})


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
    ap.add_argument("--old-env", action="append", metavar="NAME=VALUE", default=[],
                    help="an environment variable of the old side's processes only, e.g. "
                    "BEARINGDAE_VECTOR_BITS=256 (with --old .: one tree, two settings)")
    ap.add_argument("--cli", action="store_true", help="time the command `bearingdae run` "
                    "(writing its file) instead of simulate() in a script")
    ap.add_argument("--no-plot", action="store_true", help="with --cli: no overview PNG")
    ap.add_argument("--workprecision", action="store_true", help="compare at equal error: "
                    "IDA ladders of both trees over the work-precision window (docstring)")
    ap.add_argument("--rtols", default="1e-4,1e-5,1e-6,1e-7,1e-8",
                    help="--workprecision: IDA's rtols (must include 1e-6)")
    ap.add_argument("-o", "--output", help="--workprecision: folder of the figure and CSV")
    a = ap.parse_args(argv)
    old_env = {}
    for pair in a.old_env:
        key, sep, value = pair.partition("=")
        if not sep or not key:
            ap.error(f"--old-env {pair[:100]!r}: expected NAME=VALUE, e.g. "
                     "BEARINGDAE_VECTOR_BITS=256")
        old_env[key] = value
    if old_env and a.workprecision:
        ap.error("--old-env applies to the timed runs, not to --workprecision")
    import tempfile

    scratch = tempfile.mkdtemp(prefix="bearingdae-versions-")

    def run_one(label, path):
        env = old_env if label == "old" else None
        if not a.cli:
            return run_tree(path, a.case, over, env)
        return run_cli(path, a.case, over, os.path.join(scratch, f"{label}.nc"),
                       not a.no_plot, env)

    over = overrides(a.set)
    trees = {"old": tree(a.old), "new": tree(a.new)}
    if a.workprecision:
        header(f"{a.case}{f' {over}' if over else ''} at equal error: old = {trees['old']}, "
               f"new = {trees['new']}")
        return workprecision(a, trees, over)
    shown = f" with {old_env}" if old_env else ""
    header(f"{a.case}{f' {over}' if over else ''}: old = {trees['old']}{shown}, "
           f"new = {trees['new']}")
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
                        "old": str(trees["old"]), "old_env": old_env,
                        "new": str(trees["new"]), "rows": rows,
                        "median": med, "ratio_new_over_old": ratios, "same_trajectory": same})


def med_of(rows, label, q):
    return median(r[q] for r in rows[label])
