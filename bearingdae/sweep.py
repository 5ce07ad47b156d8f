"""Parameter sweeps: a base scene varied along dotted-key axes, run in parallel (issue 5).

Pipeline place: scene files -> **sweep** (many scenes) -> :func:`~bearingdae.api.simulate` per
point on dask.distributed workers -> one NetCDF file per run (kept as it completes) -> one sweep
Dataset with the axes as dimensions, holding per-run steady-state summaries
(:mod:`bearingdae.analysis`) and one roller's orbit per run for the figures.

A sweep file is TOML::

    title = "yang20 speed sweep (Figs 18-20)"
    base = "yang20_baseline"          # bundled case name, or a scene path (relative to this file)

    [overrides]                       # dotted scene keys applied to every run
    "numerics.cage_revolutions" = 1.25

    [axes]                            # dotted scene key -> list of values (outer product)
    "operating.speed_rpm" = [2000, 6000, 10000, 14000]

    [sweep]                           # optional settings, see SweepSettings
    figures = [18, 19, 20]

Keys may also be written as TOML tables (``[axes.operating]`` / ``speed_rpm = [...]``).

**Resume.** Each run is identified by the SHA-256 of its scene TOML with the title removed
(the title is a label, not an input of the physics): ``RUN_DIR/<hash>.nc`` for a completed run,
``RUN_DIR/<hash>.failed.json`` for a failed one. Both are written atomically by the client as
each run completes, so an interrupted sweep restarted with the same run directory recomputes
nothing that finished, and sweeps sharing a run directory share identical runs. Changing the
code does not change the hash: delete the run directory after changing bearingdae.

**Parallelism.** Processes, one thread each, BLAS/OpenMP pinned to one thread (measured in
SOLVER-NOTES: unpinned workers were 6x slower and forked ones hung). Workers return the
Dataset to the client, which writes it, so ``--scheduler`` may point at a cluster without a
shared file system.
"""

from __future__ import annotations

import asyncio
import contextlib
import difflib
import hashlib
import itertools
import json
import logging
import os
import time
import tomllib
import traceback
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Mapping

import numpy as np
import tomli_w
import xarray as xr
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from .scene import (
    _SECTIONS,
    Scene,
    SceneError,
    _show,
    _unknown_message,
    bundled_case_dirs,
    load_scene,
    resolve_case,
)

#: Environment of every worker process (SOLVER-NOTES "Parallel runs").
PINNED_ENV = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}

#: Paper figures a sweep may ask ``bearingdae plot`` to draw.
PAPER_FIGURES = tuple(range(11, 25))

_TOP_KEYS = ("title", "base", "overrides", "axes", "sweep")
MAX_RUNS = 100_000
MAX_AXIS_VALUES = 10_000


class SweepSettings(BaseModel):
    """The optional ``[sweep]`` table."""

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True)

    workers: int | None = Field(default=None, ge=1, le=4096, description="worker processes of "
                                "the default LocalCluster (default: CPU count, at most one per "
                                "pending run; --workers overrides)")
    figures: list[int] = Field(default_factory=list, description="paper figures (11-24) that "
                               "`bearingdae plot` draws from this sweep by default")
    orbit_points: int = Field(default=360, ge=8, le=100_000, description="azimuth points of "
                              "the one-orbit curves stored per run")
    orbit_roller: int = Field(default=1, ge=1, le=500, description="roller whose orbit is "
                              "stored (if its window holds a whole orbit; else the first that "
                              "does)")

    @field_validator("figures")
    @classmethod
    def _paper_figures(cls, v: list[int]) -> list[int]:
        bad = [f for f in v if f not in PAPER_FIGURES]
        if bad:
            raise ValueError(f"{bad} are not paper figures; allowed: 11..24")
        return v


@dataclass(frozen=True)
class Axis:
    key: str  #: dotted scene key, e.g. operating.speed_rpm
    dim: str  #: Dataset dimension name, e.g. speed_rpm
    values: tuple


@dataclass(frozen=True)
class RunPoint:
    index: tuple[int, ...]  #: position on the axes
    scene: Scene
    key: str  #: run hash (see :func:`run_key`)


@dataclass(frozen=True)
class Sweep:
    name: str
    title: str
    origin: str
    base: str
    overrides: Mapping[str, Any]
    axes: tuple[Axis, ...]
    settings: SweepSettings
    base_scene: Scene
    points: tuple[RunPoint, ...] = field(repr=False)
    text: str = field(default="", repr=False)  #: the sweep file as TOML

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(a.values) for a in self.axes)


# ---------------------------------------------------------------------------------------------
# Reading and validating sweep files
# ---------------------------------------------------------------------------------------------
def resolve_sweep(path: str | Path) -> Path:
    """A sweep file path as given, or a bundled one by name (``paper/yang20_speed_sweep``)."""
    p = Path(path)
    if p.is_file():
        return p
    name = p.name if p.suffix == ".toml" else p.name + ".toml"
    for folder in bundled_case_dirs():
        for cand in (folder / p.parent / name, folder / "paper" / name):
            if cand.is_file():
                return cand
    names = sorted(f"paper/{q.stem}" for d in bundled_case_dirs() for q in (d / "paper").glob(
        "*.toml"))
    close = difflib.get_close_matches(f"paper/{p.stem}", names, n=1)
    hint = f" Did you mean '{close[0]}'?" if close else ""
    raise SceneError(f"sweep file '{path}' does not exist and is not a bundled sweep "
                     f"(bundled: {', '.join(names)}).{hint}")


def is_sweep_file(path: str | Path) -> bool:
    """True for a TOML file with a top-level ``base`` key (a sweep, not a scene)."""
    try:
        return "base" in tomllib.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, ValueError, RecursionError):
        return False


def _read_toml(p: Path, what: str) -> dict:
    try:
        text = p.read_bytes().decode("utf-8")
    except OSError as exc:
        raise SceneError(f"cannot read {what} '{p}': {exc.strerror or exc}") from None
    except UnicodeDecodeError as exc:
        raise SceneError(f"{what} '{p}' is not UTF-8 text (byte {exc.start})") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{what} '{p}' is not valid TOML: {exc}") from None
    except (ValueError, RecursionError) as exc:
        raise SceneError(f"{what} '{p}' is not usable TOML: {type(exc).__name__}") from None


def load_sweep(path: str | Path, overrides: Mapping[str, Any] | None = None,
               override_origin: str = "--set") -> Sweep:
    """Read and validate a sweep file (or bundled sweep name); every run's scene is built.
    ``overrides`` (dotted keys, as ``bearingdae sweep --set``) are added to the file's
    ``[overrides]``; errors they cause name ``override_origin``."""
    p = resolve_sweep(path)
    return sweep_from_dict(_read_toml(p, "sweep file"), origin=str(p), name=p.stem,
                           folder=p.parent, extra_overrides=overrides,
                           override_origin=override_origin)


def _flatten(table: Any, where: str, origin: str) -> dict[str, Any]:
    """``{"operating": {"speed_rpm": v}}`` and ``{"operating.speed_rpm": v}`` -> dotted keys."""
    if not isinstance(table, dict):
        raise SceneError(f"sweep '{origin}': [{where}] must be a table of dotted scene keys, "
                         f"got {_show(table)}")
    out: dict[str, Any] = {}
    for k, v in table.items():
        items = ([(f"{k}.{k2}", v2) for k2, v2 in v.items()]
                 if isinstance(v, dict) and k in _SECTIONS else [(k, v)])
        for key, value in items:
            if key in out:
                raise SceneError(f"sweep '{origin}': '{where}.{key}' is given twice")
            out[key] = value
    return out


def _check_key(key: str, where: str, origin: str) -> None:
    sec, _, name = key.partition(".")
    if key == "title" and where == "overrides":
        return
    if sec not in _SECTIONS or name not in _SECTIONS[sec].model_fields:
        raise SceneError(f"sweep '{origin}': [{where}] " + _unknown_message(key, "scene key"))


def _axis_values(key: str, values: Any, origin: str) -> tuple:
    where = f"axes.'{key}'"
    if not isinstance(values, list) or not values:
        raise SceneError(f"sweep '{origin}': {where} = {_show(values)}: must be a non-empty "
                         "list of values, e.g. [2000, 6000]")
    if len(values) > MAX_AXIS_VALUES:
        raise SceneError(f"sweep '{origin}': {where} has {len(values)} values; allowed range "
                         f"[1, {MAX_AXIS_VALUES}]")
    kinds = set()
    for i, v in enumerate(values):
        if isinstance(v, bool):
            kinds.add("bool")
        elif isinstance(v, (int, float)):
            kinds.add("number")
        elif isinstance(v, str):
            kinds.add("str")
        else:
            raise SceneError(f"sweep '{origin}': {where}[{i}] = {_show(v)}: axis values must "
                             "be numbers, strings or booleans (one per run)")
    if len(kinds) > 1:
        raise SceneError(f"sweep '{origin}': {where} = {_show(values)}: mixes "
                         f"{' and '.join(sorted(kinds))} values; use one kind per axis")
    if kinds == {"number"} and any(isinstance(v, float) for v in values):
        values = [float(v) for v in values]
    if len(set(values)) != len(values):
        dup = next(v for v in values if values.count(v) > 1)
        raise SceneError(f"sweep '{origin}': {where} lists {_show(dup)} more than once; "
                         "each value must be distinct")
    return tuple(values)


def _dim_names(keys: list[str]) -> list[str]:
    leaves = [k.rpartition(".")[2] for k in keys]
    reserved = {"azimuth", "slice", "race", "end", "x", "time", "roller"}
    return [leaf if leaves.count(leaf) == 1 and leaf not in reserved else k.replace(".", "_")
            for k, leaf in zip(keys, leaves)]


def _resolve_base(base: Any, folder: Path | None, origin: str) -> Path:
    if not isinstance(base, str) or not base:
        raise SceneError(f"sweep '{origin}': 'base' = {_show(base)}: must be the name of a "
                         "bundled case (bearingdae cases) or the path of a scene TOML file")
    if folder is not None:
        for cand in (folder / base, folder / f"{base}.toml"):
            if cand.is_file():
                return cand
    try:
        return resolve_case(base)
    except SceneError as exc:
        raise SceneError(f"sweep '{origin}': 'base' = {base!r}: {exc}") from None


def _settings(raw: Any, origin: str) -> SweepSettings:
    if not isinstance(raw, dict):
        raise SceneError(f"sweep '{origin}': [sweep] must be a table, got {_show(raw)}")
    try:
        return SweepSettings.model_validate(raw)
    except ValidationError as exc:
        lines = [f"invalid sweep ({origin}):"]
        for err in exc.errors():
            loc = "sweep." + ".".join(str(p) for p in err["loc"][:1])
            f = SweepSettings.model_fields.get(str(err["loc"][0])) if err["loc"] else None
            rng = ""
            if f is not None:
                lo = next((getattr(c, "ge") for c in f.metadata if hasattr(c, "ge")), None)
                hi = next((getattr(c, "le") for c in f.metadata if hasattr(c, "le")), None)
                if lo is not None:
                    rng = f" (allowed range [{lo}, {hi}])"
            if err["type"] == "extra_forbidden":
                close = difflib.get_close_matches(str(err["loc"][0]),
                                                  list(SweepSettings.model_fields), n=1)
                hint = f" Did you mean 'sweep.{close[0]}'?" if close else ""
                lines.append(f"  - unknown key '{loc}'.{hint} Allowed: "
                             + ", ".join(f"sweep.{k}" for k in SweepSettings.model_fields))
            else:
                msg = err["msg"].removeprefix("Value error, ")
                lines.append(f"  - '{loc}' = {_show(err.get('input'))}: "
                             f"{msg[0].lower() + msg[1:]}{rng}.")
        raise SceneError("\n".join(lines)) from None


def sweep_from_dict(data: Mapping[str, Any], origin: str = "<dict>", name: str = "sweep",
                    folder: Path | None = None,
                    extra_overrides: Mapping[str, Any] | None = None,
                    override_origin: str = "--set") -> Sweep:
    """Validate a parsed sweep file; builds (and so validates) the scene of every run.
    ``extra_overrides`` are added to ``[overrides]`` (see :func:`load_sweep`); the title then
    ends in the values set."""
    unknown = [k for k in data if k not in _TOP_KEYS]
    if unknown:
        k = unknown[0]
        close = difflib.get_close_matches(str(k), _TOP_KEYS, n=1)
        hint = f" Did you mean '{close[0]}'?" if close else ""
        raise SceneError(f"sweep '{origin}': unknown key '{k}'.{hint} A sweep file has "
                         f"{', '.join(_TOP_KEYS)}.")
    if "base" not in data:
        raise SceneError(f"sweep '{origin}': 'base' is required: the bundled case name or scene "
                         "path the sweep starts from, e.g. base = \"yang20_baseline\"")
    title = data.get("title", name)
    if not isinstance(title, str):
        raise SceneError(f"sweep '{origin}': 'title' = {_show(title)}: must be a string")
    base_path = _resolve_base(data["base"], folder, origin)
    overrides = _flatten(data.get("overrides", {}), "overrides", origin)
    for key in overrides:
        _check_key(key, "overrides", origin)
    raw_axes = _flatten(data.get("axes", {}), "axes", origin)
    if extra_overrides:
        for key, value in extra_overrides.items():
            try:
                _check_key(key, "overrides", origin)
            except SceneError:
                raise SceneError(f"{override_origin}: " + _unknown_message(key, "scene key")) \
                    from None
            if key in raw_axes:
                raise SceneError(f"{override_origin}: '{key}' is an axis of sweep '{origin}' "
                                 f"(values {_show(raw_axes[key])}); set the other keys only")
        overrides = {**overrides, **extra_overrides}
        shown = ", ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}"
                          for k, v in extra_overrides.items() if k != "title")
        title = extra_overrides.get("title", f"{title} [set: {shown}]" if shown else title)
    for key in raw_axes:
        _check_key(key, "axes", origin)
        if key in overrides:
            raise SceneError(f"sweep '{origin}': '{key}' is both an axis and an override; "
                             "give it in one place")
    settings = _settings(data.get("sweep", {}), origin)
    try:
        base_scene = load_scene(base_path, overrides)
    except SceneError as exc:
        raise SceneError(f"sweep '{origin}': base '{data['base']}' with [overrides]"
                         f"{' and ' + override_origin if extra_overrides else ''}: {exc}") \
            from None
    keys = list(raw_axes)
    axes = []
    for key, dim in zip(keys, _dim_names(keys)):
        values = _axis_values(key, raw_axes[key], origin)
        for i, v in enumerate(values):  # each value alone, so the error names it
            try:
                load_scene(base_path, {**overrides, key: v})
            except SceneError as exc:
                raise SceneError(f"sweep '{origin}': axes.'{key}'[{i}] = {_show(v)}: {exc}") \
                    from None
        axes.append(Axis(key, dim, values))
    n_runs = int(np.prod([len(a.values) for a in axes])) if axes else 1
    if n_runs > MAX_RUNS:
        raise SceneError(f"sweep '{origin}': the axes give {n_runs} runs; allowed range "
                         f"[1, {MAX_RUNS}] per sweep file")
    points = []
    for index in itertools.product(*(range(len(a.values)) for a in axes)):
        over = dict(overrides)
        label = ", ".join(f"{a.dim} = {a.values[i]}" for a, i in zip(axes, index))
        over.setdefault("title", f"{title}: {label}" if label else title)
        over.update({a.key: a.values[i] for a, i in zip(axes, index)})
        try:
            scene = load_scene(base_path, over)
        except SceneError as exc:
            raise SceneError(f"sweep '{origin}': the run {label} is invalid: {exc}") from None
        points.append(RunPoint(tuple(index), scene, run_key(scene)))
    try:
        text = tomli_w.dumps(dict(data))
    except (TypeError, ValueError):  # a dict built in Python with non-TOML values
        text = json.dumps(dict(data), default=str)
    return Sweep(name=name, title=title, origin=origin, base=str(data["base"]),
                 overrides=overrides, axes=tuple(axes), settings=settings,
                 base_scene=base_scene, points=tuple(points), text=text)


def run_key(scene: Scene) -> str:
    """SHA-256 (16 hex digits) of the scene TOML without its title: the run's identity."""
    data = tomllib.loads(scene.to_toml())
    data.pop("title", None)
    return hashlib.sha256(tomli_w.dumps(data).encode("utf-8")).hexdigest()[:16]


# ---------------------------------------------------------------------------------------------
# The run store (resume cache)
# ---------------------------------------------------------------------------------------------
class RunStore:
    """``folder/<key>.nc`` (completed) and ``folder/<key>.failed.json`` (failed), atomic."""

    def __init__(self, folder: str | Path):
        self.folder = Path(folder)

    def result(self, key: str) -> Path:
        return self.folder / f"{key}.nc"

    def failure(self, key: str) -> Path:
        return self.folder / f"{key}.failed.json"

    def status(self, key: str) -> str | None:
        if self.result(key).is_file():
            return "completed"
        if self.failure(key).is_file():
            return "failed"
        return None

    def write_result(self, key: str, ds: xr.Dataset) -> Path:
        from .results import save

        path = save(ds, self.result(key))
        self.failure(key).unlink(missing_ok=True)
        return path

    def write_failure(self, key: str, info: dict) -> Path:
        from .atomic import atomic_write

        path = self.failure(key)
        with atomic_write(path) as tmp, open(tmp, "w", encoding="utf-8") as fh:
            json.dump(info, fh, indent=1)
        return path

    def read_failure(self, key: str) -> dict:
        try:
            return json.loads(self.failure(key).read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            return {"error": f"unreadable failure record: {exc}"}


def execute_run(scene_toml: str) -> tuple[str, xr.Dataset | None, dict]:
    """Worker task: simulate one scene given as TOML text.

    Returns ``(status, dataset, info)``; a failure of the run (solver, static equilibrium, any
    exception) is returned as ``("failed", None, {"error": ..., ...})``, never raised, so that it
    is recorded and the other runs go on.
    """
    for name, value in PINNED_ENV.items():  # effective if bearingdae is not imported yet
        os.environ.setdefault(name, value)
    from .api import SimulationError, simulate
    from .guards import PlausibilityWarning
    from .scene import scene_from_dict

    t0, c0 = time.perf_counter(), time.process_time()
    env = {k: os.environ.get(k, "") for k in PINNED_ENV}
    try:
        with warnings.catch_warnings():
            # recorded in the run's attributes and listed per run in the sweep Dataset
            warnings.simplefilter("ignore", PlausibilityWarning)
            ds = simulate(scene_from_dict(tomllib.loads(scene_toml), origin="sweep run"))
        ds.attrs["run_cpu_time_s"] = time.process_time() - c0  # contention-free cost measure
        return "completed", ds, {"wall_s": time.perf_counter() - t0, "env": env}
    except SimulationError as exc:
        failed_at = getattr(exc.dataset, "sizes", {}).get("time", 0)
        return "failed", None, {"error": f"SimulationError: {exc}", "wall_s":
                                time.perf_counter() - t0, "samples_before_failure": failed_at,
                                "env": env}
    except Exception as exc:  # noqa: BLE001 - any failure of one run is recorded, not raised
        return "failed", None, {"error": f"{type(exc).__name__}: {exc}",
                                "traceback": traceback.format_exc(limit=8),
                                "wall_s": time.perf_counter() - t0, "env": env}


# ---------------------------------------------------------------------------------------------
# Running
# ---------------------------------------------------------------------------------------------
class SweepIncomplete(RuntimeError):
    """The cluster lost runs (not a failure of the runs). ``.datasets``: the sweep Datasets
    as written, with those runs 'missing'."""

    def __init__(self, message: str, datasets: list):
        super().__init__(message)
        self.datasets = datasets


#: Communication timeouts of the local cluster: a heavily shared 2-core machine (load > 10)
#: was measured to stall worker heartbeats past the 30 s default and lose the cluster.
_LOCAL_TIMEOUTS = {"distributed.comm.timeouts.connect": "120s",
                   "distributed.comm.timeouts.tcp": "300s"}


class SchedulerUnreachable(RuntimeError):
    """The dask scheduler given by address did not answer within the timeout."""


#: Seconds to wait for a dask scheduler given by address (--scheduler-timeout).
SCHEDULER_TIMEOUT_S = 30.0


@contextlib.contextmanager
def _client(scheduler: str | None, workers: int, timeout_s: float = SCHEDULER_TIMEOUT_S):
    """None -> a LocalCluster of pinned single-thread processes; 'synchronous' -> no dask;
    anything else -> the address of a running dask scheduler (waiting ``timeout_s``)."""
    if scheduler == "synchronous":
        yield None
        return
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise SceneError("parallel sweeps need dask.distributed: pip install 'bearingdae[sweep]'"
                         ", or run in this process with scheduler 'synchronous'") from None
    if scheduler:
        try:
            client = Client(scheduler, timeout=timeout_s)
        except (OSError, TimeoutError, ValueError) as exc:  # no answer, refused, bad address
            raise SchedulerUnreachable(
                f"cannot reach the dask scheduler at '{scheduler}' within {timeout_s:g} s "
                f"({exc}); start it, check the address, or wait longer with "
                "--scheduler-timeout S") from None
        try:
            yield client
        finally:
            client.close()
        return
    import dask

    with warnings.catch_warnings(), dask.config.set(_LOCAL_TIMEOUTS):
        # Without a dashboard the scheduler still serves /health on 8787, or a free port
        # with a UserWarning when another cluster holds it: harmless on a shared machine.
        warnings.filterwarnings("ignore", message="Port .* is already in use")
        cluster = LocalCluster(n_workers=workers, processes=True, threads_per_worker=1,
                               env=dict(PINNED_ENV), dashboard_address=None,
                               silence_logs=logging.ERROR)
        client = Client(cluster)
        try:
            yield client
        finally:
            client.close()
            cluster.close()


def _cost(scene: Scene) -> float:
    """Rough relative cost for scheduling the longest runs first."""
    d = scene.dynamics
    return (d.warmup_cage_revolutions + d.cage_revolutions) * scene.bearing.rollers \
        * scene.numerics.slices


def _execute(pending: dict[str, Scene], store: RunStore, scheduler: str | None,
             workers: int | None, progress: bool, done_before: int, total: int,
             scheduler_timeout_s: float = SCHEDULER_TIMEOUT_S) -> dict[str, str]:
    """Run every pending scene, writing each result as it arrives. Returns the runs the
    cluster lost (key -> reason): not recorded, they run again on restart."""
    from tqdm.auto import tqdm

    lost: dict[str, str] = {}

    bar = tqdm(total=total, initial=done_before, unit="run", desc="sweep", disable=not progress)
    failed = 0
    warned = False

    def record(key: str, outcome: tuple) -> None:
        nonlocal failed, warned
        status, ds, info = outcome
        if status == "completed":
            store.write_result(key, ds)
        else:
            failed += 1
            store.write_failure(key, {"run": key, "scene_toml": pending[key].to_toml(), **info})
        if not warned and any(v != "1" for v in info.get("env", {}).values()):
            warned = True
            bar.write(f"bearingdae: warning: worker threads not pinned ({info['env']}); "
                      "set OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 in the workers")
        bar.set_postfix(failed=failed)
        bar.update(1)

    order = sorted(pending, key=lambda k: -_cost(pending[k]))
    n_workers = workers or os.cpu_count() or 1
    n_workers = max(1, min(n_workers, len(order)))
    try:
        if not order:
            return lost
        with _client(scheduler, n_workers, scheduler_timeout_s) as client:
            if client is None:
                for key in order:
                    record(key, execute_run(pending[key].to_toml()))
                return lost
            from distributed import as_completed

            futures = {client.submit(execute_run, pending[key].to_toml(), key=f"run-{key}",
                                     pure=False, priority=int(_cost(pending[key]))): key
                       for key in order}
            from distributed import KilledWorker

            try:
                for fut in as_completed(futures):
                    key = futures[fut]
                    try:
                        outcome = fut.result()
                    except KilledWorker as exc:  # the run crashed its worker, repeatedly
                        outcome = ("failed", None, {"error": f"the run killed its worker "
                                                             f"process: {exc}"})
                    except (Exception, asyncio.CancelledError) as exc:  # noqa: BLE001
                        # Cancelled, connection to the cluster lost, ...: a failure of the
                        # cluster, not of the run; it stays "missing" and runs on restart.
                        lost[key] = f"{type(exc).__name__}: {exc}"
                        continue
                    record(key, outcome)
            except BaseException:
                client.cancel(list(futures))
                raise
    finally:
        bar.close()
    return lost


def run_sweeps(sweeps: Iterable[Sweep], outputs: Iterable[str | Path],
               run_dir: str | Path | None = None, scheduler: str | None = None,
               workers: int | None = None, progress: bool = True,
               retry_failed: bool = False,
               scheduler_timeout_s: float = SCHEDULER_TIMEOUT_S) -> list[xr.Dataset]:
    """Run several sweeps on one cluster (identical runs once) and write each sweep's file.

    ``run_dir`` holds the per-run files (default: ``<first output>_runs`` beside it).
    ``scheduler``: None starts a LocalCluster of ``workers`` pinned processes; "synchronous"
    runs in this process without dask; any other string is a dask scheduler address, waited
    for ``scheduler_timeout_s`` (then :class:`SchedulerUnreachable`).
    Returns the sweep Datasets (also written to ``outputs`` with :func:`bearingdae.save`).
    """
    from .results import save

    sweeps, outputs = list(sweeps), [Path(o) for o in outputs]
    if len(sweeps) != len(outputs):
        raise ValueError(f"{len(sweeps)} sweeps but {len(outputs)} outputs")
    if run_dir is None:
        run_dir = outputs[0].with_name(outputs[0].stem + "_runs")
    store = RunStore(run_dir)
    unique: dict[str, Scene] = {}
    for sw in sweeps:
        for pt in sw.points:
            unique.setdefault(pt.key, pt.scene)
    done = {k for k in unique if store.status(k) == "completed"
            or (store.status(k) == "failed" and not retry_failed)}
    pending = {k: s for k, s in unique.items() if k not in done}
    if workers is None:
        workers = next((sw.settings.workers for sw in sweeps if sw.settings.workers), None)
    lost = _execute(pending, store, scheduler, workers, progress, len(done), len(unique),
                    scheduler_timeout_s)
    results = []
    for sw, out in zip(sweeps, outputs):
        ds = assemble(sw, store, relative_to=out.parent)
        save(ds, out)
        results.append(ds)
    if lost:
        reason = next(iter(lost.values()))
        raise SweepIncomplete(
            f"the dask cluster lost {len(lost)} of {len(pending)} runs ({reason}); they are "
            f"'missing' in the written file(s). Finished runs are kept in '{store.folder}': "
            "run the same command again to compute only the missing ones.", results)
    return results


def run_sweep(sweep: Sweep | str | Path, output: str | Path | None = None, **kwargs
              ) -> xr.Dataset:
    """Run one sweep (a :class:`Sweep` or a sweep file) -> Dataset, written to ``output``
    (default ``<sweep name>.nc``). Keyword arguments as for :func:`run_sweeps`."""
    if not isinstance(sweep, Sweep):
        sweep = load_sweep(sweep)
    output = Path(output) if output is not None else Path(f"{sweep.name}.nc")
    return run_sweeps([sweep], [output], **kwargs)[0]


# ---------------------------------------------------------------------------------------------
# Assembling the sweep Dataset
# ---------------------------------------------------------------------------------------------
#: attributes of an until_steady run (bearingdae/steady.py) stored per sweep point
STEADY_VARIABLES = {
    "steady_state_reached": ("1", "1 if the warm-up met the steady-state criterion "
                             "(numerics.until_steady), 0 if it hit the cap; NaN: not asked"),
    "warmup_cage_revolutions_used": ("1", "warm-up cage revolutions run before recording"),
    "steady_last_change": ("1", "change of the block-mean cage speed over the last warm-up "
                           "block / epicyclic speed"),
    "steady_remaining_estimate": ("1", "extrapolated remaining change of the cage speed / "
                                  "epicyclic speed (0: fluctuating, no drift)"),
}
_AXIS_UNITS = {"_rpm": ("min-1", "r/min"), "_Nm": ("N m", "N·m"), "_N": ("N", "N"),
               "_mm": ("mm", "mm"), "_um": ("um", "µm"), "_nm": ("nm", "nm"),
               "_GPa": ("GPa", "GPa"), "_kg_m3": ("kg m-3", "kg/m³"), "_Pa_s": ("Pa s", "Pa·s"),
               "_N_m": ("N m-1", "N/m"), "_s_m": ("s m-1", "s/m"), "_m_s": ("m s-1", "m/s")}


def axis_units(key: str) -> tuple[str, str]:
    """(CF units, display units) of a scene key from its unit suffix ('1' if none)."""
    for suffix, units in sorted(_AXIS_UNITS.items(), key=lambda kv: -len(kv[0])):
        if key.endswith(suffix):
            return units
    return "1", ""


def _coord(axis: Axis) -> xr.Variable:
    units, shown = axis_units(axis.key)
    sec, _, name = axis.key.partition(".")
    desc = _SECTIONS[sec].model_fields[name].description or axis.key
    return xr.Variable(axis.dim, np.asarray(axis.values), {
        "units": units, "long_name": desc, "scene_key": axis.key, "display_units": shown})


def assemble(sweep: Sweep, store: RunStore, relative_to: Path | None = None) -> xr.Dataset:
    """The sweep Dataset from the run store: summaries, status/error, one orbit per run."""
    from .analysis import SUMMARY_VARIABLES, one_orbit, summary
    from .guards import findings
    from .results import base_attrs

    shape = sweep.shape
    dims = tuple(a.dim for a in sweep.axes)
    status = np.full(shape, "missing", dtype=object)
    error = np.full(shape, "", dtype=object)
    files = np.full(shape, "", dtype=object)
    keys = np.full(shape, "", dtype=object)
    roller = np.zeros(shape, dtype=np.int64)
    wall = np.full(shape, np.nan)
    cpu = np.full(shape, np.nan)
    plausible = np.full(shape, "", dtype=object)
    summ = {n: np.full(shape, np.nan) for n in SUMMARY_VARIABLES}
    steady = {n: np.full(shape, np.nan) for n in STEADY_VARIABLES}  # until_steady runs only
    orbits: dict[tuple, xr.Dataset] = {}
    for pt in sweep.points:
        i = pt.index
        keys[i] = pt.key
        st = store.status(pt.key)
        if st == "completed":
            path = store.result(pt.key)
            files[i] = os.path.relpath(path, relative_to) if relative_to else str(path)
            with xr.open_dataset(path) as ds:
                ds = ds.load()
            status[i] = "completed"
            for name, value in summary(ds).items():
                summ[name][i] = value
            for name in STEADY_VARIABLES:
                steady[name][i] = float(ds.attrs.get(name, np.nan))
            wall[i] = float(ds.attrs.get("wall_time_s", np.nan))
            cpu[i] = float(ds.attrs.get("run_cpu_time_s", np.nan))
            plausible[i] = ", ".join(sorted({f["check"] for f in findings(ds)}))
            try:
                orbit = one_orbit(ds, sweep.settings.orbit_points, sweep.settings.orbit_roller)
                orbits[i] = orbit
                roller[i] = orbit.attrs["roller"]
            except ValueError:  # window shorter than an orbit: summaries only (orbit_roller 0)
                pass
        elif st == "failed":
            status[i] = "failed"
            error[i] = str(store.read_failure(pt.key).get("error", "unknown error"))
    coords = {a.dim: _coord(a) for a in sweep.axes}
    data = {
        # labels: empty units, as for the other char variables (race, end)
        "status": xr.Variable(dims, status.astype(str), {
            "units": "", "long_name": "run status: completed, failed or missing (not run yet)"}),
        "error": xr.Variable(dims, error.astype(str), {
            "units": "", "long_name": "error of a failed run"}),
        "run_key": xr.Variable(dims, keys.astype(str), {
            "units": "", "long_name": "SHA-256 (16 hex) of the run's scene TOML without title"}),
        "run_file": xr.Variable(dims, files.astype(str), {
            "units": "", "long_name": "NetCDF file of the run's full time series (relative to "
            "this file)"}),
        "plausibility_warnings": xr.Variable(dims, plausible.astype(str), {
            "units": "", "long_name": "plausibility checks the run tripped (bearingdae.guards; "
            "details in the run file's plausibility_warnings attribute)"}),
        "run_wall_time_s": xr.Variable(dims, wall, {"units": "s",
                                                    "long_name": "IDA wall time of the run"}),
        "run_cpu_time_s": xr.Variable(dims, cpu, {"units": "s", "long_name":
                                                  "CPU time of the worker for the whole run"}),
        "orbit_roller": xr.Variable(dims, roller, {
            "units": "1", "long_name": "roller whose orbit is stored (0: none)"}),
    }
    for name, (units, long_name) in SUMMARY_VARIABLES.items():
        data[name] = xr.Variable(dims, summ[name], {"units": units, "long_name": long_name})
    for name, (units, long_name) in STEADY_VARIABLES.items():
        if np.isfinite(steady[name]).any():
            data[name] = xr.Variable(dims, steady[name], {"units": units, "long_name": long_name})
    if orbits:
        template = next(iter(orbits.values()))
        for name, var in template.data_vars.items():
            arr = np.full(shape + var.shape, np.nan)
            for i, orbit in orbits.items():
                if name in orbit:
                    arr[i] = orbit[name].values
            attrs = dict(var.attrs)
            attrs["long_name"] = f"{attrs.get('long_name', name)}, one roller over one orbit"
            data[name] = xr.Variable(dims + var.dims, arr, attrs)
        for c in ("azimuth", "slice", "race", "end", "x"):
            if c in template.coords:
                coords[c] = template[c].variable
    ds = xr.Dataset(data, coords=coords)
    attrs = base_attrs(sweep.base_scene, "parameter sweep")
    attrs.update({
        "title": f"bearingdae sweep: {sweep.title}",
        "sweep_name": sweep.name,
        "sweep_toml": sweep.text,
        "sweep_axes": json.dumps([{"key": a.key, "dim": a.dim, "values": list(a.values)}
                                  for a in sweep.axes]),
        "figures": json.dumps(list(sweep.settings.figures)),
        "runs_total": len(sweep.points),
        "runs_completed": int((status == "completed").sum()),
        "runs_failed": int((status == "failed").sum()),
        "run_directory": (os.path.relpath(store.folder, relative_to) if relative_to
                          else str(store.folder)),
        "summary_window": "recorded window of each run (after numerics."
                          "warmup_cage_revolutions); formulas in bearingdae.analysis",
    })
    ds.attrs.update(attrs)
    return ds
