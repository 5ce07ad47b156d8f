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
"""

from __future__ import annotations

import numpy as np

#: sub-samples per output interval: the filter's input rate is this many times the output rate
TAPS_PER_INTERVAL = 16
#: half-length of the filter in output intervals: the taps run this far past the last sample
TAIL_INTERVALS = 9


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

    def __len__(self) -> int:
        return len(self._t)
