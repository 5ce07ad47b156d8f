"""The segment files of a long run's checkpoint (run/checkpoint.py), and reading them back.

A checkpoint file holds at most :data:`SEGMENT_SAMPLES` samples; then they move to a segment
file of their own, written once (atomically) and named in the checkpoint file, so that neither
the memory of a run nor the size of a checkpoint rewrite grows with the record. A resume reads
the segments one at a time (:class:`_Held`) and checks each against the run (fingerprint,
place, output times).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..system.extremes import PEAKS
from ..util.atomic import fit_name, shown_path

#: Samples the checkpoint file holds before they move to a segment file of their own
#: (``run.nc.checkpoint.00001.npz``, ...), written once: the memory of a long run and the
#: size of each rewrite stay bounded (~2.3 MB on the baseline), whatever the record's length.
SEGMENT_SAMPLES = 1000


def segment_path(path: str | Path, index: int) -> Path:
    """The ``index``-th segment file beside a checkpoint: ``x.checkpoint.npz`` ->
    ``x.checkpoint.00001.npz``."""
    path = Path(path)
    tail = f".{index:05d}.npz"
    return fit_name(path.with_name(path.name.removesuffix(".npz") + tail), tail)


class _Held:
    """The samples a checkpoint holds, oldest first: its segment files, read one at a time
    when iterated (never all in memory), then its own. ``last``: (t, y, y') of the last."""

    def __init__(self, ck):
        self.ck = ck
        self.size = sum(g["samples"] for g in ck.segments) + len(ck.T)
        if ck.T:
            self.last = (ck.T[-1], ck.Y[-1], ck.YP[-1])
        elif ck.segments:
            with np.load(segment_path(ck.path, len(ck.segments))) as z:
                self.last = (float(z["t"][-1]), np.array(z["y"][-1]), np.array(z["yp"][-1]))
        else:
            self.last = None

    def __bool__(self) -> bool:
        return self.size > 0

    def __len__(self) -> int:
        return self.size

    def peaks(self) -> tuple[np.ndarray, np.ndarray]:
        """(times, interval peaks) of every sample held (NaN rows where a file kept none)."""
        T, P = [], []
        for index in range(1, len(self.ck.segments) + 1):
            with np.load(segment_path(self.ck.path, index)) as z:
                t = np.array(z["t"])
                p = np.array(z["peaks"]) if "peaks" in z else np.full((t.size, len(PEAKS)),
                                                                      np.nan)
            if p.shape != (t.size, len(PEAKS)):
                p = np.full((t.size, len(PEAKS)), np.nan)
            T.append(t), P.append(p)
        T.append(np.array(self.ck.T, dtype=float))
        P.append(np.array(self.ck.P, dtype=float).reshape(len(self.ck.T), len(PEAKS)))
        return np.concatenate(T), np.concatenate(P)

    def __iter__(self):
        for t, y, yp, _ in self.samples():
            yield t, y, yp

    def samples(self):
        """(t, y, y', ring tap rows or None) of every sample held, oldest first."""
        for index in range(1, len(self.ck.segments) + 1):
            with np.load(segment_path(self.ck.path, index)) as z:
                t, y, yp = np.array(z["t"]), np.array(z["y"]), np.array(z["yp"])
                x = np.array(z["taps"]) if "taps" in z else [None] * t.size
            yield from zip(map(float, t), y, yp, x)
        yield from zip(list(self.ck.T), list(self.ck.Y), list(self.ck.YP), list(self.ck.X))


def _segment_problem(path: Path, index: int, n: int, first: int, key: str, size: int,
                     t_out) -> str:
    """What is wrong with the ``index``-th segment file of a checkpoint ('' if nothing)."""
    seg = segment_path(path, index)
    try:
        with np.load(seg, allow_pickle=False) as z:
            meta = json.loads(str(z["meta"]))
            t, y, yp = np.array(z["t"]), np.array(z["y"]), np.array(z["yp"])
            taps = np.array(z["taps"]) if "taps" in z else None
    except Exception as exc:
        return f"segment file '{shown_path(seg)}' cannot be read: {type(exc).__name__}"
    if not isinstance(meta, dict) or meta.get("fingerprint") != key \
            or meta.get("segment") != index or meta.get("first_sample") != first:
        return f"segment file '{shown_path(seg)}' belongs to another run or place"
    if t.size != n:
        return f"segment file '{shown_path(seg)}' holds {t.size} samples, expected {n}"
    if taps_problem(taps, n):
        return f"segment file '{shown_path(seg)}': {taps_problem(taps, n)}"
    return _inconsistent(t, y, yp, size, None if t_out is None else t_out[first:], {})


def _inconsistent(t, y, yp, size: int, t_out, stats, empty_ok: bool = False) -> str:
    """What is wrong with a checkpoint's contents behind a valid fingerprint ('' if nothing):
    its samples must be the first of the run's output times (after those of its segment
    files: ``t_out`` starts there), each with a finite state of the model's size."""
    if t.dtype.kind != "f" or t.ndim != 1 or (t.size == 0 and not empty_ok):
        return f"sample times of shape {t.shape} and type {t.dtype}, expected 1-D floats"
    if y.ndim != 2 or y.shape != (t.size, size) or y.shape != yp.shape \
            or y.dtype.kind != "f" or yp.dtype.kind != "f":
        return (f"states of shape {y.shape} and {yp.shape}, expected ({t.size}, {size}) floats "
                "(one per sample time)")
    if not np.all(np.isfinite(t)):
        return "a sample time is NaN or infinite"
    if t.size > 1 and not np.all(np.diff(t) > 0):
        return "the sample times do not increase"
    if not (np.all(np.isfinite(y)) and np.all(np.isfinite(yp))):
        return "a stored state is NaN or infinite"
    if not isinstance(stats, dict):
        return f"solver statistics of type {type(stats).__name__}, expected an object"
    if t_out is not None:
        t_out = np.asarray(t_out, dtype=float)
        if t.size == 0:
            return ""
        if t.size > t_out.size:
            return f"{t.size} samples, more than the run's {t_out.size} output times"
        tol = 1e-9 * max(abs(float(t_out[-1])), 1e-300)
        if not np.all(np.abs(t - t_out[: t.size]) <= tol):
            i = int(np.argmax(np.abs(t - t_out[: t.size]) > tol))
            return (f"sample {i} at t = {t[i]:.6g} s, where the run's output time is "
                    f"{t_out[i]:.6g} s")
    return ""


def _peaks_problem(peaks, n: int) -> str:
    """What is wrong with a checkpoint's interval peaks ('' if nothing; None: not kept)."""
    if peaks is None or (peaks.dtype.kind == "f" and peaks.shape == (n, len(PEAKS))):
        return ""
    return f"interval peaks of shape {peaks.shape}, expected ({n}, {len(PEAKS)}) floats"


def tap_rows(X: list) -> dict:
    """``{"taps": (n, TAPS_PER_INTERVAL, TAP_COLUMNS) array}`` of the samples' ring tap rows
    (system/taps.py; NaN where a sample has none), or {} when none has any: a checkpoint
    without a dynamic ring keeps none."""
    from ..system.taps import TAP_COLUMNS, TAPS_PER_INTERVAL

    if all(x is None for x in X):
        return {}
    blank = np.full((TAPS_PER_INTERVAL, TAP_COLUMNS), np.nan)
    return {"taps": np.array([blank if x is None else x for x in X], dtype=float)}


def taps_problem(taps, n: int) -> str:
    """What is wrong with a checkpoint's ring taps ('' if nothing; None: not kept)."""
    from ..system.taps import TAP_COLUMNS, TAPS_PER_INTERVAL

    if taps is None or (taps.dtype.kind == "f"
                        and taps.shape == (n, TAPS_PER_INTERVAL, TAP_COLUMNS)):
        return ""
    return (f"ring taps of shape {taps.shape}, expected ({n}, {TAPS_PER_INTERVAL}, "
            f"{TAP_COLUMNS}) floats")


def _maxima_problem(maxima) -> str:
    """What is wrong with a checkpoint's step maxima ('' if nothing; None: not kept); their
    size is checked against the bearing when they are folded back (Extremes.absorb)."""
    if maxima is None or (maxima.dtype.kind == "f" and maxima.ndim == 1 and maxima.size > 1
                          and not np.isnan(maxima).all()):
        return ""
    return f"step extremes of shape {maxima.shape} and type {maxima.dtype}"
