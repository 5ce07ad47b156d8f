"""Cold and warm `bearingdae run` of the default scene, its longest progress stall, and the
compile CPU of each kernel entry point.

    python benchmarks/run.py cold-start [--root REV ...] [--repeats N] [--short] [--serial]
        [--auto] [--no-warm] [--list] [--write]
    python benchmarks/run.py cold-start --compile [--phases] [--root REV ...] [--repeats 3]

"Cold": numba's cache empty, as after ``pip install`` on a new machine (``NUMBA_CACHE_DIR``
pointed at a fresh temporary folder: the tree's own ``__pycache__`` is not touched); "warm":
the same command again with that folder. The run is the whole default run as a user types it
(``bearingdae run``, figure included; ``--short``: cut to 0.02 cage revolution without
warm-up, no figure), output piped so that progress comes as lines. Reported: seconds from
process start to the title line, to the first *moving* progress line (``simulated time a/b s``
with a > 0: the integration has started), to exit; the longest wait between two progress
lines after that (a stall: something compiled mid-run); CPU of the run's own process and of
its children (the second process compiling part of the kernels, solvers/sundials/
precompile.py; forced on here, ``--serial`` also times each tree with it off, ``--auto`` as a
user runs it: aside only when a CPU is idle). Several ``--root`` trees (a folder or a git
revision; default: this checkout) are measured in turn, round by round, so that they see the
same load; the 1-minute load average before each run is printed. ``--list`` lists the numba
functions a cold run compiled and cached. ``--write``: the medians of this checkout (cold and
warm exit, their ratio, the longest stall; other ``--root`` trees as "compared") into
benchmarks/results/cold-start.json, the one source of the first-run figure the docs and
the compile notice quote (tests/docs/test_cold_start_figure.py); with ``--compile``, the
compile CPU per entry point of each tree into the same file.

``--compile``: per tree, a fresh process with an empty ``NUMBA_CACHE_DIR`` compiles the
kernel entry points of a default run one after the other, in the order a run does, and
reports the CPU time and the number of functions numba compiled for each.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from run import RESULTS, ROOT, cpu_model, fail, header, median, summary, tree, write_json

SHORT = ["--set", "numerics.cage_revolutions=0.02", "--set", "numerics.warmup_cage_revolutions=0",
         "--no-plot"]
#: the one source of the first-run figure (docs/performance.md, "Cold start")
FIGURE = RESULTS / "cold-start.json"
_PROGRESS = re.compile(rb"simulated time ([0-9.eE+-]+)/")
PROGRAM = (  # the run's own CPU and its children's, printed at exit; a --root tree from before
    # the package's folders were laid out by stage has the program at the package root
    "import atexit, resource, sys\n"
    "def cpu():\n"
    "    s, c = (resource.getrusage(w) for w in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))\n"
    "    print(f'[cpu] {s.ru_utime + s.ru_stime:.2f} {c.ru_utime + c.ru_stime:.2f}', "
    "file=sys.stderr, flush=True)\n"
    "atexit.register(cpu)\n"
    "try:\n"
    "    from bearingdae.cli.program import main\n"
    "except ImportError:\n"
    "    from bearingdae.program import main\n"
    "sys.exit(main())")
COMPILE = r"""
import json, sys, time
import bearingdae  # first, as in a run: its settings for numba (error text not coloured)
import numpy as np
from numba.core import event

class Counter(event.Listener):  # numba's compile events: how many functions each step compiled
    n = 0
    def on_start(self, e): pass
    def on_end(self, e): Counter.n += 1

event.register("numba:compile", Counter())
PHASES = {}  # --phases: CPU by phase, exclusive of the phases nested in it (a callee's compile)
if "--phases" in sys.argv:
    from numba.core import codegen, compiler_machinery
    stack = []

    def timed(name, fn):
        def wrapper(*args, **kwargs):
            stack.append([time.process_time(), 0.0])
            try:
                return fn(*args, **kwargs)
            finally:
                t0, inner = stack.pop()
                dt = time.process_time() - t0
                PHASES[name] = PHASES.get(name, 0.0) + dt - inner
                if stack:
                    stack[-1][1] += dt
        return wrapper

    run_pass = compiler_machinery.PassManager._runPass
    numba_phase = {"nopython_type_inference": "numba typing", "native_lowering": "numba lowering"}
    compiler_machinery.PassManager._runPass = lambda self, i, p, st: timed(
        numba_phase.get(p.name(), "numba other passes"), run_pass)(self, i, p, st)
    for cls, name, phase in ((codegen.CPUCodeLibrary, "_optimize_functions", "LLVM function passes"),
                             (codegen.CPUCodeLibrary, "_optimize_final_module", "LLVM module passes"),
                             (codegen.JITCodeLibrary, "_finalize_specific", "LLVM machine code")):
        setattr(cls, name, timed(phase, getattr(cls, name)))
from bearingdae import load_scene
from bearingdae.solvers.algebraic import AlgebraicProjector, initial_state
from bearingdae.solvers.sundials import callbacks, linsol
from bearingdae.physics.film import line_contact_film
from bearingdae.system.model import build_model
m = build_model(load_scene("yang20_baseline"))

def project(p):  # an older tree has no prepare(): one sample (the compile is the cost)
    p.prepare() if hasattr(p, "prepare") else p.batch(np.zeros(1), initial_state(m)[0][None])

steps = [  # the entry points of a default run, in the order a run compiles them
    ("residual (initial state, from Python)", lambda: initial_state(m)),
    ("IDA residual callback", lambda: callbacks.compiled("residual")),
    ("block-arrow linear solver (6 ops)", linsol.compile_operations),
    ("IDA analytic Jacobian callback", lambda: callbacks.compiled("analytic")),
    ("IDA per-step extremes hook", lambda: callbacks.compiled("extremes")),
    ("projection of the samples", lambda: project(AlgebraicProjector(m))),
    ("EHL film (post-processing)", lambda: line_contact_film(*[np.ones(1)] * 3, 1.0, 1.0, 1.0)),
]
rows = []
for name, step in steps:
    n0, t0, p0 = Counter.n, time.process_time(), dict(PHASES)
    step()
    rows.append((name, time.process_time() - t0, Counter.n - n0,
                 {k: round(v - p0.get(k, 0.0), 2) for k, v in PHASES.items()}))
print(json.dumps(rows))
"""


def timed_run(root, out: str, cache: str, full=True, debug_cache=False,
              aside: bool | None = True) -> dict:
    """One ``bearingdae run`` in a fresh process with numba's cache in ``cache``: times of the
    title, the first moving progress line and exit, the longest wait between progress lines
    after the first moving one; CPU of the process and its children; the output lines with
    their times."""
    env = dict(os.environ, PYTHONUNBUFFERED="1", PYTHONPATH=f"{root}{os.pathsep}"
               + os.environ.get("PYTHONPATH", ""), NUMBA_CACHE_DIR=cache)
    if debug_cache:
        env["NUMBA_DEBUG_CACHE"] = "1"
    env.pop("BEARINGDAE_COMPILE_ASIDE", None)
    if aside is not None:  # forced, not decided by the load of the moment
        env["BEARINGDAE_COMPILE_ASIDE"] = "1" if aside else "0"
    args = ["run", "-o", out] + ([] if full else SHORT)
    load, cpu0 = os.getloadavg()[0], resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.Popen([sys.executable, "-c", PROGRAM, *args], env=env, cwd=tempfile.gettempdir(),
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    lines, title, moving, own, child, last, stall = [], None, None, None, None, None, 0.0
    for line in iter(p.stdout.readline, b""):
        t = time.perf_counter() - t0
        lines.append((t, line.decode(errors="replace").rstrip()))
        if title is None and b"rollers x" in line:
            title = t
        m = _PROGRESS.search(line)
        if moving is None and m and float(m.group(1)) > 0:
            moving = t
        if m and moving is not None:
            stall = max(stall, t - last) if last is not None else 0.0
            last = t
        if line.startswith(b"[cpu] "):
            own, child = (float(v) for v in line.split()[1:3])
    p.wait()
    end = time.perf_counter() - t0
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (cpu1.ru_utime + cpu1.ru_stime) - (cpu0.ru_utime + cpu0.ru_stime)
    return {"title": title, "moving": moving, "end": end, "stall": stall, "cpu": cpu, "load": load,
            "cpu_own": own, "cpu_aside": child, "status": p.returncode, "lines": lines}


def _s(x) -> str:
    return "  —  " if x is None else f"{x:5.1f}"


def compile_cpu(roots, repeats: int, phases: bool = False) -> list:
    """Per tree and round, the compile CPU of each entry point of a default run in one fresh
    process with an empty ``NUMBA_CACHE_DIR`` (what it compiles, in the order a run does);
    ``phases``: each split into numba's typing, lowering and other passes and LLVM's
    function passes, module passes (of the module with its callees linked in) and machine
    code, each exclusive of the compiles nested in it (the timers cost ~1 %)."""
    out_rows = []
    for r in range(repeats):
        for root in roots:
            with tempfile.TemporaryDirectory(prefix="bd_numba_cache_") as cache:
                env = {**os.environ, "PYTHONPATH": str(root), "NUMBA_CACHE_DIR": cache}
                out = subprocess.run([sys.executable, "-c", COMPILE]
                                     + (["--phases"] if phases else []), env=env, cwd=root,
                                     capture_output=True, text=True)
            if out.returncode:
                fail(f"--compile in {root}: {out.stderr.strip().splitlines()[-1]}")
            out = out.stdout
            rows = json.loads(out.strip().splitlines()[-1])
            out_rows.append({"root": str(root), "round": r + 1, "steps": rows})
            print(f"round {r + 1} {str(root)[-40:]}: compile CPU per entry point "
                  f"(load {os.getloadavg()[0]:.1f})")
            for name, cpu, n, split in rows:
                print(f"  {name:42s} {cpu:6.2f} s  ({n} functions)"
                      + "".join(f"\n      {k:28s} {v:6.2f} s" for k, v in sorted(split.items())))
            total = {}
            for _, _, _, split in rows:
                for k, v in split.items():
                    total[k] = total.get(k, 0.0) + v
            print(f"  {'sum':42s} {sum(r[1] for r in rows):6.2f} s" + "".join(
                f"\n      {k:28s} {v:6.2f} s" for k, v in sorted(total.items())), flush=True)
    return out_rows


def main(argv=None, name="cold-start") -> None:
    ap = argparse.ArgumentParser(prog=f"run.py {name}", description=summary(__doc__))
    ap.add_argument("--root", action="append", help="tree to time: a folder or a git revision "
                    "(repeatable; default: this checkout)")
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--short", action="store_true", help="0.02 cage revolution, no warm-up, "
                    "no figure (default: the whole default run)")
    ap.add_argument("--list", action="store_true", help="list what a cold run compiled")
    ap.add_argument("--no-warm", action="store_true")
    ap.add_argument("--serial", action="store_true", help="also each tree with "
                    "BEARINGDAE_COMPILE_ASIDE=0 (no second process compiling)")
    ap.add_argument("--auto", action="store_true", help="also each tree as a user runs it")
    ap.add_argument("--compile", action="store_true", help="compile CPU per kernel entry point")
    ap.add_argument("--phases", action="store_true", help="with --compile: each entry point's "
                    "CPU split into numba's passes and LLVM's phases")
    ap.add_argument("--write", action="store_true", help=f"medians of this checkout into "
                    f"{FIGURE.relative_to(ROOT)}")
    ap.add_argument("--json", help="write the raw rows to this file")
    a = ap.parse_args(argv)
    roots = [tree(r) for r in a.root] if a.root else [ROOT]
    header(f"{name}: {', '.join(map(str, roots))}")
    if a.compile:
        rows = compile_cpu(roots, a.repeats, a.phases)
        write_json(a.json, {"compile": rows})
        if a.write:
            per_tree = {}
            for r in rows:
                label = "this checkout" if r["root"] == str(ROOT) else Path(r["root"]).name
                for step, cpu, n, *_ in r["steps"]:
                    per_tree.setdefault(label, {}).setdefault(step, []).append((cpu, n))
            fig = json.loads(FIGURE.read_text()) if FIGURE.exists() else {}
            fig["compile_cpu_s"] = {  # median CPU and functions compiled per entry point
                label: {step: [round(median(c for c, _ in v), 1), v[0][1]]
                        for step, v in steps.items()} for label, steps in per_tree.items()}
            fig["compile_load_1min"] = round(os.getloadavg()[0], 1)
            FIGURE.write_text(json.dumps(fig, indent=1, ensure_ascii=False) + "\n")
            print(f"wrote {FIGURE}")
        return None
    if a.write and (a.short or a.no_warm or ROOT not in roots):
        fail("--write: the whole default run of this checkout, cold and warm (no --short or "
             "--no-warm; other --root trees are measured beside it)")
    runs = ([(r, True) for r in roots] + ([(r, False) for r in roots] if a.serial else [])
            + ([(r, None) for r in roots] if a.auto else []))
    label = {True: "", False: " (serial)", None: " (auto)"}
    out = os.path.join(tempfile.gettempdir(), f"cold_start_{os.getpid()}.nc")
    rows = {f"{r}{label[s]}": [] for r, s in runs}
    print(f"{'tree':40s} {'kind':4s} {'load':>5s} {'title':>5s} {'moving':>6s} "
          f"{'exit':>5s} {'stall':>5s} {'CPU':>5s} {'(own':>5s} {'aside)':>6s}", flush=True)
    for _ in range(a.repeats):
        for root, aside in runs:
            key = f"{root}{label[aside]}"
            with tempfile.TemporaryDirectory(prefix="bd_numba_cache_") as cache:
                kinds = [("cold", timed_run(root, out, cache, not a.short, a.list, aside))]
                if not a.no_warm:
                    kinds.append(("warm", timed_run(root, out, cache, not a.short,
                                                    aside=aside)))
            for kind, r in kinds:
                rows[key].append((kind, r))
                print(f"{key[-40:]:40s} {kind:4s} {r['load']:5.1f} {_s(r['title'])} "
                      f"{_s(r['moving']):>6s} {_s(r['end'])} {_s(r['stall'])} {_s(r['cpu'])} "
                      f"{_s(r['cpu_own'])} {_s(r['cpu_aside']):>6s}"
                      + ("" if r["status"] == 0 else f"  exit status {r['status']}"), flush=True)
                if r["status"] != 0 or r["moving"] is None:
                    print("\n".join(f"    {t:6.2f} {ln}" for t, ln in r["lines"][-15:]))
            if len(kinds) == 2:
                print(f"{'':40s} cold/warm exit {kinds[0][1]['end'] / kinds[1][1]['end']:.2f}")
            if a.list:
                saved = sorted({os.path.basename(ln.split("data saved to")[1]).strip(" '\"")
                                for _, ln in kinds[0][1]["lines"] if "data saved to" in ln})
                print(f"{len(saved)} cache data files written by the cold run:\n  "
                      + "\n  ".join(saved))
    medians = {}
    print("medians:")
    for key, rs in rows.items():
        m = medians[key] = {}
        for kind in ("cold", "warm"):
            sel = [r for k, r in rs if k == kind and r["moving"] is not None]
            if sel:
                m[kind] = {v: median(r[v] for r in sel) for v in ("moving", "end", "stall", "cpu",
                                                                  "load")} | {"n": len(sel)}
                print(f"{key[-40:]:40s} {kind:4s} first moving progress "
                      f"{m[kind]['moving']:5.1f} s, exit {m[kind]['end']:5.1f} s, longest "
                      f"stall {m[kind]['stall']:4.1f} s, CPU {m[kind]['cpu']:5.1f} s "
                      f"(n = {len(sel)})")
        ratios = [c["end"] / w["end"] for (kc, c), (kw, w) in zip(rs[::2], rs[1::2])
                  if kc == "cold" and kw == "warm"]
        if ratios:
            m["ratio"] = median(ratios)
            print(f"{key[-40:]:40s} cold/warm exit, median of the rounds: {m['ratio']:.2f}")
    write_json(a.json, {"rows": {k: [(kind, {v: x for v, x in r.items() if v != "lines"})
                                      for kind, r in rs] for k, rs in rows.items()},
                        "medians": medians})
    if a.write:
        m = medians[str(ROOT)]
        fig = json.loads(FIGURE.read_text()) if FIGURE.exists() else {}
        fig.update({
            "what": "bearingdae run of the default scene, numba cache empty (cold) then again "
                    "(warm); medians of the rounds; the second process forced on "
                    "(BEARINGDAE_COMPILE_ASIDE=1, what a user gets with a CPU idle)",
            "command": "python benchmarks/run.py cold-start " + " ".join(
                sys.argv[2:] if argv is None else argv),
            "date": time.strftime("%Y-%m-%d"), "cpu": cpu_model(), "rounds": a.repeats,
            "load_1min": round(m["cold"]["load"], 1),
            "cold_exit_s": round(m["cold"]["end"], 1), "warm_exit_s": round(m["warm"]["end"], 1),
            "cold_over_warm": round(m["ratio"], 1),
            "cold_first_moving_progress_s": round(m["cold"]["moving"], 1),
            "cold_longest_stall_s": round(m["cold"]["stall"], 1),
            "warm_longest_stall_s": round(m["warm"]["stall"], 1),
            "cold_cpu_s": round(m["cold"]["cpu"], 1), "warm_cpu_s": round(m["warm"]["cpu"], 1),
            "compared": {Path(k).name: {"cold_exit_s": round(v["cold"]["end"], 1),
                                        "warm_exit_s": round(v["warm"]["end"], 1),
                                        "cold_over_warm": round(v["ratio"], 1),
                                        "cold_longest_stall_s": round(v["cold"]["stall"], 1),
                                        "cold_cpu_s": round(v["cold"]["cpu"], 1)}
                         for k, v in medians.items() if k != str(ROOT) and "ratio" in v}})
        FIGURE.write_text(json.dumps(fig, indent=1, ensure_ascii=False) + "\n")
        print(f"wrote {FIGURE}")
    for f in (out, out[:-3] + ".png"):
        if os.path.exists(f):
            os.remove(f)
