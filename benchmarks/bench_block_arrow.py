"""Block-arrow factor/solve kernels (solvers/blockarrow.py) timed inside compiled loops.

Run on demand: ``python benchmarks/bench_block_arrow.py`` — the iteration matrix of the
baseline (Z = 20) and of harris36 (Z = 36) at c_j = 1e6, residual of the solve against numpy,
then factor and solve in µs (numba loops of 20 000 / 200 000 calls: no dispatch or ctypes
overhead). Results: docs/performance.md, "Linear algebra".
"""
import os, sys, time
os.environ["OMP_NUM_THREADS"]="1"
sys.path.insert(0, "/work/main/benchmarks")
import numpy as np
from numba import njit
from bearingdae import load_scene
from bearingdae.system.model import build_model
from bearingdae.solvers.algebraic import initial_state
import bench_compiled_ida as B
from bearingdae.solvers.blockarrow import factor, solve, work_arrays

@njit(cache=False)
def loop_factor(reps, J, Z, nl, ng, Ainv, W, G, S, pivS, M):
    for r in range(reps):
        factor(J, Z, nl, ng, Ainv, W, G, S, pivS, M)
@njit(cache=False)
def loop_solve(reps, Z, nl, ng, Ainv, W, G, S, pivS, b, x):
    for r in range(reps):
        solve(Z, nl, ng, Ainv, W, G, S, pivS, b, x)
        b[0] += 1e-300

for case in ("yang20_baseline", "harris36_static"):
    m = build_model(load_scene(case)); y0, yp0 = initial_state(m)
    J, JJ, rows, ptr = B.iteration_matrix(m, y0, yp0, cj=1e6)
    lay = m.layout; Z, nl, ng = lay.rollers, lay.n_local, lay.n_global; n = m.size
    Ainv, W, G, S, pivS, M = work_arrays(Z, nl, ng)
    print(factor(J, Z, nl, ng, Ainv, W, G, S, pivS, M))
    b = np.random.default_rng(0).standard_normal(n); x = np.zeros(n)
    solve(Z, nl, ng, Ainv, W, G, S, pivS, b, x)
    print(case, "n", n, "Z nl ng", Z, nl, ng, "resid", np.abs(J @ x - b).max() / np.abs(b).max(), "vs numpy", np.abs(x - np.linalg.solve(J, b)).max()/np.abs(x).max())
    loop_factor(1, J, Z, nl, ng, Ainv, W, G, S, pivS, M); loop_solve(1, Z, nl, ng, Ainv, W, G, S, pivS, b, x)
    for _ in range(3):
        t = time.perf_counter(); loop_factor(20000, J, Z, nl, ng, Ainv, W, G, S, pivS, M); tf = (time.perf_counter() - t) / 20000
        t = time.perf_counter(); loop_solve(200000, Z, nl, ng, Ainv, W, G, S, pivS, b, x); ts = (time.perf_counter() - t) / 200000
        print(f"factor {tf*1e6:.2f} us, solve {ts*1e6:.2f} us")
