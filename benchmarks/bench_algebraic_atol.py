"""Benchmark: a looser absolute tolerance on the algebraic unknowns as the public-API stand-in
for SUNDIALS' ``IDASetSuppressAlg`` (which scikit-sundae 1.2 does not expose).

Run on demand:  python benchmarks/bench_algebraic_atol.py [--alg-atol 1e-8 1e-6 1e-4 ...]
                [--rtol 1e-6] [--atol 1e-8] [--revolutions 0.2] [--steps-ms 20]
                [--set operating.speed_rpm=10000]
(``--alg-atol 0``: the package default; ``--steps-ms 0``: no separate cost run)

SuppressAlg leaves the algebraic unknowns out of IDA's local error test only. A large atol on
them (the per-component ``atol`` array) does that too, but IDA uses the same weights in its
Newton convergence test, so it also loosens how accurately each step solves the algebraic
equations. This script measures what that costs and buys on the baseline scene:

- accuracy: first ``--revolutions`` cage revolution from t = 0 (0.2: the window where runs at
  different tolerances have not yet diverged, docs/performance.md "Work-precision"), against
  IDA at rtol 1e-9 (atol 1e-11, default algebraic treatment); relative RMS errors of cage,
  orbit and spin speed, skew angle and slice contact force (bearingdae/studies/workprecision/__init__.py);
- the algebraic equations at IDA's own outputs, before the projection that ``simulate`` applies
  (max |F_alg| in units of each row's scale, i.e. of the force scale), and the projection's
  change of the algebraic unknowns (in units of the run's algebraic atol);
- cost: IDA steps, error-test and convergence failures (IDA's own statistics, recorded in the
  Dataset's ``solver_statistics`` by the compiled IDA core), residual and Jacobian calls, and
  the integrator's wall time, on the first ``--steps-ms`` ms and on the accuracy window.

The algebraic atol is set through ``bearingdae.solvers.ida.ALG_ATOL_FACTOR`` / ``ALG_ATOL_MAX``
(patched for one run, restored after).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from contextlib import contextmanager
from pathlib import Path
from types import SimpleNamespace

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from bearingdae import load_scene, simulate  # noqa: E402
from bearingdae.solvers import ida  # noqa: E402
from bearingdae.solvers.algebraic import initial_state, project_algebraic  # noqa: E402
from bearingdae.system.model import build_model  # noqa: E402
from bearingdae.studies.workprecision import QUANTITIES, derive, quantity_errors  # noqa: E402


@contextmanager
def algebraic_atol(value: float | None, atol: float):
    """Algebraic atol = ``value`` for the runs inside (None: the package default)."""
    saved = ida.ALG_ATOL_FACTOR, ida.ALG_ATOL_MAX
    if value is not None:
        ida.ALG_ATOL_FACTOR, ida.ALG_ATOL_MAX = value / atol, value
    try:
        yield
    finally:
        ida.ALG_ATOL_FACTOR, ida.ALG_ATOL_MAX = saved


EXTRA: dict = {}  # --set KEY=VALUE overrides of the scene


def window_scene(revolutions: float, rtol: float, atol: float):
    return load_scene("yang20_baseline", {**EXTRA, "numerics.warmup_cage_revolutions": 0.0,
                                          "numerics.cage_revolutions": revolutions,
                                          "numerics.samples_per_cage_revolution": 200,
                                          "numerics.rtol": rtol, "numerics.atol": atol})


def raw_algebraic(scene) -> dict:
    """IDA's outputs before projection: max |F_alg| (row-scaled) and the projection's change
    of the algebraic unknowns (scaled units)."""
    m = build_model(scene)
    y0, yp0 = initial_state(m)
    from bearingdae.api import output_times

    t_out, _ = output_times(m)
    r = ida.integrate(m, y0, yp0, t_out)
    alg = m.layout.algebraic
    f_max, dz_max = 0.0, 0.0
    for tk, y, yp in zip(r.t, r.y, r.yp):
        f_max = max(f_max, float(np.abs(m.residual(tk, y, yp)[alg]).max()))
        y_proj, _ = project_algebraic(m, tk, y)
        dz_max = max(dz_max, float(np.abs(y_proj - y)[alg].max()))
    return {"raw_alg_residual_max": f_max, "projection_change_max": dz_max,
            "raw_success": bool(r.success)}


def one_run(scene, value):
    """Simulate: (Dataset or None, IDA's step counts, stats, message)."""
    with algebraic_atol(value, scene.dynamics.atol):
        t0 = time.perf_counter()
        try:
            ds = simulate(scene)
            msg = "completed"
        except Exception as exc:  # noqa: BLE001 - a failed variant is a result
            ds, msg = getattr(exc, "dataset", None), f"{type(exc).__name__}: {exc}"
        wall = time.perf_counter() - t0
    stats = json.loads(ds.attrs["solver_statistics"]) if ds is not None else {}
    stats["simulate_wall_s"] = wall
    return ds, step_counts(stats), stats, msg


def step_counts(stats: dict) -> SimpleNamespace:
    return SimpleNamespace(steps=stats.get("steps"),
                           error_test_failures=stats.get("error_test_failures"),
                           nonlinear_convergence_failures=stats.get(
                               "nonlinear_convergence_failures"))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--alg-atol", type=float, nargs="+",
                    default=[1e-8, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1.0, 1e4])
    ap.add_argument("--rtol", type=float, default=1e-6)
    ap.add_argument("--atol", type=float, default=1e-8)
    ap.add_argument("--revolutions", type=float, default=0.2)
    ap.add_argument("--steps-ms", type=float, default=20.0)
    ap.add_argument("--json", type=Path, help="write the rows here")
    ap.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE",
                    help="scene overrides, e.g. operating.speed_rpm=10000")
    args = ap.parse_args()
    for kv in args.set:
        key, value = kv.split("=", 1)
        EXTRA[key] = float(value)

    simulate(window_scene(0.01, 1e-6, 1e-8))  # JIT warm-up
    ref_scene = window_scene(args.revolutions, 1e-9, 1e-11)
    ref, ref_rec, ref_stats, ref_msg = one_run(ref_scene, None)
    print(f"reference IDA rtol 1e-9: {ref_msg}, {ref_rec.steps} steps, "
          f"{ref_stats.get('wall_time_s', math.nan):.2f} s")
    period_s = float(ref.time[-1]) / args.revolutions if args.revolutions > 0 else math.nan
    long_scene = (derive(window_scene(args.revolutions, args.rtol, args.atol),
                         {"numerics.cage_revolutions": args.steps_ms * 1e-3 / period_s})
                  if args.steps_ms > 0 else None)
    rows = []
    for value in args.alg_atol:
        value = value or None  # 0: the package default
        sc = window_scene(args.revolutions, args.rtol, args.atol)
        ds, rec, st, msg = one_run(sc, value)
        row = {"alg_atol": value if value else ida.algebraic_atol(args.atol), "status": msg, "steps": rec.steps,
               "error_test_failures": rec.error_test_failures,
               "convergence_failures": rec.nonlinear_convergence_failures,
               "residual_calls": st.get("residual_calls"), "jacobian_calls": st.get("jacobian_calls"),
               "wall_s": st.get("wall_time_s"),
               "projection_newton_iterations": st.get("projection_newton_iterations")}
        if ds is not None and msg == "completed":
            row.update(quantity_errors(ds, ref, {q: 1.0 for q in QUANTITIES}))
            with algebraic_atol(value, sc.dynamics.atol):
                row.update(raw_algebraic(sc))
        if args.steps_ms > 0:
            _, rec_l, st_l, msg_l = one_run(long_scene, value)
        else:
            rec_l, st_l, msg_l = step_counts({}), {}, "not run"
        row.update({f"steps_{args.steps_ms:g}ms": rec_l.steps,
                    f"residual_calls_{args.steps_ms:g}ms": st_l.get("residual_calls"),
                    f"wall_{args.steps_ms:g}ms_s": st_l.get("wall_time_s"),
                    f"status_{args.steps_ms:g}ms": msg_l})
        rows.append(row)
        errs = " ".join(f"{q.split('_')[0]} {row.get(q + '_rel_rms', math.nan):.2e}"
                        for q in QUANTITIES)
        print(f"rtol {args.rtol:.0e} alg atol {row['alg_atol']:8.0e}: {msg[:60]}; steps {rec.steps} (ETF "
              f"{rec.error_test_failures}, NCF {rec.nonlinear_convergence_failures}), res "
              f"{row['residual_calls']}, {row['wall_s'] or math.nan:.2f} s; errors: {errs}; "
              f"raw |F_alg| {row.get('raw_alg_residual_max', math.nan):.1e}, projection "
              f"change {row.get('projection_change_max', math.nan):.1e}; "
              f"{args.steps_ms:g} ms: {rec_l.steps} steps, "
              f"{row[f'residual_calls_{args.steps_ms:g}ms']} res ({msg_l[:40]})", flush=True)
    if args.json:
        args.json.write_text(json.dumps({"reference_steps": ref_rec.steps, "rows": rows},
                                        indent=1, default=str))


if __name__ == "__main__":
    main()
