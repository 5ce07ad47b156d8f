"""Benchmark: dynamic baseline run (issue 3 target: yang20 baseline, 1 warm-up + 3 recorded
cage revolutions, rtol 1e-6, median wall <= 5 s on the 2-core machine).

Run on demand:  python benchmarks/bench_dynamic.py [--repeat 3] [--revolutions 3]
                [--jacobian analytic fd]

Each repeat runs every Jacobian variant back to back (interleaved), so the ratios compare runs
made under the same machine load. Reports wall time (median of repeats, after a JIT warm-up
run), residual and Jacobian calls, the isolated cost of one residual and one Jacobian call, the
split of the wall time, and IDA's own step count and failures (compiled IDA core statistics).
The compiled core against the scikit-sundae path: benchmarks/bench_compiled_ida.py.
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
import scipy.sparse as sp  # noqa: E402

from bearingdae import load_scene, simulate  # noqa: E402
from bearingdae.solvers import ida  # noqa: E402
from bearingdae.system.jacobian import jacobian_sparse  # noqa: E402
from bearingdae.system.jacobian_analytic import analytic_work, jacobian_analytic_sparse  # noqa: E402
from bearingdae.solvers.algebraic import initial_state  # noqa: E402
from bearingdae.system.model import build_model  # noqa: E402
from bearingdae.system.residual import residual_flat  # noqa: E402


def kernel_costs_us(scene, n=3000, repeat=7) -> dict[str, float]:
    """Isolated cost [µs] of one residual, one FD and one analytic Jacobian (medians), each
    called from Python as IDA calls it (numba dispatch included; the residual is IDA's own
    callback ``residual_flat``), at the initial state."""
    m = build_model(scene)
    y0, yp0 = initial_state(m)
    res = np.empty(m.size)
    r_pat, c_pat = m.layout.sparsity()
    pattern = sp.csc_matrix((np.ones(r_pat.size), (r_pat, c_pat)), shape=(m.size, m.size))
    jd, pat = ida._jacobian_work(m, pattern)
    ja = analytic_work(m, jd[1], jd[2])
    JJ = np.zeros(pat.nnz)
    calls = {
        "residual": (lambda: residual_flat(0.0, y0, yp0, res, m.work), n),
        "jacobian_fd": (lambda: jacobian_sparse(0.0, y0, yp0, res, 10.0, JJ, m.data, jd), n // 10),
        "jacobian_analytic": (lambda: jacobian_analytic_sparse(0.0, y0, yp0, res, 10.0, JJ,
                                                               m.data, ja), n // 10),
    }
    out = {k: [] for k in calls}
    for f, _ in calls.values():
        f()
    for _ in range(repeat):
        for k, (f, cnt) in calls.items():
            t0 = time.perf_counter()
            for _ in range(cnt):
                f()
            out[k].append((time.perf_counter() - t0) / cnt * 1e6)
    return {k: statistics.median(v) for k, v in out.items()}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--revolutions", type=float, default=3.0)
    ap.add_argument("--rtol", type=float, default=1e-6)
    ap.add_argument("--jacobian", nargs="+", default=["analytic", "fd"])
    ap.add_argument("--steps", action="store_true",
                    help="(kept for old command lines: IDA's step counts are always reported)")
    args = ap.parse_args()
    scene = load_scene("yang20_baseline", {"numerics.rtol": args.rtol,
                                           "numerics.warmup_cage_revolutions": 1.0,
                                           "numerics.cage_revolutions": args.revolutions})
    short = load_scene("yang20_baseline", {"numerics.warmup_cage_revolutions": 0.01,
                                           "numerics.cage_revolutions": 0.01})
    for jac in args.jacobian:
        simulate(short, solver=ida.IDA(jacobian=jac))  # JIT warm-up (numba cache) outside the timing
    costs = kernel_costs_us(scene)
    walls = {j: [] for j in args.jacobian}
    stats = {}
    for _ in range(args.repeat):
        for jac in args.jacobian:
            t0 = time.perf_counter()
            ds = simulate(scene, solver=ida.IDA(jacobian=jac))
            walls[jac].append(time.perf_counter() - t0)
            stats[jac] = json.loads(ds.attrs["solver_statistics"])
    t_end = float(ds.time[-1])
    print(f"yang20 baseline, 1 + {args.revolutions:g} cage revolutions ({t_end * 1e3:.1f} ms), "
          f"rtol {args.rtol:g}")
    print("isolated call cost [µs]: " + ", ".join(f"{k} {v:.1f}" for k, v in costs.items()))
    for jac in args.jacobian:
        st, w = stats[jac], walls[jac]
        med = statistics.median(w)
        per_jac = costs[f"jacobian_{jac}"]
        in_res = st["residual_calls"] * costs["residual"] * 1e-6
        in_jac = st["jacobian_calls"] * per_jac * 1e-6
        print(f"[{jac} Jacobian] wall (simulate, median of {args.repeat}): {med:.2f} s "
              f"[{', '.join(f'{x:.2f}' for x in w)}]")
        print(f"  IDA integration {st['wall_time_s']:.2f} s; post-processing "
              f"{med - st['wall_time_s']:.2f} s")
        print(f"  residual calls {st['residual_calls']} (x cost = {in_res:.2f} s), "
              f"Jacobians {st['jacobian_calls']} (x cost = {in_jac:.2f} s), rest (IDA "
              f"internals, callbacks) {st['wall_time_s'] - in_res - in_jac:.2f} s")
    if len(args.jacobian) > 1:
        a, b = args.jacobian[:2]
        ratios = [x / y for x, y in zip(walls[b], walls[a])]
        print(f"wall ratio {b}/{a} per repeat: {', '.join(f'{r:.2f}' for r in ratios)}")
    for jac in args.jacobian:
        st = stats[jac]
        n = st["steps"]
        print(f"[{jac}] IDA steps: {n} (mean step {t_end / n * 1e6:.2f} µs), error-test "
              f"failures {st['error_test_failures']}, convergence failures "
              f"{st['nonlinear_convergence_failures']}; per step: "
              f"{st['residual_calls'] / n:.2f} residual calls, "
              f"{st['jacobian_calls'] / n:.3f} Jacobians; "
              f"IDA wall per step {st['wall_time_s'] / n * 1e6:.1f} µs")

if __name__ == "__main__":
    main()
