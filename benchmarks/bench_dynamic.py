"""Benchmark: dynamic baseline run (issue 3 target: yang20 baseline, 1 warm-up + 3 recorded
cage revolutions, rtol 1e-6, median wall <= 5 s on the 2-core machine).

Run on demand:  python benchmarks/bench_dynamic.py [--repeat 3] [--revolutions 3]
Reports wall time (median of repeats, after a JIT warm-up run), residual calls, Jacobian calls,
the cost of one residual call measured in isolation, and the split of the wall time.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from bearingdae import load_scene, simulate  # noqa: E402
from bearingdae.system.model import build_model, initial_state  # noqa: E402
from bearingdae.system.residual import residual  # noqa: E402


def residual_cost_us(scene, n=20000) -> float:
    m = build_model(scene)
    y0, yp0 = initial_state(m)
    res = np.empty(m.size)
    residual(0.0, y0, yp0, res, m.data)
    t0 = time.perf_counter()
    for _ in range(n):
        residual(0.0, y0, yp0, res, m.data)
    return (time.perf_counter() - t0) / n * 1e6


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--revolutions", type=float, default=3.0)
    ap.add_argument("--rtol", type=float, default=1e-6)
    args = ap.parse_args()
    scene = load_scene("yang20_baseline", {"numerics.rtol": args.rtol,
                                           "numerics.warmup_cage_revolutions": 1.0,
                                           "numerics.cage_revolutions": args.revolutions})
    short = load_scene("yang20_baseline", {"numerics.warmup_cage_revolutions": 0.01,
                                           "numerics.cage_revolutions": 0.01})
    simulate(short)  # JIT warm-up (numba cache) outside the timing
    cost = residual_cost_us(scene)
    walls, stats = [], None
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        ds = simulate(scene)
        walls.append(time.perf_counter() - t0)
        stats = json.loads(ds.attrs["solver_statistics"])
    total_res = stats["residual_calls"] + stats["residual_calls_in_jacobian"]
    ida = stats["wall_time_s"]
    print(f"yang20 baseline, 1 + {args.revolutions:g} cage revolutions, rtol {args.rtol:g}")
    print(f"wall (simulate, median of {args.repeat}): {statistics.median(walls):.2f} s "
          f"[{', '.join(f'{w:.2f}' for w in walls)}]")
    print(f"  IDA integration          {ida:.2f} s")
    print(f"  output post-processing   {statistics.median(walls) - ida:.2f} s "
          f"(algebraic projection + diagnostics + Dataset)")
    print(f"residual call (isolated): {cost:.1f} µs")
    print(f"residual calls: {stats['residual_calls']} by IDA + "
          f"{stats['residual_calls_in_jacobian']} in {stats['jacobian_calls']} Jacobians")
    print(f"  residual evaluations x cost = {total_res * cost * 1e-6:.2f} s of {ida:.2f} s")


if __name__ == "__main__":
    main()
