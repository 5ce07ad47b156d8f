"""The worker task of a sweep: one scene (TOML text) -> simulate -> (status, Dataset, info).

Pipeline place: studies; runs in a dask worker process (pinned to one thread, PINNED_ENV) or in
this process (scheduler 'synchronous'); a failed run is returned, never raised.
"""

from __future__ import annotations

import os
import time
import tomllib
import traceback
import warnings

import xarray as xr


#: Environment of every worker process (SOLVER-NOTES "Parallel runs").
PINNED_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}

def execute_run(scene_toml: str) -> tuple[str, xr.Dataset | None, dict]:
    """Worker task: simulate one scene given as TOML text.

    Returns ``(status, dataset, info)``; a failure of the run (solver, static equilibrium, any
    exception) is returned as ``("failed", None, {"error": ..., ...})``, never raised, so that it
    is recorded and the other runs go on.
    """
    for name, value in PINNED_ENV.items():  # effective if bearingdae is not imported yet
        os.environ.setdefault(name, value)
    from ...api import SimulationError, simulate
    from ...analysis.guards import PlausibilityWarning
    from ...scene import scene_from_dict
    from ...util.warning_lines import caught_lines

    t0, c0 = time.perf_counter(), time.process_time()
    env = {k: os.environ.get(k, "") for k in PINNED_ENV}
    # The run's other warnings (a warm-up that did not settle, ...) are handed back as lines
    # (util/warning_lines.py) for the sweep to print, naming the run: a worker process would
    # print them with Python's file name and source line, between the progress lines.
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        # recorded in the run's attributes and listed per run in the sweep Dataset
        warnings.simplefilter("ignore", PlausibilityWarning)
        try:
            ds = simulate(scene_from_dict(tomllib.loads(scene_toml), origin="sweep run"),
                          progress=False)  # the sweep shows its own progress
            ds.attrs["run_cpu_time_s"] = time.process_time() - c0  # contention-free cost
            outcome = "completed", ds, {"wall_s": time.perf_counter() - t0, "env": env}
        except SimulationError as exc:
            failed_at = getattr(exc.dataset, "sizes", {}).get("time", 0)
            outcome = "failed", None, {"error": f"SimulationError: {exc}", "wall_s":
                                       time.perf_counter() - t0,
                                       "samples_before_failure": failed_at, "env": env}
        except Exception as exc:  # noqa: BLE001 - any failure of one run is recorded
            outcome = "failed", None, {"error": f"{type(exc).__name__}: {exc}",
                                       "traceback": traceback.format_exc(limit=8),
                                       "wall_s": time.perf_counter() - t0, "env": env}
    outcome[2]["warnings"] = caught_lines(caught)
    return outcome
