"""Quasi-static solve (``solve_static``): median time of the whole public call.

    python benchmarks/run.py static [--repeat 50] [--json F]

Times ``solve_static(scene)`` (geometry, Newton, the xarray Dataset) for each scene below after
one untimed call, and prints a Markdown table: median and quartiles of the CPU time in ms (the
solve is single-threaded, so on a shared machine its CPU time is the steadier figure), the
median wall time, Newton iterations.
The second row is the hard case: 36 rollers floating in their clearance under a pure moment,
where plain Newton fails and the ε-continuation of solvers/static.py takes over.
"""

from __future__ import annotations

import argparse
import statistics
import time

from run import header, summary, write_json

CASES = [
    ("harris36, 30 slices, 12 kN, 5000 r/min", "harris36_static", {}),
    ("harris36, 30 slices, 1 N + 3 N·m (continuation)", "harris36_static",
     {"operating.radial_load_N": 1.0, "operating.moment_Nm": 3.0}),
    ("yang20 baseline, 10 slices", "yang20_baseline", {}),
    ("yang20, 100 slices", "yang20_baseline", {"numerics.slices": 100}),
]


def main(argv=None, name="static") -> None:
    from bearingdae import load_scene, solve_static

    ap = argparse.ArgumentParser(prog=f"run.py {name}", description=summary(__doc__))
    ap.add_argument("--repeat", type=int, default=50)
    ap.add_argument("--json", help="write the rows here")
    a = ap.parse_args(argv)
    header(f"solve_static, {a.repeat} calls per scene")
    print("| scene | CPU, median [ms] | q25–q75 [ms] | wall, median [ms] | Newton iterations |\n"
          "|---|---|---|---|---|")
    rows = []
    for label, case, over in CASES:
        scene = load_scene(case, over)
        ds = solve_static(scene)  # warm-up
        times, walls = [], []
        for _ in range(a.repeat):
            c0, t0 = time.process_time(), time.perf_counter()
            solve_static(scene)
            times.append((time.process_time() - c0) * 1e3)
            walls.append((time.perf_counter() - t0) * 1e3)
        q = statistics.quantiles(times, n=4) if len(times) > 1 else times * 3
        rows.append({"scene": label, "cpu_median_ms": statistics.median(times), "q25_ms": q[0],
                     "q75_ms": q[2], "wall_median_ms": statistics.median(walls),
                     "newton_iterations": ds["newton_iterations"].item()})
        print(f"| {label} | {rows[-1]['cpu_median_ms']:.1f} | {q[0]:.1f}–{q[2]:.1f} | "
              f"{rows[-1]['wall_median_ms']:.1f} | {ds['newton_iterations'].item()} |", flush=True)
    write_json(a.json, {"benchmark": name, "rows": rows})
