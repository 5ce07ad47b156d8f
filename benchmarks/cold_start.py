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

from run import ROOT, header, median, tree

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
import json, time
import numpy as np
from bearingdae import load_scene
from bearingdae.solvers.ida import _jacobian_work, sparsity_pattern
from bearingdae.system.jacobian_analytic import analytic_work, jacobian_analytic_sparse
from bearingdae.system.model import build_model
from bearingdae.system.residual import residual_flat
m = build_model(load_scene("yang20_baseline"))
y, yp = np.full(m.size, 0.5), np.zeros(m.size)  # any state: only the compilation counts
jd0, _ = _jacobian_work(m, sparsity_pattern(m))
jd = analytic_work(m, jd0[1], jd0[2])
JJ, res = np.zeros(jd0[1].size), np.zeros(m.size)
t0 = time.process_time()
residual_flat(0.0, y, yp, res, m.work)
t1 = time.process_time()
jacobian_analytic_sparse(0.0, y, yp, res, 1e3, JJ, m.data, jd)
print(json.dumps({"residual_s": t1 - t0, "jacobian_s": time.process_time() - t1}))
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


def compile_cpu(roots, repeats: int) -> None:
    for r in range(repeats):
        for root in roots:
            with tempfile.TemporaryDirectory(prefix="bd_numba_cache_") as cache:
                env = {**os.environ, "PYTHONPATH": str(root), "NUMBA_CACHE_DIR": cache}
                out = subprocess.run([sys.executable, "-c", COMPILE], env=env, cwd=root,
                                     check=True, capture_output=True, text=True).stdout
            m = json.loads(out.strip().splitlines()[-1])
            print(f"round {r + 1} {str(root)[-40:]:40s} residual_flat {m['residual_s']:5.2f} s, "
                  f"analytic Jacobian {m['jacobian_s']:5.2f} s, sum "
                  f"{m['residual_s'] + m['jacobian_s']:5.2f} s of compile CPU", flush=True)


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
