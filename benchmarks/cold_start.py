"""Cold and warm start of ``bearingdae run``, and the compile CPU of the two DAE kernels.

    python benchmarks/run.py cold-start [--root REV ...] [--repeats N] [--full] [--serial]
        [--auto] [--no-warm] [--list]
    python benchmarks/run.py cold-start --compile [--root REV ...] [--repeats 3]

"Cold": every numba cache file (``__pycache__/*.nbi``, ``*.nbc``) under the tree's package is
deleted first, as after ``pip install`` on a new machine; "warm": the same command again. The
run is the default scene, by default cut to 0.02 cage revolution without warm-up (``--full``:
the whole default run), output piped so that progress comes as lines. Reported: seconds from
process start to the title line, to the first *moving* progress line (``simulated time a/b s``
with a > 0: the integration has started), to exit; CPU of the run's own process and of its
children (the Jacobian callback compiled aside in a second process,
bearingdae/solvers/sundials/precompile.py; forced on here, ``--serial`` also times each tree
with it off, ``--auto`` as a user runs it: aside only when a CPU is idle). Several ``--root``
trees (a folder or a git revision; default: this checkout) are measured in turn, round by
round, so that they see the same load; the 1-minute load average before each run is printed.
``--list`` lists the numba functions a cold run compiled and cached.

``--compile``: per tree, a fresh process with an empty ``NUMBA_CACHE_DIR`` reports the CPU
time of the first call of IDA's residual callback (``residual_flat``) and of the analytic
Jacobian on the baseline model, i.e. their compilation with every kernel they inline.
"""

from __future__ import annotations

import argparse
import glob
import json
import os
import re
import resource
import subprocess
import sys
import tempfile
import time

from run import ROOT, fail, header, median, tree

SHORT = ["--set", "numerics.cage_revolutions=0.02", "--set", "numerics.warmup_cage_revolutions=0"]
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
import numpy as np
from numba.core import event

class Counter(event.Listener):  # numba's compile events: how many functions each step compiled
    n = 0
    def on_start(self, e): pass
    def on_end(self, e): Counter.n += 1

event.register("numba:compile", Counter())
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
    n0, t0 = Counter.n, time.process_time()
    step()
    rows.append((name, time.process_time() - t0, Counter.n - n0))
print(json.dumps(rows))
"""


def clear_cache(root) -> int:
    files = [f for pat in ("*.nbi", "*.nbc")
             for f in glob.glob(os.path.join(root, "bearingdae", "**", "__pycache__", pat),
                                recursive=True)]
    for f in files:
        os.remove(f)
    return len(files)


def timed_run(root, out: str, full=False, debug_cache=False, aside: bool | None = True) -> dict:
    """One ``bearingdae run`` in a fresh process: times of the title, the first moving progress
    line and exit; CPU of the process and its children; the output lines with their times."""
    env = dict(os.environ, PYTHONUNBUFFERED="1", PYTHONPATH=f"{root}{os.pathsep}"
               + os.environ.get("PYTHONPATH", ""))
    if debug_cache:
        env["NUMBA_DEBUG_CACHE"] = "1"
    env.pop("BEARINGDAE_COMPILE_ASIDE", None)
    if aside is not None:  # forced, not decided by the load of the moment
        env["BEARINGDAE_COMPILE_ASIDE"] = "1" if aside else "0"
    args = ["run", "-o", out, "--no-plot"] + ([] if full else SHORT)
    load, cpu0 = os.getloadavg()[0], resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.Popen([sys.executable, "-c", PROGRAM, *args], env=env, cwd=tempfile.gettempdir(),
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    lines, title, moving, own, child = [], None, None, None, None
    for line in iter(p.stdout.readline, b""):
        t = time.perf_counter() - t0
        lines.append((t, line.decode(errors="replace").rstrip()))
        if title is None and b"rollers x" in line:
            title = t
        m = _PROGRESS.search(line)
        if moving is None and m and float(m.group(1)) > 0:
            moving = t
        if line.startswith(b"[cpu] "):
            own, child = (float(v) for v in line.split()[1:3])
    p.wait()
    end = time.perf_counter() - t0
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (cpu1.ru_utime + cpu1.ru_stime) - (cpu0.ru_utime + cpu0.ru_stime)
    return {"title": title, "moving": moving, "end": end, "cpu": cpu, "load": load,
            "cpu_own": own, "cpu_aside": child, "status": p.returncode, "lines": lines}


def _s(x) -> str:
    return "  —  " if x is None else f"{x:5.1f}"


def compile_cpu(roots, repeats: int) -> list:
    """Per tree and round, the compile CPU of each entry point of a default run in one fresh
    process with an empty ``NUMBA_CACHE_DIR`` (what it compiles, in the order a run does)."""
    out_rows = []
    for r in range(repeats):
        for root in roots:
            with tempfile.TemporaryDirectory(prefix="bd_numba_cache_") as cache:
                env = {**os.environ, "PYTHONPATH": str(root), "NUMBA_CACHE_DIR": cache}
                out = subprocess.run([sys.executable, "-c", COMPILE], env=env, cwd=root,
                                     capture_output=True, text=True)
            if out.returncode:
                fail(f"--compile in {root}: {out.stderr.strip().splitlines()[-1]}")
            out = out.stdout
            rows = json.loads(out.strip().splitlines()[-1])
            out_rows.append({"root": str(root), "round": r + 1, "steps": rows})
            print(f"round {r + 1} {str(root)[-40:]}: compile CPU per entry point "
                  f"(load {os.getloadavg()[0]:.1f})")
            for name, cpu, n in rows:
                print(f"  {name:42s} {cpu:6.2f} s  ({n} functions)")
            print(f"  {'sum':42s} {sum(c for _, c, _ in rows):6.2f} s", flush=True)
    return out_rows


def main(argv=None, name="cold-start") -> None:
    ap = argparse.ArgumentParser(prog=f"run.py {name}", description=__doc__.splitlines()[0])
    ap.add_argument("--root", action="append", help="tree to time: a folder or a git revision "
                    "(repeatable; default: this checkout)")
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--full", action="store_true", help="the whole default run")
    ap.add_argument("--list", action="store_true", help="list what a cold run compiled")
    ap.add_argument("--no-warm", action="store_true")
    ap.add_argument("--serial", action="store_true", help="also each tree with "
                    "BEARINGDAE_COMPILE_ASIDE=0 (no second process compiling the Jacobian)")
    ap.add_argument("--auto", action="store_true", help="also each tree as a user runs it")
    ap.add_argument("--compile", action="store_true", help="compile CPU of the two kernels only")
    a = ap.parse_args(argv)
    roots = [tree(r) for r in a.root] if a.root else [ROOT]
    header(f"{name}: {', '.join(map(str, roots))}")
    if a.compile:
        return compile_cpu(roots, a.repeats)
    runs = ([(r, True) for r in roots] + ([(r, False) for r in roots] if a.serial else [])
            + ([(r, None) for r in roots] if a.auto else []))
    label = {True: "", False: " (serial)", None: " (auto)"}
    out = os.path.join(tempfile.gettempdir(), f"cold_start_{os.getpid()}.nc")
    rows = {f"{r}{label[s]}": [] for r, s in runs}
    print(f"{'tree':40s} {'kind':4s} {'load':>5s} {'title':>5s} {'moving':>6s} "
          f"{'exit':>5s} {'CPU':>5s} {'(own':>5s} {'aside)':>6s}", flush=True)
    for _ in range(a.repeats):
        for root, aside in runs:
            key = f"{root}{label[aside]}"
            clear_cache(root)
            kinds = [("cold", timed_run(root, out, a.full, a.list, aside))]
            if not a.no_warm:
                kinds.append(("warm", timed_run(root, out, a.full, aside=aside)))
            for kind, r in kinds:
                rows[key].append((kind, r))
                print(f"{key[-40:]:40s} {kind:4s} {r['load']:5.1f} {_s(r['title'])} "
                      f"{_s(r['moving']):>6s} {_s(r['end'])} {_s(r['cpu'])} {_s(r['cpu_own'])} "
                      f"{_s(r['cpu_aside']):>6s}"
                      + ("" if r["status"] == 0 else f"  exit status {r['status']}"), flush=True)
                if r["status"] != 0 or r["moving"] is None:
                    print("\n".join(f"    {t:6.2f} {ln}" for t, ln in r["lines"][-15:]))
            if a.list:
                saved = sorted({os.path.basename(ln.split("data saved to")[1]).strip(" '\"")
                                for _, ln in kinds[0][1]["lines"] if "data saved to" in ln})
                print(f"{len(saved)} cache data files written by the cold run:\n  "
                      + "\n  ".join(saved))
    if a.repeats > 1:
        print("medians:")
        for key, rs in rows.items():
            for kind in ("cold", "warm"):
                sel = [r for k, r in rs if k == kind and r["moving"] is not None]
                if sel:
                    print(f"{key[-40:]:40s} {kind:4s} first moving progress "
                          f"{median(r['moving'] for r in sel):5.1f} s, exit "
                          f"{median(r['end'] for r in sel):5.1f} s, CPU "
                          f"{median(r['cpu'] for r in sel):5.1f} s (n = {len(sel)})")
    if os.path.exists(out):
        os.remove(out)
