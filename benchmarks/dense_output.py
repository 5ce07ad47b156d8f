"""What an output sample costs, and how much memory a run holds, by samples per revolution.

    python benchmarks/run.py dense-output [--samples 200 4000] [--warmup 1] [--revolutions 1]
        [--repeat 2] [--case yang20_baseline] [--json F]
    python benchmarks/run.py memory [--revolutions 3 30] [--old REV] [--set KEY=VALUE ...]
                                    [--json F]

Both benchmarks ask what the record costs: ``dense-output`` by samples per revolution (time,
and the peak memory of each run), ``memory`` by recorded length (the peak memory of
``bearingdae run``; ``MEMORY_DOC`` below says how).

Each repeat runs ``simulate`` of the scene once per ``numerics.samples_per_cage_revolution``
value, alternating, each in a fresh process (so that its peak resident memory is its own),
after one untimed process that loads the kernels. Sampling does not change IDA's steps (it
interpolates at the output times), so the difference in time between two settings is the cost
of the extra samples: interpolation, projection onto the algebraic equations, diagnostics and
the Dataset. Reported: process wall and CPU time, IDA's integration wall time, steps, peak RSS,
the largest pocket force at every step (``cage_force_max``, which must not depend on the
sampling beyond round-off) and at the samples,
the ratios of CPU and wall time to the first setting (median per repeat; on a shared machine
the CPU ratio is the steadier one) and the CPU cost per extra sample. Then, in this process,
the projection alone on 601 samples of the first 13 ms: ``AlgebraicProjector.batch`` (what
``simulate`` uses), the per-sample ``AlgebraicProjector`` and the static numpy Newton.

With ``--cli`` each run is the command ``bearingdae run CASE -o FILE --no-plot`` instead: the
record streamed to a compressed NetCDF file and checkpointed, as a user runs it; its wall and
CPU time (user + system, from ``wait4``) measured from outside, and ``cage_force_max`` read
from the file.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

from run import ROOT, header, median, overrides, run_process, summary, tree, write_json

CHILD = r"""
import json, resource, sys, time
t0, c0 = time.perf_counter(), time.process_time()
from bearingdae import load_scene, simulate
ds = simulate(load_scene(sys.argv[1], json.loads(sys.argv[2])))
st = json.loads(ds.attrs["solver_statistics"])
wall, cpu = time.perf_counter() - t0, time.process_time() - c0
import numpy as np
peak = ds.cage_force_max.values if "cage_force_max" in ds else None
print(json.dumps({"wall_s": wall, "cpu_s": cpu,
                  "integration_wall_s": st.get("wall_time_s"), "steps": st.get("steps"),
                  "samples": int(ds.sizes["time"]),
                  "max_rss_MB": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                  "cage_force_max_N": None if peak is None else peak.tolist(),
                  "sampled_peak_cage_force_N": float(np.abs(ds.cage_force).max())}))
"""


def _peak(r: dict) -> str:
    peak = r.get("cage_force_max_N")
    return "n/a" if peak is None else f"{max(max(x) for x in peak):.4f}"


def run_child(case: str, over: dict) -> dict:
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    out = subprocess.run([sys.executable, "-c", CHILD, case, json.dumps(over)], env=env,
                         cwd=ROOT, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def projection(case: str) -> dict:
    """ms per sample of the compiled projector and of the static Newton, 601 samples."""
    import numpy as np

    from bearingdae import load_scene
    from bearingdae.solvers.algebraic import AlgebraicProjector, initial_state, project_algebraic
    from bearingdae.solvers.ida import IDA
    from bearingdae.system.model import build_model

    m = build_model(load_scene(case))
    y0, yp0 = initial_state(m)
    sol = IDA().integrate(m, y0, yp0, np.linspace(0.0, 0.013, 601))
    P = AlgebraicProjector(m)
    P(sol.t[0], sol.y[0])  # compiled (or loaded from the cache) outside the timing
    P.batch(sol.t[:1], sol.y[:1])
    t = time.process_time()
    new = [P(tk, y) for tk, y in zip(sol.t, sol.y)]
    t_new = (time.process_time() - t) / len(new) * 1e3
    t = time.process_time()
    old = [project_algebraic(m, tk, y) for tk, y in zip(sol.t, sol.y)]
    t_old = (time.process_time() - t) / len(old) * 1e3
    diff = max(float(np.abs(a[0] - b[0]).max()) for a, b in zip(new, old))
    t = time.process_time()
    Yb, _, settled, _ = P.batch(sol.t, sol.y)  # what ``simulate`` uses: all samples at once
    t_batch = (time.process_time() - t) / len(new) * 1e3
    same = bool(settled.all() and all(np.array_equal(a[0], b) for a, b in zip(new, Yb)))
    return {"projector_ms": t_new, "batch_ms": t_batch, "batch_identical": same,
            "static_newton_ms": t_old, "max_scaled_difference": diff, "fallbacks": P.fallbacks}


#: the absolute floor [N] of the comparison of the peak pocket forces between samplings (main)
PEAK_FORCE_FLOOR_N = 1e-12


def run_cli(case: str, over: dict) -> dict:
    """``bearingdae run`` of this checkout with the overrides ``over``: the row of
    :func:`run_child` from the file it wrote and the process's ``wait4`` usage."""
    import numpy as np
    import xarray as xr

    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "run.nc")
        ru, wall = run_process(ROOT, case, over, out, plot=False)
        with xr.open_dataset(out, decode_timedelta=False) as ds:
            st = json.loads(ds.attrs.get("solver_statistics", "{}"))
            peak = ds.cage_force_max.values if "cage_force_max" in ds else None
            return {"wall_s": wall, "cpu_s": ru.ru_utime + ru.ru_stime,
                    "integration_wall_s": st.get("wall_time_s"), "steps": st.get("steps"),
                    "samples": int(ds.sizes["time"]), "max_rss_MB": ru.ru_maxrss / 1024,
                    "cage_force_max_N": None if peak is None else peak.tolist(),
                    "sampled_peak_cage_force_N": float(np.abs(ds.cage_force.values).max())}


def main(argv=None, name="dense-output") -> None:
    import numpy as np

    if name == "memory":
        return memory_main(argv, name)
    ap = argparse.ArgumentParser(prog=f"run.py {name}", description=summary(__doc__))
    ap.add_argument("--samples", type=int, nargs="+", default=[200, 4000],
                    help="samples per cage revolution to compare (the first is the reference)")
    ap.add_argument("--case", default="yang20_baseline")
    ap.add_argument("--warmup", type=float, default=1.0, help="warm-up cage revolutions")
    ap.add_argument("--revolutions", type=float, default=1.0, help="recorded cage revolutions")
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--json", help="write the rows and ratios here")
    ap.add_argument("--cli", action="store_true",
                    help="time the command `bearingdae run` (file written) instead of simulate")
    a = ap.parse_args(argv)
    run = run_cli if a.cli else run_child
    window = {"numerics.warmup_cage_revolutions": a.warmup,
              "numerics.cage_revolutions": a.revolutions}
    header(f"dense output on {a.case}, {a.warmup:g} + {a.revolutions:g} cage revolutions"
           + (", `bearingdae run`" if a.cli else ""))
    run(a.case, {**window, "numerics.cage_revolutions": 0.01})  # kernels loaded, untimed
    rows = {n: [] for n in a.samples}
    for rep in range(a.repeat):
        for n in a.samples:
            r = run(a.case, {**window, "numerics.samples_per_cage_revolution": n})
            rows[n].append(r)
            print(f"repeat {rep + 1}, {n:6d} samples/rev: wall {r['wall_s']:6.2f} s, CPU "
                  f"{r['cpu_s']:6.2f} s, integration {r['integration_wall_s']:6.2f} s, steps "
                  f"{r['steps']}, {r['samples']} samples, peak RSS {r['max_rss_MB']:.0f} MB; "
                  f"peak pocket force {_peak(r)} N at every step, "
                  f"{r['sampled_peak_cage_force_N']:.4f} N sampled", flush=True)
    ref = a.samples[0]
    result = {"benchmark": name, "case": a.case, "window": window, "cli": a.cli, "rows": rows,
              "wall_ratio_to_first": {}, "cpu_ratio_to_first": {}, "cpu_ms_per_extra_sample": {}}
    for n in a.samples[1:]:
        wall, cpu = (median(r[q] / f[q] for r, f in zip(rows[n], rows[ref]))
                     for q in ("wall_s", "cpu_s"))
        per = median((r["cpu_s"] - f["cpu_s"]) / (r["samples"] - f["samples"]) * 1e3
                     for r, f in zip(rows[n], rows[ref]))
        result["wall_ratio_to_first"][n], result["cpu_ratio_to_first"][n] = wall, cpu
        result["cpu_ms_per_extra_sample"][n] = per
        print(f"{n} against {ref} samples/rev (medians per repeat): CPU ratio {cpu:.2f}, wall "
              f"ratio {wall:.2f}; {per:.2f} ms of CPU per extra sample")
    # to round-off of the largest: the first and last samples enter it, and their projected
    # contact states differ in the last digits with the previous sample (its starting guess).
    # Where no roller touches a bar (a short window from the start) every value is the contact
    # smoothing's tail (~1e-9 N), whose relative round-off is larger: the floor of
    # PEAK_FORCE_FLOOR_N, far below the 0.1 mN the peak is printed to, takes that apart
    first = np.asarray(rows[ref][0]["cage_force_max_N"], float)
    same = all(np.allclose(np.asarray(r["cage_force_max_N"], float), first, rtol=1e-9,
                           atol=max(1e-9 * np.nanmax(np.abs(first)), PEAK_FORCE_FLOOR_N),
                           equal_nan=True)
               for n in a.samples for r in rows[n])
    result["cage_force_max_equal"] = same
    print(f"cage_force_max (every step, per roller and end) the same at every sampling: "
          f"{'yes' if same else 'NO'}")
    if a.cli:
        write_json(a.json, result)
        return
    result["projection"] = p = projection(a.case)
    print(f"projection of 601 samples: batch (simulate's) {p['batch_ms']:.3f} ms per sample, "
          f"identical to the per-sample projector: {'yes' if p['batch_identical'] else 'NO'};")
    print(f"per-sample projector {p['projector_ms']:.3f} ms per sample,"
          f" static Newton {p['static_newton_ms']:.3f} ms; largest difference "
          f"{p['max_scaled_difference']:.1e} (scaled units), fallbacks {p['fallbacks']}")
    write_json(a.json, result)


# --- memory: the peak RSS of `bearingdae run` against the recorded length ---------------
#: the ``memory`` benchmark's description (its first line is its ``--help`` summary)
MEMORY_DOC = """Peak memory of `bearingdae run` against the recorded length: does it grow?

    python benchmarks/run.py memory [--revolutions 3 30] [--old REV] [--set KEY=VALUE ...]
                                    [--json F]

Each point is one ``bearingdae run CASE -o FILE --no-progress --set
numerics.cage_revolutions=N`` (overview PNG included) in a fresh process, after one untimed
short run per tree that loads (or compiles) its kernels. Measured from outside the process
with ``os.wait4``: the peak resident set size (``ru_maxrss``; the child that compiles the
Jacobian on a cold start is not in it: it is compiled before the timed runs), the CPU time
(user + system) and the wall time; and the size of the file written. ``--old REV`` measures
another git revision (or a folder holding ``bearingdae/``) at the same points, interleaved.

Streaming (results/streamed_record.py) keeps one block of samples in memory: the peaks at 3 and 30
revolutions must be within 10 % of each other (docs/performance.md, "Memory").
"""


def one_run(path, case: str, over: dict, out: str) -> dict:
    ru, wall = run_process(path, case, over, out)
    return {"max_rss_MB": ru.ru_maxrss / 1024, "cpu_s": ru.ru_utime + ru.ru_stime,
            "wall_s": wall, "file_MB": os.path.getsize(out) / 2**20}


def memory_main(argv=None, name="memory") -> None:
    ap = argparse.ArgumentParser(prog=f"run.py {name}", description=summary(MEMORY_DOC))
    ap.add_argument("--revolutions", type=float, nargs="+", default=[3.0, 30.0],
                    help="recorded cage revolutions of each point (default 3 30)")
    ap.add_argument("--old", help="also measure this git revision or folder")
    ap.add_argument("--case", default="yang20_baseline")
    ap.add_argument("--set", action="append", metavar="KEY=VALUE",
                    help="further scene overrides, e.g. numerics.samples_per_cage_revolution=400")
    ap.add_argument("--json", help="write the rows here")
    a = ap.parse_args(argv)
    over = overrides(a.set)
    trees = {"new": tree(str(ROOT))}
    if a.old:
        trees["old"] = tree(a.old)
    header(f"{a.case}{f' {over}' if over else ''}: peak RSS of bearingdae run against the "
           f"recorded length; trees {', '.join(f'{k} = {v}' for k, v in trees.items())}")
    scratch = tempfile.mkdtemp(prefix="bearingdae-memory-")
    for label, path in trees.items():  # kernels loaded (or compiled) first, untimed
        one_run(path, a.case, {**over, "numerics.cage_revolutions": 0.05,
                               "numerics.warmup_cage_revolutions": 0},
                os.path.join(scratch, f"warm-{label}.nc"))
    rows = []
    for revs in a.revolutions:
        for label, path in trees.items():
            out = os.path.join(scratch, f"{label}-{revs:g}.nc")
            r = one_run(path, a.case, {**over, "numerics.cage_revolutions": revs}, out)
            os.unlink(out)
            r.update(tree=label, cage_revolutions=revs)
            rows.append(r)
            print(f"{label}: {revs:g} recorded cage revolutions: peak RSS {r['max_rss_MB']:.0f} "
                  f"MB, CPU {r['cpu_s']:.1f} s, wall {r['wall_s']:.1f} s, file "
                  f"{r['file_MB']:.1f} MB", flush=True)
    for label in trees:
        mine = [r for r in rows if r["tree"] == label]
        if len(mine) > 1:
            lo, hi = mine[0]["max_rss_MB"], mine[-1]["max_rss_MB"]
            print(f"{label}: peak RSS at {mine[-1]['cage_revolutions']:g} over "
                  f"{mine[0]['cage_revolutions']:g} revolutions: {hi / lo:.3f}")
    write_json(a.json, {"benchmark": name, "case": a.case, "overrides": over, "rows": rows,
                        "trees": {k: str(v) for k, v in trees.items()}})
