"""Statistical work-precision: what IDA's tolerance does to the statistics a run reports.

The pointwise study (the rest of this package) measures trajectory errors over a fraction of
a revolution; past ~0.3 revolution two runs at different tolerances have decorrelated (the
motion is chaotic), so a pointwise error says nothing about the time means a reference run is
used for. This study runs the same scene at each rtol of a ladder (atol scaled alongside,
:func:`~.ladders.tolerance_overrides`) over a window of many correlation times and compares
each run's statistics (mean cage speed, cage slip, skew RMS, RMS pocket force, and the mean
peak pocket force and slice pressure per roller pass from every solver step; with their
batch-means standard errors, analysis/statistics.py) with the tightest run's:

    Δ_k = x_k − x_ref,   σ_Δ = sqrt(SE_k² + SE_ref²)

Δ_k holds the tolerance's bias b_k plus the sampling noise of two decorrelated windows (σ_Δ).

**The rule for the default rtol.** The default run (the scene's own record, e.g. 3 cage
revolutions) reports each statistic with a standard error SE_def. A rung is *adequate* when,
for every statistic, its bias estimate is below that error: |Δ_k| < max(SE_def, floor), the
floor being the smallest difference the default run resolves in the quantity at all: its atol
times the unknown's scale (a statistic that is zero, e.g. the skew of a bearing without moment,
differs between runs only by integration noise below it), and its rtol times the statistic (a
statistic steadier than the default tolerance, e.g. the peak slice pressure per roller pass,
which varies by ~2e-7 of itself: a difference below rtol |x| is not resolved by the default run
itself). The chosen rtol is
the loosest (cheapest) adequate rung whose tighter rungs are all adequate as well. The study's
window is :data:`WINDOW_FACTOR` times the default record, so σ_Δ ≈ sqrt(2 / WINDOW_FACTOR)
SE_def ≈ 0.7 SE_def: a rung without bias fails the test by chance in ~15 % of the statistics
(|N(0, 0.7)| > 1), a bias of 2 SE_def is caught in ~92 %. SE_def is measured, not assumed:
the default-rtol run's first record (the same steps as the default run, the samples do not
change IDA's steps) gives it.
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
#: the statistics compared: key of analysis/statistics.run_statistics -> units
STATISTICS = {"mean_cage_speed_rad_s": "rad s-1", "cage_slip_ratio": "1",
              "skew_rms_rad": "rad", "rms_cage_force_N": "N",
              "roller_pass_peak_cage_force_N": "N",
              "roller_pass_peak_contact_pressure_Pa": "Pa"}
#: the study's record against the default record (cage revolutions)
WINDOW_FACTOR = 4


def statistical_study(scene, default_revolutions: float, rtols=STATISTICS_RTOLS,
                      default_rtol: float = 1e-6, progress=None) -> xr.Dataset:
    """Run ``scene`` at every rtol in ``rtols`` (each a full run: its warm-up, then its
    recorded window) and tabulate the statistics, their standard errors, their differences
    from the tightest run and the cost (module docstring). ``default_revolutions``: the
    default run's record [cage revolutions]; the standard errors of the first such stretch
    of the ``default_rtol`` run are the rule's yardstick. ``progress``: a callable
    ``progress(text)`` told of each run as it starts and ends, or None."""
    from ...api import simulate
    from ...analysis.statistics import run_statistics

    rtols = sorted({float(r) for r in rtols}, reverse=True)
    if len(rtols) < 2:
        raise ValueError(f"rtols = {rtols}: at least two tolerances are needed")
    if default_rtol not in rtols:
        raise ValueError(f"default_rtol = {default_rtol:g} is not one of the rtols {rtols}")
    names = list(STATISTICS)
    value = np.full((len(rtols), len(names)), np.nan)
    stderr = np.full_like(value, np.nan)
    se_def = np.full(len(names), np.nan)
    floor = np.zeros(len(names))
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
        if r == default_rtol:
            n = int(round(default_revolutions * sc.dynamics.samples_per_cage_revolution)) + 1
            first = run_statistics(ds.isel(time=slice(0, n)))
            se_def[:] = [first[k].stderr if k in first else np.nan for k in names]
            floor[:] = np.maximum(_resolution_floor(ds, names), r * np.abs(value[i]))
        s = json.loads(ds.attrs["solver_statistics"])
        wall[i] = s.get("wall_time_s", np.nan)
        steps[i], calls[i] = s.get("steps", np.nan), s.get("residual_calls", np.nan)
        status.append("ok")
        if progress:
            progress(f"rtol {r:g}: {wall[i]:.1f} s integrating, {int(steps[i])} steps")
    return _table(scene, rtols, names, value, stderr, se_def, wall, cpu, steps, calls, status,
                  default_rtol, default_revolutions, floor)


def _resolution_floor(ds, names) -> list[float]:
    """The smallest difference of each statistic the run ``ds`` resolves: its atol in the
    unknown's units (cage speed, skew angle); 0 where the statistic is no unknown."""
    scales = json.loads(ds.attrs["unknown_scales"])
    atol = float(ds.attrs["atol"])
    epi = float(ds.attrs.get("epicyclic_cage_speed_rad_s", np.nan))
    by_name = {"mean_cage_speed_rad_s": atol * scales.get("cage_speed", 0.0),
               "cage_slip_ratio": atol * scales.get("cage_speed", 0.0) / epi,
               "skew_rms_rad": atol * scales.get("skew_angle", 0.0)}
    return [by_name.get(n, 0.0) for n in names]


def _table(scene, rtols, names, value, stderr, se_def, wall, cpu, steps, calls, status,
           default_rtol, default_revolutions, floor=None) -> xr.Dataset:
    ref = len(rtols) - 1  # the tightest rung
    diff = value - value[ref]
    diff_se = np.sqrt(stderr ** 2 + stderr[ref] ** 2)
    diff[ref], diff_se[ref] = 0.0, 0.0
    floor = np.zeros(len(names)) if floor is None else np.asarray(floor, float)
    adequate = (np.all(np.abs(diff) < np.maximum(se_def, floor), axis=1)
                & np.array([s == "ok" for s in status]))
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
         "default_run_standard_error": (("statistic",), se_def, {
             "long_name": "standard error of the default run (the default rtol's first "
                          "default-length record): the rule's yardstick"}),
         "resolution_floor": (("statistic",), floor, {
             "long_name": "smallest difference the default run resolves (the larger of its "
                          "atol in the unknown's units and its rtol times the statistic)"}),
         "adequate": (("rtol",), adequate.astype(np.int8), {
             "long_name": "1 where every statistic's |difference| is below the default "
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
               "default_cage_revolutions": default_revolutions,
               "warmup_cage_revolutions": scene.dynamics.warmup_cage_revolutions,
               "rule": "chosen_rtol: the loosest rtol from which every tighter one is adequate; "
                       "adequate: for every statistic |difference| < max("
                       "default_run_standard_error, resolution_floor) (the tolerance's bias "
                       "estimate is below the statistical error of the default run)"})
    return ds


def summary_lines(ds: xr.Dataset) -> list[str]:
    """The study as text: one line per rtol and statistic, then the chosen rtol and why."""
    from ...analysis.statistics import with_error

    lines = []
    # without a standard error of the default run (a record too short for two blocks) no
    # rung can be judged: say so, rather than call every rung biased
    judged = bool(np.isfinite(ds.default_run_standard_error.values).all())
    for r in ds.rtol.values:
        row = ds.sel(rtol=r)
        label = ("reference" if r == ds.attrs["reference_rtol"] else
                 "adequate" if int(row.adequate) else
                 "biased" if judged and row.status.item() == "ok" else
                 "not judged" if row.status.item() == "ok" else str(row.status.item()))
        head = f"  rtol {r:7.0e}  {float(row.wall_time_s):8.2f} s  {label:10s}"
        parts = []
        for s in ds.statistic.values:
            d = row.sel(statistic=s)
            parts.append(f"{s} Δ {with_error(float(d.difference), float(d.difference_standard_error))}")
        lines.append(head + "  " + "; ".join(parts))
    chosen = ds.attrs["chosen_rtol"]
    if np.isfinite(chosen):
        lines.append(f"chosen rtol: {chosen:g} (default {ds.attrs['default_rtol']:g}); "
                     f"rule: {ds.attrs['rule']}")
    elif not judged:
        lines.append("chosen rtol: none; the record is too short for a standard error of the "
                     "default run, so no tolerance can be judged (raise --revolutions)")
    else:
        lines.append("chosen rtol: none adequate (record longer or check the failed runs)")
    return lines


def plot(ds: xr.Dataset, path):
    """Difference from the tightest run (± its standard error) against wall time, one panel
    per statistic, the default run's standard error shaded."""
    import matplotlib.pyplot as plt

    from ...plots.figure_common import panel_grid

    names = list(ds.statistic.values)
    fig, axes = panel_grid(len(names), 3, 4.2, 3.6)
    se_def = ds.default_run_standard_error
    for ax, s in zip(axes, names):
        d = ds.sel(statistic=s)
        ax.errorbar(d.wall_time_s, d.difference, yerr=d.difference_standard_error, fmt="o-",
                    capsize=3)
        for r, x, y in zip(ds.rtol.values, d.wall_time_s.values, d.difference.values):
            ax.annotate(f"{r:.0e}", (x, y), textcoords="offset points", xytext=(4, 4),
                        fontsize=7)
        e = float(se_def.sel(statistic=s))
        ax.axhspan(-e, e, color="0.85", label="± SE of the default run")
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set(xscale="log", xlabel="integrator wall time [s]",
               ylabel=f"Δ [{d.statistic_units.item()}]", title=str(s))
    axes[0].legend(fontsize=7)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
