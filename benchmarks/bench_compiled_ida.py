"""Benchmark: the compiled IDA core against the scikit-sundae path (issue 11, "Must show").

Run on demand:  python benchmarks/bench_compiled_ida.py [--repeat 3] [--revolutions 3]
                [--skip-full] [--linalg-only]

1. Full run: the default scene (yang20_baseline, 1 warm-up + ``--revolutions`` cage revolutions,
   rtol 1e-6) through ``simulate``, compiled ``IDA`` and ``IDAScikitSundae`` interleaved in each
   repeat (same machine load), after a JIT warm-up of both (warm numba cache). Reports the
   median wall of ``simulate`` and of the integration alone, IDA's steps and calls, and the wall
   per step.
   CPU time of the integration (``time.process_time``) is reported beside the wall time: on
   an oversubscribed machine it is the figure that still measures the code.
2. Breakdown per step of the compiled run (CPU time throughout): kernels = residual calls x isolated residual cost +
   Jacobians x isolated Jacobian cost (both timed in a compiled loop, no dispatch); linear
   solve = setups x factorisation + Newton iterations x solve (SuperLU_MT timed standalone on
   the run's Jacobian through the same SUNDIALS objects); IDA and the rest = the remainder.
3. Linear algebra (issue 11 item 3): factorisation and solve of the iteration matrix at a state
   1 ms into the run, for SuperLU_MT, SUNDIALS dense LU and LAPACK dense LU, for Z = 20
   (yang20_baseline) and Z = 36 (harris36_static's bearing, same operating point style), and a
   standalone numba block-arrow solve (per-roller LU + Schur complement on the global
   unknowns; called from Python, so ~0.3 µs of dispatch is in its numbers).

Timings are medians; the machine has 2 cores shared with other work, so quote ratios measured
side by side (this script) rather than absolute seconds.
"""

from __future__ import annotations

import argparse
import ctypes as C
import json
import os
import statistics
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from numba import njit  # noqa: E402

from bearingdae import load_scene, simulate  # noqa: E402
from bearingdae.solvers import ida  # noqa: E402
from bearingdae.solvers.sundials import prototypes  # noqa: E402
from bearingdae.system.jacobian_analytic import analytic_work, jacobian_analytic_sparse  # noqa: E402
from bearingdae.solvers.algebraic import initial_state  # noqa: E402
from bearingdae.system.model import build_model  # noqa: E402
from bearingdae.system.residual import residual_flat  # noqa: E402


def run_with(solver_cls, scene):
    """simulate(scene, solver=solver_cls()): (Dataset, wall [s], CPU [s] of the integration
    alone — CPU time is the robust figure on a shared, oversubscribed box)."""
    class Timed(solver_cls):
        def _run(self, *args):
            c0 = time.process_time()
            try:
                return super()._run(*args)
            finally:
                self.cpu_s = time.process_time() - c0
    solver = Timed()
    t0 = time.perf_counter()
    ds = simulate(scene, solver=solver)
    return ds, time.perf_counter() - t0, solver.cpu_s


@njit(cache=False)
def _loop_residual(y, yp, res, work, k):
    for i in range(k):
        residual_flat(1e-3 + i * 1e-12, y, yp, res, work)


@njit(cache=False)
def _loop_jacobian(y, yp, res, JJ, d, jd, k):
    for i in range(k):
        jacobian_analytic_sparse(1e-3 + i * 1e-12, y, yp, res, 1e6, JJ, d, jd)


def state_after(model, t_s: float):
    y0, yp0 = initial_state(model)
    r = ida.IDA().integrate(model, y0, yp0, np.array([0.0, t_s]))
    return r.y[-1], r.yp[-1]


def kernel_costs_us(model, y, yp, k=4000) -> dict:
    """Isolated residual and analytic-Jacobian cost [µs], timed inside compiled loops."""
    res = np.empty(model.size)
    pat = ida.sparsity_pattern(model)
    jd0, csc = ida._jacobian_work(model, pat)
    jd = analytic_work(model, jd0[1], jd0[2])
    JJ = np.zeros(csc.nnz)
    _loop_residual(y, yp, res, model.work, 1)
    _loop_jacobian(y, yp, res, JJ, model.data, jd, 1)
    out = {"residual": [], "jacobian": []}
    for _ in range(7):
        t0 = time.process_time()
        _loop_residual(y, yp, res, model.work, k)
        out["residual"].append((time.process_time() - t0) / k * 1e6)
        t0 = time.process_time()
        _loop_jacobian(y, yp, res, JJ, model.data, jd, k // 4)
        out["jacobian"].append((time.process_time() - t0) / (k // 4) * 1e6)
    return {key: statistics.median(v) for key, v in out.items()}


def iteration_matrix(model, y, yp, cj=1e6):
    """(dense N x N, CSC data, rows, indptr) of dF/dy + cj dF/dy' at (y, yp)."""
    n = model.size
    pat = ida.sparsity_pattern(model)
    jd0, csc = ida._jacobian_work(model, pat)
    jd = analytic_work(model, jd0[1], jd0[2])
    JJ = np.zeros(csc.nnz)
    jacobian_analytic_sparse(0.0, y, yp, np.zeros(n), cj, JJ, model.data, jd)
    dense = np.zeros((n, n))
    dense[jd0[1], jd0[2]] = JJ
    return dense, JJ, csc.indices.astype(np.int64), csc.indptr.astype(np.int64)


def block_arrow_costs_us(model, y, yp, reps=2000) -> dict:
    """The package's block-arrow factor/solve (solvers/blockarrow.py) on the same iteration
    matrix [µs], called from Python (numba's dispatch included; benchmarks/bench_block_arrow.py
    times the kernels alone)."""
    from bearingdae.solvers import blockarrow

    dense, _, _, _ = iteration_matrix(model, y, yp)
    lay = model.layout
    Z, nl, ng = lay.rollers, lay.n_local, lay.n_global
    work = blockarrow.work_arrays(Z, nl, ng)
    b = np.ones(model.size)
    x = np.zeros(model.size)
    blockarrow.factor(dense, Z, nl, ng, *work)
    blockarrow.solve(Z, nl, ng, *work[:5], b, x)
    f, s = [], []
    for _ in range(7):
        t0 = time.process_time()
        for _ in range(reps):
            blockarrow.factor(dense, Z, nl, ng, *work)
        f.append((time.process_time() - t0) / reps)
        t0 = time.process_time()
        for _ in range(reps):
            blockarrow.solve(Z, nl, ng, *work[:5], b, x)
        s.append((time.process_time() - t0) / reps)
    return {"factor_us": statistics.median(f) * 1e6, "solve_us": statistics.median(s) * 1e6,
            "residual_max": float(np.abs(dense @ x - b).max())}


def linear_solver_costs_us(model, y, yp, reps=400) -> dict:
    """Factorisation (a refactorisation, as in a run) and solve [µs] of the iteration matrix by
    SuperLU_MT, SUNDIALS dense LU and LAPACK dense LU, through the bundled SUNDIALS (ctypes
    call overhead, ~1 µs, included)."""
    api = prototypes.load()
    n = model.size
    dense, JJ, rows, indptr = iteration_matrix(model, y, yp)
    ctx = C.c_void_p()
    api.SUNContext_Create(None, C.byref(ctx))
    out = {}
    objs = []
    try:
        x, b = api.N_VNew_Serial(n, ctx), api.N_VNew_Serial(n, ctx)
        objs += [("v", x), ("v", b)]
        bd = np.ctypeslib.as_array(C.cast(api.N_VGetArrayPointer(b), C.POINTER(C.c_double)),
                                   shape=(n,))
        libs = api.libraries
        lapack = None
        if "sunlinsollapackdense" in libs:
            lapack = prototypes._proto(libs["sunlinsollapackdense"], "SUNLinSol_LapackDense",
                                       C.c_void_p, C.c_void_p, C.c_void_p, C.c_void_p)
        kinds = [("SuperLU_MT (sparse)", "sparse", lambda A: api.SUNLinSol_SuperLUMT(x, A, 1,
                                                                                   ctx)),
                 ("SUNDIALS dense LU", "dense", lambda A: api.SUNLinSol_Dense(x, A, ctx))]
        if lapack is not None:
            kinds.append(("LAPACK dense LU (OpenBLAS, 1 thread)", "dense",
                          lambda A: lapack(x, A, ctx)))
        for label, kind, make in kinds:
            if kind == "sparse":
                A = api.SUNSparseMatrix(n, n, JJ.size, prototypes.CSC_MAT, ctx)
                data = np.ctypeslib.as_array(C.cast(api.SUNSparseMatrix_Data(A),
                                                    C.POINTER(C.c_double)), shape=(JJ.size,))
                iv = np.ctypeslib.as_array(C.cast(api.SUNSparseMatrix_IndexValues(A),
                                                  C.POINTER(api.index_type)), shape=(JJ.size,))
                ip = np.ctypeslib.as_array(C.cast(api.SUNSparseMatrix_IndexPointers(A),
                                                  C.POINTER(api.index_type)), shape=(n + 1,))
                data[:], iv[:], ip[:] = JJ, rows, indptr
            else:
                A = api.SUNDenseMatrix(n, n, ctx)
                data = np.ctypeslib.as_array(C.cast(api.SUNDenseMatrix_Data(A),
                                                    C.POINTER(C.c_double)), shape=(n * n,))
                data[:] = dense.T.ravel()  # column-major
            LS = make(A)
            objs += [("m", A), ("ls", LS)]
            api.SUNLinSolInitialize(LS)
            saved = data.copy()
            f, s = [], []
            for rep in range(reps):
                data[:] = saved  # dense LU factors in place
                t0 = time.process_time()
                flag = api.SUNLinSolSetup(LS, A)
                f.append(time.process_time() - t0)
                if flag != 0:
                    raise RuntimeError(f"{label}: setup flag {flag}")
                bd[:] = 1.0
                t0 = time.process_time()
                api.SUNLinSolSolve(LS, A, x, b, 0.0)
                s.append(time.process_time() - t0)
            xd = np.ctypeslib.as_array(C.cast(api.N_VGetArrayPointer(x), C.POINTER(C.c_double)),
                                       shape=(n,))
            err = float(np.abs(dense @ xd - 1.0).max())
            out[label] = {"factor_us": statistics.median(f) * 1e6,
                          "solve_us": statistics.median(s) * 1e6, "residual_max": err}
    finally:
        for kind, o in reversed(objs):
            {"v": api.N_VDestroy, "m": api.SUNMatDestroy, "ls": api.SUNLinSolFree}[kind](o)
        api.SUNContext_Free(C.byref(ctx))
    out["block-arrow Schur (numba, standalone; dispatch incl.)"] = block_arrow_costs_us(
        model, y, yp)
    out["n"] = n
    out["nnz"] = int(JJ.size)
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--revolutions", type=float, default=3.0)
    ap.add_argument("--skip-full", action="store_true", help="only breakdown and linear algebra")
    ap.add_argument("--json", help="write the numbers here")
    args = ap.parse_args()
    report = {}
    scene = load_scene("yang20_baseline", {"numerics.rtol": 1e-6,
                                           "numerics.warmup_cage_revolutions": 1.0,
                                           "numerics.cage_revolutions": args.revolutions})
    short = load_scene("yang20_baseline", {"numerics.warmup_cage_revolutions": 0.01,
                                           "numerics.cage_revolutions": 0.01})
    solvers = {"compiled": ida.IDA, "scikit-sundae": ida.IDAScikitSundae}
    for cls in solvers.values():
        run_with(cls, short)  # JIT and library loading outside the timing
    stats = {}
    if not args.skip_full:
        walls = {k: [] for k in solvers}
        for rep in range(args.repeat):
            for key, cls in solvers.items():
                ds, w, cpu = run_with(cls, scene)
                st = json.loads(ds.attrs["solver_statistics"])
                walls[key].append((w, st["wall_time_s"], cpu))
                stats[key] = st
                print(f"repeat {rep}: {key}: simulate {w:.2f} s, integration "
                      f"{st['wall_time_s']:.2f} s (CPU {cpu:.2f} s), residual calls "
                      f"{st['residual_calls']}, load {os.getloadavg()[0]:.1f}", flush=True)
        steps = stats["compiled"]["steps"]
        print(f"\nyang20 baseline, 1 + {args.revolutions:g} cage revolutions, rtol 1e-6, "
              f"median of {args.repeat}; IDA steps {steps} (from the compiled run)")
        for key in solvers:
            ws = statistics.median(w[0] for w in walls[key])
            wi = statistics.median(w[1] for w in walls[key])
            wc = statistics.median(w[2] for w in walls[key])
            st = stats[key]
            print(f"  {key:14s} simulate {ws:6.2f} s  integration {wi:6.2f} s (CPU {wc:6.2f} s) "
                  f" {wi / steps * 1e6:5.1f} µs/step wall, {wc / steps * 1e6:5.1f} µs/step CPU  "
                  f"residual calls {st['residual_calls']}  Jacobians {st['jacobian_calls']}")
            report[key] = {"simulate_s": ws, "integration_s": wi, "integration_cpu_s": wc,
                           "walls": walls[key], "us_per_step": wi / steps * 1e6,
                           "cpu_us_per_step": wc / steps * 1e6, **{k: st.get(k) for k in (
                               "residual_calls", "jacobian_calls")}}
        report["steps"] = steps
        report["compiled_stats"] = stats["compiled"]
        for i, what in ((1, "wall"), (2, "CPU")):
            ratio = [a[i] / b[i] for a, b in zip(walls["compiled"], walls["scikit-sundae"])]
            print(f"  integration {what} ratio compiled / scikit-sundae per repeat: "
                  + ", ".join(f"{r:.2f}" for r in ratio))

    m = build_model(load_scene("yang20_baseline"))
    y, yp = state_after(m, 1e-3)
    kc = kernel_costs_us(m, y, yp)
    lc = {"Z=20": linear_solver_costs_us(m, y, yp)}
    print(f"\nisolated costs at t = 1 ms: residual {kc['residual']:.1f} µs, analytic Jacobian "
          f"{kc['jacobian']:.1f} µs")
    if stats:
        st = stats["compiled"]
        n_st = st["steps"]
        slu = lc["Z=20"]["SuperLU_MT (sparse)"]
        per = report["compiled"]["cpu_us_per_step"]  # CPU: the kernel costs are CPU-bound too
        kern = (st["residual_calls"] * kc["residual"] + st["jacobian_calls"] * kc["jacobian"]) / n_st
        lin = (st["linear_solver_setups"] * slu["factor_us"]
               + st["nonlinear_iterations"] * slu["solve_us"]) / n_st
        print(f"per step (compiled, CPU): {per:.1f} µs = kernels {kern:.1f} "
              f"({st['residual_calls'] / n_st:.2f} residuals, {st['jacobian_calls'] / n_st:.3f} "
              f"Jacobians) + linear solve {lin:.1f} ({st['linear_solver_setups'] / n_st:.3f} "
              f"factorisations, {st['nonlinear_iterations'] / n_st:.2f} solves) + IDA and the "
              f"rest {per - kern - lin:.1f}")
        report["breakdown_us_per_step"] = {"total": per, "kernels": kern, "linear_solve": lin,
                                           "ida_and_rest": per - kern - lin}
    h36 = build_model(load_scene("harris36_static"))
    y36, yp36 = state_after(h36, 2e-4)
    lc["Z=36"] = linear_solver_costs_us(h36, y36, yp36)
    print("\nlinear algebra on the iteration matrix (cj = 1e6), median µs:")
    for z, d in lc.items():
        print(f"  {z}: n = {d['n']}, nnz = {d['nnz']}")
        for label, v in d.items():
            if isinstance(v, dict):
                print(f"    {label:38s} factor {v['factor_us']:7.1f}  solve {v['solve_us']:5.1f}"
                      f"  |Ax - b| {v['residual_max']:.1e}")
    report["kernels_us"], report["linear_algebra_us"] = kc, lc
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(report, fh, indent=1, default=str)


if __name__ == "__main__":
    main()
