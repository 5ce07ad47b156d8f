"""Why IDASetSuppressAlg fails on the baseline (issue 11 item 5; docs/performance.md).

Run on demand:  python benchmarks/suppress_alg_replay.py [--until 0.02]

Integrates the baseline from t = 0 with ``IDA(max_restarts=0)`` (SuppressAlg without the
projected restart of the default) until it fails, keeps the
last accepted state y_n that IDA returns on failure, and replays IDA's Newton iteration on it in
Python with the exact analytic Jacobian at several step sizes, as full Newton (a Jacobian at
every iterate) and as IDA's modified Newton (the Jacobian of the first iterate kept): the
algebraic rows of the worst roller at y_n, its contact forces, and the weighted Newton updates
per iteration (IDA stops after 4, ``IDASetMaxNonlinIters``).
"""

from __future__ import annotations

import argparse
import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import bearingdae.solvers.sundials.session as session  # noqa: E402
from bearingdae import load_scene  # noqa: E402
from bearingdae.solvers.ida import IDA, algebraic_atol, jacobian_filler  # noqa: E402
from bearingdae.solvers.algebraic import initial_state  # noqa: E402
from bearingdae.system.model import build_model  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--until", type=float, default=0.02)
    args = ap.parse_args()
    captured = {}
    original = session.Session.solve

    def solve(self, t):
        flag, reached = original(self, t)
        if flag < 0:
            captured.update(y=self.y.copy(), yp=self.yp.copy(), t=reached)
        return flag, reached
    session.Session.solve = solve
    m = build_model(load_scene("yang20_baseline"))
    y0, yp0 = initial_state(m)
    r = IDA(suppress_alg=True, max_restarts=0).integrate(m, y0, yp0,
                                                      np.linspace(0, args.until, 201))
    session.Session.solve = original
    print(r.message)
    if not captured:
        return
    y, yp, t = captured["y"], captured["yp"], captured["t"]
    dyn, alg = m.scene.dynamics, m.layout.algebraic
    w = 1.0 / (dyn.rtol * np.abs(y) + np.where(alg, algebraic_atol(dyn.atol), dyn.atol))
    names = [f"roller {j} {n}" for j in range(m.layout.rollers) for n in m.layout.local_names]
    names += list(m.layout.global_names)
    F = m.residual(t, y, yp)
    worst = np.argsort(-np.abs(F) * alg)[:3]
    print("largest algebraic residuals at y_n (force-scale units):",
          ", ".join(f"{names[i]} {F[i]:.2e}" for i in worst))
    j = int(names[worst[0]].split()[1])
    q = m.diagnostics(t, y)["contact_force"]
    print(f"roller {j} contact force: inner {q[j, :, 0].sum():.2f} N, outer "
          f"{q[j, :, 1].sum():.2f} N (most loaded roller: {q[:, :, 0].sum(1).max():.1f} N)")
    jd, fill, _ = jacobian_filler(m, "analytic")
    for h in (4e-7, 1e-9, 1e-12):
        cj = 1.0 / h
        for label, refresh in (("full Newton (Jacobian at every iterate)", True),
                               ("modified Newton (Jacobian of the first iterate, as IDA)",
                                False)):
            yy, ypp = y.copy(), yp.copy()
            updates = []
            for it in range(8):
                if refresh or it == 0:
                    fill(t + h, yy, ypp, cj, m.data, jd)
                    J = jd[0].copy()
                d = -np.linalg.solve(J, m.residual(t + h, yy, ypp))
                updates.append(float(np.sqrt(np.mean((d * w) ** 2))))
                yy += d
                ypp += cj * d
            print(f"h = {h:g} s, {label}: weighted updates "
                  + ", ".join(f"{u:.1e}" for u in updates))

if __name__ == "__main__":
    main()
