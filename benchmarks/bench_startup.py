"""Benchmark: process start to the end of the first IDA integration, warm numba cache
(issue 11 item 8: the compiled callbacks must load from the cache, not recompile).

Run on demand, in a fresh process each time:
    python benchmarks/bench_startup.py compiled
    python benchmarks/bench_startup.py scikit-sundae

Prints the wall time of the imports, of the model and its consistent initial state, and of the
first integration (10 µs of the baseline, i.e. the first IDASolve), plus the process CPU time
(``time.process_time``: about 1 s when nothing compiles; a recompilation shows as seconds).
"""

from __future__ import annotations

import os
import sys
import time

T0 = time.perf_counter()
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from bearingdae import load_scene  # noqa: E402
from bearingdae.solvers import ida  # noqa: E402
from bearingdae.solvers.algebraic import initial_state  # noqa: E402
from bearingdae.system.model import build_model  # noqa: E402


def main() -> None:
    which = sys.argv[1] if len(sys.argv) > 1 else "compiled"
    t1 = time.perf_counter()
    m = build_model(load_scene("yang20_baseline"))
    y0, yp0 = initial_state(m)
    t2 = time.perf_counter()
    cls = ida.IDA if which == "compiled" else ida.IDAScikitSundae
    r = cls().integrate(m, y0, yp0, np.array([0.0, 1e-5]))
    t3 = time.perf_counter()
    print(f"{which}: imports {t1 - T0:.2f} s, model + initial state {t2 - t1:.2f} s, first "
          f"integration {t3 - t2:.2f} s; total {t3 - T0:.2f} s wall, process CPU "
          f"{time.process_time():.2f} s ({r.message})")


if __name__ == "__main__":
    main()
