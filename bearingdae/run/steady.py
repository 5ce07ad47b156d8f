"""Steady state on demand: run the warm-up in blocks until the cage speed is steady.

Stage: scene -> model -> **solver, block by block** -> results. With ``[numerics]
until_steady = true`` :func:`bearingdae.api.simulate` hands the integration to
:func:`integrate_until_steady`, which drives any solver of the contract
(bearingdae/solvers/base.py: ``solver.integrate(model, y, y', t_out, t_start=t, ...)``
continues a run from a state) one block of ``steady_block_cage_revolutions`` at a time, and
then records the requested window (``cage_revolutions``) from the state it reached.

**The criterion** (all in fractions of the epicyclic cage speed Ω_e = ω_i/2 (1 − D_w/d_m),
tolerance ε = ``steady_tolerance``, default 1e-3; m_k = mean cage speed of block k over its
samples, cage switched off: mean roller orbit speed). After block k the warm-up is steady when

1. **two blocks in a row**: |m_k − m_{k−1}| < ε and |m_{k−1} − m_{k−2}| < ε; and
2. **no drift (trend test)**: take the run of block-to-block differences that ends with the
   last one and has one sign, at most ``TREND_WINDOW`` = 7 long. Shorter than 3 (the signs
   alternate): the means fluctuate about a level, no drift. Otherwise (a monotone approach)
   the remaining change is extrapolated as a geometric tail, d_last (r + r² + …) =
   d_last r/(1 − r), with r the *largest* ratio |d_{k+1} / d_k| in the run (the slowest decay
   seen), and must be below ε; r ≥ 1 (the change is not dying out) fails the test. Exact for a
   geometric approach; conservative for one with several time constants. Why not criterion 1
   alone: a cage spinning down with a time constant of τ blocks changes by ~1/τ of its
   remaining distance per block, so a per-block change below ε would still leave ~τ ε to go
   (τ ≈ 25 at 1000 N on the Harris bearing from pure rolling). Why the largest ratio: the
   spin-down from pure rolling at 1000 N has a fast transient (ratios 0.3-0.6 over the first
   blocks) and then the slow mode (0.93-0.97, noisy): the ratio of the last two differences
   (Aitken's Δ²) once read 0.70 there and a least-squares fit over the run 0.57, and both
   versions of the test stopped that run 0.6 % and 1.9 % of epicyclic short of its steady
   state (tests/studies/test_steady.py keeps the block means as a regression case).
   A last difference at or below ``DRIFT_RESOLUTION`` ε = ε/20 (or the integration's
   ``rtol``, if larger) is no measurable drift: block means of a steady run scatter by
   ~1e-5 of epicyclic and are monotone over three blocks by chance one time in four, with
   ratios anywhere (a cage at rest at 0 N creeps by 1e-10 per block: "r ≈ 1"); and a slow mode
   with a time constant of up to 20 blocks that changes by less than ε/20 per block has less
   than ε left to go. A slower mode is the limit of this criterion: harris36 at 250 N from
   pure rolling (τ ≈ 28 blocks) stopped 1.4 ε short of the steady state the torque-balance
   start reaches (docs/validation.md, "Two starts"); ask for a smaller ε there.

and at least ``warmup_cage_revolutions`` have been run. The warm-up stops without a steady
state when the next block would pass ``max_warmup_cage_revolutions``: the Dataset then says
``steady_state_reached = 0`` and a :class:`NotSteadyWarning` is issued. Dataset attributes:
``steady_state_reached`` (1/0), ``warmup_cage_revolutions_used``, ``steady_last_change``
(m_k − m_{k−1}), ``steady_drift_per_block`` (least-squares slope of the last 4 block means),
``steady_remaining_estimate`` (the extrapolated remaining change; 0 when the means
fluctuate), ``steady_block_means`` (JSON list) and ``steady_criterion`` (JSON).

Each block re-starts the solver from the last state; IDA re-solves the consistent initial
condition there (a no-op up to its Newton tolerance) and restarts at order 1 with a small step,
so a blocked run follows a slightly different step sequence from one long run (the same
agreement to the tolerance as checkpoint/resume, docs/robustness.md). Resumable: with a
``warmup_path`` the state, block means, counters and a dynamic ring's last taps are written
atomically after every block and a later call with the same scene continues from the last
block written. The record itself keeps no checkpoint: interrupted, it is recomputed from the
warm-up's end, which gives the uninterrupted record (the same state, taps and solver start).
"""

from __future__ import annotations

import json
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..solvers.base import merge_statistics
from ..system.extremes import requested
from ..util.warning_lines import BearingdaeWarning
from .warmup_checkpoint import Run, fingerprint, load, save

#: block means the trend test needs at least (three differences)
TREND_BLOCKS = 4
#: longest run of one-signed differences the trend test looks at
TREND_WINDOW = 7
#: a last change below this fraction of the tolerance is no measurable drift: block means
#: scatter by ~1e-5 of epicyclic (pocket impacts), and with a time constant of up to
#: 1/fraction = 20 blocks what is left to go is then still below the tolerance
DRIFT_RESOLUTION = 0.05
#: consecutive block-to-block changes that must be below the tolerance
CONSECUTIVE_BLOCKS = 2
#: blocks a thermal coupling not yet steady is guessed to need (a progress estimate only;
#: the coupled runs of the tests took 2 to 5)
THERMAL_BLOCKS_GUESS = 2


class NotSteadyWarning(BearingdaeWarning):
    """The warm-up reached ``max_warmup_cage_revolutions`` before the cage speed was steady."""


@dataclass(frozen=True)
class Verdict:
    steady: bool
    last_change: float  #: m_k − m_{k−1} (fraction of epicyclic); NaN with < 2 blocks
    drift_per_block: float  #: least-squares slope of the last TREND_BLOCKS means; NaN if fewer
    remaining: float  #: extrapolated remaining change (0: fluctuating; inf: not dying out)
    reason: str


def assess(means, tolerance: float, floor: float = 0.0) -> Verdict:
    """The criterion of the module docstring on block means (fractions of epicyclic).
    ``floor``: a last change at or below it is no measurable drift (the integration's
    relative tolerance: block means are not resolved more finely)."""
    m = np.asarray(means, dtype=float)
    d = np.diff(m)
    last = float(d[-1]) if d.size else np.nan
    tail = m[-TREND_BLOCKS:]
    slope = float(np.polyfit(np.arange(tail.size), tail, 1)[0]) if tail.size >= 2 else np.nan
    if m.size < max(CONSECUTIVE_BLOCKS + 1, TREND_BLOCKS):
        return Verdict(False, last, slope, np.inf, f"{m.size} blocks; the criterion needs "
                       f"{max(CONSECUTIVE_BLOCKS + 1, TREND_BLOCKS)}")
    recent = d[-CONSECUTIVE_BLOCKS:]
    run = 1  # length of the one-signed run of differences ending with the last one
    while run < min(d.size, TREND_WINDOW) and d[-run - 1] * d[-1] > 0:
        run += 1
    floor = max(floor, DRIFT_RESOLUTION * tolerance)
    if run >= TREND_BLOCKS - 1 and abs(d[-1]) > floor:  # monotone: extrapolate the tail
        td = np.abs(d[-run:])
        r = float(np.max(td[1:] / td[:-1]))  # the slowest decay seen: conservative
        remaining = float(d[-1] * r / (1.0 - r)) if r < 1.0 else np.inf * np.sign(d[-1])
    else:
        remaining = 0.0
    if np.any(np.abs(recent) >= tolerance):
        return Verdict(False, last, slope, remaining,
                       f"block-to-block change {np.abs(recent).max():.3g} >= {tolerance:g}")
    if not abs(remaining) < tolerance:
        return Verdict(False, last, slope, remaining,
                       f"monotone drift, extrapolated remaining change {remaining:.3g}")
    return Verdict(True, last, slope, remaining, "steady")


def _speed_index(model) -> tuple[np.ndarray, float]:
    """Compact indices whose mean is the tracked speed (cage, else every roller's orbit) and
    their (common) scale."""
    lay = model.layout
    if "cage_speed" in lay.global_names:
        idx = np.array([lay.index("cage_speed")])
    else:
        idx = np.array([lay.index("orbit_speed", j) for j in range(lay.rollers)])
    return idx, float(model.scale[idx[0]])


def _period_s(model) -> float:
    """One cage revolution at the final speed [s] (as api.output_times)."""
    from ..system.model import STATIC_REFERENCE_PERIOD_S

    epi = model.final_cage_speed()
    return 2.0 * np.pi / epi if epi > 0 else STATIC_REFERENCE_PERIOD_S


def horizon_s(model) -> float:
    """Latest end of an until_steady run [s]: ramp, the capped warm-up, the window (for a
    progress bar, which then finishes early when the criterion holds early)."""
    dyn = model.scene.dynamics
    return float(model.ramp_t[-1]) + _period_s(model) * (dyn.max_warmup_cage_revolutions
                                                         + dyn.cage_revolutions)


def blocks_to_go(verdict: Verdict, tolerance: float, blocks_run: int) -> int:
    """How many more blocks the criterion will probably want (for a progress estimate only).

    Too few blocks for the criterion: the blocks it still needs. A monotone approach with a
    geometric tail (remaining = d r / (1 − r), so r = remaining / (d + remaining)): each block
    multiplies the last change d and the remaining change by r, so the criterion holds after
    n = max(n_tail, n_changes) further blocks, with n_tail the blocks until the remaining change
    is below ε (or the last change below the drift resolution, whichever comes first) and
    n_changes the blocks until the last ``CONSECUTIVE_BLOCKS`` changes are below ε. Not dying
    out: the cap decides (a huge number). Fluctuating: the consecutive-change test."""
    needed = max(CONSECUTIVE_BLOCKS + 1, TREND_BLOCKS) - blocks_run
    if needed > 0:
        return needed
    if verdict.steady:
        return 0
    rem, last = abs(verdict.remaining), abs(verdict.last_change)
    if not np.isfinite(rem):
        return 10**9
    if rem > 0 and last > 0:
        r = rem / (last + rem)
        if 0.0 < r < 1.0:
            def after(value, bound):  # blocks until value r^n < bound
                return max(0, int(np.ceil(np.log(bound / value) / np.log(r) - 1e-9)))

            n_tail = min(after(rem, tolerance), after(last, DRIFT_RESOLUTION * tolerance))
            n_changes = after(last, tolerance) + CONSECUTIVE_BLOCKS - 1
            return max(1, n_tail, n_changes)
    return CONSECUTIVE_BLOCKS


def integrate_until_steady(solver, model, y0: np.ndarray, yp0: np.ndarray, *, progress=None,
                           warmup_path: str | Path | None = None, resume: bool = False,
                           expected_end=None, on_sample=None, keep_samples: bool = True,
                           coupling=None):
    """Warm up block by block until steady (or the cap), then record the window.

    ``solver``: a :class:`bearingdae.solvers.base.Solver`. Returns ``(solution, record_start_s,
    attrs)``: the Solution of the recorded window (its ``stats`` summed over every segment,
    warm-up included), the time the window starts, and the Dataset attributes of the
    criterion. On a solver failure the Solution has ``success = False`` and holds the samples
    of the failing segment (the run's state is in ``warmup_path`` if given).
    ``expected_end``: called after every block with the run's probable end [s] (the warm-up's
    end by :func:`blocks_to_go`, capped, plus the recorded window), for a progress display.
    ``on_sample``, ``keep_samples``: those of ``solver.integrate`` for the recorded window
    (a streamed run). ``coupling``: a :class:`bearingdae.run.thermal_coupling.ThermalCoupling`, told
    every block and asked whether it is steady too; without ``until_steady`` (a thermal run
    alone) only the coupling decides when the warm-up ends.
    """
    from ..solvers.base import Solution

    dyn = model.scene.dynamics
    epi = model.final_cage_speed()
    period = _period_s(model)
    ref = epi if epi > 0 else 1.0
    dt = period / dyn.samples_per_cage_revolution
    per_block = max(2, int(round(dyn.steady_block_cage_revolutions
                                 * dyn.samples_per_cage_revolution)))
    block_s = per_block * dt
    t_ramp = float(model.ramp_t[-1])
    idx, scale = _speed_index(model)
    key = fingerprint(model, solver)
    path = Path(warmup_path) if warmup_path is not None else None
    wall0 = time.perf_counter()

    from ..system.taps import TAIL_INTERVALS, RingTaps

    # the taps a segment continues reach back this far: the filter of the segment's first
    # samples reads TAIL_INTERVALS intervals before them (system/taps.py)
    taps_reach_s = (TAIL_INTERVALS + 2) * dt
    tapped = []  # model.ring_taps holds the taps of the run so far (a segment, a resume)
    run = None
    if resume and path is not None and path.exists():
        run = load(path, key, model.size, horizon_s(model), model.scene.input_files(),
                   taps_needed=bool(model.layout.ring_dynamic
                                    and getattr(solver, "ring_taps", False)))
    if run is None:
        run = Run(0.0, np.asarray(y0, float), np.asarray(yp0, float))
    else:
        if coupling is not None:
            coupling.restore(run.coupling)
        if len(run.taps) and model.layout.ring_dynamic and getattr(solver, "ring_taps", False):
            # the last block's taps, as the uninterrupted run carries them on
            model.ring_taps = RingTaps(model)
            model.ring_taps.restore(run.taps)
            tapped.append(True)

    def segment(t_out, extremes_from=None, record=False):
        if tapped and model.ring_taps is not None:
            # a dynamic ring's taps run on from block to block, the record included, as in
            # one integration (system/taps.py): the solver continues them; those past the
            # last block's end it takes again, those the filter no longer reaches go
            model.ring_taps.drop_after(run.t)
            model.ring_taps.drop_before(run.t - taps_reach_s)
            model.ring_taps_carried = model.ring_taps
        res = solver.integrate(model, run.y, run.yp, t_out, t_start=run.t, progress=progress,
                               extremes_from=extremes_from,
                               on_sample=on_sample if record else None,
                               keep_samples=keep_samples or not record)
        run.stats = merge_statistics(run.stats, res.stats)
        run.segments += 1
        tapped.append(True)
        return res

    def failed(res):
        res.stats = dict(run.stats, segments=run.segments)
        return res, float(res.t[0]) if res.t.size else run.t, {}

    min_revs, cap = dyn.warmup_cage_revolutions, dyn.max_warmup_cage_revolutions
    told, ahead = [-np.inf], period * (dyn.cage_revolutions + dyn.steady_block_cage_revolutions)
    verdict = assess(run.means, dyn.steady_tolerance, dyn.rtol)

    def settled() -> bool:  # the criteria asked for: the cage speed's, the oil temperature's
        cage = verdict.steady or not dyn.until_steady
        return cage and (coupling is None or coupling.converged)

    def estimate_end():
        if expected_end is None:
            return
        used = max(0.0, (run.t - t_ramp) / period)
        more = blocks_to_go(verdict, dyn.steady_tolerance, len(run.means)) \
            if dyn.until_steady else 0
        if coupling is not None and not coupling.converged:  # a fixed point: a few blocks
            more = max(more, THERMAL_BLOCKS_GUESS)
        if used < min_revs:
            more = max(more, int(np.ceil((min_revs - used)
                                         / dyn.steady_block_cage_revolutions - 1e-9)))
        warm_end = min(used + more * dyn.steady_block_cage_revolutions, cap)
        end = t_ramp + period * (warm_end + dyn.cage_revolutions)
        # the oil's guess moves a block on per block: the end told stays while a block is left
        if coupling is None or told[0] >= end or told[0] - ahead < run.t:
            told[0] = end
            expected_end(end)

    estimate_end()
    if run.t < t_ramp:  # the speed ramp first: blocks measure revolutions at the final speed
        n = max(1, int(np.ceil((t_ramp - run.t) / dt)))
        res = segment(np.linspace(run.t, t_ramp, n + 1)[1:])
        if not res.success:
            return failed(res)
        run.t, run.y, run.yp = float(res.t[-1]), res.y[-1], res.yp[-1]
    while True:
        used = (run.t - t_ramp) / period
        if used >= min_revs - 1e-9 and settled():
            break
        if used + dyn.steady_block_cage_revolutions > cap + 1e-9:
            break
        t_out = run.t + dt * np.arange(1, per_block + 1)
        res = segment(t_out)
        if not res.success:
            return failed(res)
        speeds = res.y[:, idx].mean(axis=1) * scale
        run.means.append(float(speeds.mean() / ref))
        run.t, run.y, run.yp = float(res.t[-1]), res.y[-1], res.yp[-1]
        verdict = assess(run.means, dyn.steady_tolerance, dyn.rtol)
        if coupling is not None:  # the network under this block's losses: the next viscosity
            coupling.after_block(res.t, res.y)
            run.coupling = coupling.state()
        if model.ring_taps is not None:  # those the next segment continues (and a resume)
            run.taps = model.ring_taps.rows_in(run.t - taps_reach_s, run.t)
        if path is not None:
            save(path, key, run, model.scene.input_files())
        estimate_end()
    used = (run.t - t_ramp) / period
    steady = bool(verdict.steady and used >= min_revs - 1e-9)
    if coupling is not None and not coupling.converged:
        from .thermal_coupling import ThermalNotSteadyWarning

        warnings.warn(f"thermal: the oil temperature is not steady after {coupling.blocks} "
                      f"blocks (last change {coupling.last_change_K:.3g} K, tolerance "
                      f"thermal.temperature_tolerance_K = {coupling.tolerance_K:g} K); raise "
                      f"numerics.max_warmup_cage_revolutions (now {cap:g})",
                      ThermalNotSteadyWarning, stacklevel=4)
    n_rec = int(round(dyn.cage_revolutions * dyn.samples_per_cage_revolution))
    t_rec = run.t + dt * np.arange(n_rec + 1)
    res = segment(t_rec, run.t if requested(model.scene) else None, record=True)
    stats = dict(run.stats, segments=run.segments,
                 until_steady_wall_time_s=time.perf_counter() - wall0)
    sol = Solution(res.t, res.y, res.yp, res.success, res.message, res.failure_time_s, stats,
                   res.error_estimate, res.extremes)
    if not dyn.until_steady:  # a thermal run alone: no cage-speed criterion to report
        if res.success and path is not None:
            path.unlink(missing_ok=True)
        return sol, run.t, {"warmup_cage_revolutions_used": float(used)}
    attrs = {
        "steady_state_reached": int(steady), "warmup_cage_revolutions_used": float(used),
        "steady_last_change": _num(verdict.last_change),
        "steady_drift_per_block": _num(verdict.drift_per_block),
        "steady_remaining_estimate": _num(verdict.remaining),
        "steady_verdict": verdict.reason if steady or not verdict.steady else
        f"steady, but before warmup_cage_revolutions = {min_revs:g}",
        "steady_block_means": json.dumps([round(m, 10) for m in run.means]),
        "steady_criterion": json.dumps({
            "quantity": ("block-mean cage speed" if idx.size == 1 else
                         "block-mean roller orbit speed (no cage)") + " / epicyclic",
            "tolerance": dyn.steady_tolerance, "consecutive_blocks": CONSECUTIVE_BLOCKS,
            "trend_blocks": TREND_BLOCKS, "trend_window_differences": TREND_WINDOW,
            "drift_floor": max(dyn.rtol, DRIFT_RESOLUTION * dyn.steady_tolerance),
            "block_cage_revolutions": per_block / dyn.samples_per_cage_revolution,
            "min_warmup_cage_revolutions": min_revs, "max_warmup_cage_revolutions": cap,
            "definition": "bearingdae/run/steady.py"}),
    }
    if not steady:
        warnings.warn(f"until_steady: the cage speed is not steady after {used:.3g} warm-up "
                      f"cage revolutions (cap max_warmup_cage_revolutions = {cap:g}): "
                      f"{verdict.reason}; the recorded window is marked "
                      "steady_state_reached = 0", NotSteadyWarning, stacklevel=4)
    if res.success and path is not None:
        path.unlink(missing_ok=True)
    return sol, run.t, attrs


def _num(x: float) -> float:
    """A NetCDF-safe number (inf/NaN are legal floats in netCDF4 attributes, kept as such)."""
    return float(x)
