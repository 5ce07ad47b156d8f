"""The trend quantities of docs/validation.md, read four ways, with block error bars.

Stage: analysis (reads a run's Dataset). The paper describes each quantity over a roller's
whole orbit; a bearing engineer may rather ask about the loaded zone, the typical roller pass
or the extreme impact. Each **reading** below is one function of a block of the record and says
what it means physically; :data:`READINGS` lists them per quantity.

**Blocks.** The recorded window is cut into non-overlapping blocks of
:data:`BLOCK_CAGE_REVOLUTIONS` cage revolutions at the epicyclic cage speed (only whole blocks
count). With Z = 20 rollers every azimuth of the bearing is passed Z/2 = 10 times per half
revolution, so a block sees the whole orbit (the loaded and the unloaded zone) many times over;
the orbit-wide extremes of a block are those of the roller set over half a revolution.

**Error bars.** A reading gives one value per block; :func:`block_estimate` returns their mean
and a standard error from the blocking levels of :func:`bearingdae.analysis.statistics.
blocking_levels` (successive blocks merged in pairs). Blocks of a chaotic run are correlated
over a few tens of ms (a few revolutions at 6000 r/min), so the error is taken as the
**largest** standard error over the levels that still have at least :data:`MIN_LEVEL_BLOCKS`
blocks (block lengths 0.5, 1 and 2 revolutions for a 32-revolution record): where the levels
have reached the plateau this is the plateau; the maximum errs on the safe side.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from .statistics import block_maxima, blocking_levels, roller_pass_blocks

#: block length [cage revolutions] of the trend statistics
BLOCK_CAGE_REVOLUTIONS = 0.5
#: the loaded zone: rollers within this angle of the radial-load line [deg]
LOADED_ZONE_DEG = 30.0
#: fewest blocks a blocking level must have to enter the standard error (relative error of one
#: level's SE ~ 1/sqrt(2 (n - 1)): 18 % at 16 blocks)
MIN_LEVEL_BLOCKS = 16


@dataclass(frozen=True)
class BlockEstimate:
    """Mean of the block values ± standard error; ``n_blocks`` blocks of ``block_revolutions``;
    ``level_stderr``: SE at block lengths of 1, 2, 4 ... base blocks (all levels with at least
    two blocks, for the plateau check)."""

    mean: float
    stderr: float
    n_blocks: int
    block_revolutions: float
    level_stderr: tuple


def block_estimate(values, block_revolutions: float = BLOCK_CAGE_REVOLUTIONS) -> BlockEstimate:
    """Mean ± the largest blocking SE over levels with >= MIN_LEVEL_BLOCKS blocks (module
    docstring) of a series of block values."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size < 2:
        return BlockEstimate(float(v.mean()) if v.size else np.nan, np.nan, int(v.size),
                             block_revolutions, ())
    levels = blocking_levels(v, 2)
    usable = [se for se, n, _ in levels if n >= MIN_LEVEL_BLOCKS] or [levels[0][0]]
    return BlockEstimate(float(v.mean()), float(max(usable)), int(v.size), block_revolutions,
                         tuple(se for se, _, _ in levels))


# ---------------------------------------------------------------------------------------------
# Blocks and masks
# ---------------------------------------------------------------------------------------------
def _epicyclic(ds: xr.Dataset) -> float:
    return float(ds.attrs.get("epicyclic_cage_speed_rad_s", np.nan))


def cage_blocks(ds: xr.Dataset, block_revolutions: float = BLOCK_CAGE_REVOLUTIONS) -> np.ndarray:
    """Block number of each sample: whole blocks of ``block_revolutions`` epicyclic cage
    revolutions, -1 outside a whole block. A block of b revolutions is the roller-pass period
    of 1/b "rollers", so the sample convention of statistics.roller_pass_blocks carries over."""
    return roller_pass_blocks(ds["time"].values, 1.0 / block_revolutions, _epicyclic(ds))


def loaded_zone(ds: xr.Dataset, half_angle_deg: float = LOADED_ZONE_DEG) -> np.ndarray:
    """(time, roller) True where the roller is within ``half_angle_deg`` of the radial-load
    line (azimuth θX = 0, the centre of the loaded zone)."""
    az = np.asarray(ds.roller_azimuth.values, dtype=float)
    wrapped = (az + np.pi) % (2 * np.pi) - np.pi
    return np.abs(wrapped) < np.radians(half_angle_deg)


def _per_block(x: np.ndarray, blocks: np.ndarray, reduce) -> np.ndarray:
    """``reduce`` of the samples of each whole block of the per-sample array ``x``."""
    n = int(blocks.max()) + 1 if blocks.size else 0
    return np.array([reduce(x[blocks == b]) for b in range(max(n, 0))])


def _ratio_per_block(num: np.ndarray, den: np.ndarray, blocks: np.ndarray) -> np.ndarray:
    """Σ num / Σ den over each block (num, den per sample)."""
    n = int(blocks.max()) + 1 if blocks.size else 0
    out = np.full(max(n, 0), np.nan)
    for b in range(max(n, 0)):
        d = den[blocks == b].sum()
        out[b] = num[blocks == b].sum() / d if d > 0 else np.nan
    return out


def _nanmax(x):
    return np.nanmax(x) if np.isfinite(x).any() else np.nan


def _pass_peaks_per_block(ds: xr.Dataset, per_sample: np.ndarray,
                          block_revolutions: float) -> np.ndarray:
    """Mean over the roller passes of each block of the largest value in the pass."""
    rollers = ds.sizes["roller"]
    passes = roller_pass_blocks(ds["time"].values, rollers, _epicyclic(ds))
    peaks = block_maxima(per_sample, passes)
    per = int(round(rollers * block_revolutions))  # passes per block
    n = peaks.size // per
    return np.nanmean(peaks[:n * per].reshape(n, per), axis=1) if n else np.array([])


def _inner(da: xr.DataArray) -> np.ndarray:
    return np.asarray(da.sel(race="inner").values, dtype=float)  # (time, roller, slice)


def _roller_load(ds: xr.Dataset) -> np.ndarray:
    """(time, roller) total contact force of each roller (slices, both races) [N]."""
    return np.asarray(ds.contact_force.sum(("slice", "race")).values, dtype=float)


def _zone_only(x: np.ndarray, zone: np.ndarray) -> np.ndarray:
    """x (time, roller, ...) with the rollers outside the loaded zone set to NaN."""
    shape = zone.shape + (1,) * (x.ndim - 2)
    return np.where(zone.reshape(shape), x, np.nan)


def _flat_max(x: np.ndarray) -> np.ndarray:
    """Per sample, the largest finite value over all other dimensions (NaN if none)."""
    flat = x.reshape(x.shape[0], -1)
    ok = np.isfinite(flat).any(axis=1)
    out = np.full(x.shape[0], np.nan)
    out[ok] = np.nanmax(flat[ok], axis=1)
    return out


# ---------------------------------------------------------------------------------------------
# The readings: each maps (run, block numbers, block length) to one value per block
# ---------------------------------------------------------------------------------------------
def _spread(da: xr.DataArray) -> np.ndarray:
    """(time, roller) max_λ − min_λ of the inner-race slices."""
    x = _inner(da)
    return x.max(axis=2) - x.min(axis=2)


def slip_orbit_max(ds, blocks, b):
    """Orbit-wide extreme sliding: the largest |slip velocity| of any slice, roller and race
    in the block, at every solver step (peak trace). What a roller suffers once in a while,
    mostly in the unloaded zone where it slides freely."""
    return _per_block(ds.slip_velocity_peak.values, blocks, _nanmax)


def slip_pass_peak(ds, blocks, b):
    """Typical pass peak of sliding: mean over the roller passes (1/Z revolution each) of the
    largest |slip velocity| in the pass, every solver step: the extreme of a typical pass."""
    return _pass_peaks_per_block(ds, ds.slip_velocity_peak.values, b)


def slip_loaded_zone(ds, blocks, b):
    """Sliding under load: the largest |slip velocity| (slices, races, samples) of the rollers
    within LOADED_ZONE_DEG of the load line in the block: the slip that can smear a loaded
    raceway."""
    v = _zone_only(np.abs(np.asarray(ds.slip_velocity.values, float)), loaded_zone(ds))
    return _per_block(_flat_max(v), blocks, _nanmax)


def slip_load_weighted(ds, blocks, b):
    """Load-weighted sliding Σ q|V| / Σ q over slices, rollers, races and the block's samples:
    the slip where the load is, proportional to the frictional power per unit traction
    coefficient."""
    q = np.asarray(ds.contact_force.values, float)
    qv = q * np.abs(np.asarray(ds.slip_velocity.values, float))
    num = qv.reshape(qv.shape[0], -1).sum(axis=1)
    return _ratio_per_block(num, q.reshape(q.shape[0], -1).sum(axis=1), blocks)


def skew_orbit_amplitude(ds, blocks, b):
    """Orbit-wide skew amplitude (the paper's Figs 18, 22): each roller's largest |θz| in the
    block, averaged over the rollers (samples)."""
    th = np.abs(np.asarray(ds.skew_angle.values, float))
    n = int(blocks.max()) + 1 if blocks.size else 0
    return np.array([th[blocks == k].max(axis=0).mean() for k in range(max(n, 0))])


def skew_pass_peak(ds, blocks, b):
    """Typical pass peak of skew: mean over the roller passes of the largest |θz| of any
    roller in the pass, every solver step (peak trace)."""
    return _pass_peaks_per_block(ds, ds.skew_angle_peak.values, b)


def skew_loaded_zone(ds, blocks, b):
    """Skew under load: the mean |θz| of the rollers within LOADED_ZONE_DEG of the load line
    (samples): the misalignment that sets edge loading and the slice-to-slice difference
    where the rollers carry load."""
    th = _zone_only(np.abs(np.asarray(ds.skew_angle.values, float)), loaded_zone(ds))
    ok = np.isfinite(th)
    return _ratio_per_block(np.where(ok, th, 0).sum(axis=1), ok.sum(axis=1).astype(float),
                            blocks)


def skew_load_weighted(ds, blocks, b):
    """Load-weighted skew Σ Q|θz| / Σ Q (Q the roller's total contact force, samples): the
    skew the load sees."""
    q = _roller_load(ds)
    th = np.abs(np.asarray(ds.skew_angle.values, float))
    return _ratio_per_block((q * th).sum(axis=1), q.sum(axis=1), blocks)


def cage_force_orbit_peak(ds, blocks, b):
    """Orbit-wide peak pocket force: the largest |pocket force| on any roller end in the
    block, every solver step: the worst impact on the cage bars."""
    return _per_block(ds.cage_force_peak.values, blocks, _nanmax)


def cage_force_orbit_rms(ds, blocks, b):
    """Orbit-wide RMS pocket force sqrt(mean F²) over rollers, ends and samples: the steady
    push between rollers and cage, which sets cage wear."""
    f2 = np.asarray((ds.cage_force ** 2).mean(("roller", "end")).values, float)
    return np.sqrt(_per_block(f2, blocks, np.mean))


def cage_force_pass_peak(ds, blocks, b):
    """Typical pass peak of the pocket force: mean over the roller passes of the largest
    |pocket force| in the pass, every solver step: the impact of a typical pass."""
    return _pass_peaks_per_block(ds, ds.cage_force_peak.values, b)


def cage_force_loaded_zone(ds, blocks, b):
    """Pocket force under load: the RMS pocket force (both ends, samples) of the rollers within
    LOADED_ZONE_DEG of the load line: how hard the cage drives or brakes the loaded rollers."""
    f = _zone_only(np.asarray(ds.cage_force.values, float), loaded_zone(ds))
    ok = np.isfinite(f)
    num = np.where(ok, f * f, 0).reshape(f.shape[0], -1).sum(axis=1)
    return np.sqrt(_ratio_per_block(num, ok.reshape(f.shape[0], -1).sum(axis=1).astype(float),
                                    blocks))


def _spread_readings(var: str, what: str):
    def orbit(ds, blocks, b):
        return _per_block(_spread(ds[var]).max(axis=1), blocks, _nanmax)

    def pass_peak(ds, blocks, b):
        return _pass_peaks_per_block(ds, _spread(ds[var]).max(axis=1), b)

    def zone(ds, blocks, b):
        return _per_block(_flat_max(_zone_only(_spread(ds[var]), loaded_zone(ds))), blocks,
                          _nanmax)

    def weighted(ds, blocks, b):
        q = np.asarray(ds.contact_force.sel(race="inner").sum("slice").values, float)
        return _ratio_per_block((q * _spread(ds[var])).sum(axis=1), q.sum(axis=1), blocks)

    orbit.__doc__ = (f"Orbit-wide slice {what} difference: the largest inner-race max_λ − "
                     "min_λ of one roller over rollers and samples in the block (the paper's "
                     "'difference between slices', conclusions (1)-(3)).")
    pass_peak.__doc__ = (f"Typical pass peak of the slice {what} difference: mean over the "
                         "roller passes of its largest value in the pass (samples).")
    zone.__doc__ = (f"Slice {what} difference under load: its largest value among the rollers "
                    "within LOADED_ZONE_DEG of the load line: the uneven loading of a roller "
                    "that carries load.")
    weighted.__doc__ = (f"Load-weighted slice {what} difference Σ Q_i d / Σ Q_i (Q_i the "
                        "roller's inner-race load): the difference the load sees.")
    return orbit, pass_peak, zone, weighted


(slice_slip_orbit, slice_slip_pass_peak, slice_slip_loaded_zone,
 slice_slip_load_weighted) = _spread_readings("slip_velocity", "slip")
(slice_traction_orbit, slice_traction_pass_peak, slice_traction_loaded_zone,
 slice_traction_load_weighted) = _spread_readings("traction_force", "traction")


def cage_slip_orbit(ds, blocks, b):
    """Cage slip 1 − mean cage speed / epicyclic speed over the block: how far the roller set
    as a whole lags pure rolling (today's cage_slip_ratio)."""
    w = np.asarray(ds.cage_speed.values, float)
    return 1.0 - _per_block(w, blocks, np.mean) / _epicyclic(ds)


def cage_slip_loaded_zone(ds, blocks, b):
    """Orbit slip of the loaded rollers: 1 − mean orbit speed of the rollers within
    LOADED_ZONE_DEG of the load line / epicyclic speed: skidding where the load is carried."""
    w = _zone_only(np.asarray(ds.orbit_speed.values, float), loaded_zone(ds))
    ok = np.isfinite(w)
    mean = _ratio_per_block(np.where(ok, w, 0).sum(axis=1), ok.sum(axis=1).astype(float),
                            blocks)
    return 1.0 - mean / _epicyclic(ds)


def cage_slip_load_weighted(ds, blocks, b):
    """Load-weighted orbit slip 1 − Σ Q ω_orbit / Σ Q / epicyclic speed (Q the roller's total
    contact force): the lag of the rollers weighted by the load they carry."""
    q = _roller_load(ds)
    w = np.asarray(ds.orbit_speed.values, float)
    return 1.0 - _ratio_per_block((q * w).sum(axis=1), q.sum(axis=1), blocks) / _epicyclic(ds)


#: quantity -> (units, {reading: function}); the readings a claim about the quantity is
#: checked under (docs/validation.md)
READINGS = {
    "sliding_speed": ("m s-1", {"orbit_max": slip_orbit_max, "pass_peak": slip_pass_peak,
                                "loaded_zone": slip_loaded_zone,
                                "load_weighted": slip_load_weighted}),
    "skew": ("rad", {"orbit_amplitude": skew_orbit_amplitude, "pass_peak": skew_pass_peak,
                     "loaded_zone": skew_loaded_zone, "load_weighted": skew_load_weighted}),
    "pocket_force": ("N", {"orbit_peak": cage_force_orbit_peak,
                           "orbit_rms": cage_force_orbit_rms,
                           "pass_peak": cage_force_pass_peak,
                           "loaded_zone": cage_force_loaded_zone}),
    "slice_slip_difference": ("m s-1", {"orbit_max": slice_slip_orbit,
                                        "pass_peak": slice_slip_pass_peak,
                                        "loaded_zone": slice_slip_loaded_zone,
                                        "load_weighted": slice_slip_load_weighted}),
    "slice_traction_difference": ("N", {"orbit_max": slice_traction_orbit,
                                        "pass_peak": slice_traction_pass_peak,
                                        "loaded_zone": slice_traction_loaded_zone,
                                        "load_weighted": slice_traction_load_weighted}),
    "cage_slip": ("1", {"orbit_mean": cage_slip_orbit, "loaded_zone": cage_slip_loaded_zone,
                        "load_weighted": cage_slip_load_weighted}),
}


def block_values(ds: xr.Dataset, quantity: str, reading: str,
                 block_revolutions: float = BLOCK_CAGE_REVOLUTIONS) -> np.ndarray:
    """One value per whole block of the run ``ds`` of ``quantity`` read as ``reading``."""
    blocks = cage_blocks(ds, block_revolutions)
    return np.asarray(READINGS[quantity][1][reading](ds, blocks, block_revolutions), float)


def trend_estimate(ds: xr.Dataset, quantity: str, reading: str,
                   block_revolutions: float = BLOCK_CAGE_REVOLUTIONS) -> BlockEstimate:
    """Mean ± standard error over the blocks of ``quantity`` read as ``reading`` (READINGS)."""
    return block_estimate(block_values(ds, quantity, reading, block_revolutions),
                          block_revolutions)


def trend_statistics(ds: xr.Dataset, block_revolutions: float = BLOCK_CAGE_REVOLUTIONS
                     ) -> dict[tuple[str, str], BlockEstimate]:
    """(quantity, reading) -> mean ± SE over the blocks of the run, for every reading."""
    blocks = cage_blocks(ds, block_revolutions)
    return {(q, r): block_estimate(fn(ds, blocks, block_revolutions), block_revolutions)
            for q, (_, readings) in READINGS.items() for r, fn in readings.items()}
