"""Per-call time of the DAE kernels: residual and analytic Jacobian (docs/performance.md,
"Kernels at their floor").

    python benchmarks/bench_kernels.py [--state FILE] [--calls N] [--repeats R]

Times ``residual`` (work tuple), ``residual_flat`` (IDA's callback: the work as two flat buffers,
views rebuilt in compiled code) and ``jacobian_analytic_sparse`` of whichever ``bearingdae`` is
imported, at
one state of a baseline run (yang20_baseline after 2 ms: rollers in and out of the load zone,
some in pocket contact), from inside compiled code (an @njit loop), so numba's dispatch from
Python is not counted. ``--state`` stores/loads that state (npz), so that two versions of the
package can be timed at the same state: run once per version in one session, e.g.

    python benchmarks/bench_kernels.py --state /tmp/s.npz
    PYTHONPATH=/path/to/old/checkout python benchmarks/bench_kernels.py --state /tmp/s.npz

and quote the medians side by side. The contact pass is 400 slice contacts (20 rollers x 10
slices x 2 races) on the baseline, so ns per contact = time per call / 400. Times are process
CPU time (``time.process_time``): on the shared machine wall time also counts the other jobs'
time slices.
"""

from __future__ import annotations

import argparse
import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from numba import njit  # noqa: E402

import bearingdae  # noqa: E402
from bearingdae import load_scene  # noqa: E402
from bearingdae.system.jacobian_analytic import analytic_work, jacobian_analytic_sparse  # noqa
from bearingdae.solvers.algebraic import initial_state  # noqa: E402
from bearingdae.system.model import build_model  # noqa: E402
from bearingdae.system.residual import residual, residual_flat  # noqa: E402


@njit
def _residual_loop(n, t, y, yp, res, d):
    for _ in range(n):
        residual(t, y, yp, res, d)
    return res[0]


@njit
def _residual_flat_loop(n, t, y, yp, res, work):
    for _ in range(n):
        residual_flat(t, y, yp, res, work)
    return res[0]


@njit
def _jacobian_loop(n, t, y, yp, res, cj, JJ, d, jd):
    for _ in range(n):
        jacobian_analytic_sparse(t, y, yp, res, cj, JJ, d, jd)
    return JJ[0]


def baseline_state(model, t_end=2e-3):
    """(t, y, y') of the baseline at t_end, integrated with IDA from the initial state."""
    from bearingdae.solvers import ida

    y0, yp0 = initial_state(model)
    r = ida.integrate(model, y0, yp0, np.array([0.0, t_end]))
    return float(r.t[-1]), np.array(r.y[-1]), np.array(r.yp[-1])


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--state", help="npz file with t, y, yp (written if missing)")
    ap.add_argument("--calls", type=int, default=2000)
    ap.add_argument("--repeats", type=int, default=15)
    a = ap.parse_args(argv)
    m = build_model(load_scene("yang20_baseline"))
    if a.state and os.path.exists(a.state):
        s = np.load(a.state)
        t, y, yp = float(s["t"]), s["y"], s["yp"]
    else:
        t, y, yp = baseline_state(m)
        if a.state:
            np.savez(a.state, t=t, y=y, yp=yp)
    from bearingdae.solvers.ida import _jacobian_work, sparsity_pattern

    jd0, _ = _jacobian_work(m, sparsity_pattern(m))
    jd = analytic_work(m, jd0[1], jd0[2])
    JJ = np.zeros(jd0[1].size)
    res = np.zeros(m.size)
    _residual_loop(1, t, y, yp, res, m.data)
    _residual_flat_loop(1, t, y, yp, res, m.work)
    _jacobian_loop(1, t, y, yp, res, 1e3, JJ, m.data, jd)
    clock = time.process_time
    rt, ft, jt = [], [], []
    for _ in range(a.repeats):
        t0 = clock()
        _residual_loop(a.calls, t, y, yp, res, m.data)
        rt.append((clock() - t0) / a.calls)
        t0 = clock()
        _residual_flat_loop(a.calls, t, y, yp, res, m.work)
        ft.append((clock() - t0) / a.calls)
        t0 = clock()
        _jacobian_loop(a.calls // 4, t, y, yp, res, 1e3, JJ, m.data, jd)
        jt.append((clock() - t0) / (a.calls // 4))
    contacts = 2 * m.geometry.rollers * m.geometry.slices
    r_med, j_med = np.median(rt) * 1e6, np.median(jt) * 1e6
    print(f"package {os.path.dirname(bearingdae.__file__)}")
    print(f"residual  median {r_med:7.2f} us/call (min {min(rt) * 1e6:.2f}), "
          f"{r_med * 1e3 / contacts:5.1f} ns per contact ({contacts} contacts)")
    print(f"residual_flat (IDA's callback) median {np.median(ft) * 1e6:7.2f} us/call "
          f"(min {min(ft) * 1e6:.2f})")
    print(f"jacobian  median {j_med:7.2f} us/call (min {min(jt) * 1e6:.2f}), "
          f"{j_med / r_med:4.2f} residuals")
    print(f"checksum  |res|_1 = {np.abs(res).sum():.10e}, |JJ|_1 = {np.abs(JJ).sum():.10e}")


if __name__ == "__main__":
    main()
