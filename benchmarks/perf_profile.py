"""Where the CPU time of an IDA step goes, by shared object (Linux ``perf``, native code).

    python benchmarks/run.py profile [--runs 6] [--hz 4000] [--scikit-sundae]
        [--set KEY=VALUE ...] [--keep DIR] [--json F]

Records two profiles with ``perf record``: a process that integrates the first 20 ms of the
baseline ``--runs`` times (IDA only: no projection or Dataset; after an untimed warm-up), and
the same process without the integrations. The difference is the integrations alone (imports,
numba cache loading and start-up cancel). Every sample is sorted by the shared object it was
taken in and reported as CPU time per 20-ms run and per IDA step. Samples in numba's compiled
code have no symbol ("[JIT]"); they include numba's argument unboxing, which runs as compiled
code too. perf adds a few per cent of its own. ``--scikit-sundae``: the same through
``IDAScikitSundae`` (Python callbacks), for comparison. ``--json``: the counts, the samples
per category and the µs per step, with the CPU and the load.
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from run import HERE, header, overrides, summary, write_json

CATEGORIES = (  # (label, substrings of the shared object's name)
    ("numba kernels and cfunc callbacks: compiled code (incl. argument unboxing)",
     ("[JIT]", "_helperlib")),
    ("numba kernels: libm (exp, pow, sin/cos, log10)", ("libm.so",)),
    ("SuperLU_MT: factorisation and solves", ("superlumt", "sunmatrixsparse", "libgomp")),
    ("IDA itself and N_Vector operations", ("libsundials_ida", "nvecserial", "sundials_core")),
    ("scikit-sundae's Cython callback wrappers (IDAScikitSundae only)", ("_cy_ida", "_cy_common")),
    ("numba dispatch (typing the arguments)", ("_dispatcher", "_nrt_python")),
    ("operating system", ("kallsyms", "[vdso]")),
    ("Python, numpy, libc (per-output work; per-call glue of Python callbacks)", ("",)),
)


def window(over: dict):
    """(model, y0, y'0, output times) of the profiled window: the first 20 ms of the baseline."""
    import numpy as np

    from bearingdae import load_scene
    from bearingdae.solvers.algebraic import initial_state
    from bearingdae.system.model import build_model

    m = build_model(load_scene("yang20_baseline", over))
    return (m, *initial_state(m), np.linspace(0.0, 0.02, 601))


def child(n: int, scikit: bool, over: dict) -> None:
    """The profiled process: n integrations of the first 20 ms of the baseline."""
    from bearingdae.solvers import ida

    m, y0, yp0, t_out = window(over)
    cls = ida.IDAScikitSundae if scikit else ida.IDA
    cls().integrate(m, y0, yp0, t_out[:3])  # kernels loaded outside the profiles' difference
    for _ in range(n):
        t0 = time.perf_counter()
        r = cls().integrate(m, y0, yp0, t_out)
        print(json.dumps({"wall_s": time.perf_counter() - t0, **{k: r.stats[k] for k in (
            "steps", "residual_calls", "jacobian_calls")}}), flush=True)


def compiled_ida_steps(over: dict) -> int:
    """IDA's steps over the profiled window with the compiled callbacks: scikit-sundae counts
    none, and its IDA takes the same steps (same method, tolerances and residual)."""
    from bearingdae.solvers import ida

    return int(ida.IDA().integrate(*window(over)).stats["steps"])


def samples(path: Path) -> collections.Counter:
    out = subprocess.run(["perf", "report", "-i", str(path), "--sort", "dso", "-F",
                          "sample,dso", "--stdio"], capture_output=True, text=True,
                         check=True).stdout
    c = collections.Counter()
    for line in out.splitlines():
        parts = line.split(None, 1)
        if len(parts) == 2 and parts[0].isdigit():
            c[parts[1].strip()] += int(parts[0])
    return c


def main(argv=None, name="profile") -> None:
    ap = argparse.ArgumentParser(prog=f"run.py {name}", description=summary(__doc__))
    ap.add_argument("--runs", type=int, default=6)
    ap.add_argument("--hz", type=int, default=4000, help="perf's sampling frequency")
    ap.add_argument("--scikit-sundae", action="store_true")
    ap.add_argument("--set", action="append", metavar="KEY=VALUE", help="scene override")
    ap.add_argument("--keep", type=Path, help="keep the perf data files in this folder")
    ap.add_argument("--json", type=Path, help="write the categories and counts here")
    ap.add_argument("--child", type=int, help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    over = overrides(a.set)
    if a.child is not None:
        return child(a.child, a.scikit_sundae, over)
    header(f"{name}: first 20 ms of yang20_baseline{f' {over}' if over else ''}, {a.runs} runs")
    folder = a.keep or Path(tempfile.mkdtemp(prefix="bd_profile_"))
    folder.mkdir(parents=True, exist_ok=True)
    extra = (["--scikit-sundae"] if a.scikit_sundae else []) + [
        x for kv in (a.set or ()) for x in ("--set", kv)]
    stats = []
    for n, data in ((a.runs, folder / "run.data"), (0, folder / "base.data")):
        cmd = ["perf", "record", "-q", "-F", str(a.hz), "-o", str(data), "--", sys.executable,
               str(HERE / "run.py"), name, "--child", str(n), *extra]
        out = subprocess.run(cmd, check=True, capture_output=True, text=True,
                             env={**os.environ, "PYTHONWARNINGS": "ignore"}).stdout
        stats += [json.loads(ln) for ln in out.splitlines() if ln.startswith("{")]
    a_, b_ = samples(folder / "run.data"), samples(folder / "base.data")
    per_cat = collections.Counter()
    for dso in a_:
        for label, keys in CATEGORIES:
            if any(k in dso for k in keys):
                per_cat[label] += a_[dso] - b_.get(dso, 0)
                break
    total = sum(per_cat.values())
    steps = stats[-1]["steps"]
    whose = ""
    if not steps:  # scikit-sundae's IDA counts none
        steps, whose = compiled_ida_steps(over), " (the compiled IDA's count)"
    print(f"IDA per 20-ms run: {steps} steps{whose}, {stats[-1]['residual_calls']} residual calls, "
          f"{stats[-1]['jacobian_calls']} Jacobians; CPU {total / a.hz / a.runs * 1e3:.0f} ms per "
          f"run, {total / a.hz / a.runs / steps * 1e6:.1f} µs per step")
    rows = []
    for label, _ in CATEGORIES:
        v = per_cat[label] / a.hz / a.runs
        rows.append({"category": label, "samples": per_cat[label], "ms_per_run": v * 1e3,
                     "share": per_cat[label] / total, "us_per_step": v / steps * 1e6})
        print(f"{v * 1e3:7.1f} ms  {100 * per_cat[label] / total:5.1f} %  "
              f"{v / steps * 1e6:5.2f} µs/step  {label}")
    write_json(a.json, {"runs": a.runs, "hz": a.hz, "scikit_sundae": a.scikit_sundae,
                        "overrides": over, "steps": steps, "runs_stats": stats,
                        "us_per_step": total / a.hz / a.runs / steps * 1e6, "rows": rows})
    if a.keep is None:
        for f in folder.iterdir():
            f.unlink()
        folder.rmdir()
