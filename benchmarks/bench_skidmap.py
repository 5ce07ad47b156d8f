"""Benchmark: a skid map (issue 14): speed x radial-load grid, every point until steady.

    python benchmarks/bench_skidmap.py [--case yang20_baseline] [--speeds ...] [--loads ...]
                                       [--workers 2] [--out DIR]

Runs ``bearingdae.studies.skidmap.run_skidmap`` (a dask sweep of pinned single-thread processes,
``until_steady`` from the torque-balance start) into OUT (default: a fresh temporary folder;
a folder with finished runs resumes them, which is then not a benchmark) and reports:

- the wall time of the whole map (cluster start, runs, assembly, PNG), and the load average
  before/after (the project machine is shared: wall times are inflated by other jobs);
- the sum of the workers' CPU time per run, and that sum / workers (the wall time on
  otherwise idle cores with perfect packing);
- warm-up revolutions used per point, and how many points met the criterion.

Writes OUT/bench_skidmap.json, OUT/<case>_skidmap.nc and .png (copied into docs/figures by
hand).
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--case", default="yang20_baseline")
    ap.add_argument("--speeds", type=float, nargs="+",
                    default=[2000, 4000, 6000, 8000, 10000, 14000])
    ap.add_argument("--loads", type=float, nargs="+", default=[100, 200, 400, 800, 1200, 1600])
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path)
    args = ap.parse_args()
    import numpy as np

    from bearingdae.cli import _overrides
    from bearingdae.studies.skidmap import run_skidmap

    out = args.out or Path(tempfile.mkdtemp(prefix="bench_skidmap_"))
    out.mkdir(parents=True, exist_ok=True)
    target = out / f"{Path(args.case).stem}_skidmap.nc"
    load0 = os.getloadavg()
    t0 = time.perf_counter()
    ds, paths = run_skidmap(args.case, args.speeds, args.loads, target,
                            overrides=_overrides(args.set), workers=args.workers,
                            progress=False)
    wall = time.perf_counter() - t0
    load1 = os.getloadavg()
    sweep = __import__("xarray").open_dataset(target.with_name(target.stem + "_sweep.nc"))
    cpu = float(np.nansum(sweep.run_cpu_time_s.values))
    res = {
        "case": args.case, "speeds_rpm": args.speeds, "loads_N": args.loads,
        "points": int(ds.cage_slip_ratio.size), "workers": args.workers,
        "wall_s": wall, "run_cpu_s_sum": cpu, "cpu_over_workers_s": cpu / args.workers,
        "load_average_before": load0, "load_average_after": load1,
        "steady_points": int(np.nansum(ds.steady_state_reached.values == 1)),
        "completed": int(ds.attrs["runs_completed"]),
        "warmup_revolutions": ds.warmup_cage_revolutions_used.values.tolist(),
        "cage_slip_percent": (100 * ds.cage_slip_ratio.values).round(3).tolist(),
        "overrides": args.set,
    }
    (out / "bench_skidmap.json").write_text(json.dumps(res, indent=1))
    print(json.dumps({k: v for k, v in res.items() if k not in ("warmup_revolutions",
                                                                  "cage_slip_percent")},
                     indent=1))
    for p in paths:
        print(f"wrote {p}")


if __name__ == "__main__":
    main()
