"""Cold and warm start of ``bearingdae run``: process start to first progress output
(docs/performance.md, "Cold start").

    python benchmarks/bench_cold_start.py [--repeats N] [--package-root DIR]

"Cold": every numba cache file (``__pycache__/*.nbi``, ``*.nbc``) under the package is deleted
first, as after ``pip install`` on a fresh machine; "warm": the same command again. The run is
the default scene (IDA) cut to 0.02 cage revolution, so the time to the first progress line is
the start-up (imports, scene, model, numba compilation or cache loading, static solve,
consistent initialisation). ``--package-root`` times another checkout (put on PYTHONPATH), e.g.
the one before a change, side by side. With ``--list`` the numba functions compiled by a cold
run are listed (NUMBA_DEBUG_CACHE).
"""

from __future__ import annotations

import argparse
import glob
import resource
import os
import subprocess
import sys
import time

ARGS = ["--set", "numerics.cage_revolutions=0.02", "--set", "numerics.warmup_cage_revolutions=0",
        "--no-plot"]


def clear_cache(root: str) -> int:
    files = [f for pat in ("*.nbi", "*.nbc")
             for f in glob.glob(os.path.join(root, "bearingdae", "**", "__pycache__", pat),
                                recursive=True)]
    for f in files:
        os.remove(f)
    return len(files)


def time_to_progress(root: str, out: str, debug_cache=False):
    """(seconds to the first progress output, seconds to exit, CPU seconds of the process,
    stderr text). CPU time is the steadier measure on a shared machine."""
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", PYTHONUNBUFFERED="1")
    env["PYTHONPATH"] = root + os.pathsep + env.get("PYTHONPATH", "")
    if debug_cache:
        env["NUMBA_DEBUG_CACHE"] = "1"
    code = "import sys; from bearingdae.program import main; sys.exit(main())"
    cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.Popen([sys.executable, "-c", code, "run", "-o", out, *ARGS], env=env,
                         stderr=subprocess.PIPE, stdout=subprocess.PIPE, cwd=root)
    first = None
    err = bytearray()
    while True:
        b = p.stderr.read1(4096) if hasattr(p.stderr, "read1") else p.stderr.read(1)
        if not b:
            break
        err += b
        if first is None and b"%" in err:  # tqdm's first line: "  0%|  ..."
            first = time.perf_counter() - t0
    p.wait()
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (cpu1.ru_utime + cpu1.ru_stime) - (cpu0.ru_utime + cpu0.ru_stime)
    return (first, time.perf_counter() - t0, cpu,
            err.decode(errors="replace") + p.stdout.read().decode())


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--package-root", default=os.path.dirname(os.path.dirname(
        os.path.abspath(__file__))))
    ap.add_argument("--list", action="store_true")
    a = ap.parse_args(argv)
    out = os.path.join("/tmp", f"cold_start_{os.getpid()}.nc")
    for _ in range(a.repeats):
        n = clear_cache(a.package_root)
        cold, cold_total, cold_cpu, err = time_to_progress(a.package_root, out, a.list)
        warm, warm_total, warm_cpu, _ = time_to_progress(a.package_root, out)
        print(f"{a.package_root}: cold (deleted {n} cache files) first progress {cold:.1f} s "
              f"(exit {cold_total:.1f} s, CPU {cold_cpu:.1f} s); warm first progress {warm:.1f} s "
              f"(exit {warm_total:.1f} s, CPU {warm_cpu:.1f} s)", flush=True)
        if a.list:
            saved = sorted({os.path.basename(line.split("data saved to")[1]).strip(" '\"")
                            for line in err.splitlines() if "data saved to" in line})
            print(f"{len(saved)} compiled and cached:\n  " + "\n  ".join(saved))
        if cold is None:
            print(err[-2000:])
    if os.path.exists(out):
        os.remove(out)


if __name__ == "__main__":
    main()
