"""IDASetSuppressAlg variants on the baseline: steps, residual calls, Jacobians, where it fails.

Run on demand (counts, not wall time: the machine is shared):

    python benchmarks/suppress_alg_mask.py --until 0.02 --variants off all restarts mask:0.1
    python benchmarks/suppress_alg_mask.py --full --variants off restarts mask:0.1:ring mask:0:ring

Variants (output samples as in ``simulate``, 200 per cage revolution, from t = 0):

- ``off``: ``IDA()`` = ``IDA(suppress_alg=False)``, every unknown in the error test (the default);
- ``all``: ``IDA(suppress_alg=True, max_restarts=0)``: every algebraic unknown out, no restart;
- ``restarts``: ``IDA(suppress_alg=True)``: every algebraic unknown out, projected restart on
  corrector failure;
- ``mask:F[:ring][:floor=Q]``: *selective* suppression, no restart: after each output sample the
  id vector is rewritten (``Session.set_error_test_mask``) so that roller j's radial position
  and tilt stay in the error test while its smaller race load min(Q_inner, Q_outer) is below
  F × the largest such load in the bearing (leaving only above 2 F: hysteresis); ``ring``: the
  ring unknowns stay in too; ``floor=Q``: only rollers above Q newtons on both races count
  as light (the rollers at the edge of the load zone; the unloaded ones are out);
- any of these with ``/maxnl=K``: ``IDASetMaxNonlinIters(K)`` (IDA's default 4 Newton
  iterations per attempt).

A failed run reports the algebraic rows that are off at IDA's last accepted state, the loads
of that roller and whether its unknowns were in the error test at that moment.
"""

from __future__ import annotations

import argparse
import json
import os
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import bearingdae.solvers.sundials.session as session  # noqa: E402
from bearingdae import load_scene  # noqa: E402
from bearingdae.api import output_times  # noqa: E402
from bearingdae.solvers.algebraic import initial_state  # noqa: E402
from bearingdae.solvers.ida import IDA  # noqa: E402
from bearingdae.system.layout import ALGEBRAIC  # noqa: E402
from bearingdae.system.model import build_model  # noqa: E402

LEAVE_FACTOR = 2.0  # a light roller leaves the error test above LEAVE_FACTOR × the threshold


class LoadMask:
    """Selective error-test mask from the roller loads (see module docstring)."""

    def __init__(self, model, fraction: float, ring_in_test: bool, floor_N: float):
        lay = model.layout
        self.model, self.fraction, self.floor_N = model, fraction, floor_N
        alg_local = np.flatnonzero([n in ALGEBRAIC for n in lay.local_names])
        self.rows = np.arange(lay.rollers)[:, None] * lay.n_local + alg_local[None, :]
        self.base = ~lay.algebraic
        if ring_in_test:
            self.base[lay.rollers * lay.n_local:] = True
        self.light = np.ones(lay.rollers, dtype=bool)
        self.updates, self.light_sum = 0, 0

    def __call__(self, t, y) -> np.ndarray:
        q = self.model.diagnostics(t, y)["contact_force"].sum(axis=1).min(axis=1)  # (Z,) [N]
        q_ref = float(q.max())
        if q_ref > 0:
            light = (q < self.fraction * q_ref) | (
                self.light & (q < LEAVE_FACTOR * self.fraction * q_ref))
            if self.floor_N > 0:
                light &= q > self.floor_N
            self.light = light
        self.updates += 1
        self.light_sum += int(self.light.sum())
        mask = self.base.copy()
        mask[self.rows[self.light].ravel()] = True
        return mask


def parse(variant: str):
    """(IDA keywords, selective-mask settings or None, IDASetMaxNonlinIters or None)."""
    variant, _, maxnl = variant.partition("/maxnl=")
    opts, sel = _parse(variant)
    return opts, sel, int(maxnl) if maxnl else None


def _parse(variant: str):
    if variant == "off":
        return {"suppress_alg": False}, None
    if variant == "all":
        return {"suppress_alg": True, "max_restarts": 0}, None
    if variant == "restarts":
        return {"suppress_alg": True}, None
    parts = variant.split(":")
    assert parts[0] == "mask", variant
    floor = [float(p.split("=")[1]) for p in parts[2:] if p.startswith("floor=")]
    return ({"suppress_alg": True, "max_restarts": 0},
            (float(parts[1]), "ring" in parts[2:], floor[0] if floor else 0.0))


def run(scene_name: str, variant: str, until: float | None) -> dict:
    m = build_model(load_scene(scene_name))
    y0, yp0 = initial_state(m)
    t_out, _ = output_times(m)
    if until is not None:
        t_out = t_out[t_out <= until]
        if t_out[-1] < until:
            t_out = np.append(t_out, until)
    opts, selective, maxnl = parse(variant)
    mask = LoadMask(m, *selective) if selective else None
    captured = {}
    orig_solve, orig_ic = session.Session.solve, session.Session.calc_ic

    def calc_ic(self, t1):
        if maxnl is not None:
            self._check(self.api.IDASetMaxNonlinIters(self.mem, maxnl), "IDASetMaxNonlinIters")
        flag = orig_ic(self, t1)
        if mask is not None and flag >= 0:
            self.set_error_test_mask(mask(t1, self.y))
        return flag

    def solve(self, t):
        flag, reached = orig_solve(self, t)
        if flag < 0:
            captured.update(y=self.y.copy(), yp=self.yp.copy(), t=reached,
                            mask=self._id.copy())
        elif mask is not None:
            self.set_error_test_mask(mask(reached, self.y))
        return flag, reached
    session.Session.solve, session.Session.calc_ic = solve, calc_ic
    c0 = time.process_time()
    try:
        r = IDA(**opts).integrate(m, y0, yp0, t_out)
    finally:
        session.Session.solve, session.Session.calc_ic = orig_solve, orig_ic
    st = r.stats
    return {"variant": variant, "success": bool(r.success), "message": r.message[:200],
            "t_end": float(r.t[-1]) if len(r.t) else None, "steps": st["steps"],
            "residual_calls": st["residual_calls"], "jacobians": st["jacobian_calls"],
            "error_test_failures": st["error_test_failures"],
            "convergence_failures": st["nonlinear_convergence_failures"],
            "newton_iterations": st.get("nonlinear_iterations"),
            "restarts": st.get("restarts", 0), "restart_times_s": st.get("restart_times_s"),
            "mean_rollers_in_test": mask.light_sum / max(mask.updates, 1) if mask else None,
            "cpu_s": time.process_time() - c0,
            "failure": _failure_report(m, captured) if captured and not r.success else None}


def _failure_report(m, cap) -> dict:
    """Where the algebraic rows are off at the last accepted state of a failed run."""
    lay = m.layout
    y, t = cap["y"], cap["t"]
    F = m.residual(t, y, cap["yp"])
    names = lay.names()
    worst = np.argsort(-np.abs(F) * lay.algebraic)[:3]
    q = m.diagnostics(t, y)["contact_force"]
    rows = []
    for i in worst:
        j = i // lay.n_local if i < lay.rollers * lay.n_local else None
        rows.append({"unknown": names[i], "F": float(F[i]),
                     "in_error_test": bool(cap["mask"][i] > 0),
                     "inner_N": None if j is None else float(q[j, :, 0].sum()),
                     "outer_N": None if j is None else float(q[j, :, 1].sum())})
    return {"t": float(t), "max_roller_N": float(q[:, :, 0].sum(1).max()), "worst": rows}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", default="yang20_baseline")
    ap.add_argument("--until", type=float, default=0.02)
    ap.add_argument("--full", action="store_true", help="the whole default run")
    ap.add_argument("--variants", nargs="+", default=["off", "all", "restarts"])
    ap.add_argument("--json", default=None)
    args = ap.parse_args()
    rows = []
    for v in args.variants:
        row = run(args.scene, v, None if args.full else args.until)
        rows.append(row)
        print(json.dumps(row), flush=True)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
