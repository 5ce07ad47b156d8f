"""Parameter sweeps: a base scene varied along dotted-key axes, run in parallel.

Pipeline place: scene files -> **sweep** (many scenes) -> :func:`~bearingdae.api.simulate` per
point on dask.distributed workers -> one NetCDF file per run (kept as it completes) -> one sweep
Dataset with the axes as dimensions, holding per-run steady-state summaries
(:mod:`bearingdae.analysis.summary`) and one roller's orbit per run for the figures.

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

**Parallelism.** Processes, one thread each, BLAS/OpenMP pinned to one thread (measured:
unpinned workers were 6x slower and forked ones hung). Workers return the
Dataset to the client, which writes it, so ``--scheduler`` may point at a cluster without a
shared file system.

The package is split by job: ``parse`` (sweep files), ``store`` (run store, run key),
``worker`` (the task of one run), ``cluster`` (dask client, running, resume), ``assemble``
(the sweep Dataset). Every name is re-exported here; ``bearingdae.studies.sweep`` re-exports them too.
"""

from __future__ import annotations

from .worker import (  # noqa: F401
    PINNED_ENV,
    execute_run,
)
from .store import (  # noqa: F401
    run_key,
    RunStore,
)
from .parse import (  # noqa: F401
    PAPER_FIGURES,
    _TOP_KEYS,
    MAX_RUNS,
    MAX_AXIS_VALUES,
    SweepSettings,
    Axis,
    RunPoint,
    Sweep,
    resolve_sweep,
    is_sweep_file,
    _read_toml,
    load_sweep,
    _flatten,
    _check_key,
    _axis_values,
    _dim_names,
    _resolve_base,
    _settings,
    sweep_from_dict,
)
from .assemble import (  # noqa: F401
    STEADY_VARIABLES,
    _AXIS_UNITS,
    axis_units,
    _coord,
    assemble,
)
from .cluster import (  # noqa: F401
    SweepIncomplete,
    _LOCAL_TIMEOUTS,
    SchedulerUnreachable,
    SCHEDULER_TIMEOUT_S,
    _client,
    _cost,
    _execute,
    run_sweeps,
    run_sweep,
)
