"""Accuracy of the SuppressAlg variants on the work-precision window (docs/performance.md).

Run on demand:  python benchmarks/suppress_alg_accuracy.py [--revolutions 0.2] [--json out]
                [--set operating.speed_rpm=10000]

Baseline, first ``--revolutions`` cage revolution from t = 0 (the window where runs at different
tolerances have not yet diverged), rtol 1e-6, against IDA at rtol 1e-9 / atol 1e-11 (default
error test); relative RMS errors of cage, orbit and spin speed, skew angle and slice contact
force as in benchmarks/bench_algebraic_atol.py (bearingdae/studies/workprecision.py), plus
IDA's counts. Variants: ``off`` (the default), ``restarts`` (``IDA(suppress_alg=True)``),
``no restarts`` (VARIANTS below).
"""

from __future__ import annotations

import argparse
import json
import math
import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from bearingdae import load_scene, simulate  # noqa: E402
from bearingdae.solvers.ida import IDA  # noqa: E402
from bearingdae.studies.workprecision import QUANTITIES, quantity_errors  # noqa: E402

VARIANTS = {
    "off": {"suppress_alg": False},  # every unknown in the error test (the default)
    "restarts": {"suppress_alg": True},  # SuppressAlg, projected restart on corrector failure
    "no restarts": {"suppress_alg": True, "max_restarts": 0},  # SuppressAlg alone
}


EXTRA: dict = {}  # --set KEY=VALUE overrides of the scene


def window_scene(revolutions: float, rtol: float, atol: float):
    return load_scene("yang20_baseline", {**EXTRA, "numerics.warmup_cage_revolutions": 0.0,
                                          "numerics.cage_revolutions": revolutions,
                                          "numerics.samples_per_cage_revolution": 200,
                                          "numerics.rtol": rtol, "numerics.atol": atol})


def run(scene, opts):
    try:
        ds, msg = simulate(scene, solver=IDA(**opts)), "completed"
    except Exception as exc:  # noqa: BLE001 - a failed variant is a result
        ds, msg = getattr(exc, "dataset", None), f"{type(exc).__name__}: {exc}"[:160]
    stats = json.loads(ds.attrs["solver_statistics"]) if ds is not None else {}
    return ds, msg, stats


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--revolutions", type=float, default=0.2)
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS))
    ap.add_argument("--json", default=None)
    ap.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE",
                    help="scene overrides, e.g. operating.speed_rpm=10000")
    args = ap.parse_args()
    for kv in args.set:
        key, value = kv.split("=", 1)
        EXTRA[key] = float(value)
    ref, ref_msg, ref_stats = run(window_scene(args.revolutions, 1e-9, 1e-11),
                                  VARIANTS["off"])
    print(f"reference rtol 1e-9: {ref_msg}, {ref_stats.get('steps')} steps", flush=True)
    rows = []
    for name in args.variants:
        ds, msg, st = run(window_scene(args.revolutions, 1e-6, 1e-8), VARIANTS[name])
        row = {"variant": name, "status": msg, "steps": st.get("steps"),
               "residual_calls": st.get("residual_calls"),
               "jacobian_calls": st.get("jacobian_calls"), "restarts": st.get("restarts", 0)}
        if ds is not None and msg == "completed":
            row.update(quantity_errors(ds, ref, {q: 1.0 for q in QUANTITIES}))
        rows.append(row)
        errs = " ".join(f"{q.split('_')[0]} {row.get(q + '_rel_rms', math.nan):.2e}"
                        for q in QUANTITIES)
        print(f"{name}: {msg[:60]}; steps {row['steps']}, res {row['residual_calls']}, jac "
              f"{row['jacobian_calls']}, restarts {row['restarts']}; errors {errs}", flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1, default=str)


if __name__ == "__main__":
    main()
