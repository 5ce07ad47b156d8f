"""Per-call cost of the compiled kernels, and agreement with another tree.

    python benchmarks/run.py kernels [--repeats 15] [--calls 2000] [--set KEY=VALUE ...]
    python benchmarks/run.py kernels --old REV [--repeats 21] [--set KEY=VALUE ...] [--json F]
    python benchmarks/run.py kernels --passes [--set KEY=VALUE ...]
    python benchmarks/run.py kernels --per-step [--set KEY=VALUE ...] [--json F]

Times, from inside compiled loops (numba's dispatch from Python not counted) and in process
CPU time (wall time on a shared machine also counts the other jobs), at one state of a run of
the scene (default yang20_baseline, 1 ms into the run: rollers in and out of the load zone):

- ``residual``: the DAE residual with its work tuple; ``residual_flat``: the same as IDA's
  callback reaches it (the work as two flat buffers, views rebuilt in compiled code);
- the analytic Jacobian (``jacobian_analytic_sparse``);
- the block-arrow factorisation and solve of IDA's iteration matrix dF/dy + c_j dF/dy' at
  c_j = 1e6 (the default linear solver; skipped for a tree that does not have it).

``--passes``: this tree's passes apart, to say which loop a switch's cost is in: the
residual's kinematics, contact (loads and tractions) and roller passes, and of the Jacobian
the contact slopes; with mixed lubrication each contact loop also with the full-film tractions
at the same state (the parameter switched off in a copy), the difference being the mixed
pass; with rolling resistance its residual pass and Jacobian block.

``--per-step``: then the scene's whole run (``simulate``, its window as the scene sets it)
once in this process, and what a step costs: IDA's counts per step (residual calls, Newton
iterations = block-arrow solves, Jacobians, factorisations) times the CPU of one call above,
beside the run's process CPU over its steps; the difference is IDA's own work (vector
operations, error test), the per-step hooks and the per-sample output.

``--old``: the other tree's package is copied to a temporary folder as ``bearingdae_old`` (the
package imports itself only relatively), so both run in one process, interleaved repeat by
repeat; the ratios are medians of the per-repeat ratios new/old. Agreement first: residual and
Jacobian of both on the 81 states of the run's first 4 ms, as max |F_new - F_old| over the
largest force term max |F_old(y, 0)| and max |J_new - J_old| / max |J_old|. Round-off is
~1e-15; a changed formula shows at 1e-8 or more.
"""

from __future__ import annotations

import argparse
import importlib
import os
import shutil
import sys
import tempfile
import time

import numpy as np
from numba import njit

from run import header, median, overrides, summary, tree, write_json

CJ = 1e6  # c_j of the iteration matrix: 1/h for a step of 1 µs


def states(pkg: str, case: str, over: dict):
    """(t, y, y') at the 81 outputs of the first 4 ms of a run (IDA of package ``pkg``)."""
    m = importlib.import_module(pkg + ".system.model").build_model(
        importlib.import_module(pkg).load_scene(case, over))
    algebraic = importlib.import_module(pkg + ".solvers.algebraic")
    y0, yp0 = algebraic.initial_state(m)
    r = importlib.import_module(pkg + ".solvers.ida").IDA().integrate(
        m, y0, yp0, np.linspace(0.0, 4e-3, 81))
    return np.asarray(r.t), np.asarray(r.y), np.asarray(r.yp)


class Kernels:
    """One package's model of the scene and compiled loops over its kernels."""

    def __init__(self, pkg: str, case: str, over: dict):
        imp = lambda name: importlib.import_module(f"{pkg}.{name}")  # noqa: E731
        ida, ja, rr = imp("solvers.ida"), imp("system.jacobian_analytic"), imp("system.residual")
        self.name = pkg
        self.m = m = imp("system.model").build_model(importlib.import_module(pkg).load_scene(
            case, over))
        jd0, csc = ida._jacobian_work(m, ida.sparsity_pattern(m))
        self.rows, self.cols = jd0[1], jd0[2]
        self.jd = ja.analytic_work(m, jd0[1], jd0[2])
        self.JJ, self.res = np.zeros(csc.nnz), np.zeros(m.size)
        # IDA's flat callback: in system.residual with work (W, I, marker) in older trees, in
        # solvers.ida_scikit_sundae with (W, I, marker, scratch for y and y') since 2026-11-30
        self.flat_scratch = not hasattr(rr, "residual_flat")
        flat_f = imp("solvers.ida_scikit_sundae").residual_flat if self.flat_scratch \
            else rr.residual_flat
        res_f, jac_f = rr.residual, ja.jacobian_analytic_sparse

        @njit
        def residual_loop(n, t, y, yp, res, d):
            for _ in range(n):
                res_f(t, y, yp, res, d)

        @njit
        def flat_loop(n, t, y, yp, res, w):
            for _ in range(n):
                flat_f(t, y, yp, res, w)

        @njit
        def jacobian_loop(n, t, y, yp, res, cj, JJ, d, jd):
            for _ in range(n):
                jac_f(t, y, yp, res, cj, JJ, d, jd)

        self.loops = residual_loop, flat_loop, jacobian_loop
        try:
            self.ba = imp("solvers.blockarrow")
        except ImportError:
            self.ba = None
        if self.ba is not None:
            factor, solve = self.ba.factor, self.ba.solve

            @njit
            def factor_loop(n, J, Z, nl, ng, Ainv, W, G, S, pivS, M):
                for _ in range(n):
                    factor(J, Z, nl, ng, Ainv, W, G, S, pivS, M)

            @njit
            def solve_loop(n, Z, nl, ng, Ainv, W, G, S, pivS, b, x):
                for _ in range(n):
                    solve(Z, nl, ng, Ainv, W, G, S, pivS, b, x)
                    b[0] += 1e-300  # a changing input: the solve is not hoisted out

            self.ba_loops = factor_loop, solve_loop

    def evaluate(self, t, y, yp):
        """(F(y, 0), F(y, y'), Jacobian values) at one state."""
        rl, _, jl = self.loops
        f0 = np.zeros(self.m.size)
        rl(1, t, y, np.zeros_like(yp), f0, self.m.data)
        res = np.zeros(self.m.size)
        rl(1, t, y, yp, res, self.m.data)
        JJ = np.zeros_like(self.JJ)
        jl(1, t, y, yp, res, 1e3, JJ, self.m.data, self.jd)
        return f0, res, JJ

    def time(self, t, y, yp, calls: int) -> dict:
        """µs of CPU per call of each kernel at (t, y, y')."""
        rl, fl, jl = self.loops
        m, clock, out = self.m, time.process_time, {}
        # (W, I, marker): trees whose model.work lacks the marker take it from model.data
        flat = m.work if len(m.work) >= 3 else m.work + m.data[-1:]
        if self.flat_scratch:
            flat = flat + (np.empty((2, m.size)),)
        for key, run, n in (
                ("residual", lambda n: rl(n, t, y, yp, self.res, m.data), calls),
                ("residual_flat", lambda n: fl(n, t, y, yp, self.res, flat), calls),
                ("jacobian", lambda n: jl(n, t, y, yp, self.res, CJ, self.JJ, m.data, self.jd),
                 calls // 4)):
            c0 = clock()
            run(n)
            out[key] = (clock() - c0) / n * 1e6
        if self.ba is not None:
            lay = m.layout
            Z, nl, ng = lay.rollers, lay.n_local, lay.n_global
            dense = np.zeros((m.size, m.size))
            dense[self.rows, self.cols] = self.JJ
            work = self.ba.work_arrays(Z, nl, ng)
            b, x = np.ones(m.size), np.zeros(m.size)
            fl_, sl_ = self.ba_loops
            fl_(1, dense, Z, nl, ng, *work)
            c0 = clock()
            fl_(calls, dense, Z, nl, ng, *work)
            out["blockarrow_factor"] = (clock() - c0) / calls * 1e6
            c0 = clock()
            sl_(calls * 4, Z, nl, ng, *work[:5], b, x)
            out["blockarrow_solve"] = (clock() - c0) / (calls * 4) * 1e6
        return out


def pass_times(k: Kernels, t, y, yp, calls: int, repeats: int) -> dict:
    """µs of CPU per call of the residual's and Jacobian's passes (``--passes``) at (t, y, y'),
    medians of ``repeats``; each contact loop runs after the kinematics pass that refills its
    inputs, whose time is taken off."""
    from bearingdae.system import contact_slopes as cs, residual as R
    from bearingdae.system import rolling_resistance as rr
    from bearingdae.system.model import WORK_SLOTS
    from bearingdae.system.param_vector import P_MX, P_RR

    m = k.m
    d = m.data
    R.residual(t, y, yp, k.res, d)
    P = d[0]
    P_full = P.copy()
    P_full[P_MX] = 0.0  # the full-film tractions (no code of mixed lubrication runs)
    tr = np.empty((4,) + d[16].shape)
    Jd = np.zeros((m.size, m.size))

    # the work tuple's slots, indexed by constants (the optional passes' marker last)
    (X, C, RT, RW, YL, YPL, YG, S, RS, LM, GM, RESL, CON, Q, PR, V, F, FP, SCR) = (
        WORK_SLOTS.index(n) for n in (
            "x_m", "profile_drop_m", "ramp_t", "ramp_w", "y_local", "yp_local", "y_global",
            "unknown_scale", "row_scale", "local_map", "global_map", "res_local",
            "contributions", "contact_force", "contact_pressure", "slip_velocity",
            "traction_force", "cage_force", "roller_scratch"))
    OPT = len(d) - 1

    @njit
    def kinematics(P, d):
        R.kinematics_pass(d[YL], d[YG], R.ring_speed_at(t, d[RT], d[RW]), P, d[X], d[C], d[Q],
                          d[V], d[F], d[CON])

    @njit
    def kin(n, P, d):
        for _ in range(n):
            kinematics(P, d)

    @njit
    def contact(n, P, d):
        for _ in range(n):
            kinematics(P, d)
            R.contact_pass(P, d[Q], d[PR], d[V], d[F], d[OPT])

    @njit
    def slopes(n, P, d, tr):
        for _ in range(n):
            kinematics(P, d)
            cs.contact_slopes(P, d[Q], d[PR], d[V], d[F], tr, d[OPT])

    @njit
    def roller(n, P, d):
        for _ in range(n):
            R.roller_pass(d[YL], d[YPL], d[YG], P, d[X], d[RESL], d[CON], d[Q], d[F], d[FP],
                          d[SCR])

    @njit
    def rolling(n, P, d):
        for _ in range(n):
            rr.rolling_resistance_pass(d[YL], R.ring_speed_at(t, d[RT], d[RW]), P[P_RR:], d[X],
                                       d[Q], d[RESL])

    @njit
    def rolling_jac(n, P, d, Jd):
        for _ in range(n):
            rr.rolling_resistance_jacobian(d[YL], d[YG], R.ring_speed_at(t, d[RT], d[RW]),
                                           P[P_RR:], d[X], d[Q], d[PR], d[CON], d[S], d[RS],
                                           d[LM], d[GM], Jd)

    mixed, rolling_on = P[P_MX] > 0.5, P[P_RR] > 0.5
    runs = {"kinematics": (kin, (P, d)), "contact": (contact, (P, d)),
            "contact_slopes": (slopes, (P, d, tr))}
    if mixed:
        runs["contact_full_film"] = (contact, (P_full, d))
        runs["contact_slopes_full_film"] = (slopes, (P_full, d, tr))
    runs["roller"] = (roller, (P, d))
    if rolling_on:
        runs["rolling_resistance"] = (rolling, (P, d))
        # loads and their slopes in q, pr, as the rolling resistance's passes find them
        # (the slopes pass leaves both; the contact pass, run last in a repeat, leaves loads)
        runs["rolling_resistance_jacobian"] = (rolling_jac, (P, d, Jd))
    times = {key: [] for key in runs}
    clock = time.process_time
    for fn, args in runs.values():
        fn(1, *args)  # compiled outside the timing
    for _ in range(repeats):
        for key, (fn, args) in runs.items():
            if key in ("roller", "rolling_resistance"):
                contact(1, P, d)  # loads and tractions of the state
            elif key == "rolling_resistance_jacobian":
                slopes(1, P, d, tr)
            c0 = clock()
            fn(calls, *args)
            times[key].append((clock() - c0) / calls * 1e6)
    med = {key: median(v) for key, v in times.items()}
    for key in ("contact", "contact_slopes", "contact_full_film", "contact_slopes_full_film"):
        if key in med:
            med[key] -= med["kinematics"]
    return med


PASS_LABELS = {
    "kinematics": "residual: kinematics pass", "contact": "residual: contact pass",
    "contact_full_film": "  the same with full-film tractions", "roller": "residual: roller pass",
    "rolling_resistance": "residual: rolling resistance pass",
    "contact_slopes": "Jacobian: contact slopes",
    "contact_slopes_full_film": "  the same with full-film tractions",
    "rolling_resistance_jacobian": "Jacobian: rolling resistance block"}


LABELS = {"residual": "residual (work tuple)", "residual_flat": "residual_flat (IDA's callback)",
          "jacobian": "analytic Jacobian", "blockarrow_factor": "block-arrow factorisation",
          "blockarrow_solve": "block-arrow solve"}


#: per-step rows: (label, IDA's count in solver_statistics, kernel timed above)
PER_STEP = (("residual, as IDA calls it", "residual_calls", "residual_flat"),
            ("block-arrow solve (one per Newton iteration)", "nonlinear_iterations",
             "blockarrow_solve"),
            ("analytic Jacobian", "jacobian_calls", "jacobian"),
            ("block-arrow factorisation of the iteration matrix", "linear_solver_setups",
             "blockarrow_factor"))


def per_step(case: str, over: dict, us: dict) -> dict:
    """The scene's run once: its counts per step times ``us`` (µs per call), and its process
    CPU per step (module docstring, ``--per-step``)."""
    import json
    import warnings

    from bearingdae import load_scene, simulate

    scene = load_scene(case, over)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        c0 = time.process_time()
        ds = simulate(scene)
        cpu = time.process_time() - c0
    st = json.loads(ds.attrs["solver_statistics"])
    steps = st["steps"]
    out = {"steps": steps, "process_cpu_s": cpu, "rows": []}
    print(f"\nper IDA step of the whole run ({steps} steps, {cpu:.2f} s of CPU):")
    print(f"{'part of a step':50s} calls/step  µs/call  µs/step")
    kernels = 0.0
    for label, count, key in PER_STEP:
        per = st[count] / steps
        kernels += per * us[key]
        out["rows"].append({"part": label, "count": count, "calls": st[count],
                            "calls_per_step": per, "us_per_call": us[key],
                            "us_per_step": per * us[key]})
        print(f"{label:50s} {per:10.3f} {us[key]:8.2f} {per * us[key]:8.2f}")
    out["kernels_us_per_step"] = kernels
    out["process_us_per_step"] = cpu / steps * 1e6
    print(f"{'compiled kernels by these counts':50s} {'':19s} {kernels:8.2f}")
    print(f"{'the run (simulate) by its process CPU':50s} {'':19s} "
          f"{out['process_us_per_step']:8.2f}")
    return out


def main(argv=None, name="kernels") -> None:
    ap = argparse.ArgumentParser(prog=f"run.py {name}", description=summary(__doc__))
    ap.add_argument("--old", help="git revision or folder to compare with (agreement and time)")
    ap.add_argument("--case", default="yang20_baseline")
    ap.add_argument("--set", action="append", metavar="KEY=VALUE",
                    help="scene override for both trees, e.g. traction.law=slide-roll")
    ap.add_argument("--repeats", type=int, default=15)
    ap.add_argument("--calls", type=int, default=2000)
    ap.add_argument("--passes", action="store_true", help="also this tree's passes apart "
                    "(module docstring)")
    ap.add_argument("--per-step", action="store_true", help="then the scene's whole run: "
                    "CPU per IDA step by kernel (module docstring)")
    ap.add_argument("--json", help="write the medians (and ratios) here")
    a = ap.parse_args(argv)
    over = overrides(a.set)
    from bearingdae.scene.lookup import resolve_case

    case = str(resolve_case(a.case))  # a path: the old tree's copy finds no bundled cases
    shown = f" {over}" if over else ""
    header(f"kernels of {a.case}{shown}, µs of CPU per call, medians of {a.repeats}")
    tmp = None
    names = ["bearingdae"]
    try:
        if a.old:
            tmp = tempfile.mkdtemp(prefix="bd_kernels_old_")
            shutil.copytree(tree(a.old) / "bearingdae", os.path.join(tmp, "bearingdae_old"),
                            ignore=shutil.ignore_patterns("*.nbi", "*.nbc", "__pycache__"))
            sys.path.insert(0, tmp)
            names.insert(0, "bearingdae_old")
        V = {n: Kernels(n, case, over) for n in names}
        T, Y, YP = states("bearingdae", case, over)
        if a.old:
            worst_f = worst_j = 0.0
            for t, y, yp in zip(T, Y, YP):
                (f0, r0, J0), (f1, r1, J1) = (V[n].evaluate(float(t), y, yp) for n in names)
                scale = np.abs(f0).max()
                worst_f = max(worst_f, np.abs(f1 - f0).max() / scale,
                              np.abs(r1 - r0).max() / scale)
                worst_j = max(worst_j, np.abs(J1 - J0).max() / np.abs(J0).max())
            print(f"agreement on {len(T)} states (0-4 ms): residual {worst_f:.1e} of the largest "
                  f"force term, Jacobian {worst_j:.1e} relative")
        t, y, yp = float(T[20]), Y[20], YP[20]  # 1 ms into the run
        for k in V.values():
            k.evaluate(t, y, yp)  # compiles the loops outside the timing
            k.time(t, y, yp, 4)
        rows = {n: [] for n in names}
        for _ in range(a.repeats):
            for n in names:
                rows[n].append(V[n].time(t, y, yp, a.calls))
        g = V["bearingdae"].m.geometry
        contacts = 2 * g.rollers * g.slices
        result = {"benchmark": name, "case": a.case, "overrides": over, "median_us": {},
                  "ratio_new_over_old": {}}
        print(f"{'kernel':32s} " + ("   old     new   new/old" if a.old else "  µs/call"))
        for key, label in LABELS.items():
            if not all(key in r for n in names for r in rows[n]):
                continue
            med = {n: median(r[key] for r in rows[n]) for n in names}
            result["median_us"][key] = med
            line = f"{label:32s} " + " ".join(f"{med[n]:7.2f}" for n in names)
            if a.old:
                ratio = median(rn[key] / ro[key] for rn, ro in
                               zip(rows["bearingdae"], rows["bearingdae_old"]))
                result["ratio_new_over_old"][key] = ratio
                line += f"  {ratio:6.3f}"
            print(line)
        r_med = result["median_us"]["residual"]["bearingdae"]
        print(f"residual: {r_med * 1e3 / contacts:.1f} ns per slice contact ({contacts} contacts)")
        if a.passes:
            result["passes_us"] = pt = pass_times(V["bearingdae"], t, y, yp, a.calls,
                                                  a.repeats)
            for key, label in PASS_LABELS.items():
                if key in pt:
                    print(f"{label:36s} {pt[key]:7.2f}")
        if a.per_step:
            result["per_step"] = per_step(case, over, {k: v["bearingdae"] for k, v in
                                                       result["median_us"].items()})
        write_json(a.json, result)
    finally:
        if tmp:
            shutil.rmtree(tmp, ignore_errors=True)
