"""The cost of each scene or solver switch against the default run, side by side in one process.

    python benchmarks/run.py switches [--repeat 3] [--warmup 1] [--revolutions 1]
        [--only NAME ...] [--try KEY=VALUE[,KEY=VALUE...] ...] [--case yang20_baseline]
        [--set KEY=VALUE ...] [--ida KEY=VALUE[,...] ...] [--atol NAME=FACTOR[,...] ...]
        [--limiters] [--modes] [--errors] [--json F]

Each repeat runs ``simulate`` of the scene (by default yang20_baseline over 1 warm-up + 1
recorded cage revolution, half the default run) once per switch below, in turn, after an
untimed short run of every switch (its kernels loaded or compiled). Reported per switch: the
process CPU and wall time of ``simulate`` (medians), IDA's steps, residual calls and
Jacobians, and the median of the per-repeat ratios of CPU time to the default's (same machine
load), with their range. ``--try`` adds a switch of your own: scene overrides,
comma-separated; ``--set`` changes the case for every switch (e.g. a defect case at another
clearance). A scene switch changes the physics and so the trajectory and its step count;
a solver switch leaves the scene alone. (The scikit-sundae path reports no step count.)

``--ida`` adds a solver switch of IDA's options (e.g. ``--ida max_order=4``); ``--atol`` one
with those unknowns' absolute tolerance times the factor
(``IDA(atol_factors=...)``, e.g. ``--atol skew_angle=10,skew_rate=10``). ``--errors``: then,
for every IDA switch, its error over the work-precision window (the first 0.2 cage revolution
from t = 0) against the case at rtol 1e-10 (relative RMS of the cage speed and the skew angle,
as the work-precision study), to judge a cheaper switch at equal error.

``--limiters``: after the timed repeats, one more run of each IDA switch with
``IDA(record_steps=True)`` (untimed: a Python round trip per step) that names, per accepted
step, the unknown with the largest weighted local error (IDA's error test, which sets the
step): the share of the steps each unknown limits and the median step, to tell whether a
switch costs steps because of the physics it adds or a feature IDA must resolve.

``--modes``: then, per IDA switch, the linearised DAE's modes (analysis/modes.py) at
:data:`MODE_STATES` states evenly spread over the recorded window of one more run: the fastest
lightly damped oscillation at each (frequency, damping ratio, the unknown that moves most),
and the run's mean step against its period (steps per period), to tell a step set by a mode
the physics keeps ringing from one set by events. Beside them, the steps per period IDA takes
on an undamped oscillator alone (u' = ω v, v' = -ω u, amplitude 1, over :data:`OSCILLATOR_PERIODS`
periods, scikit-sundae's IDA at the case's rtol and at atol = the case's and 1e-12): what
following a ringing mode costs at this tolerance, whatever else a step does.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from run import fail, header, median, overrides, summary, write_json

#: name: (scene overrides, solver name, solver options)
SWITCHES = {
    "default": ({}, "ida", {}),
    "20 slices": ({"numerics.slices": 20}, "ida", {}),
    "5 slices": ({"numerics.slices": 5}, "ida", {}),
    "slide-to-roll traction law": ({"traction.law": "slide-roll"}, "ida", {}),
    "paper slip kinematics": ({"physics.slip": "paper"}, "ida", {}),
    "no cage (no pocket contact)": ({"physics.cage": False}, "ida", {}),
    "no lubricant drag": ({"physics.drag": False}, "ida", {}),
    "rtol 1e-5": ({"numerics.rtol": 1e-5}, "ida", {}),
    "rtol 1e-7": ({"numerics.rtol": 1e-7}, "ida", {}),
    "SuperLU_MT linear solver": ({}, "ida", {"linsolver": "sparse"}),
    "dense linear solver": ({}, "ida", {"linsolver": "dense"}),
    "finite-difference Jacobian": ({}, "ida", {"jacobian": "fd"}),
    "IDASetSuppressAlg": ({}, "ida", {"suppress_alg": True}),
    "scikit-sundae callbacks": ({}, "ida-scikit-sundae", {}),
    "Newmark-beta, h = 2 µs": ({}, "newmark", {}),
    # the case without its [[defects]] and [[waviness]] (the default run on a case with none):
    # what a defect costs, e.g. --case defects/outer_spall --only "no defects or waviness"
    "no defects or waviness": ({"defects": [], "waviness": []}, "ida", {}),
}


def _simulate(case: str, window: dict, switch: tuple, **solver_options):
    """(the IDA statistics, CPU [s], wall [s]) of ``simulate`` of ``switch`` on the case."""
    from bearingdae import load_scene, simulate
    from bearingdae.solvers import from_name

    over, solver, options = switch
    scene = load_scene(case, {**window, **over})
    c0, t0 = time.process_time(), time.perf_counter()
    ds = simulate(scene, solver=from_name(solver, **options, **solver_options))
    cpu, wall = time.process_time() - c0, time.perf_counter() - t0
    return json.loads(ds.attrs["solver_statistics"]), cpu, wall


def run_one(case: str, window: dict, switch: tuple) -> dict:
    st, cpu, wall = _simulate(case, window, switch)
    return {"cpu_s": cpu, "wall_s": wall, "steps": st.get("steps"),
            "residual_calls": st.get("residual_calls"), "jacobians": st.get("jacobian_calls")}


def limiters(case: str, window: dict, switch: tuple) -> dict:
    """{median_step_s, step_limiters (shares of the steps, most first), steps} of one run
    of ``switch`` with every internal step recorded (solvers/ida.py ``record_steps``)."""
    st = _simulate(case, window, switch, record_steps=True)[0]
    n = sum(st["step_limiters"].values())
    return {"median_step_s": st["median_step_s"], "steps": st["steps"],
            "step_limiters": {k: v / n for k, v in st["step_limiters"].items()}}


def main(argv=None, name="switches") -> None:
    ap = argparse.ArgumentParser(prog=f"run.py {name}", description=summary(__doc__))
    ap.add_argument("--case", default="yang20_baseline")
    ap.add_argument("--warmup", type=float, default=1.0, help="warm-up cage revolutions")
    ap.add_argument("--revolutions", type=float, default=1.0, help="recorded cage revolutions")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--only", nargs="+", metavar="NAME", help="these switches (and the "
                    f"default) only; names: {', '.join(repr(s) for s in SWITCHES)}")
    ap.add_argument("--try", dest="extra", action="append", metavar="KEY=VALUE[,KEY=VALUE]",
                    help="a switch of your own (scene overrides), e.g. --try numerics.slices=15")
    ap.add_argument("--set", dest="case_set", action="append", default=[], metavar="KEY=VALUE",
                    help="an override of the case for every switch, e.g. --set "
                    "bearing.radial_clearance_mm=0.01")
    ap.add_argument("--atol", dest="atols", action="append", metavar="NAME=FACTOR[,...]",
                    help="an IDA switch: these unknowns' atol times the factor, e.g. --atol "
                    "skew_rate=10")
    ap.add_argument("--ida", dest="idas", action="append", metavar="KEY=VALUE[,...]",
                    help="an IDA switch: these IDA(...) options, e.g. --ida max_order=4 or "
                    "--ida nonlin_conv_coef=0.2")
    ap.add_argument("--errors", action="store_true", help="then each IDA switch's error over "
                    "the work-precision window against rtol 1e-10 (module docstring)")
    ap.add_argument("--limiters", action="store_true", help="then one untimed run per IDA "
                    "switch naming the unknown that limits each step (module docstring)")
    ap.add_argument("--modes", action="store_true", help="then, per IDA switch, the fastest "
                    "lightly damped mode along the run and the steps per its period (module "
                    "docstring)")
    ap.add_argument("--json", help="write the rows and ratios here")
    a = ap.parse_args(argv)
    unknown = set(a.only or ()) - set(SWITCHES)
    if unknown:
        fail(f"--only {sorted(unknown)}: unknown; allowed: {list(SWITCHES)}")
    chosen = {k: v for k, v in SWITCHES.items()
              if k == "default" or (not a.only and not a.extra) or k in (a.only or ())}
    for spec in a.extra or ():
        chosen[spec] = (overrides(spec.split(",")), "ida", {})
    for spec in a.atols or ():
        chosen[f"atol {spec}"] = ({}, "ida", {"atol_factors": overrides(spec.split(","))})
    for spec in a.idas or ():
        chosen[f"ida {spec}"] = ({}, "ida", overrides(spec.split(",")))
    from bearingdae import IDA

    for k, (_, solver, options) in chosen.items():  # bad solver options: one line, no timing
        if solver == "ida" and options:
            try:
                IDA(**options)
            except (TypeError, ValueError) as exc:
                fail(f"switch {k[:100]!r}: {exc}")
    case_set = overrides(a.case_set)
    window = {**case_set, "numerics.warmup_cage_revolutions": a.warmup,
              "numerics.cage_revolutions": a.revolutions}
    sets = "".join(f" --set {x}" for x in a.case_set)
    header(f"switches on {a.case}{sets}, {a.warmup:g} warm-up + {a.revolutions:g} recorded "
           f"cage revolutions, {a.repeat} repeats")
    short = {**case_set, "numerics.warmup_cage_revolutions": 0.0,
             "numerics.cage_revolutions": 0.01}
    from bearingdae import load_scene
    from bearingdae.scene import SceneError

    for k, sw in chosen.items():  # a switch the case cannot take: one line, before any timing
        try:
            load_scene(a.case, {**window, **sw[0]})
        except SceneError as exc:
            fail(f"switch {k!r} on {a.case}: {exc}")
    for k, sw in chosen.items():  # kernels loaded (or compiled) outside the timings
        run_one(a.case, short, sw)
    rows = {k: [] for k in chosen}
    for rep in range(a.repeat):
        for k, sw in chosen.items():
            r = run_one(a.case, window, sw)
            rows[k].append(r)
            print(f"repeat {rep + 1} {k:28s} CPU {r['cpu_s']:6.2f} s, wall {r['wall_s']:6.2f} s,"
                  f" steps {r['steps']}, residual calls {r['residual_calls']}", flush=True)
    print(f"\n| switch | CPU [s] | CPU / default (range) | steps | residual calls | Jacobians |"
          "\n|---|---|---|---|---|---|")
    ratios = {}
    for k, rs in rows.items():
        each = [r["cpu_s"] / d["cpu_s"] for r, d in zip(rs, rows["default"])]
        ratios[k], last = median(each), rs[-1]
        print(f"| {k} | {median(r['cpu_s'] for r in rs):.2f} | {ratios[k]:.2f} "
              f"({min(each):.2f}–{max(each):.2f}) | {last['steps'] or '–'} | "
              f"{last['residual_calls']} | {last['jacobians']} |")
    limited = {}
    if a.limiters:
        print("\n| switch | median step [µs] | steps limited by (share) |\n|---|---|---|")
        for k, sw in chosen.items():
            if sw[1] != "ida":
                continue
            limited[k] = r = limiters(a.case, window, sw)
            top = ", ".join(f"{n} {s:.0%}" for n, s in list(r["step_limiters"].items())[:3])
            print(f"| {k} | {r['median_step_s'] * 1e6:.3f} | {top} |", flush=True)
    moded = {}
    if a.modes:
        print(f"\n| switch | fastest lightly damped mode: frequency [kHz] (range) | damping "
              "ratio (range) | moves most | mean step [µs] | steps per period |\n"
              "|---|---|---|---|---|---|")
        for k, sw in chosen.items():
            if sw[1] != "ida":
                continue
            moded[k] = r = run_modes(a.case, window, sw)
            f, z = r["frequency_Hz"], r["damping_ratio"]
            if not f:
                print(f"| {k} | none rings (no mode with ζ ≤ 0.2) | | | "
                      f"{r['mean_step_s'] * 1e6:.3f} | |", flush=True)
                continue
            print(f"| {k} | {median(f) / 1e3:.1f} ({min(f) / 1e3:.1f}–{max(f) / 1e3:.1f}) | "
                  f"{median(z):.3f} ({min(z):.3f}–{max(z):.3f}) | {r['moves_most']} | "
                  f"{r['mean_step_s'] * 1e6:.3f} | {r['steps_per_period']:.0f} |", flush=True)
        from bearingdae import load_scene

        num = load_scene(a.case, window).dynamics
        moded["oscillator_steps_per_period"] = osc = {
            "rtol": num.rtol, f"atol {num.atol:g}": oscillator_steps_per_period(num.rtol, num.atol),
            "atol 1e-12": oscillator_steps_per_period(num.rtol, 1e-12)}
        print(f"IDA alone on an undamped oscillator at rtol {num.rtol:g}: "
              f"{osc[f'atol {num.atol:g}']:.0f} steps per period at atol {num.atol:g}, "
              f"{osc['atol 1e-12']:.0f} at atol 1e-12")
    errors = window_errors(a.case, case_set, chosen) if a.errors else {}
    write_json(a.json, {"benchmark": name, "case": a.case, "window": window, "rows": rows,
                        "cpu_ratio_to_default": ratios, **({"limiters": limited} if limited
                                                           else {}),
                        **({"modes": moded} if moded else {}),
                        **({"window_errors": errors} if errors else {})})


#: ``--modes``: the states per run at which the linearised DAE's modes are taken
MODE_STATES = 8
#: ``--modes``: the periods of the undamped oscillator IDA follows alone
OSCILLATOR_PERIODS = 100


def oscillator_steps_per_period(rtol: float, atol: float) -> float:
    """IDA's steps per period on the undamped oscillator u' = ω v, v' = -ω u from (1, 0) (order
    up to 5, as ours), over :data:`OSCILLATOR_PERIODS` periods: both unknowns of amplitude 1,
    so the count is independent of ω (time scales out)."""
    from sksundae.ida import IDA as SkIDA

    w = 2.0 * np.pi

    def res(t, y, yp, r):
        r[0] = yp[0] - w * y[1]
        r[1] = yp[1] + w * y[0]

    sol = SkIDA(res, rtol=rtol, atol=atol, max_order=5).solve(
        np.array([0.0, float(OSCILLATOR_PERIODS)]), np.array([1.0, 0.0]), np.array([0.0, -w]))
    if not sol.success:
        raise RuntimeError(f"the oscillator: {sol.message}")
    return (sol.t.size - 1) / OSCILLATOR_PERIODS


def run_modes(case: str, window: dict, switch: tuple) -> dict:
    """One run of ``switch`` (IDA with its options, its kernels' integration from the
    quasi-static start, as ``simulate``'s) and, at :data:`MODE_STATES` states evenly spread
    over its recorded window, the fastest lightly damped mode (analysis/modes.py): lists of
    frequency [Hz], damping ratio and the unknown moving most; the family most often moving
    most; the mean step of the whole run and steps per period of the median frequency."""
    from collections import Counter

    from bearingdae import load_scene
    from bearingdae.analysis.modes import family, linear_modes
    from bearingdae.run.integrate import output_times
    from bearingdae.solvers import from_name
    from bearingdae.solvers.algebraic import initial_state
    from bearingdae.system.model import build_model

    over, solver, options = switch
    model = build_model(load_scene(case, {**window, **over}))
    t_out, start = output_times(model)
    pick = np.unique(np.searchsorted(t_out, np.linspace(start, t_out[-1], MODE_STATES + 1)[1:]))
    y0, yp0 = initial_state(model)
    ida = from_name(solver, **options)
    sol = ida.integrate(model, y0, yp0, t_out)
    if not sol.success:
        raise RuntimeError(f"{case}: {sol.message}")
    f, z, names = [], [], []
    for i in pick:
        modes = linear_modes(model, sol.t[i], sol.y[i], sol.yp[i])
        k = modes.fastest_oscillation()
        if k is None:
            continue
        f.append(float(modes.frequency_Hz[k]))
        z.append(float(modes.damping_ratio[k]))
        names.append(modes.dominant[k])
    steps = int(sol.stats.get("steps", 0))
    mean_step = float(t_out[-1]) / steps if steps else float("nan")
    return {"frequency_Hz": f, "damping_ratio": z, "moves_most_each": names,
            "moves_most": Counter(family(n) for n in names).most_common(1)[0][0] if names
            else "–", "steps": steps, "mean_step_s": mean_step,
            "steps_per_period": 1.0 / (median(f) * mean_step) if f else float("nan")}


#: ``--errors``: the work-precision window, its reference rtol and the quantities compared
ERROR_WINDOW = {"numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 0.2}
ERROR_REFERENCE_RTOL = 1e-10
ERROR_QUANTITIES = ("cage_speed", "skew_angle")


def window_errors(case: str, case_set: dict, chosen: dict) -> dict:
    """{switch: {quantity: relative RMS error}} of every IDA switch over :data:`ERROR_WINDOW`
    against the case at rtol 1e-10 (printed as a table)."""
    from bearingdae import load_scene, simulate
    from bearingdae.solvers import from_name
    from bearingdae.studies.workprecision.errors import relative_rms_errors

    ref = simulate(load_scene(case, {**case_set, **ERROR_WINDOW,
                                     "numerics.rtol": ERROR_REFERENCE_RTOL,
                                     "numerics.atol": 1e-2 * ERROR_REFERENCE_RTOL}))
    out = {}
    print(f"\n| switch | {' | '.join(q.replace('_', ' ') + ' error' for q in ERROR_QUANTITIES)}"
          f" |\n|---|{'---|' * len(ERROR_QUANTITIES)}")
    for k, (over, solver, options) in chosen.items():
        if solver != "ida" or over:  # scene switches change the trajectory, not its error
            continue
        ds = simulate(load_scene(case, {**case_set, **ERROR_WINDOW}),
                      solver=from_name(solver, **options))
        out[k] = relative_rms_errors(ds.time.values, ds, ref.time.values, ref,
                                     ERROR_QUANTITIES)
        print(f"| {k} | {' | '.join(f'{out[k][q]:.2e}' for q in ERROR_QUANTITIES)} |",
              flush=True)
    return out
