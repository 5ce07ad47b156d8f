"""Taps: a dynamic ring's displacement at sub-sample times, for the record's anti-alias filter.

Stage: system (a run's work buffer) -> solvers (IDA fills it) -> results (analysis/vibration.py
filters the ring acceleration from it). The ring of a scene with ``physics.ring = "dynamic"``
rings at its contact resonances (kHz), above the Nyquist frequency of the output samples.
What a sample records of its acceleration must be what the signal holds below that Nyquist
frequency: a low-pass filter has to see the signal denser than the samples. IDA gives the
state at any time it has passed by interpolating its own polynomial (``IDASolve`` in
``IDA_NORMAL`` mode, no extra step: the steps and the samples are those of a run without taps),
so the solver also stops at :data:`TAPS_PER_INTERVAL` − 1 equally spaced times inside every
output interval, at the samples themselves, and for :data:`TAIL_INTERVALS` intervals past the
last sample (the filter is centred on each sample), and keeps the ring displacement there.

A solver that cannot tap (Newmark-β, the scipy peers) leaves ``model.ring_taps`` None; the
results then fall back to the filter that needs the samples only (analysis/vibration.py).

A checkpoint keeps each sample's taps (:meth:`RingTaps.rows_since`, run/checkpoint.py): a resumed
run replays its samples with them and the solver continues them (``model.ring_taps_carried``),
tapping from the first interval after the resume, so that the resumed record is filtered as an
uninterrupted one. A run warmed up block by block (run/steady.py) carries the last block's taps
into its record the same way, and its warm-up checkpoint keeps them (:meth:`RingTaps.rows_in`)
for a resumed warm-up or a record recomputed after an interruption.
"""

from __future__ import annotations

import numpy as np

#: sub-samples per output interval: the filter's input rate is this many times the output rate
TAPS_PER_INTERVAL = 16
#: half-length of the filter in output intervals: the taps run this far past the last sample
TAIL_INTERVALS = 9
#: columns of a sample's tap rows in a checkpoint: time [s], δ_r [m], δ_t [m]
TAP_COLUMNS = 3


class RingTaps:
    """The ring displacement (δ_r, δ_t) [m] at the tap times of one run of ``model``."""

    def __init__(self, model):
        lay = model.layout
        self.index = np.array([lay.index(n) for n in ("ring_dr", "ring_dt")])
        self.scale = np.asarray(model.scale, dtype=float)[self.index]
        self._t: list[float] = []
        self._x: list[np.ndarray] = []

    @staticmethod
    def between(t0: float, t1: float) -> np.ndarray:
        """The tap times strictly inside the output interval (t0, t1)."""
        return t0 + (t1 - t0) * np.arange(1, TAPS_PER_INTERVAL) / TAPS_PER_INTERVAL

    def add(self, t: float, y: np.ndarray) -> None:
        """Keep the ring displacement of the scaled state ``y`` at ``t`` (times increasing)."""
        self._t.append(float(t))
        self._x.append(np.asarray(y)[self.index] * self.scale)

    def arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """(times (n,), displacements (n, 2)) kept so far."""
        return np.array(self._t), np.array(self._x).reshape(-1, 2)

    def drop_before(self, t: float) -> None:
        """Forget the taps before ``t`` (a streamed record has filtered the samples they
        served)."""
        k = int(np.searchsorted(np.asarray(self._t), t))
        del self._t[:k], self._x[:k]

    def drop_after(self, t: float) -> None:
        """Forget the taps after ``t``: those a block's tail took past its last sample, which
        the next block, starting there, takes again (run/steady.py)."""
        k = int(np.searchsorted(np.asarray(self._t), t, side="right"))
        del self._t[k:], self._x[k:]

    def __len__(self) -> int:
        return len(self._t)

    def rows_since(self, t0: float | None) -> np.ndarray:
        """The taps after ``t0`` (the previous sample; None: the taps of the last time only)
        as (TAPS_PER_INTERVAL, TAP_COLUMNS) rows (t, δ_r, δ_t), oldest first, NaN rows where
        the interval has fewer: what a checkpoint keeps of one sample's interval."""
        rows = np.full((TAPS_PER_INTERVAL, TAP_COLUMNS), np.nan)
        k = len(self._t)
        first = k  # scan from the end: the interval's taps are the last ones
        while first > 0 and k - first < TAPS_PER_INTERVAL and (
                t0 is None and first == k or t0 is not None and self._t[first - 1] > t0):
            first -= 1
        n = k - first
        if n:
            rows[TAPS_PER_INTERVAL - n:, 0] = self._t[first:]
            rows[TAPS_PER_INTERVAL - n:, 1:] = self._x[first:]
        return rows

    def rows_in(self, t0: float, t1: float) -> np.ndarray:
        """The taps at times in [t0, t1] as (n, TAP_COLUMNS) rows (t, δ_r, δ_t), oldest first:
        what a warm-up checkpoint keeps for the next block (run/steady.py)."""
        t = np.asarray(self._t)
        a, b = np.searchsorted(t, t0, side="left"), np.searchsorted(t, t1, side="right")
        rows = np.empty((max(0, b - a), TAP_COLUMNS))
        if b > a:
            rows[:, 0] = t[a:b]
            rows[:, 1:] = np.array(self._x[a:b]).reshape(-1, 2)
        return rows

    def restore(self, rows: np.ndarray) -> None:
        """Keep the taps of checkpoint rows (:meth:`rows_since`; NaN rows skipped) after those
        kept, in order."""
        for t, xr, xt in np.asarray(rows, dtype=float).reshape(-1, TAP_COLUMNS):
            if np.isfinite(t) and (not self._t or t > self._t[-1]):
                self._t.append(float(t))
                self._x.append(np.array([xr, xt]))

    @classmethod
    def for_run(cls, model) -> "RingTaps":
        """The taps a solver fills: those a resumed run's replay restored
        (``model.ring_taps_carried``, taken once), else a new, empty set."""
        carried = getattr(model, "ring_taps_carried", None)
        model.ring_taps_carried = None
        return carried if carried is not None else cls(model)
