"""Where the CPU time of an IDA run goes, by shared object (Linux ``perf``, native code).

Two steps (docs/performance.md, "Where the time goes"):

    perf record -F 4000 -o run.data  python benchmarks/perf_breakdown.py run 6 [KEY=VALUE ...]
    perf record -F 4000 -o base.data python benchmarks/perf_breakdown.py run 0 [KEY=VALUE ...]
    (``run-scikit-sundae N``: the same through ``IDAScikitSundae``)
    python benchmarks/perf_breakdown.py report run.data base.data 6 [STEPS]

(``python benchmarks/perf_breakdown.py steps [KEY=VALUE ...]`` prints STEPS, the IDA step
count of one run, from IDA's own statistics; KEY=VALUE are scene overrides, e.g.
``cage.smoothing_um=0.1`` for the numbers of docs/performance.md.)

``run N`` integrates the first 20 ms of the baseline N times (IDA only: no projection or
Dataset), after a warm-up; ``run 0`` is the same process without the integrations, so the
difference of the two profiles is the integrations alone (imports, numba cache loading and
start-up cancel). ``report`` sorts every sample by the shared object it was taken in and prints
CPU time per 20-ms run and per IDA step. Samples in numba's compiled code have no symbol
("[JIT]"); they include numba's argument unboxing, which runs as compiled code too.
"""

from __future__ import annotations

import collections
import os
import subprocess
import sys
import time

CATEGORIES = (  # (label, substrings of the shared object's name)
    ("numba kernels and cfunc callbacks: compiled code (incl. argument unboxing)",
     ("[JIT]", "_helperlib")),
    ("numba kernels: libm (exp, pow, sin/cos, log10)", ("libm.so",)),
    ("SuperLU_MT: factorisation and solves", ("superlumt", "sunmatrixsparse", "libgomp")),
    ("IDA itself and N_Vector operations", ("libsundials_ida", "nvecserial", "sundials_core")),
    ("scikit-sundae's Cython callback wrappers (IDAScikitSundae only)", ("_cy_ida", "_cy_common")),
    ("numba dispatch (typing the arguments)", ("_dispatcher", "_nrt_python")),
    ("operating system", ("kallsyms", "[vdso]")),
    ("Python, numpy, libc (callback glue: arrays made per call, the calls themselves)", ("",)),
)


OVERRIDES: dict = {}


def _setup():
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    import numpy as np

    from bearingdae import load_scene
    from bearingdae.solvers.algebraic import initial_state
    from bearingdae.system.model import build_model

    m = build_model(load_scene("yang20_baseline", OVERRIDES))
    y0, yp0 = initial_state(m)
    return m, y0, yp0, np.linspace(0.0, 0.02, 601)


def run(n: int, path: str = "compiled") -> None:
    """``path``: "compiled" (``IDA``, the default) or "scikit-sundae" (``IDAScikitSundae``)."""
    from bearingdae.solvers import ida

    cls = ida.IDA if path == "compiled" else ida.IDAScikitSundae
    m, y0, yp0, t_out = _setup()
    cls().integrate(m, y0, yp0, t_out[:3])  # JIT and cache loading outside the profile's delta
    for _ in range(n):
        t0 = time.perf_counter()
        r = cls().integrate(m, y0, yp0, t_out)
        print(f"{time.perf_counter() - t0:.3f} s, residual calls {r.stats['residual_calls']}, "
              f"Jacobians {r.stats['jacobian_calls']}, {r.message}", flush=True)


def steps() -> None:
    from bearingdae.solvers import ida

    m, y0, yp0, t_out = _setup()
    s = ida.integrate(m, y0, yp0, t_out).stats
    print(f"{s['steps']} steps, {s['residual_calls']} residual calls, "
          f"{s['jacobian_calls']} Jacobians, {s['error_test_failures']} error-test and "
          f"{s['nonlinear_convergence_failures']} convergence failures")


def samples(path: str) -> collections.Counter:
    out = subprocess.run(["perf", "report", "-i", path, "--sort", "dso", "-F", "sample,dso",
                          "--stdio"], capture_output=True, text=True, check=True).stdout
    c = collections.Counter()
    for line in out.splitlines():
        parts = line.split(None, 1)
        if len(parts) == 2 and parts[0].isdigit():
            c[parts[1].strip()] += int(parts[0])
    return c


def report(run_data: str, base_data: str, n: int, hz: float = 4000.0,
           steps_per_run: int | None = None) -> None:
    a, b = samples(run_data), samples(base_data)
    per_cat = collections.Counter()
    for dso in a:
        d = a[dso] - b.get(dso, 0)
        for label, keys in CATEGORIES:
            if any(k in dso for k in keys):
                per_cat[label] += d
                break
    total = sum(per_cat.values())
    print(f"CPU time per 20-ms run: {total / hz / n * 1e3:.0f} ms")
    for label, _ in CATEGORIES:
        v = per_cat[label]
        per_step = (f", {v / hz / n / steps_per_run * 1e6:5.1f} µs per step"
                    if steps_per_run else "")
        print(f"{v / hz / n * 1e3:7.1f} ms  {100 * v / total:5.1f} %{per_step}  {label}")


if __name__ == "__main__":
    for kv in sys.argv[2:]:
        if "=" in kv:
            key, value = kv.split("=", 1)
            OVERRIDES[key] = float(value)
    if sys.argv[1] == "run":
        run(int(sys.argv[2]))
    elif sys.argv[1] == "run-scikit-sundae":
        run(int(sys.argv[2]), "scikit-sundae")
    elif sys.argv[1] == "steps":
        steps()
    elif sys.argv[1] == "report":
        report(sys.argv[2], sys.argv[3], int(sys.argv[4]),
               steps_per_run=int(sys.argv[5]) if len(sys.argv) > 5 else None)
    else:
        raise SystemExit(__doc__)
