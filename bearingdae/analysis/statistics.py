"""Error bars for the statistics of a chaotic run: batch means (blocking) on correlated samples.

Stage: analysis (reads a Dataset). The roller and cage motions are chaotic (two runs that
differ at round-off level decorrelate after ~30 ms), so a time mean over the recorded window is
a statistical estimate whose error is set by the window's length in correlation times, not by
the solver's tolerance. Successive samples are correlated, so the naive σ/√n underestimates it.

**Estimator** (Flyvbjerg & Petersen, J. Chem. Phys. 91, 461 (1989), "blocking"): the series
x_1..x_n is averaged in pairs again and again; at level k it holds n_k = n / 2^k block means of
B = 2^k samples, and s_k / √n_k (s_k their sample standard deviation) estimates the standard
error of the mean. It grows with k while the blocks are shorter than the correlation time and
levels off once they are longer. The level used is the first whose block length satisfies
B³ > 2 n (s_k √n_0 / (s_0 √n_k))⁴ (Lee, Kent & Needs, Phys. Rev. E 83, 066706 (2011), Eq. 14;
(s_k √n_0 / (s_0 √n_k))² estimates 2τ, τ the integrated autocorrelation time in samples): blocks
long against τ, yet as many as possible. ``batches`` says how many blocks that level has;
``correlated`` is True when no level with at least ``MIN_BATCHES`` blocks satisfies the rule
(the window spans too few correlation times for a reliable error bar: record longer; the
estimate of the last such level is then given, a lower bound).

Functions of a mean are propagated linearly: the cage slip 1 − Ω̄/Ω_e has the standard error of
Ω̄ over Ω_e; an RMS sqrt(mean x²) has SE(mean x²) / (2 RMS).

**Peaks.** The largest value over a window (``cage_force_max``) grows with the window's length
and has no standard error of its own. What converges, and gets an error bar, is the **mean
peak per roller pass**: the record is cut into blocks of one roller-pass period
2π / (Z Ω_e) (the time in which the cage advances by one pocket, after which the bearing's
configuration repeats with the rollers renumbered), the largest value of each block is taken
from the peak trace (``<quantity>_peak``: every solver step, results/extremes.py), and the
block maxima, themselves a correlated series, get their mean and blocking error as above. Only
whole blocks count. Each sample carries the peak of the interval ending at it, so a block
takes the intervals whose samples fall into it: its edges move by at most one sample interval
with the sampling density (none when a period holds a whole number of samples).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from .result_variables import value as result_value

#: fewest blocks a level may have to count (below it s_k is too uncertain: its relative error is
#: ~1/sqrt(2 (n_k - 1)), 24 % at 10 blocks)
MIN_BATCHES = 10


@dataclass(frozen=True)
class MeanEstimate:
    """A time mean and its standard error (same units); ``batches``: blocks of the level used."""

    mean: float
    stderr: float
    batches: int
    correlated: bool


def batch_mean(x) -> MeanEstimate:
    """Mean of a correlated series ``x`` (1-D, equally spaced samples) with its blocking
    standard error (module docstring). NaN error with fewer than ``MIN_BATCHES`` samples."""
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    n = x.size
    if n == 0:
        return MeanEstimate(np.nan, np.nan, 0, False)
    mean = float(x.mean())
    if n < MIN_BATCHES:
        return MeanEstimate(mean, np.nan, n, False)
    levels = blocking_levels(x)  # (standard error, blocks, block length)
    se0 = levels[0][0]
    if not se0 > 0:  # a constant series
        return MeanEstimate(mean, 0.0, n, False)
    for se, batches, length in levels:
        if length**3 > 2.0 * n * (se / se0) ** 4:
            return MeanEstimate(mean, se, batches, False)
    se, batches, _ = levels[-1]
    growing = True
    return MeanEstimate(mean, se, batches, bool(growing))


def blocking_levels(x, min_blocks: int = MIN_BATCHES) -> list[tuple[float, int, int]]:
    """The blocking levels of a series ``x`` (finite, equally spaced): (standard error of the
    mean, blocks, block length in samples) at block lengths 1, 2, 4, ... samples, while a level
    has at least ``min_blocks`` blocks (module docstring; a trailing odd block is dropped)."""
    x = np.asarray(x, dtype=float)
    levels = []
    b, length = x.copy(), 1
    while b.size >= max(min_blocks, 2):
        levels.append((float(b.std(ddof=1) / np.sqrt(b.size)), b.size, length))
        m = b.size // 2
        b, length = 0.5 * (b[:2 * m:2] + b[1:2 * m:2]), 2 * length
    return levels


def _per_time(da: xr.DataArray, reduce) -> np.ndarray:
    """A per-sample series: ``reduce`` over every dimension but time."""
    other = [d for d in da.dims if d != "time"]
    return np.asarray(reduce(da, other).values, dtype=float)


def _source_total(da: xr.DataArray) -> np.ndarray:
    """The per-sample total over every dimension but time, added in coordinate order one term
    at a time: a source that is exactly 0 (mixed lubrication's asperities under a thick film)
    leaves the total the same to the last bit, which a vectorised or pairwise sum need not."""
    other = [d for d in da.dims if d != "time"]
    terms = np.asarray(da.transpose("time", *other).values, dtype=float)
    terms = terms.reshape(terms.shape[0], -1)
    total = np.zeros(terms.shape[0])
    for k in range(terms.shape[1]):
        total = total + terms[:, k]
    return total


def run_statistics(ds: xr.Dataset) -> dict[str, MeanEstimate]:
    """The mean statistics of a dynamic run with their error bars: mean cage speed [rad/s], cage
    slip ratio [1], skew RMS over rollers [rad] and RMS pocket force [N], each from the per-sample
    series of the recorded window, and the mean peaks per roller pass (:func:`peak_statistics`).
    Only what the Dataset holds is returned."""
    if ds.sizes.get("time", 0) == 0:
        return {}
    epicyclic = float(result_value(ds, "epicyclic_cage_speed_rad_s"))
    out = series_statistics(per_sample_series(ds), epicyclic)
    out.update(peak_statistics(ds, epicyclic))
    return out


#: the mean peaks per roller pass: statistic -> the peak trace it is made of
PEAK_STATISTICS = {"roller_pass_peak_cage_force_N": "cage_force_peak",
                   "roller_pass_peak_contact_pressure_Pa": "contact_pressure_peak",
                   "roller_pass_peak_skew_angle_rad": "skew_angle_peak",
                   "roller_pass_peak_slip_velocity_m_s": "slip_velocity_peak"}


def roller_pass_blocks(t, rollers: int, epicyclic: float) -> np.ndarray:
    """Block number of each sample time ``t``: whole roller-pass periods 2π / (Z Ω_e) from the
    first sample on. A sample carries the peak of the interval that ends at it, so it belongs
    to the block its interval lies in (a sample on a block's end, to the block that ends
    there); -1 for the first sample (its interval lies before the window) and for the samples
    of a last, incomplete block (module docstring)."""
    t = np.asarray(t, dtype=float)
    if t.size < 2 or not (rollers > 0 and epicyclic > 0):
        return np.full(t.size, -1)
    period = 2.0 * np.pi / (rollers * epicyclic)
    x = (t - t[0]) / period
    b = np.ceil(x * (1 - 1e-12)).astype(int) - 1
    b[b >= int(np.floor(x[-1] * (1 + 1e-12)))] = -1
    return b


def block_maxima(values, blocks) -> np.ndarray:
    """Largest value of each block (``blocks`` from :func:`roller_pass_blocks`); NaN for a
    block without a finite value."""
    v = np.asarray(values, dtype=float)
    n = int(blocks.max()) + 1 if blocks.size else 0
    out = np.full(max(n, 0), -np.inf)
    ok = (blocks >= 0) & np.isfinite(v)
    np.maximum.at(out, blocks[ok], v[ok])
    out[~np.isfinite(out)] = np.nan
    return out


def peak_statistics(ds: xr.Dataset, epicyclic: float) -> dict[str, MeanEstimate]:
    """The mean peak per roller pass of each peak trace ``ds`` holds, with its blocking
    standard error over the blocks (module docstring)."""
    traces = {k: v for k, v in PEAK_STATISTICS.items() if v in ds}
    if not traces or "roller" not in ds.sizes:
        return {}
    blocks = roller_pass_blocks(ds["time"].values, ds.sizes["roller"], epicyclic)
    out = {}
    for key, var in traces.items():
        m = block_maxima(ds[var].values, blocks)
        if np.isfinite(m).any():
            out[key] = batch_mean(m)
    return out


#: the per-sample series the statistics are made of: name -> (variable, squared)
SERIES = {"mean_cage_speed_rad_s": ("cage_speed", False), "skew_rms_rad": ("skew_angle", True),
          "rms_cage_force_N": ("cage_force", True)}


#: per-sample totals over a variable's other dimension (its sources): series -> variable
SUMMED_SERIES = {"mean_power_loss_W": "power_loss_W",
                 "mean_friction_torque_N_m": "friction_torque_N_m"}
#: the torque as a catalogue states it [N mm]
N_MM_PER_N_M = 1e3


def per_sample_series(ds: xr.Dataset) -> dict[str, np.ndarray]:
    """The series of :data:`SERIES` that ``ds`` has: the cage speed, and the mean square over
    rollers (and ends) of the skew and the pocket force, one value per sample. A streamed run
    keeps these (8 bytes per sample each) from its blocks: each value depends on its own
    sample only."""
    out = {}
    for key, (var, squared) in SERIES.items():
        if var in ds:
            out[key] = (_per_time(ds[var] ** 2, lambda a, d: a.mean(d)) if squared
                        else np.asarray(ds[var].values, dtype=float))
    if "spin_speed" in ds:  # the rollers' mean spin: the measured ball-spin frequency
        out["mean_roller_spin_speed_rad_s"] = _per_time(ds["spin_speed"],
                                                        lambda a, d: a.mean(d))
    for key, var in SUMMED_SERIES.items():  # the total over the sources, per sample
        if var in ds:
            out[key] = _source_total(ds[var])
    if "cage_center" in ds:  # cage whirl: the centre, for the whirl attributes (analysis/whirl.py)
        out["cage_center_x_m"] = np.asarray(ds["cage_center"].isel(direction=0).values, float)
        out["cage_center_y_m"] = np.asarray(ds["cage_center"].isel(direction=1).values, float)
    return out


def series_statistics(series: dict, epicyclic: float) -> dict[str, MeanEstimate]:
    """:func:`run_statistics` from the series of :func:`per_sample_series`."""
    out = {}
    if "mean_cage_speed_rad_s" in series:
        cage = batch_mean(series["mean_cage_speed_rad_s"])
        out["mean_cage_speed_rad_s"] = cage
        if epicyclic > 0:
            out["cage_slip_ratio"] = MeanEstimate(1.0 - cage.mean / epicyclic,
                                                  cage.stderr / epicyclic,
                                                  cage.batches, cage.correlated)
    for name in ("skew_rms_rad", "rms_cage_force_N"):
        if name in series:
            out[name] = rms_of(batch_mean(series[name]))
    if "mean_roller_spin_speed_rad_s" in series:
        out["mean_roller_spin_speed_rad_s"] = batch_mean(series["mean_roller_spin_speed_rad_s"])
    if "mean_power_loss_W" in series:
        out["mean_power_loss_W"] = batch_mean(series["mean_power_loss_W"])
    if "mean_friction_torque_N_m" in series:
        m = batch_mean(series["mean_friction_torque_N_m"])
        out["mean_friction_torque_N_mm"] = MeanEstimate(
            N_MM_PER_N_M * m.mean, N_MM_PER_N_M * m.stderr, m.batches, m.correlated)
    return out


def rms_of(mean_square: MeanEstimate) -> MeanEstimate:
    """The RMS sqrt(mean x²) from the estimate of mean x², its error propagated linearly:
    SE(mean x²) / (2 RMS)."""
    rms = float(np.sqrt(mean_square.mean))
    se = mean_square.stderr / (2.0 * rms) if rms > 0 else np.nan
    return MeanEstimate(rms, se, mean_square.batches, mean_square.correlated)


#: the most decimals :func:`with_error` prints in fixed point; a value whose error needs more
#: (a quantity at round-off, e.g. the skew of a preloaded defect case) shares a power of ten
MAX_DECIMALS = 7


def with_error(value: float, stderr: float, digits: int = 2) -> str:
    """``95.052 ± 0.002``: the value to the decimal of the error's ``digits`` significant
    figures (plain value when the error is unknown or zero); beyond :data:`MAX_DECIMALS`
    decimals with a shared power of ten, ``(3.881 ± 0.020)e-17``."""
    if not (np.isfinite(stderr) and stderr > 0 and np.isfinite(value)):
        return f"{value:.6g}"
    decimals = max(0, digits - 1 - int(np.floor(np.log10(stderr))))
    if decimals <= MAX_DECIMALS:
        return f"{value:.{decimals}f} ± {stderr:.{decimals}f}"
    exponent = int(np.floor(np.log10(max(abs(value), stderr))))
    scale = 10.0 ** exponent
    decimals = max(0, decimals + exponent)
    return f"({value / scale:.{decimals}f} ± {stderr / scale:.{decimals}f})e{exponent:+03d}"


#: Dataset attribute names of each statistic: (value, standard error)
ATTRIBUTES = {
    "mean_cage_speed_rad_s": ("mean_cage_speed_rad_s", "mean_cage_speed_stderr_rad_s"),
    "cage_slip_ratio": ("cage_slip_ratio", "cage_slip_ratio_stderr"),
    "mean_roller_spin_speed_rad_s": ("mean_roller_spin_speed_rad_s",
                                     "mean_roller_spin_speed_stderr_rad_s"),
    "skew_rms_rad": ("skew_rms_rad", "skew_rms_stderr_rad"),
    "rms_cage_force_N": ("rms_cage_force_N", "rms_cage_force_stderr_N"),
    "roller_pass_peak_cage_force_N": ("roller_pass_peak_cage_force_N",
                                      "roller_pass_peak_cage_force_stderr_N"),
    "roller_pass_peak_contact_pressure_Pa": ("roller_pass_peak_contact_pressure_Pa",
                                             "roller_pass_peak_contact_pressure_stderr_Pa"),
    "roller_pass_peak_skew_angle_rad": ("roller_pass_peak_skew_angle_rad",
                                        "roller_pass_peak_skew_angle_stderr_rad"),
    "roller_pass_peak_slip_velocity_m_s": ("roller_pass_peak_slip_velocity_m_s",
                                           "roller_pass_peak_slip_velocity_stderr_m_s"),
    "mean_power_loss_W": ("mean_power_loss_W", "mean_power_loss_stderr_W"),
    "mean_friction_torque_N_mm": ("mean_friction_torque_N_mm",
                                  "mean_friction_torque_stderr_N_mm"),
}


def statistics_attrs(ds: xr.Dataset, estimates: dict | None = None) -> dict:
    """The statistics of :func:`run_statistics` as Dataset attributes (value and standard
    error, names with units), the estimator named in ``statistics_estimator``; NaN errors (too
    short a record) are left out, and ``statistics_window_too_short`` lists the statistics whose
    record spans too few correlation times. ``estimates``: those of :func:`series_statistics`
    instead of the Dataset's (a streamed run)."""
    out, short = {}, []
    estimates = run_statistics(ds) if estimates is None else estimates
    for key, est in estimates.items():
        value_name, error_name = ATTRIBUTES[key]
        out[value_name] = float(est.mean)
        if np.isfinite(est.stderr):
            out[error_name] = float(est.stderr)
        if est.correlated:
            short.append(key)
    if out:
        out["statistics_estimator"] = (
            "time means over the recorded samples; roller_pass_peak_*: the mean over whole "
            "roller-pass periods 2 pi/(Z epicyclic cage speed) of the largest value of the "
            "peak trace in each; standard errors by blocking (batch means, "
            "Flyvbjerg & Petersen 1989) at the block length of Lee, Kent & Needs 2011 Eq. 14 "
            "(bearingdae/analysis/statistics.py)")
        if short:
            out["statistics_window_too_short"] = ", ".join(short)
    # the defect frequencies from the measured cage and roller spin speeds
    from .defect_frequencies import statistics_defect_attrs

    out.update(statistics_defect_attrs(ds, estimates))
    return out
