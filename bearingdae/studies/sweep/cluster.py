"""Running sweeps on dask: the client (local cluster or a scheduler address), the runs, resume.

Pipeline place: studies; :func:`run_sweeps` runs the pending points on the cluster, records each
result in the run store as it arrives, then assembles and writes each sweep's Dataset.
"""

from __future__ import annotations

import asyncio
import contextlib
import math
import logging
import os
import warnings
from pathlib import Path
from typing import Iterable

import xarray as xr

from ...scene import Scene, SceneError
from .assemble import assemble
from .parse import Sweep, load_sweep
from .store import RunStore
from .worker import PINNED_ENV, execute_run


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
#: the longest wait for a scheduler that is accepted (a day: longer is a typo, and dask's
#: own time arithmetic fails on an infinite or huge one)
SCHEDULER_TIMEOUT_MAX_S = 86400.0


def check_scheduler_timeout(seconds, option: str = "scheduler_timeout_s") -> float:
    """``seconds`` as a float when it is a finite wait in (0, :data:`SCHEDULER_TIMEOUT_MAX_S`];
    ValueError with one line naming ``option`` otherwise (every study that reaches a
    scheduler checks it before any run)."""
    try:
        value = float(seconds)
    except (TypeError, ValueError):
        value = math.nan
    if not (math.isfinite(value) and 0.0 < value <= SCHEDULER_TIMEOUT_MAX_S):
        raise ValueError(f"{option} {seconds!r}: expected a finite number of seconds in "
                         f"(0, {SCHEDULER_TIMEOUT_MAX_S:g}], e.g. 30")
    return value


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


#: the run that compiles a scene's kernels in the client: its start, a few IDA steps and the
#: projection of three samples (what a run compiles, in the order it does)
_TINY = {"numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 0.002,
         "numerics.samples_per_cage_revolution": 1000, "numerics.until_steady": False}


def _variants(scenes: Iterable[Scene]) -> dict:
    """The first scene of each kernel variant among ``scenes`` (system/optional.variant: the
    effects compiled apart that it switches on, with or without a defect table), keyed by the
    variant. A scene with extensions has none here: their passes live in the user's module
    and compile in each worker (uncached)."""
    from ...system.effects import scene_marker
    from ...system.optional import variant

    firsts: dict = {}
    for scene in scenes:
        if not scene.extensions:
            firsts.setdefault(variant(scene_marker(scene)), scene)
    return firsts


def _cold(optional) -> bool:
    """Whether a run of the kernel variant ``optional`` would start by compiling (its C
    callbacks, or for the default's, any kernel :func:`~bearingdae.run.progress.kernels_cold`
    reads)."""
    from ...run.progress import kernels_cold
    from ...solvers.sundials.callbacks import is_cold

    if optional is False:
        return kernels_cold()
    return is_cold("residual", optional) or is_cold("analytic", optional)


def _compile_run(scene: Scene) -> None:
    """A run of ``scene`` cut to :data:`_TINY`, whose only product is the kernels it leaves in
    numba's cache: the Jacobian and the projection in a second process whatever the load (the
    workers are about to take every CPU anyway), the rest here."""
    import tomllib

    from ...api import simulate
    from ...run.integrate import compile_aside
    from ...scene import scene_from_dict
    from ...solvers.ida import IDA

    tiny = scene_from_dict(tomllib.loads(scene.to_toml()), dict(_TINY), origin="sweep run")
    solver = IDA()
    compile_aside(solver, tiny, busy_ok=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        simulate(tiny, solver=solver, progress=False)


def _compile_before_workers(scheduler: str | None, n_workers: int,
                            scenes: Iterable[Scene] = ()) -> bool:
    """First sweep after installation (or after a source change): compile each kernel variant
    the pending ``scenes`` need once here, before a LocalCluster's worker processes start,
    instead of in every worker at once (each would spend 15-25 s of CPU on the same
    compilation, the projection of the samples and the per-step hook included). Only the
    variants the scenes use: a sweep of a switched scene does not compile the default's.
    Not for a remote scheduler (its workers have their own cache) nor in this process
    ("synchronous": the first run compiles them). True when it compiled something."""
    if scheduler is not None or n_workers < 2:
        return False
    cold = [scene for optional, scene in _variants(scenes).items() if _cold(optional)]
    if not cold:
        return False
    import sys

    print("compiling kernels once for the workers (first run only); later runs load them "
          "from numba's cache", file=sys.stderr, flush=True)
    compiled = False
    for scene in cold:
        try:
            _compile_run(scene)
            compiled = True
        except Exception:  # noqa: BLE001 - only an optimisation: the workers compile what they need
            pass
    return compiled


def _run_name(scene: Scene) -> str:
    """A sweep run as a warning names it: its title, which ends in the values the sweep set
    ("run 'speeds: speed_rpm = 4000'")."""
    return f"run '{scene.title}'"


def _execute(pending: dict[str, Scene], store: RunStore, scheduler: str | None,
             workers: int | None, progress: bool, done_before: int, total: int,
             scheduler_timeout_s: float = SCHEDULER_TIMEOUT_S) -> dict[str, str]:
    """Run every pending scene, writing each result as it arrives. Returns the runs the
    cluster lost (key -> reason): not recorded, they run again on restart."""
    import sys

    from tqdm.auto import tqdm

    from ...run.progress import is_terminal
    from ...util.warning_lines import PREFIX

    lost: dict[str, str] = {}
    # A bar on a terminal; elsewhere (a log, a pipe) one line per run instead of redraws.
    lines = progress and not is_terminal(sys.stderr)
    bar = tqdm(total=total, initial=done_before, unit="run", desc="sweep",
               disable=not progress or lines)
    failed = 0
    finished = done_before
    warned = False

    def record(key: str, outcome: tuple) -> None:
        nonlocal failed, warned, finished
        status, ds, info = outcome
        if status == "completed":
            store.write_result(key, ds)
        else:
            failed += 1
            store.write_failure(key, {"run": key, "scene_toml": pending[key].to_toml(), **info})
        for line in info.get("warnings", ()):  # the run's own, one line each, naming it
            bar.write(line.replace(PREFIX, f"{PREFIX}{_run_name(pending[key])}: ", 1),
                      file=sys.stderr)
        if not warned and any(v != "1" for v in info.get("env", {}).values()):
            warned = True
            bar.write(f"bearingdae: warning: worker threads not pinned ({info['env']}); "
                      "set OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 in the workers")
        bar.set_postfix(failed=failed)
        bar.update(1)
        finished += 1
        if lines:
            print(f"sweep: {finished}/{total} runs done, {failed} failed", file=sys.stderr,
                  flush=True)

    order = sorted(pending, key=lambda k: -_cost(pending[k]))
    n_workers = workers or os.cpu_count() or 1
    n_workers = max(1, min(n_workers, len(order)))
    try:
        if not order:
            return lost
        _compile_before_workers(scheduler, n_workers, (pending[k] for k in order))
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
    from ...results import save

    scheduler_timeout_s = check_scheduler_timeout(scheduler_timeout_s)
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
        if not isinstance(sweep, (str, os.PathLike)):
            raise TypeError(f"run_sweep: 'sweep' must be a Sweep or a sweep file's path or "
                            f"bundled name (str or pathlib.Path), not {type(sweep).__name__}")
        sweep = load_sweep(sweep)
    if output is not None and not isinstance(output, (str, os.PathLike)):
        raise TypeError(f"run_sweep: 'output' must be a path (str or pathlib.Path) or None, "
                        f"not {type(output).__name__}")
    output = Path(output) if output is not None else Path(f"{sweep.name}.nc")
    return run_sweeps([sweep], [output], **kwargs)[0]
