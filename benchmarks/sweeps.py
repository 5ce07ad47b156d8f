"""Sweeps on a dask LocalCluster: the paper set, scaling over workers, a skid map.

    python benchmarks/run.py paper [--workers 2] [--set KEY=VALUE ...] [--out DIR]
    python benchmarks/run.py sweep-scaling [--workers 1 2] [--repeat 2] [--speeds ...]
        [--set KEY=VALUE ...]
    python benchmarks/run.py skidmap [--case yang20_baseline] [--speeds ...] [--loads ...]
        [--workers 2] [--set KEY=VALUE ...] [--out DIR]

Each starts from an empty run folder (a folder with finished runs would resume them, which is
then not a benchmark), so every run is computed. Wall times include the cluster start, the
runs, assembly and figures. Beside them: the sum of the runs' own CPU time (recorded per run
in the sweep Dataset) over the workers, i.e. the wall time on otherwise idle cores with perfect
packing, and the load average before and after (above the CPU count: the machine was shared).

``paper``: ``run_paper`` (24 distinct runs: 13 Harris loads until steady + 11 yang20 scenes,
18 figures). ``sweep-scaling``: one sweep (default: yang20_baseline over 4 speeds, 0.25 +
0.5 cage revolutions) run with each worker count in turn, alternating, into fresh folders;
speed-up = wall time with the first count / wall time with the others (median per repeat).
``skidmap``: ``run_skidmap`` (speed x radial-load grid, ``until_steady`` from the
torque-balance start); also writes OUT/bench_skidmap.json.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np

from run import fail, header, median, overrides, summary, write_json


def _fresh(out: Path | None, prefix: str) -> Path:
    out = out or Path(tempfile.mkdtemp(prefix=prefix))
    if out.exists() and any(out.iterdir()):
        fail(f"--out {str(out)[:100]}: not empty; a benchmark starts from an empty folder")
    out.mkdir(parents=True, exist_ok=True)
    return out


def _run_cpu(datasets) -> float:
    """Summed CPU time of the distinct runs of the sweep Datasets."""
    seen = {}
    for ds in datasets:
        for key, c in zip(ds.run_key.values.ravel(), ds.run_cpu_time_s.values.ravel()):
            seen.setdefault(key, float(c))
    return float(np.nansum(list(seen.values())))


def paper(a) -> None:
    from bearingdae.studies.paper import run_paper

    out = _fresh(a.out, "bench_paper_")
    load0, t0 = os.getloadavg()[0], time.perf_counter()
    res = run_paper(out, workers=a.workers[0], progress=False, overrides=overrides(a.set) or None)
    wall = time.perf_counter() - t0
    cpu_all = sum(getattr(resource.getrusage(who), f) for who in
                  (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN) for f in ("ru_utime",
                                                                             "ru_stime"))
    for sweep, ds in res.items():
        print(f"{sweep:28s} {ds.status.size:3d} runs, run CPU {_run_cpu([ds]):7.1f} s")
    runs = len({k for ds in res.values() for k in ds.run_key.values.ravel()})
    cpu = _run_cpu(res.values())
    print(f"paper set into {out}: {runs} distinct runs, {a.workers[0]} workers\n"
          f"wall {wall:.1f} s = {wall / 60:.2f} min; run CPU {cpu:.1f} s, / workers "
          f"{cpu / a.workers[0]:.1f} s; CPU of the whole set (client, workers, figures) "
          f"{cpu_all:.1f} s; load {load0:.1f} -> {os.getloadavg()[0]:.1f}")
    write_json(a.json, {"benchmark": "paper", "workers": a.workers[0], "wall_s": wall,
                        "run_cpu_s": cpu, "cpu_all_s": cpu_all, "runs": runs})


def scaling(a) -> None:
    from bearingdae.studies.sweep import run_sweep, sweep_from_dict

    over = {"numerics.warmup_cage_revolutions": 0.25, "numerics.cage_revolutions": 0.5,
            **overrides(a.set)}
    spec = {"title": "scaling", "base": a.case, "overrides": over,
            "axes": {"operating.speed_rpm": a.speeds}}
    sweep = sweep_from_dict(spec, name="scaling")
    rows = {w: [] for w in a.workers}
    for rep in range(a.repeat):
        for w in a.workers:
            out = Path(tempfile.mkdtemp(prefix="bench_scaling_"))
            try:
                load0, t0 = os.getloadavg()[0], time.perf_counter()
                ds = run_sweep(sweep, out / "scaling.nc", workers=w, progress=False)
                wall = time.perf_counter() - t0
            finally:
                shutil.rmtree(out, ignore_errors=True)
            rows[w].append({"wall_s": wall, "run_cpu_s": _run_cpu([ds]), "load": load0})
            print(f"repeat {rep + 1}, {w} workers: wall {wall:6.1f} s, run CPU "
                  f"{rows[w][-1]['run_cpu_s']:6.1f} s, load before {load0:.1f}", flush=True)
    first = a.workers[0]
    speedup = {w: median(f["wall_s"] / r["wall_s"] for f, r in zip(rows[first], rows[w]))
               for w in a.workers}
    for w in a.workers:
        print(f"{w} workers: wall {median(r['wall_s'] for r in rows[w]):6.1f} s (median), "
              f"speed-up against {first}: {speedup[w]:.2f}")
    write_json(a.json, {"benchmark": "sweep-scaling", "case": a.case, "speeds_rpm": a.speeds,
                        "overrides": over, "rows": rows, "speedup": speedup})


def skidmap(a) -> None:
    from bearingdae.studies.skidmap import run_skidmap

    out = _fresh(a.out, "bench_skidmap_")
    target = out / f"{Path(a.case).stem}_skidmap.nc"
    load0, t0 = os.getloadavg()[0], time.perf_counter()
    ds, paths = run_skidmap(a.case, a.speeds, a.loads, target, overrides=overrides(a.set),
                            workers=a.workers[0], progress=False)
    wall = time.perf_counter() - t0
    import xarray as xr

    with xr.open_dataset(target.with_name(target.stem + "_sweep.nc")) as sweep:
        cpu = float(np.nansum(sweep.run_cpu_time_s.values))
    res = {"benchmark": "skidmap", "case": a.case, "speeds_rpm": a.speeds, "loads_N": a.loads,
           "points": int(ds.cage_slip_ratio.size), "workers": a.workers[0], "wall_s": wall,
           "run_cpu_s_sum": cpu, "load_before": load0, "load_after": os.getloadavg()[0],
           "steady_points": int(np.nansum(ds.steady_state_reached.values == 1)),
           "warmup_revolutions": ds.warmup_cage_revolutions_used.values.tolist()}
    print(f"skid map {a.case}: {res['points']} points ({res['steady_points']} steady), "
          f"{a.workers[0]} workers: wall {wall:.1f} s, run CPU {cpu:.1f} s (/ workers "
          f"{cpu / a.workers[0]:.1f} s); load {load0:.1f} -> {res['load_after']:.1f}")
    write_json(out / "bench_skidmap.json", res)
    write_json(a.json, res)
    for p in paths:
        print(f"wrote {p}")


def main(argv=None, name="paper") -> None:
    ap = argparse.ArgumentParser(prog=f"run.py {name}", description=summary(__doc__))
    ap.add_argument("--workers", type=int, nargs="+",
                    default=[1, 2] if name == "sweep-scaling" else [2])
    ap.add_argument("--set", action="append", metavar="KEY=VALUE", help="scene override for "
                    "every run, e.g. numerics.cage_revolutions=0.5")
    ap.add_argument("--json", help="write the figures here")
    if name == "sweep-scaling":
        ap.add_argument("--case", default="yang20_baseline")
        ap.add_argument("--speeds", type=float, nargs="+", default=[2000, 4000, 6000, 8000])
        ap.add_argument("--repeat", type=int, default=2)
    if name in ("paper", "skidmap"):
        ap.add_argument("--out", type=Path, help="empty output folder (default: a new one)")
    if name == "skidmap":
        ap.add_argument("--case", default="yang20_baseline")
        ap.add_argument("--speeds", type=float, nargs="+",
                        default=[2000, 4000, 6000, 8000, 10000, 14000])
        ap.add_argument("--loads", type=float, nargs="+",
                        default=[100, 200, 400, 800, 1200, 1600])
    a = ap.parse_args(argv)
    header(f"{name}, {a.workers} worker processes")
    {"paper": paper, "sweep-scaling": scaling, "skidmap": skidmap}[name](a)
