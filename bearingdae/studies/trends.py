"""The paper's trend claims with error bars: long-window sweeps -> trends table and verdicts.

Pipeline place: studies (runs the paper's one-axis sweeps through :mod:`.sweep`, reads each
run file and hands it to :mod:`bearingdae.analysis.trends`). ``bearingdae paper --trends``
calls :func:`.trends_report.run_paper_trends`.

**Windows.** The paper sweeps of ``cases/paper/`` record 1.25 cage revolutions, one orbit per
roller: enough for the figures, not for an error bar. The trend runs record
:data:`TREND_WINDOW`: a warm-up of 2 cage revolutions, then 32 revolutions cut into 64 blocks of
half a revolution (:data:`bearingdae.analysis.trends.BLOCK_CAGE_REVOLUTIONS`), sampled 180
times per revolution, keeping only the variables the readings use, in float32. ``--set``
overrides apply on top (``--set numerics.warmup_cage_revolutions=4`` is the repeat from another
start state). The runs are ordinary sweep runs (``OUT/runs/<hash>.nc``): an interrupted
generation resumes, and a second call only reads them.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import xarray as xr

#: the one-axis sweeps whose claims are tested (cases/paper/), in the paper's order
TREND_SWEEPS = ("yang20_speed_sweep", "yang20_moment_sweep", "yang20_radial_load_sweep")

#: output variables the readings of analysis/trends.py use (the others are not written)
TREND_VARIABLES = ["cage_speed", "roller_azimuth", "orbit_speed", "skew_angle", "contact_force",
                   "slip_velocity", "traction_force", "cage_force", "cage_force_peak",
                   "skew_angle_peak", "slip_velocity_peak"]

#: scene overrides of every trend run (before the user's --set): see the module docstring
TREND_WINDOW = {
    "numerics.warmup_cage_revolutions": 2.0,
    "numerics.cage_revolutions": 32.0,
    "numerics.samples_per_cage_revolution": 180,
    "output.variables": TREND_VARIABLES,
    "output.precision": "float32",
}


def trend_sweeps(overrides: dict | None = None, override_origin: str = "--set") -> list:
    """The sweeps of :data:`TREND_SWEEPS` with :data:`TREND_WINDOW`, then ``overrides``."""
    from .sweep import load_sweep

    extra = {**TREND_WINDOW, **(overrides or {})}
    return [load_sweep(f"paper/{name}", extra, override_origin) for name in TREND_SWEEPS]


def run_trend_sweeps(out_dir: str | Path, overrides: dict | None = None,
                     scheduler: str | None = "synchronous", workers: int | None = 1,
                     progress: bool = True, retry_failed: bool = False,
                     override_origin: str = "--set",
                     scheduler_timeout_s: float | None = None) -> dict[str, xr.Dataset]:
    """Run (or resume, or only read) the trend sweeps into ``out_dir`` (``<sweep>.nc``,
    ``runs/``); returns the sweep Datasets by name, with the time spent in
    ``trend_sweeps_wall_time_s``; ``scheduler_timeout_s``: the wait for a scheduler given
    by address (None: the sweeps' default)."""
    from .sweep import run_sweeps

    t0 = time.perf_counter()
    out = Path(out_dir)
    sweeps = trend_sweeps(overrides, override_origin)
    results = run_sweeps(sweeps, [out / f"{sw.name}.nc" for sw in sweeps], run_dir=out / "runs",
                         scheduler=scheduler, workers=workers, progress=progress,
                         retry_failed=retry_failed,
                         **({} if scheduler_timeout_s is None
                            else {"scheduler_timeout_s": scheduler_timeout_s}))
    wall = time.perf_counter() - t0
    for ds in results:
        ds.attrs["trend_sweeps_wall_time_s"] = wall
    return {sw.name: ds for sw, ds in zip(sweeps, results)}


# ---------------------------------------------------------------------------------------------
# The claims and their verdicts
# ---------------------------------------------------------------------------------------------
#: claim -> (sweep, quantity of analysis/trends.READINGS, claimed direction (+1 rises, -1
#: falls), the paper's words). Every claim of the summary table of docs/validation.md on the
#: three one-axis sweeps; the slice slip and traction differences are separate claims.
CLAIMS = {
    "speed: sliding speed rises": ("yang20_speed_sweep", "sliding_speed", +1,
                                   "conclusion (1), Fig 20"),
    "speed: skew rises": ("yang20_speed_sweep", "skew", +1, "conclusion (1), Fig 18"),
    "speed: pocket force rises": ("yang20_speed_sweep", "pocket_force", +1,
                                  "conclusion (1), Fig 19"),
    "speed: slice slip difference rises": ("yang20_speed_sweep", "slice_slip_difference", +1,
                                           "conclusion (1), Fig 20"),
    "speed: slice traction difference rises": ("yang20_speed_sweep",
                                               "slice_traction_difference", +1,
                                               "conclusion (1)"),
    "load: sliding speed falls": ("yang20_radial_load_sweep", "sliding_speed", -1,
                                  "conclusion (2)"),
    "load: skew falls": ("yang20_radial_load_sweep", "skew", -1, "conclusion (2)"),
    "load: pocket force falls": ("yang20_radial_load_sweep", "pocket_force", -1,
                                 "conclusion (2)"),
    "load: slice slip difference falls": ("yang20_radial_load_sweep", "slice_slip_difference",
                                          -1, "conclusion (2)"),
    "load: slice traction difference falls": ("yang20_radial_load_sweep",
                                              "slice_traction_difference", -1,
                                              "conclusion (2)"),
    "moment: roller speeds rise (cage slip falls)": ("yang20_moment_sweep", "cage_slip", -1,
                                                     "Fig 21"),
    "moment: sliding speed falls": ("yang20_moment_sweep", "sliding_speed", -1,
                                    "conclusion (3), Fig 24"),
    "moment: skew rises": ("yang20_moment_sweep", "skew", +1, "conclusion (3), Fig 22"),
    "moment: slice slip difference rises": ("yang20_moment_sweep", "slice_slip_difference", +1,
                                            "conclusion (3), Fig 24"),
    "moment: slice traction difference rises": ("yang20_moment_sweep",
                                                "slice_traction_difference", +1,
                                                "conclusion (3)"),
    "moment: pocket force rises (Fig 23 text)": ("yang20_moment_sweep", "pocket_force", +1,
                                                 "Fig 23 text"),
    "moment: pocket force falls (conclusion 3)": ("yang20_moment_sweep", "pocket_force", -1,
                                                  "conclusion (3)"),
}

#: significance of a change, in standard errors of the difference
SIGNIFICANCE_SE = 2.0


def verdict(values, stderr, direction: int) -> tuple[str, float, float]:
    """(verdict, z of the first-to-last change along the claim, most negative z along the claim
    of any pair i < j) for values along the sweep axis with standard errors (independent runs).

    ``holds``: no pair of points moves against the claim by more than SIGNIFICANCE_SE standard
    errors of their difference (monotone within 2 SE) and the first-to-last change goes with
    the claim by more than that; ``contradicted``: some pair moves significantly against the
    claim; ``not resolved``: neither.
    """
    v, s = np.asarray(values, float), np.asarray(stderr, float)
    with np.errstate(divide="ignore", invalid="ignore"):  # no error bar: nothing significant
        z_pairs = [direction * (v[j] - v[i]) / np.hypot(s[i], s[j])
                   for i in range(v.size) for j in range(i + 1, v.size)]
        z_first_last = direction * (v[-1] - v[0]) / np.hypot(s[0], s[-1])
    worst = float(np.nanmin(z_pairs)) if np.isfinite(z_pairs).any() else np.nan
    if worst < -SIGNIFICANCE_SE:
        return "contradicted", float(z_first_last), worst
    if z_first_last > SIGNIFICANCE_SE:
        return "holds", float(z_first_last), worst
    return "not resolved", float(z_first_last), worst


def against_of_range(values, direction: int) -> float:
    """The largest change against the claim between two points i < j, as a fraction of the
    range max − min of the values (0: monotone in the claimed direction): how large a
    contradiction is, beside how significant."""
    v = np.asarray(values, float)
    span = np.ptp(v)
    against = max((-direction * (v[j] - v[i]) for i in range(v.size)
                   for j in range(i + 1, v.size)), default=0.0)
    return float(max(against, 0.0) / span) if span > 0 else 0.0


#: columns of trends.csv (a contract) and of the verdicts table
TABLE_COLUMNS = ["claim", "reading", "sweep_variable", "sweep_value", "value", "stderr",
                 "n_blocks", "units"]
#: the blocking standard errors of each row at 1, 2, 4, 8 half-revolution blocks (the plateau
#: check; ``table.attrs["level_stderr"]``, written to trends.nc)
LEVEL_COLUMNS = ["stderr_0.5rev", "stderr_1rev", "stderr_2rev", "stderr_4rev"]
VERDICT_COLUMNS = ["claim", "reading", "source", "direction", "verdict", "z_first_last",
                   "z_most_against", "against_of_range", "n_points", "units"]


def _run_statistics(path: Path, cache: dict) -> dict:
    from ..analysis.trends import trend_statistics

    key = str(path.resolve())
    if key not in cache:
        with xr.open_dataset(path) as ds:
            cache[key] = trend_statistics(ds.load())
    return cache[key]


def trend_table(sweeps: dict[str, xr.Dataset], folder: str | Path):
    """(table, verdicts) as pandas DataFrames from the sweep Datasets ``sweeps`` (by name) whose
    run files lie relative to ``folder``: one table row per claim x reading x sweep point
    (TABLE_COLUMNS), one verdict per claim x reading (VERDICT_COLUMNS)."""
    import pandas as pd

    from ..analysis.trends import READINGS

    cache: dict = {}
    rows, verdicts, levels = [], [], []
    for claim, (sweep, quantity, direction, source) in CLAIMS.items():
        ds = sweeps[sweep]
        dim = ds.status.dims[0]
        units, readings = READINGS[quantity]
        for reading in readings:
            values, errors = [], []
            for i in range(ds.sizes[dim]):
                run = ds.isel({dim: i})
                if str(run.status.values) != "completed":
                    raise ValueError(f"{sweep}: the run at {dim} = {run[dim].item():g} is "
                                     f"{run.status.item()}: the trends need every run")
                est = _run_statistics(Path(folder) / str(run.run_file.values),
                                      cache)[(quantity, reading)]
                rows.append([claim, reading, dim, float(run[dim].values), est.mean, est.stderr,
                             est.n_blocks, units])
                se = list(est.level_stderr[:len(LEVEL_COLUMNS)])
                levels.append(se + [np.nan] * (len(LEVEL_COLUMNS) - len(se)))
                values.append(est.mean)
                errors.append(est.stderr)
            word, z, worst = verdict(values, errors, direction)
            verdicts.append([claim, reading, source, direction, word, z, worst,
                             against_of_range(values, direction), len(values), units])
    table = pd.DataFrame(rows, columns=TABLE_COLUMNS)
    table.attrs["level_stderr"] = pd.DataFrame(levels, columns=LEVEL_COLUMNS)
    return table, pd.DataFrame(verdicts, columns=VERDICT_COLUMNS)
