"""Benchmark: the whole paper set with one command (issue 5 target: <= 5 min on 2 cores).

    python benchmarks/bench_paper.py [--workers 2] [--out DIR]

Runs ``bearingdae.studies.paper.run_paper`` (24 distinct runs: 13 Harris loads + 11 yang20 scenes,
figures included) into a fresh folder (no resumed runs) and reports:

- the wall time of the whole set (cluster start, runs, assembly, 18 PNGs);
- the sum of the workers' CPU time per run, and CPU / workers (the wall time the runs would
  take on otherwise idle cores with perfect packing), because the project machine is shared
  and its wall times are inflated by other jobs (the load average is printed before/after);
- per sweep: runs, recorded windows, CPU time.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path, help="output folder (default: a fresh temporary one)")
    args = ap.parse_args()
    from bearingdae.studies.paper import run_paper

    out = args.out or Path(tempfile.mkdtemp(prefix="bench_paper_"))
    if (out / "runs").exists() and any((out / "runs").iterdir()):
        raise SystemExit(f"{out}/runs is not empty: a benchmark must start without cached runs")
    load0 = os.getloadavg()
    t0 = time.perf_counter()
    res = run_paper(out, workers=args.workers, progress=False)
    wall = time.perf_counter() - t0
    # CPU of this process and of every (terminated) worker and nanny process below it
    cpu_all = sum(getattr(resource.getrusage(who), f) for who in
                  (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)
                  for f in ("ru_utime", "ru_stime"))
    load1 = os.getloadavg()
    seen: dict[str, float] = {}
    print(f"paper set into {out}, {args.workers} worker processes")
    print(f"{'sweep':28s} {'runs':>4s} {'warm-up+recorded rev':>21s} {'CPU s':>8s}")
    for name, ds in res.items():
        over = json.loads(ds.attrs["sweep_axes"])
        toml = ds.attrs["sweep_toml"]
        import tomllib

        o = tomllib.loads(toml).get("overrides", {})
        flat = {**o, **{f"numerics.{k}": v for k, v in o.get("numerics", {}).items()}}
        win = (f"{flat.get('numerics.warmup_cage_revolutions', '?')}+"
               f"{flat.get('numerics.cage_revolutions', '?')}")
        cpu = 0.0
        for key, c in zip(ds.run_key.values.ravel(), ds.run_cpu_time_s.values.ravel()):
            if key not in seen:
                seen[key] = float(c)
                cpu += float(c)
        print(f"{name:28s} {ds.status.size:4d} {win:>21s} {cpu:8.1f}   axes "
              f"{[a['dim'] for a in over]}")
    total_cpu = sum(seen.values())
    print(f"distinct runs: {len(seen)}")
    print(f"wall time (whole set, incl. cluster start and figures): {wall:.1f} s "
          f"= {wall / 60:.2f} min  (target <= 5 min)")
    print(f"sum of run CPU time: {total_cpu:.1f} s; / {args.workers} workers = "
          f"{total_cpu / args.workers:.1f} s")
    print(f"CPU time of the whole set (client + workers, incl. start-up, JIT loading, "
          f"figures): {cpu_all:.1f} s; / 2 cores = {cpu_all / 2:.1f} s = "
          f"{cpu_all / 120:.2f} min (the wall time on two otherwise idle cores, at best)")
    print(f"load average before {load0[0]:.2f}, after {load1[0]:.2f} (2 cores; > 2 means the "
          "machine was shared)")


if __name__ == "__main__":
    main()
