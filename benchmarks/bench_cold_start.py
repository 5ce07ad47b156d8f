"""Cold and warm start of ``bearingdae run``: process start to the title, to the first *moving*
progress line, to exit, and the CPU time of the process and its children
(docs/performance.md, "Cold start").

    python benchmarks/bench_cold_start.py [--repeats N] [--root DIR ...] [--full] [--list]

"Cold": every numba cache file (``__pycache__/*.nbi``, ``*.nbc``) under the package is deleted
first, as after ``pip install`` on a fresh machine; "warm": the same command again. The run is
the default scene (IDA), by default cut to 0.02 cage revolution without warm-up (``--full``: the
whole default run), output piped, so the progress comes as lines. "First moving progress": the
first line ``simulated time a/b s`` with a > 0, i.e. the integration has started (the code
before this work printed its first line at 10 % of the run). Several ``--root`` checkouts (each
put first on PYTHONPATH, e.g. a ``git archive`` of the code before a change) are measured in
turn, round by round, so that old and new see the same load; the load average (1 min) before
each run is printed beside it: the machine is shared, CPU time is the steadier number; it is
given in all, and split into the run's own process and its children (the Jacobian callback
compiled aside, solvers/sundials/precompile.py, here forced on whatever the load; ``--serial``
also times each checkout with it switched off).
``--list`` also lists the numba functions a cold run compiled and cached (NUMBA_DEBUG_CACHE).
"""

from __future__ import annotations

import argparse
import glob
import os
import re
import resource
import statistics
import subprocess
import sys
import time

SHORT = ["--set", "numerics.cage_revolutions=0.02", "--set", "numerics.warmup_cage_revolutions=0"]
_PROGRESS = re.compile(rb"simulated time ([0-9.eE+-]+)/")


def clear_cache(root: str) -> int:
    files = [f for pat in ("*.nbi", "*.nbc")
             for f in glob.glob(os.path.join(root, "bearingdae", "**", "__pycache__", pat),
                                recursive=True)]
    for f in files:
        os.remove(f)
    return len(files)


def timed_run(root: str, out: str, full: bool = False, debug_cache: bool = False,
              aside: bool | None = True) -> dict:
    """One ``bearingdae run`` in a fresh process: seconds from start to the title line, to the
    first moving progress line, to exit; CPU seconds of the process and its children; the
    output lines with their times."""
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", PYTHONUNBUFFERED="1",
               MPLBACKEND="Agg")
    env["PYTHONPATH"] = root + os.pathsep + env.get("PYTHONPATH", "")
    if debug_cache:
        env["NUMBA_DEBUG_CACHE"] = "1"
    env.pop("BEARINGDAE_COMPILE_ASIDE", None)
    if aside is not None:  # forced, not decided by the load of the moment
        env["BEARINGDAE_COMPILE_ASIDE"] = "1" if aside else "0"
    # the process's own CPU and its children's (the Jacobian compiled aside), printed at exit
    code = ("import atexit, resource, sys\n"
            "def cpu():\n"
            "    s, c = (resource.getrusage(w) for w in (resource.RUSAGE_SELF, "
            "resource.RUSAGE_CHILDREN))\n"
            "    print(f'[cpu] {s.ru_utime + s.ru_stime:.2f} {c.ru_utime + c.ru_stime:.2f}', "
            "file=sys.stderr, flush=True)\n"
            "atexit.register(cpu)\n"
            "from bearingdae.cli.program import main; sys.exit(main())")
    args = ["run", "-o", out, "--no-plot"] + ([] if full else SHORT)
    load = os.getloadavg()[0]
    cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.Popen([sys.executable, "-c", code, *args], env=env, stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, cwd="/tmp")
    lines, title, moving, own, aside = [], None, None, None, None
    for line in iter(p.stdout.readline, b""):
        t = time.perf_counter() - t0
        lines.append((t, line.decode(errors="replace").rstrip()))
        if title is None and b"rollers x" in line:
            title = t
        m = _PROGRESS.search(line)
        if moving is None and m and float(m.group(1)) > 0:
            moving = t
        if line.startswith(b"[cpu] "):
            own, aside = (float(v) for v in line.split()[1:3])
    p.wait()
    end = time.perf_counter() - t0
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (cpu1.ru_utime + cpu1.ru_stime) - (cpu0.ru_utime + cpu0.ru_stime)
    return {"title": title, "moving": moving, "end": end, "cpu": cpu, "load": load,
            "cpu_own": own, "cpu_aside": aside,
            "status": p.returncode, "lines": lines}


def _name(root: str, aside: bool | None) -> str:
    return root + {True: "", False: " (serial)", None: " (auto)"}[aside]


def _s(x) -> str:
    return "  —  " if x is None else f"{x:5.1f}"


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--root", action="append", help="checkout to time (repeatable; default: "
                    "this one)")
    ap.add_argument("--full", action="store_true", help="the whole default run")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--no-warm", action="store_true")
    ap.add_argument("--serial", action="store_true", help="also each root with "
                    "BEARINGDAE_COMPILE_ASIDE=0 (no second process compiling the Jacobian)")
    ap.add_argument("--auto", action="store_true", help="also each root as a user runs it "
                    "(the second process only if a CPU is idle)")
    a = ap.parse_args(argv)
    roots = a.root or [os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]
    roots = ([(r, True) for r in roots] + ([(r, False) for r in roots] if a.serial else [])
             + ([(r, None) for r in roots] if a.auto else []))
    out = os.path.join("/tmp", f"cold_start_{os.getpid()}.nc")
    rows: dict[str, list] = {_name(*r): [] for r in roots}
    print(f"{'checkout':40s} {'kind':4s} {'load':>5s} {'title':>5s} {'moving':>6s} "
          f"{'exit':>5s} {'CPU':>5s} {'(own':>5s} {'aside)':>6s}", flush=True)
    for _ in range(a.repeats):
        for root, aside in roots:
            name = _name(root, aside)
            clear_cache(root)
            kinds = [("cold", timed_run(root, out, a.full, a.list, aside))]
            if not a.no_warm:
                kinds.append(("warm", timed_run(root, out, a.full, aside=aside)))
            for kind, r in kinds:
                rows[name].append((kind, r))
                print(f"{name[-40:]:40s} {kind:4s} {r['load']:5.1f} {_s(r['title'])} "
                      f"{_s(r['moving']):>6s} {_s(r['end'])} {_s(r['cpu'])} {_s(r['cpu_own'])} "
                      f"{_s(r['cpu_aside']):>6s}"
                      + ("" if r["status"] == 0 else f"  exit status {r['status']}"),
                      flush=True)
                if r["status"] != 0 or r["moving"] is None:
                    print("\n".join(f"    {t:6.2f} {ln}" for t, ln in r["lines"][-15:]))
            if a.list:
                saved = sorted({os.path.basename(ln.split("data saved to")[1]).strip(" '\"")
                                for _, ln in kinds[0][1]["lines"] if "data saved to" in ln})
                print(f"{len(saved)} cache data files written by the cold run:\n  "
                      + "\n  ".join(saved))
    if a.repeats > 1:
        print("medians:")
        for root, rs in rows.items():
            for kind in ("cold", "warm"):
                sel = [r for k, r in rs if k == kind and r["moving"] is not None]
                if sel:
                    print(f"{root[-40:]:40s} {kind:4s} first moving progress "
                          f"{statistics.median(r['moving'] for r in sel):5.1f} s, exit "
                          f"{statistics.median(r['end'] for r in sel):5.1f} s, CPU "
                          f"{statistics.median(r['cpu'] for r in sel):5.1f} s (this process "
                          f"{statistics.median(r['cpu_own'] or 0 for r in sel):5.1f} s, the "
                          f"child {statistics.median(r['cpu_aside'] or 0 for r in sel):5.1f} s) "
                          f"(n = {len(sel)})")
    if os.path.exists(out):
        os.remove(out)


if __name__ == "__main__":
    main()
