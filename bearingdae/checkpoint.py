"""Checkpoints of a dynamic run, and resuming from them (``bearingdae run --resume``).

A :class:`Checkpoint` rides on :func:`bearingdae.solvers.ida.integrate` through its
``on_sample(t, y, y')`` hook: it keeps every output sample (scaled y and y') and writes them,
with a fingerprint of the run, to ``<target>.checkpoint.npz`` every ``every_samples`` samples or
``every_s`` seconds of wall time, and once more when the integration stops (completed, failed or
interrupted by Ctrl-C). Each write is atomic (a temporary file beside it, fsync, ``os.replace``),
so a run killed at any moment (even SIGKILL) leaves either the previous checkpoint or the new
one, never a torn file.

Resuming re-initialises IDA at the last sample (t, y, y'): ``init_step`` with
``calc_initcond='yp0'`` re-solves the algebraic unknowns and y' at that t (a consistent state
already, so it changes them only within the Newton tolerance), and IDA restarts at order 1
with a small step. The resumed run therefore follows a different step sequence from an
uninterrupted one and agrees with it to the integration tolerance, not bit for bit
(tests/test_faults.py measures the agreement).

The fingerprint holds the scene (as TOML), the solver, the linear solver, the output times and
the package version: a checkpoint is only resumed by the run that wrote it.
"""

from __future__ import annotations

import hashlib
import json
import time
from pathlib import Path

import numpy as np

from . import __version__
from .atomic import atomic_write

CHECKPOINT_EVERY_SAMPLES = 50
CHECKPOINT_EVERY_S = 10.0
FORMAT = 1


class CheckpointError(ValueError):
    """A checkpoint that cannot be resumed (another scene, unreadable): the message says why."""


def checkpoint_path(target: str | Path) -> Path:
    """The checkpoint beside a NetCDF target: ``run.nc`` -> ``run.nc.checkpoint.npz``."""
    target = Path(target)
    return target.with_name(target.name + ".checkpoint.npz")


def fingerprint(scene, t_out: np.ndarray, solver: str = "ida", linsolver: str = "sparse") -> str:
    h = hashlib.sha256()
    for part in (scene.to_toml(), solver, linsolver, __version__):
        h.update(part.encode("utf-8") + b"\0")
    h.update(np.ascontiguousarray(t_out, dtype=np.float64).tobytes())
    return h.hexdigest()


class Checkpoint:
    """Collects the samples of one run and writes them to ``path``; optionally resumes.

    Use: ``simulate(scene, checkpoint=Checkpoint(path, resume=True))``; after the result is
    saved, :meth:`discard` removes the file.
    """

    def __init__(self, path: str | Path, resume: bool = False,
                 every_samples: int = CHECKPOINT_EVERY_SAMPLES,
                 every_s: float = CHECKPOINT_EVERY_S):
        self.path = Path(path)
        self.resume = resume
        self.every_samples = max(1, int(every_samples))
        self.every_s = float(every_s)
        self.T: list[float] = []
        self.Y: list[np.ndarray] = []
        self.YP: list[np.ndarray] = []
        self.stats: dict = {}
        self.resumed_from_s: float | None = None
        self.writes = 0
        self.write_error: OSError | None = None  #: the last write's failure, None once written
        self._unwritten = 0
        self._last_write = time.monotonic()
        self._key = ""

    # -- the integrator ------------------------------------------------------------------------
    def integrate(self, model, y0, yp0, t_out, linsolver: str = "sparse", progress=None,
                  jacobian: str = "analytic"):
        """Drop-in for :func:`bearingdae.solvers.ida.integrate` that checkpoints, and continues
        from the checkpoint at ``self.path`` when ``resume`` is set and one exists."""
        from .solvers.ida import IntegrationResult, integrate

        t_out = np.asarray(t_out, dtype=float)
        self._key = fingerprint(model.scene, t_out, "ida", linsolver)
        start, y_start, yp_start, rest = 0.0, y0, yp0, t_out
        if self.resume and self.path.exists():
            self._load(model.size)
            start, y_start, yp_start = self.T[-1], self.Y[-1], self.YP[-1]
            self.resumed_from_s = start
            rest = t_out[t_out > start]
            if progress is not None:
                progress(start)
        else:
            self.T, self.Y, self.YP, self.stats = [], [], [], {}
        if rest.size == 0:  # the checkpoint already holds the whole run
            res = IntegrationResult(np.empty(0), np.empty((0, model.size)),
                                    np.empty((0, model.size)), True, "completed", None,
                                    {"residual_calls": 0, "jacobian_calls": 0,
                                     "residual_calls_in_jacobian": 0, "output_samples": 0,
                                     "wall_time_s": 0.0})
        else:
            res = integrate(model, y_start, yp_start, rest, linsolver=linsolver,
                            progress=progress, jacobian=jacobian, t_start=start,
                            on_sample=self.sample)
        self.stats = _merge_stats(self.stats, res.stats)
        self.write()
        stats = dict(self.stats)
        if self.resumed_from_s is not None:
            stats["resumed_from_s"] = self.resumed_from_s
        stats["output_samples"] = len(self.T)
        n = model.size
        return IntegrationResult(np.array(self.T), np.array(self.Y).reshape(-1, n),
                                 np.array(self.YP).reshape(-1, n), res.success, res.message,
                                 res.failure_time_s, stats)

    def sample(self, t: float, y: np.ndarray, yp: np.ndarray) -> None:
        """``on_sample`` hook: keep the sample; write when enough samples or time have passed."""
        self.T.append(float(t)), self.Y.append(np.array(y)), self.YP.append(np.array(yp))
        self._unwritten += 1
        if (self._unwritten >= self.every_samples
                or time.monotonic() - self._last_write >= self.every_s):
            self.write()

    # -- files ---------------------------------------------------------------------------------
    def write(self) -> None:
        """Write every sample so far, atomically (no-op before the first sample)."""
        if not self.T:
            return
        meta = {"format": FORMAT, "fingerprint": self._key, "bearingdae_version": __version__,
                "stats": self.stats}
        try:
            _atomic_savez(self.path, t=np.array(self.T), y=np.array(self.Y),
                          yp=np.array(self.YP), meta=np.array(json.dumps(meta)))
        except OSError as exc:
            # A full disk must not stop the run: the samples stay in memory (the caller saves
            # them, or a fallback copy) and the error is kept for the caller to report.
            self.write_error = exc
            self._unwritten = 0
            self._last_write = time.monotonic()
            return
        self.write_error = None  # the file now holds every sample so far
        self.writes += 1
        self._unwritten = 0
        self._last_write = time.monotonic()

    def _load(self, size: int) -> None:
        try:
            with np.load(self.path, allow_pickle=False) as z:
                meta = json.loads(str(z["meta"]))
                t, y, yp = z["t"], z["y"], z["yp"]
        except Exception as exc:  # a foreign or damaged file: say which and what to do
            raise CheckpointError(
                f"checkpoint '{self.path}' cannot be read ({type(exc).__name__}: {exc}); delete "
                "it to start the run afresh") from None
        if meta.get("format") != FORMAT or meta.get("fingerprint") != self._key:
            raise CheckpointError(
                f"checkpoint '{self.path}' was written by a different run (scene, solver, output "
                f"times or bearingdae version differ); delete it, or run without --resume to "
                "overwrite it")
        if y.ndim != 2 or y.shape[1] != size or t.size == 0 or y.shape != yp.shape:
            raise CheckpointError(f"checkpoint '{self.path}' holds states of the wrong size; "
                                  "delete it to start afresh")
        self.T, self.Y, self.YP = list(map(float, t)), list(y), list(yp)
        self.stats = meta.get("stats", {})

    def discard(self) -> None:
        """Remove the checkpoint (after the result has been saved)."""
        try:
            self.path.unlink()
        except FileNotFoundError:
            pass


def _merge_stats(before: dict, now: dict) -> dict:
    """Counters of the segments of a resumed run, summed."""
    out = dict(now)
    for key, value in before.items():
        if key in now and isinstance(value, (int, float)) and isinstance(now[key], (int, float)) \
                and not isinstance(value, bool):
            out[key] = now[key] + value
    if before:
        out["segments"] = int(before.get("segments", 1)) + 1
    return out


def _atomic_savez(path: Path, **arrays) -> None:
    """np.savez through atomic.atomic_write: a reader or a killed writer never sees a partial
    file at ``path``."""
    with atomic_write(path) as tmp, open(tmp, "wb") as fh:
        np.savez(fh, **arrays)
