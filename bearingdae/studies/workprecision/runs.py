"""Running the work-precision study: every rung of every ladder, the reference chosen and
confirmed, the errors computed."""

from __future__ import annotations

import json
import math
import statistics
import tomllib
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from .errors import error_scales, quantity_errors
from .ladders import (
    IDA_TARGET_RTOL,
    QUANTITIES,
    TIME_LIMIT_FACTOR,
    WARMUP_OVERRIDES,
    Ladder,
    ladders,
)


# ---------------------------------------------------------------------------------------------
# Running the study
# ---------------------------------------------------------------------------------------------
@dataclass
class Run:
    solver: str
    parameter: str
    value: float
    rtol: float = math.nan
    atol: float = math.nan
    status: str = "ok"  #: ok | failed | skipped
    message: str = ""
    wall_s: float = math.nan  #: median integrator wall time
    walls_s: list = field(default_factory=list)
    time_limit_s: float = math.nan
    kernel_evaluations: int = -1  #: residual-kernel calls, including those in Jacobians
    steps: int = -1
    errors: dict = field(default_factory=dict)
    is_reference: bool = False
    dataset: xr.Dataset | None = field(default=None, repr=False)

    @property
    def label(self) -> str:
        return f"{self.solver} {self.parameter}={self.value:g}"


def derive(scene, overrides: dict):
    """A copy of ``scene`` with dotted-key ``overrides`` applied (through its TOML text)."""
    from ...scene import scene_from_dict

    return scene_from_dict(tomllib.loads(scene.to_toml()), overrides)


def _execute(scene, solver: str, options: dict):
    """One run -> (Dataset or None, status, message, integrator wall [s], statistics)."""
    from ...api import SimulationError, simulate
    from ...solvers import from_name

    try:
        ds = simulate(scene, solver=from_name(solver, **(options or {})), progress=False)
        status, msg = "ok", "completed"
    except SimulationError as exc:
        ds, status, msg = exc.dataset, "failed", str(exc)
    except Exception as exc:  # noqa: BLE001 - a failed rung is a result, not a crash
        return None, "failed", f"{type(exc).__name__}: {exc}", math.nan, {}
    stats = json.loads(ds.attrs["solver_statistics"]) if ds is not None else {}
    return ds, status, msg, float(stats.get("wall_time_s", math.nan)), stats


def warm_up(scene, solvers) -> None:
    """Compile every solver's kernels (numba) outside the timings."""
    tiny = derive(scene, WARMUP_OVERRIDES)
    for s in solvers:
        _execute(tiny, s, {})


def run_ladder(scene, ladder: Ladder, repeat: int, time_limit_s: float | None,
               bar=None) -> list[Run]:
    """Every rung of one ladder; after a time-out the tighter rungs are recorded as skipped."""
    runs, stopped = [], None
    for v in ladder.values:
        overrides, options = ladder.configure(v)
        sc = derive(scene, overrides)
        tol = ladder.parameter == "rtol"
        run = Run(ladder.name, ladder.parameter, v, rtol=sc.dynamics.rtol if tol else math.nan,
                  atol=sc.dynamics.atol if tol else math.nan)
        if ladder.timed_limit and time_limit_s is not None:
            options = {**options, "time_limit_s": time_limit_s}
            run.time_limit_s = time_limit_s
        if stopped is not None:
            run.status, run.message = "skipped", stopped
            runs.append(run)
            if bar is not None:
                bar.update(repeat)
            continue
        for k in range(repeat):
            if bar is not None:
                bar.set_description(f"{run.label} ({k + 1}/{repeat})")
            ds, status, msg, wall, stats = _execute(sc, ladder.solver, options)
            if k == 0:
                # keep only what the errors need (a long window's slice fields are large)
                run.dataset = ds[[q for q in QUANTITIES if q in ds]] if ds is not None else None
                run.status, run.message = status, msg
                run.kernel_evaluations = int(stats.get("residual_calls", -1)
                                             + stats.get("residual_calls_in_jacobian", 0))
                run.steps = int(stats.get("steps", -1))  # IDA's step count is not exposed
            run.walls_s.append(wall)
            if bar is not None:
                bar.update(1)
            if status != "ok":
                if bar is not None:
                    bar.update(repeat - k - 1)
                break
        run.wall_s = float(statistics.median(run.walls_s)) if run.walls_s else math.nan
        if run.status != "ok" and "time limit" in run.message:
            stopped = f"not run: {run.label} already exceeded the time limit"
        runs.append(run)
    return runs


@dataclass
class Study:
    scene_title: str
    runs: list[Run]
    reference: Run | None
    floor: dict  #: errors of the next-tightest IDA run against the reference
    confirmations: dict  #: solver -> errors of its finest run against the reference
    time_limit_s: float
    repeat: int
    overrides: dict


def study(scene, repeat: int = 3, quick: bool = False, solvers=None,
          time_limit_factor: float = TIME_LIMIT_FACTOR, progress: bool = True,
          base_overrides: dict | None = None, extra: list[Ladder] = ()) -> Study:
    """Run every ladder (and the ``extra`` ones) on ``scene``, choose and confirm the
    reference, compute the errors."""
    lads = ladders(quick, solvers) + list(extra)
    bar = None
    if progress:  # a bar on a terminal; in a log one line per run, never a carriage return
        from ...run.progress import CountProgress

        bar = CountProgress(sum(len(ld.values) for ld in lads) * repeat, "work-precision")
    warm_up(scene, list(dict.fromkeys(ld.solver for ld in lads)))
    runs = run_ladder(scene, lads[0], repeat, None, bar)
    ida_ok = [r for r in runs if r.status == "ok"]
    target = [r for r in ida_ok if math.isclose(r.value, IDA_TARGET_RTOL)]
    basis = target[0].wall_s if target else (
        statistics.median(r.wall_s for r in ida_ok) if ida_ok else math.nan)
    limit = time_limit_factor * basis if np.isfinite(basis) else None
    for ld in lads[1:]:
        runs += run_ladder(scene, ld, repeat, limit, bar)
    if bar is not None:
        bar.close()

    ref = min(ida_ok, key=lambda r: r.rtol) if ida_ok else None
    floor, confirmations = {}, {}
    if ref is not None:
        ref.is_reference = True
        scales = error_scales(scene)
        for r in runs:
            if r.status == "ok" and r.dataset is not None:
                r.errors = quantity_errors(r.dataset, ref.dataset, scales)
        nxt = [r for r in ida_ok if r is not ref]
        if nxt:
            second = min(nxt, key=lambda r: r.rtol)
            floor = {"run": second.label, **second.errors}
        for ld in lads:
            if ld.confirms_reference:
                ok = [r for r in runs if r.solver == ld.name and r.status == "ok"]
                if ok:
                    finest = min(ok, key=lambda r: r.value)
                    confirmations[ld.name] = {"run": finest.label, **finest.errors}
    return Study(scene.title, runs, ref, floor, confirmations,
                 limit if limit is not None else math.nan, repeat, base_overrides or {})


