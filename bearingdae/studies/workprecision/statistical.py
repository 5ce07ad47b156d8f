"""Statistical work-precision: what IDA's tolerance does to the statistics a run reports.

The pointwise study (the rest of this package) measures trajectory errors over a fraction of
a revolution; past ~0.3 revolution two runs at different tolerances have decorrelated (the
motion is chaotic), so a pointwise error says nothing about the time means a reference run is
used for. This study runs the same scene at each rtol of a ladder (atol scaled alongside,
:func:`~.ladders.tolerance_overrides`) over a window of many correlation times and compares
each run's statistics (mean cage speed, cage slip, skew RMS, RMS pocket force; with their
batch-means standard errors, results/statistics.py) with the tightest run's:

    Δ_k = x_k − x_ref,   σ_Δ = sqrt(SE_k² + SE_ref²)

Δ_k holds the tolerance's bias b_k plus the sampling noise of two decorrelated windows (σ_Δ):
a bias is resolved only where |Δ_k| exceeds ~2 σ_Δ.

**The rule for the default rtol.** A rung is *adequate* when, for every statistic, the bias it
may carry is below the default run's own standard error SE_def at 95 % confidence:
|Δ_k| − 2 σ_Δ < SE_def. The chosen rtol is the loosest (cheapest) adequate rung whose tighter
rungs are all adequate as well. The window therefore limits what the rule can see: biases
smaller than about 2 σ_Δ pass unseen, and the report says how large that is.
"""

from __future__ import annotations

import json
import math
import time

import numpy as np
import xarray as xr

from .ladders import tolerance_overrides
from .runs import derive

#: the rtol ladder of the statistical study (loosest first)
STATISTICS_RTOLS = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
#: the statistics compared: key of results/statistics.run_statistics -> units
STATISTICS = {"mean_cage_speed_rad_s": "rad s-1", "cage_slip_ratio": "1",
              "skew_rms_rad": "rad", "rms_cage_force_N": "N"}
#: confidence factor of the adequacy test (two standard errors: ~95 %)
CONFIDENCE_SIGMAS = 2.0


def statistical_study(scene, rtols=STATISTICS_RTOLS, default_rtol: float = 1e-6,
                      progress=None) -> xr.Dataset:
    """Run ``scene`` at every rtol in ``rtols`` (each a full run: its warm-up, then its
    recorded window) and tabulate the statistics, their standard errors, their differences
    from the tightest run and the cost (module docstring). ``progress``: a callable
    ``progress(text)`` told of each run as it starts and ends, or None."""
    from ...api import simulate
    from ...results.statistics import run_statistics

    rtols = sorted({float(r) for r in rtols}, reverse=True)
    if len(rtols) < 2:
        raise ValueError(f"rtols = {rtols}: at least two tolerances are needed")
    if default_rtol not in rtols:
        raise ValueError(f"default_rtol = {default_rtol:g} is not one of the rtols {rtols}")
    names = list(STATISTICS)
    value = np.full((len(rtols), len(names)), np.nan)
    stderr = np.full_like(value, np.nan)
    wall, cpu, steps, calls = (np.full(len(rtols), np.nan) for _ in range(4))
    status = []
    for i, r in enumerate(rtols):
        if progress:
            progress(f"rtol {r:g}: running")
        sc = derive(scene, tolerance_overrides(r))
        c0 = time.process_time()
        try:
            ds = simulate(sc, progress=False)
        except Exception as exc:  # noqa: BLE001 - a failed rung is a row, not a crash
            status.append(f"failed: {type(exc).__name__}: {exc}")
            continue
        cpu[i] = time.process_time() - c0
        st = run_statistics(ds)
        for j, key in enumerate(names):
            if key in st:
                value[i, j], stderr[i, j] = st[key].mean, st[key].stderr
        s = json.loads(ds.attrs["solver_statistics"])
        wall[i] = s.get("wall_time_s", np.nan)
        steps[i], calls[i] = s.get("steps", np.nan), s.get("residual_calls", np.nan)
        status.append("ok")
        if progress:
            progress(f"rtol {r:g}: {wall[i]:.1f} s integrating, {int(steps[i])} steps")
    return _table(scene, rtols, names, value, stderr, wall, cpu, steps, calls, status,
                  default_rtol)


def _table(scene, rtols, names, value, stderr, wall, cpu, steps, calls, status,
           default_rtol) -> xr.Dataset:
    ref = len(rtols) - 1  # the tightest rung
    diff = value - value[ref]
    diff_se = np.sqrt(stderr ** 2 + stderr[ref] ** 2)
    diff[ref], diff_se[ref] = 0.0, 0.0
    se_def = stderr[rtols.index(default_rtol)]
    bound = np.abs(diff) - CONFIDENCE_SIGMAS * diff_se  # bias resolved beyond this, 95 %
    adequate = np.all(bound < se_def, axis=1) & np.array([s == "ok" for s in status])
    chosen = None
    for i in range(len(rtols)):  # loosest rung from which every tighter one is adequate
        if adequate[i:].all():
            chosen = rtols[i]
            break
    dims = ("rtol", "statistic")
    ds = xr.Dataset(
        {"value": (dims, value, {"long_name": "statistic of the run (units: statistic_units)"}),
         "standard_error": (dims, stderr, {"long_name": "batch-means standard error of value"}),
         "difference": (dims, diff, {"long_name": "value minus the tightest run's value"}),
         "difference_standard_error": (dims, diff_se, {
             "long_name": "standard error of difference, sqrt(SE² + SE_ref²)"}),
         "resolved_bias": (dims, bound, {
             "long_name": f"|difference| - {CONFIDENCE_SIGMAS:g} x its standard error: the "
                          "smallest tolerance bias the data show at 95 % (<= 0: none)"}),
         "adequate": (("rtol",), adequate.astype(np.int8), {
             "long_name": "1 where every statistic's resolved bias is below the default "
                          "run's standard error", "flag_values": "0 1"}),
         "wall_time_s": (("rtol",), wall, {"units": "s", "long_name": "integrator wall time"}),
         "cpu_time_s": (("rtol",), cpu, {"units": "s", "long_name": "CPU time of the run"}),
         "steps": (("rtol",), steps, {"long_name": "IDA steps"}),
         "residual_calls": (("rtol",), calls, {"long_name": "residual evaluations"}),
         "status": (("rtol",), np.array(status, dtype=object), {"long_name": "run outcome"}),
         "statistic_units": (("statistic",), np.array([STATISTICS[n] for n in names],
                                                      dtype=object),
                             {"long_name": "units of value for each statistic"})},
        coords={"rtol": ("rtol", np.array(rtols), {"long_name": "IDA relative tolerance "
                                                     "(atol = 1e-2 rtol, at most 1e-4)"}),
                "statistic": ("statistic", np.array(names, dtype=object),
                              {"long_name": "statistic"})},
        attrs={"title": f"{scene.title}: statistical work-precision",
               "reference_rtol": rtols[ref], "default_rtol": default_rtol,
               "chosen_rtol": chosen if chosen is not None else math.nan,
               "cage_revolutions": scene.dynamics.cage_revolutions,
               "warmup_cage_revolutions": scene.dynamics.warmup_cage_revolutions,
               "rule": "chosen_rtol: the loosest rtol from which every tighter one is adequate; "
                       "adequate: for every statistic |difference| - "
                       f"{CONFIDENCE_SIGMAS:g} x difference_standard_error < the default run's "
                       "standard_error (the tolerance's bias is below the default run's "
                       "statistical error at 95 %)"})
    return ds


def summary_lines(ds: xr.Dataset) -> list[str]:
    """The study as text: one line per rtol and statistic, then the chosen rtol and why."""
    from ...results.statistics import with_error

    lines = []
    for r in ds.rtol.values:
        row = ds.sel(rtol=r)
        head = (f"  rtol {r:7.0e}  {float(row.wall_time_s):8.2f} s  "
                f"{'adequate' if int(row.adequate) else 'biased  '}")
        parts = []
        for s in ds.statistic.values:
            d = row.sel(statistic=s)
            parts.append(f"{s} Δ {with_error(float(d.difference), float(d.difference_standard_error))}")
        lines.append(head + "  " + "; ".join(parts))
    chosen = ds.attrs["chosen_rtol"]
    lines.append(f"chosen rtol: {chosen:g} (default {ds.attrs['default_rtol']:g}); "
                 f"rule: {ds.attrs['rule']}" if np.isfinite(chosen) else
                 "chosen rtol: none adequate (record longer or check the failed runs)")
    return lines


def plot(ds: xr.Dataset, path):
    """Difference from the tightest run (± 2 standard errors) against wall time, one panel per
    statistic, the default run's standard error shaded."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    names = list(ds.statistic.values)
    fig, axes = plt.subplots(1, len(names), figsize=(4.2 * len(names), 3.6),
                             layout="constrained")
    se_def = ds.standard_error.sel(rtol=ds.attrs["default_rtol"])
    for ax, s in zip(np.atleast_1d(axes), names):
        d = ds.sel(statistic=s)
        ax.errorbar(d.wall_time_s, d.difference,
                    yerr=CONFIDENCE_SIGMAS * d.difference_standard_error, fmt="o-", capsize=3)
        for r, x, y in zip(ds.rtol.values, d.wall_time_s.values, d.difference.values):
            ax.annotate(f"{r:.0e}", (x, y), textcoords="offset points", xytext=(4, 4),
                        fontsize=7)
        e = float(se_def.sel(statistic=s))
        ax.axhspan(-e, e, color="0.85", label="± SE of the default run")
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set(xscale="log", xlabel="integrator wall time [s]",
               ylabel=f"Δ [{d.statistic_units.item()}]", title=str(s))
    np.atleast_1d(axes)[0].legend(fontsize=7)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
