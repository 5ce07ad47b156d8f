"""Benchmark: quasi-static solve (issue 2 target: harris36, 30 slices, median <= 20 ms).

Run on demand:  python benchmarks/bench_static.py [--repeat 50]
Prints a Markdown table (median, quartiles, Newton iterations) for docs/performance.md.
Threads are pinned to 1 so that the numbers are comparable on the shared 2-core machine.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from bearingdae import load_scene, solve_static  # noqa: E402

CASES = [
    ("harris36, 30 slices, 12 kN, 5000 r/min", "harris36_static", {}),
    ("harris36, 30 slices, 1 N + 3 N·m (continuation)", "harris36_static",
     {"operating.radial_load_N": 1.0, "operating.moment_Nm": 3.0}),
    ("yang20 baseline, 10 slices", "yang20_baseline", {}),
    ("yang20, 100 slices", "yang20_baseline", {"numerics.slices": 100}),
]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=50)
    args = ap.parse_args()
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}")
    print("| scene | median [ms] | q25–q75 [ms] | Newton iterations |")
    print("|---|---|---|---|")
    for label, case, over in CASES:
        scene = load_scene(case, over)
        ds = solve_static(scene)  # warm-up
        times = []
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            solve_static(scene)
            times.append(time.perf_counter() - t0)
        q = statistics.quantiles(times, n=4)
        print(f"| {label} | {statistics.median(times) * 1e3:.2f} | "
              f"{q[0] * 1e3:.2f}–{q[2] * 1e3:.2f} | {ds.attrs['newton_iterations']} |")


if __name__ == "__main__":
    main()
