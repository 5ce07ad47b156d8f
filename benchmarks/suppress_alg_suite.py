"""SuppressAlg variants on the stability suite and harris36: completes? steps, residual calls.

Run on demand:  python benchmarks/suppress_alg_suite.py [--variants off restarts ...]
                [--cases extreme/preload paper/harris36_5000rpm] [--harris-loads] [--json out]

Every case of cases/extreme as bundled (0.25 + 0.25 cage revolution) and
paper/harris36_5000rpm shortened to 0.25 warm-up + 1 recorded cage revolution, with IDA in each
variant (benchmarks/suppress_alg_accuracy.py VARIANTS names). Counts, not wall time.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_stability import extreme_cases  # noqa: E402
from suppress_alg_accuracy import VARIANTS  # noqa: E402

from bearingdae import load_scene, simulate  # noqa: E402
from bearingdae.solvers.ida import IDA  # noqa: E402

HARRIS = ("paper/harris36_5000rpm", {"numerics.warmup_cage_revolutions": 0.25,
                                     "numerics.cage_revolutions": 1.0})
#: Fig 11's sweep points at light and heavy load (cases/paper/harris36_cage_speed.toml starts
#: them from the torque balance), shortened likewise
HARRIS_LOADS = [("paper/harris36_5000rpm", {**HARRIS[1], "operating.radial_load_N": load,
                                            "numerics.initial_speeds": "torque_balance"})
                for load in (500.0, 6000.0)]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--variants", nargs="+", default=["off", "restarts", "no restarts"])
    ap.add_argument("--cases", nargs="+", default=None)
    ap.add_argument("--harris-loads", action="store_true",
                    help="only harris36 at 500 N and 6000 N (torque-balance start)")
    ap.add_argument("--json", default=None)
    args = ap.parse_args()
    cases = [(c, {}) for c in extreme_cases()] + [HARRIS]
    if args.harris_loads:
        cases = HARRIS_LOADS
    if args.cases:
        cases = [c for c in cases if c[0] in args.cases]
    rows = []
    for case, over in cases:
        for name in args.variants:
            scene = load_scene(case, over)
            c0 = time.process_time()
            try:
                ds, msg = simulate(scene, solver=IDA(**VARIANTS[name])), "completed"
            except Exception as exc:  # noqa: BLE001 - a failed variant is a result
                ds, msg = getattr(exc, "dataset", None), f"{type(exc).__name__}: {exc}"[:200]
            st = json.loads(ds.attrs["solver_statistics"]) if ds is not None else {}
            row = {"case": case, "load_N": over.get("operating.radial_load_N"),
                   "variant": name, "status": msg, "steps": st.get("steps"),
                   "residual_calls": st.get("residual_calls"),
                   "jacobian_calls": st.get("jacobian_calls"),
                   "restarts": st.get("restarts", 0), "cpu_s": time.process_time() - c0}
            rows.append(row)
            print(json.dumps(row), flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
