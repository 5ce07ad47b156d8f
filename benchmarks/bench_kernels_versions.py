"""Kernels of this checkout against an earlier one in one process: agreement and per-call time
(docs/performance.md, "Kernels at their floor", "Third pass").

    git archive <commit> | (mkdir -p /tmp/old && tar -x -C /tmp/old)
    python benchmarks/bench_kernels_versions.py --old /tmp/old [--repeats 21] [--calls 2000]
        [--set physics.slip=paper --set traction.law=slide-roll ...]

The old tree's package is copied to a temporary folder as ``bearingdae_old`` (the package
imports itself only relatively), so both versions run in one process, interleaved repeat by
repeat (same machine load; process CPU time, medians and the median of the per-repeat
ratios).

Agreement (the check that a kernel change is round-off only): the residual and the analytic
Jacobian of both versions on the states of a baseline run (IDA, 0-4 ms, 81 samples, computed
with the new tree): max |F_new - F_old| over the largest force term max |F_old(y, 0)| (y' = 0
leaves the force side of every row; at a solution F(y, y') itself is ~0, so it is no scale),
and max |J_new - J_old| / max |J_old|. The old residual is the reference; round-off level is
~1e-15, a changed formula shows at 1e-8 or more.
"""

from __future__ import annotations

import argparse
import importlib
import os
import shutil
import sys
import tempfile
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from numba import njit  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CASE = os.path.join(ROOT, "cases", "yang20_baseline.toml")


def _overrides(pairs):
    """``key=value`` strings -> overrides (booleans and numbers parsed, the rest strings)."""
    out = {}
    for pair in pairs or ():
        key, _, text = pair.partition("=")
        value = {"true": True, "false": False}.get(text.lower(), text)
        if isinstance(value, str):
            try:
                value = float(text)
            except ValueError:
                pass
        out[key] = value
    return out


def _kernels(pkg: str, overrides):
    """Model, Jacobian work and compiled loops over residual, residual_flat and Jacobian."""
    model = importlib.import_module(pkg + ".system.model")
    rr = importlib.import_module(pkg + ".system.residual")
    ja = importlib.import_module(pkg + ".system.jacobian_analytic")
    ida = importlib.import_module(pkg + ".solvers.ida")
    m = model.build_model(importlib.import_module(pkg).load_scene(CASE, overrides))
    jd0, _ = ida._jacobian_work(m, ida.sparsity_pattern(m))
    jd = ja.analytic_work(m, jd0[1], jd0[2])
    res_f, flat_f, jac_f = rr.residual, rr.residual_flat, ja.jacobian_analytic_sparse

    @njit
    def residual_loop(n, t, y, yp, res, d):
        for _ in range(n):
            res_f(t, y, yp, res, d)

    @njit
    def flat_loop(n, t, y, yp, res, w):
        for _ in range(n):
            flat_f(t, y, yp, res, w)

    @njit
    def jacobian_loop(n, t, y, yp, res, JJ, d, jd):
        for _ in range(n):
            jac_f(t, y, yp, res, 1e3, JJ, d, jd)

    return m, jd, jd0[1].size, residual_loop, flat_loop, jacobian_loop


def run_states(overrides):
    from bearingdae import load_scene
    from bearingdae.solvers import ida
    from bearingdae.solvers.algebraic import initial_state
    from bearingdae.system.model import build_model

    m = build_model(load_scene(CASE, overrides))
    y0, yp0 = initial_state(m)
    r = ida.integrate(m, y0, yp0, np.linspace(0.0, 4e-3, 81))
    return np.asarray(r.t), np.asarray(r.y), np.asarray(r.yp)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", required=True, help="root of the old checkout (with bearingdae/)")
    ap.add_argument("--repeats", type=int, default=21)
    ap.add_argument("--calls", type=int, default=2000)
    ap.add_argument("--set", action="append", metavar="KEY=VALUE",
                    help="scene override for both trees (repeatable), e.g. physics.cage=false")
    a = ap.parse_args(argv)
    overrides = _overrides(a.set)
    tmp = tempfile.mkdtemp(prefix="bd_kernels_old_")
    try:
        shutil.copytree(os.path.join(a.old, "bearingdae"), os.path.join(tmp, "bearingdae_old"),
                        ignore=shutil.ignore_patterns("*.nbi", "*.nbc"))
        sys.path.insert(0, tmp)
        V = {name: _kernels(name, overrides) for name in ("bearingdae_old", "bearingdae")}
        T, Y, YP = run_states(overrides)
        worst_f = worst_j = 0.0
        for t, y, yp in zip(T, Y, YP):
            out = {}
            for name, (m, jd, nnz, rl, fl, jl) in V.items():
                f0 = np.zeros(m.size)
                rl(1, float(t), y, np.zeros_like(yp), f0, m.data)
                res = np.zeros(m.size)
                rl(1, float(t), y, yp, res, m.data)
                JJ = np.zeros(nnz)
                jl(1, float(t), y, yp, res, JJ, m.data, jd)
                out[name] = (f0, res, JJ)
            (f0, r0, J0), (f1, r1, J1) = out["bearingdae_old"], out["bearingdae"]
            scale = np.abs(f0).max()
            worst_f = max(worst_f, np.abs(f1 - f0).max() / scale, np.abs(r1 - r0).max() / scale)
            worst_j = max(worst_j, np.abs(J1 - J0).max() / np.abs(J0).max())
        print(f"agreement on {len(T)} states of a baseline run (0-4 ms): residual "
              f"{worst_f:.2e} of the largest force term, Jacobian {worst_j:.2e} relative")
        t, y, yp = float(T[20]), Y[20], YP[20]  # 1 ms into the run
        times = {(n, k): [] for n in V for k in ("res", "flat", "jac")}
        clock = time.process_time
        for _ in range(a.repeats):
            for name, (m, jd, nnz, rl, fl, jl) in V.items():
                res, JJ = np.zeros(m.size), np.zeros(nnz)
                t0 = clock()
                rl(a.calls, t, y, yp, res, m.data)
                times[name, "res"].append((clock() - t0) / a.calls)
                t0 = clock()
                fl(a.calls, t, y, yp, res, m.work)
                times[name, "flat"].append((clock() - t0) / a.calls)
                t0 = clock()
                jl(a.calls // 4, t, y, yp, res, JJ, m.data, jd)
                times[name, "jac"].append((clock() - t0) / (a.calls // 4))
        print(f"{'kernel, us per call (CPU)':34s} {'old':>7s} {'new':>7s} {'ratio':>6s}"
              f"   (medians of {a.repeats} interleaved repeats)")
        for k, label in (("res", "residual (work tuple)"), ("flat", "residual_flat (IDA's callback)"),
                         ("jac", "analytic Jacobian")):
            old, new = np.array(times["bearingdae_old", k]), np.array(times["bearingdae", k])
            print(f"{label:34s} {np.median(old) * 1e6:7.2f} {np.median(new) * 1e6:7.2f} "
                  f"{np.median(new / old):6.3f}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
