"""The stability suite cases/extreme/*.toml with IDA and Newmark-β: outcome, checks, cost.

    python benchmarks/run.py stability [--cases a,b] [--solvers ida,newmark] [--repeat 1]
                                       [--write] [--from-json]

(about 7 min for both solvers on a 2-core machine, IDA twice.)

For every case and solver: the outcome (completed, or the diagnostic of the failure), the
physical checks of tests/physical_checks.py on the Dataset (or on the partial Dataset of a
failure), and the solver's cost: steps, smallest step, failed steps, residual calls, wall time
(median of ``--repeat`` runs after a JIT warm-up). IDA's steps, smallest step and failures come
from a second run with ``IDA(record_steps=True)`` (one internal step per IDASolve call, IDA's own
statistics) whose residual-call count must equal the timed run's (same trajectory), else the
step columns say "n/a".

``--write`` replaces the table between the markers in docs/stability.md and writes the raw
numbers to benchmarks/results/stability.json; ``--from-json`` only re-renders the table from
that file. For Newmark-β the last column gives its mean cage speed relative to IDA's (an
independent-integrator cross-check of each case).
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import sys
import time
import traceback

from run import ROOT, cpu_model, header, summary

sys.path.insert(0, str(ROOT / "tests"))  # physical_checks.py, shared with the slow tests

import numpy as np  # noqa: E402

import bearingdae.solvers.ida as ida  # noqa: E402
import physical_checks as pc  # noqa: E402
from bearingdae import SimulationError, load_scene, simulate  # noqa: E402
from bearingdae.scene import SceneError, bundled_case_dirs  # noqa: E402
from bearingdae.solvers.static import StaticConvergenceError  # noqa: E402

DOC = ROOT / "docs" / "stability.md"
RESULTS = ROOT / "benchmarks" / "results" / "stability.json"
START, END = "<!-- stability-table:start -->", "<!-- stability-table:end -->"


def extreme_cases() -> list[str]:
    """Names ``extreme/<stem>`` of the bundled stability cases, sorted."""
    stems = sorted({p.stem for d in bundled_case_dirs() for p in (d / "extreme").glob("*.toml")})
    return [f"extreme/{s}" for s in stems]


def newmark_available() -> bool:
    try:
        from bearingdae.solvers import newmark  # noqa: F401
    except ImportError:
        return False
    return True


def run_once(scene, solver):
    """(outcome, Dataset or None, wall [s]); never raises for a diagnosed failure."""
    t0 = time.perf_counter()
    try:
        ds = simulate(scene, solver=solver)
        outcome = "completed"
    except SimulationError as exc:
        ds, outcome = exc.dataset, f"failed: {exc}"
    except (SceneError, StaticConvergenceError) as exc:
        ds, outcome = None, f"refused: {type(exc).__name__}: {exc}"
    except Exception as exc:  # an undiagnosed crash is a bug: record it, keep going
        ds, outcome = None, f"CRASH: {type(exc).__name__}: {exc}"
        traceback.print_exc()
    return outcome, ds, time.perf_counter() - t0


def checks(ds, scene) -> dict:
    if ds is None or ds.sizes.get("time", 0) == 0:
        return {}
    b = pc.speed_bounds(ds, scene)
    return {
        "samples": int(ds.sizes["time"]),
        "nonfinite": pc.nonfinite_variables(ds),
        "algebraic_residual": pc.algebraic_residual(ds, scene),
        "worst_speed_margin": min(v for k, v in b.items() if not k.startswith("contact")),
        "contact_force_min_N": b["contact_force_min"],
        "kinematic_drift": pc.kinematic_drift(ds),
        "mean_cage_speed_rad_s": (float(ds.cage_speed.mean()) if "cage_speed" in ds else None),
        "cage_to_epicyclic": (float(ds.cage_speed.mean()) / ds["epicyclic_cage_speed_rad_s"].item()
                              if "cage_speed" in ds and ds["epicyclic_cage_speed_rad_s"].item() > 0
                              else None),
        "max_abs_skew_rad": float(np.abs(ds.skew_angle).max()) if "skew_angle" in ds else 0.0,
        "max_pressure_Pa": float(ds.contact_pressure.max()),
    }


def ida_step_record(scene, residual_calls: int) -> dict:
    """Steps, smallest step, failures of IDA from a recording run (same trajectory checked)."""
    solver = ida.IDA(record_steps=True)
    _, ds, _ = run_once(scene, solver)
    if ds is None:
        return {"step_stats": "n/a (no Dataset)"}
    rc = json.loads(ds.attrs["solver_statistics"])["residual_calls"]
    if rc != residual_calls:
        return {"step_stats": f"n/a (recording run took {rc} residual calls, timed run "
                              f"{residual_calls}: not the same trajectory)"}
    st = json.loads(ds.attrs["solver_statistics"])
    h, t = solver.last_step_record
    window = h[t >= ds["record_start_s"].item()]
    keys = ("steps", "smallest_step_s", "smallest_step_at_s", "median_step_s",
            "error_test_failures", "nonlinear_convergence_failures", "nonlinear_iterations",
            "max_steps_per_output")
    return {"step_stats": "ok", **{k: st.get(k) for k in keys},
            "smallest_step_in_window_s": float(window.min()) if window.size else None}


def bench(case: str, solver: str, repeat: int) -> dict:
    scene = load_scene(case)
    walls, outcome, ds = [], "", None
    for _ in range(repeat):
        outcome, ds, wall = run_once(scene, solver)
        walls.append(wall)
    row = {"case": case, "solver": solver, "outcome": outcome,
           "wall_s": statistics.median(walls), "walls_s": walls,
           "simulated_s": float(ds.time[-1]) if ds is not None and ds.sizes["time"] else None}
    if ds is not None:
        st = json.loads(ds.attrs["solver_statistics"])
        row["residual_calls"] = st.get("residual_calls")
        row["residual_calls_in_jacobian"] = st.get("residual_calls_in_jacobian")
        row["jacobian_calls"] = st.get("jacobian_calls")
        if solver == "newmark":
            row.update({"steps": st.get("steps"), "smallest_step_s": st.get("smallest_step_s"),
                        "median_step_s": st.get("step_s"),
                        "step_halvings": st.get("step_halvings"),
                        "nonlinear_iterations": st.get("newton_iterations")})
    row["checks"] = checks(ds, scene)
    if solver == "ida" and ds is not None:
        row.update(ida_step_record(scene, row["residual_calls"]))
    return row


def _g(v, fmt="{:.2g}") -> str:
    return "–" if v is None else fmt.format(v)


def outcome_cell(row) -> str:
    o = row["outcome"]
    c = row.get("checks", {})
    if o == "completed":
        bad = []
        if c.get("nonfinite"):
            bad.append("NaN in " + ", ".join(c["nonfinite"]))
        if c.get("algebraic_residual", 0) > 1e-8:
            bad.append(f"algebraic residual {c['algebraic_residual']:.1e}")
        if c.get("worst_speed_margin", 0) < -1e-9:
            bad.append(f"speed bound violated ({c['worst_speed_margin']:.1e})")
        return "completed" + (" **but " + "; ".join(bad) + "**" if bad else "")
    return o.replace("|", "/").replace("\n", " ")


def agreement(row, rows) -> str:
    """Mean cage speed of a Newmark row relative to the IDA row of the same case."""
    ida_row = next((r for r in rows if r["case"] == row["case"] and r["solver"] == "ida"), None)
    if row["solver"] == "ida" or ida_row is None:
        return ""
    a = row.get("checks", {}).get("mean_cage_speed_rad_s")
    b = ida_row.get("checks", {}).get("mean_cage_speed_rad_s")
    if a is None or b is None:
        return "–"
    if ida_row["checks"].get("cage_to_epicyclic") is None:  # bearing at rest: absolute
        return f"{abs(a - b):.0e} rad/s"
    return f"{(a - b) / abs(b):+.1e}"


def table(rows: list[dict], solvers: list[str]) -> str:
    lines = [
        "| case | solver | outcome | steps | smallest step [s] (at t [s]); in window | "
        "median step [s] | "
        "failed steps: error test / nonlinear | residual calls (+ in Jacobians) | Jacobians | "
        "wall [s] | alg. residual | speed margin | cage / epicyclic | mean cage speed vs IDA |",
        "|" + "---|" * 14,
    ]
    for r in rows:
        c = r.get("checks", {})
        if r["solver"] == "ida":
            if r.get("step_stats", "ok") == "ok" and "steps" in r:
                steps = f"{r['steps']}"
                small = (f"{r['smallest_step_s']:.1e} ({r['smallest_step_at_s']:.2g}); "
                         f"{_g(r.get('smallest_step_in_window_s'), '{:.1e}')}")
                med = _g(r.get("median_step_s"), "{:.1e}")
                fails = f"{r['error_test_failures']} / {r['nonlinear_convergence_failures']}"
            else:
                steps = small = med = fails = r.get("step_stats", "n/a")
        else:
            steps = _g(r.get("steps"), "{}")
            small = _g(r.get("smallest_step_s"), "{:.1e}")
            med = "h = " + _g(r.get("median_step_s"), "{:.1e}")
            fails = f"– / {_g(r.get('step_halvings'), '{}')} halvings"
        calls = (f"{r['residual_calls']} (+{r['residual_calls_in_jacobian']})"
                 if r.get("residual_calls") is not None else "–")
        lines.append(
            f"| {r['case'].removeprefix('extreme/')} | {r['solver']} | {outcome_cell(r)} | "
            f"{steps} | {small} | {med} | {fails} | {calls} | {_g(r.get('jacobian_calls'), '{}')}"
            f" | {r['wall_s']:.1f} | {_g(c.get('algebraic_residual'), '{:.0e}')} | "
            f"{_g(c.get('worst_speed_margin'), '{:.2f}')} | "
            f"{_g(c.get('cage_to_epicyclic'), '{:.4f}')} | {agreement(r, rows)} |")
    for s in ("ida", "newmark"):
        if s not in solvers:
            lines.append(f"| *all cases* | {s} | not run | | | | | | | | | | | |")
    return "\n".join(lines)


def write_doc(text: str) -> None:
    doc = DOC.read_text()
    if START not in doc or END not in doc:
        raise SystemExit(f"{DOC} lacks the markers {START} / {END}")
    head, rest = doc.split(START, 1)
    _, tail = rest.split(END, 1)
    DOC.write_text(f"{head}{START}\n{text}\n{END}{tail}")


def main(argv=None, name="stability") -> None:
    ap = argparse.ArgumentParser(prog=f"run.py {name}", description=summary(__doc__))
    ap.add_argument("--cases", help="comma-separated stems (default: every extreme case)")
    ap.add_argument("--solvers", default="ida,newmark")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--write", action="store_true", help="update docs/stability.md and the JSON")
    ap.add_argument("--from-json", action="store_true",
                    help="only re-render the table from benchmarks/results/stability.json")
    args = ap.parse_args(argv)
    if args.from_json:
        data = json.loads(RESULTS.read_text())
        text = table(data["rows"], data["solvers"])
        print(text)
        if args.write:
            write_doc(text)
        return
    cases = ([f"extreme/{c}" for c in args.cases.split(",")] if args.cases else extreme_cases())
    solvers = [s for s in args.solvers.split(",") if s]
    if "newmark" in solvers and not newmark_available():
        print("newmark: solvers/newmark.py not present on this branch: not run")
        solvers.remove("newmark")
    header(f"stability suite: {len(cases)} cases, solvers {', '.join(solvers)}")
    warm = load_scene("yang20_baseline", {"numerics.warmup_cage_revolutions": 0.0,
                                          "numerics.cage_revolutions": 0.01})
    for s in solvers:
        run_once(warm, s)  # numba JIT / cache load outside the timings
    rows = []
    for case in cases:
        for s in solvers:
            row = bench(case, s, args.repeat)
            rows.append(row)
            print(json.dumps(row, default=str), flush=True)
    text = table(rows, solvers)
    print(text)
    if args.write:
        write_doc(text)
        RESULTS.parent.mkdir(parents=True, exist_ok=True)
        RESULTS.write_text(json.dumps({"machine": platform.platform(), "cpu": cpu_model(),
                                       "solvers": solvers, "rows": rows}, indent=1, default=str))
        print(f"wrote {DOC} and {RESULTS}")

