"""Checkpoints of a dynamic run, and resuming from them (``bearingdae run --resume``).

:class:`Checkpointed` wraps any solver of the contract (solvers/base.py): a
:class:`Checkpoint` rides on the solver's ``on_sample(t, y, y')`` hook: it keeps every output
sample (scaled y and y') and writes them, with a fingerprint of the run, to
``<target>.checkpoint.npz`` every ``every_samples`` samples or ``every_s`` seconds of wall time
(by default every 50 samples but at most once a second), and once more when the integration
stops (completed, failed or interrupted by Ctrl-C). Each write is atomic (a temporary file
beside it, fsync, ``os.replace``), so a run killed at any moment (even SIGKILL) leaves either
the previous checkpoint or the new one, never a torn file.

Resuming restarts the solver at the last sample (``t_start``, y, y'). For IDA: ``init_step`` with
``calc_initcond='yp0'`` re-solves the algebraic unknowns and y' at that t (a consistent state
already, so it changes them only within the Newton tolerance), and IDA restarts at order 1
with a small step. The resumed run therefore follows a different step sequence from an
uninterrupted one and agrees with it to the integration tolerance, not bit for bit
(tests/robustness/test_faults.py measures the agreement).

With per-step extremes (system/extremes.py) it also keeps each sample's interval peaks and the
window's step maxima; a resume folds them back (``Extremes.absorb``): a resumed run's peak
traces, per-pass peak statistics and ``_max`` come from every step, as an uninterrupted run's.

The fingerprint holds the scene (as TOML), the solver, the linear solver, the output times and
the package version: a checkpoint is only resumed by the run that wrote it.
"""

from __future__ import annotations

import hashlib
import json
import os
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np

from .. import __version__
from ..util.atomic import atomic_write, fit_name, shown_path
from ..solvers.base import Solver
from ..system.extremes import PEAKS

CHECKPOINT_EVERY_SAMPLES = 50
CHECKPOINT_EVERY_S = 10.0
#: with the default ``every_samples``: at least this much wall time between two writes [s].
#: Why: each write rewrites the samples held (up to a segment) and fsyncs; at 4 000 samples
#: per cage revolution 50 samples are ~15 ms of computing, and a write every 50 samples cost
#: ~75 µs per sample, more than the rest of a sample (docs/performance.md, "Dense output").
#: A run killed loses at most this second (or the 50 samples, whichever is more).
CHECKPOINT_MIN_INTERVAL_S = 1.0
FORMAT = 1
from .segments import (SEGMENT_SAMPLES, _Held, _inconsistent,  # noqa: E402,F401
                       _maxima_problem, _peaks_problem, _segment_problem, segment_path,
                       tap_rows, taps_problem)


class CheckpointError(ValueError):
    """A checkpoint that cannot be resumed (another scene, unreadable): the message says why."""


def checkpoint_path(target: str | Path) -> Path:
    """The checkpoint beside a NetCDF target: ``run.nc`` -> ``run.nc.checkpoint.npz``."""
    target = Path(target)
    return fit_name(target.with_name(target.name + ".checkpoint.npz"), ".checkpoint.npz")


def fingerprint(scene, t_out: np.ndarray, solver: str = "ida", linsolver: str = "sparse") -> str:
    """Hash of what makes a run: the scene (its text and the contents of the files it read,
    ``Scene.identity``), the solver's name and settings (``linsolver``: any
    text, e.g. the JSON of ``describe()["options"]``), the output times and the version."""
    h = hashlib.sha256()
    for part in (scene.identity(), solver, linsolver, __version__):
        h.update(part.encode("utf-8") + b"\0")
    h.update(np.ascontiguousarray(t_out, dtype=np.float64).tobytes())
    return h.hexdigest()


class Checkpoint:
    """Collects the samples of one run and writes them to ``path``; optionally resumes.

    Use: ``simulate(scene, checkpoint=Checkpoint(path, resume=True))`` (or
    ``Checkpointed(solver, checkpoint)``); after the result is saved, :meth:`discard` removes
    the file.
    """

    def __init__(self, path: str | Path, resume: bool = False,
                 every_samples: int | None = None,
                 every_s: float = CHECKPOINT_EVERY_S):
        if not isinstance(path, (str, os.PathLike)):
            raise TypeError(f"Checkpoint: path: expected a file path, got {type(path).__name__}")
        if not isinstance(resume, (bool, np.bool_)):
            raise TypeError(f"Checkpoint: resume: expected True or False, got "
                            f"{type(resume).__name__}")
        # None: every CHECKPOINT_EVERY_SAMPLES samples, at most once per
        # CHECKPOINT_MIN_INTERVAL_S; a number given: every that many samples exactly
        self.min_interval_s = CHECKPOINT_MIN_INTERVAL_S if every_samples is None else 0.0
        if every_samples is None:
            every_samples = CHECKPOINT_EVERY_SAMPLES
        if isinstance(every_samples, bool) or not isinstance(every_samples, (int, np.integer)) \
                or every_samples < 1:
            raise ValueError(f"Checkpoint: every_samples (--checkpoint-every) = "
                             f"{every_samples!r:.100}: expected an integer >= 1")
        if isinstance(every_s, bool) or not isinstance(every_s, (int, float, np.floating)) \
                or not every_s > 0:
            raise ValueError(f"Checkpoint: every_s = {every_s!r:.100}: expected a number of "
                             "seconds > 0")
        self.path = Path(path)
        self.resume = bool(resume)
        self.every_samples = int(every_samples)
        self.every_s = float(every_s)
        self.T: list[float] = []
        self.Y: list[np.ndarray] = []
        self.YP: list[np.ndarray] = []
        self.P: list[np.ndarray] = []  #: each sample's interval peaks (NaN: none)
        #: each sample's ring taps since the sample before (system/taps.py; None: none), and
        #: the solver's taps (a callable giving model.ring_taps)
        self.X: list[np.ndarray | None] = []
        self.taps = lambda: None
        self._t_last: float | None = None
        self.stats: dict = {}
        #: the running extremes of the run being checkpointed (a callable giving the solver's
        #: Extremes or None), and those a resumed checkpoint held (maxima, peak times, peaks)
        self.extremes = lambda: None
        self.held_steps: tuple | None = None
        self._held_maxima: np.ndarray | None = None
        self.segments: list[dict] = []  #: the segment files written: {"samples": n}
        self._size = 0
        self.resumed_from_s: float | None = None
        self.writes = 0
        self.write_error: OSError | None = None  #: the last write's failure, None once written
        self._unwritten = 0
        self._last_write = time.monotonic()
        self._key = ""

    # -- the integrator ------------------------------------------------------------------------
    def integrate(self, model, y0, yp0, t_out, linsolver: str = "sparse", progress=None,
                  jacobian: str = "analytic"):
        """Deprecated: ``Checkpointed(IDA(linsolver, jacobian), self).integrate(model, y0, yp0,
        t_out, progress=progress)``."""
        import warnings

        from ..solvers.ida import IDA

        warnings.warn("Checkpoint.integrate is deprecated; use Checkpointed(solver, checkpoint)"
                      ".integrate(...) or simulate(scene, solver, checkpoint=checkpoint)",
                      DeprecationWarning, stacklevel=2)
        return Checkpointed(IDA(linsolver, jacobian), self).integrate(model, y0, yp0, t_out,
                                                                      progress=progress)

    def begin(self, key: str, size: int, t_out: np.ndarray | None = None,
              inputs: dict | None = None) -> list[tuple[float, np.ndarray, np.ndarray]]:
        """Start a run with fingerprint ``key``: the samples already held (resume) or none.
        ``t_out``: the run's output times, which the samples of a checkpoint must be the first
        of (its fingerprint covers them); ``inputs``: the scene's input files (``{key: (path,
        SHA-256)}``, ``Scene.input_files``), kept to name the one that changed."""
        self._key, self._size = key, int(size)
        self._inputs = {k: list(v) for k, v in (inputs or {}).items()}
        self.resumed_from_s = None
        self.held_steps = self._held_maxima = None
        if self.resume and self.path.exists():
            self._load(size, t_out)
            held = _Held(self)
            self.resumed_from_s = held.last[0]
            if self._held_maxima is not None:
                self.held_steps = (self._held_maxima, *held.peaks())
            return held
        self.T, self.Y, self.YP, self.P, self.stats, self.segments = [], [], [], [], {}, []
        self.X, self._t_last = [], None
        return _Held(self)

    @property
    def sampled_until_s(self) -> float | None:
        """The time before which a resumed run's extremes come from its output samples only
        (its checkpoint kept no step extremes), None when every step counts."""
        return None if self.held_steps is not None else self.resumed_from_s

    def sample(self, t: float, y: np.ndarray, yp: np.ndarray) -> None:
        """``on_sample`` hook: keep the sample (with the interval peaks the solver closed at
        it, when it keeps step extremes); write when enough samples or time have passed."""
        ext = self.extremes()
        self.T.append(float(t)), self.Y.append(np.array(y)), self.YP.append(np.array(yp))
        self.P.append(np.full(len(PEAKS), np.nan) if ext is None else ext.closed_peaks(t))
        taps = self.taps()
        self.X.append(None if taps is None else taps.rows_since(self._t_last))
        self._t_last = float(t)
        self._unwritten += 1
        if len(self.T) >= SEGMENT_SAMPLES:
            self._roll()
        else:
            elapsed = time.monotonic() - self._last_write
            if ((self._unwritten >= self.every_samples and elapsed >= self.min_interval_s)
                    or elapsed >= self.every_s):
                self.write()

    # -- files ---------------------------------------------------------------------------------
    def _roll(self) -> None:
        """The samples held move to the next segment file (written once, atomically); the
        checkpoint file then names it. A segment that cannot be written stays in memory."""
        index = len(self.segments) + 1
        meta = {"format": FORMAT, "fingerprint": self._key, "segment": index,
                "first_sample": sum(seg["samples"] for seg in self.segments)}
        try:
            _atomic_savez(segment_path(self.path, index), t=np.array(self.T),
                          y=np.array(self.Y), yp=np.array(self.YP), peaks=self._peak_rows(),
                          meta=np.array(json.dumps(meta)), **tap_rows(self.X))
        except OSError as exc:
            self.write_error = exc
            self.write()
            return
        self.segments.append({"samples": len(self.T)})
        self.T, self.Y, self.YP, self.P, self.X = [], [], [], [], []
        self.write()

    def _peak_rows(self) -> np.ndarray:
        return np.array(self.P, dtype=float).reshape(len(self.P), len(PEAKS))

    def _maxima(self) -> np.ndarray | None:
        """The window's step maxima so far: the solver's, with those a resumed checkpoint
        held folded in unless the solver has them already (None: no step extremes)."""
        ext = self.extremes()
        if ext is None:
            return self._held_maxima
        m = ext.maxima()
        if self._held_maxima is not None and not ext.absorbed:
            from ..system.extremes import Extremes

            both = Extremes(ext.rollers, ext.slices, ext.t_from)
            both.buffer[:] = ext.buffer
            both.absorb(self._held_maxima, [], [])
            m = both.maxima()
        return m

    def write(self) -> None:
        """Write every sample so far, atomically (no-op before the first sample): those held
        here and the names of the segment files before them."""
        if not self.T and not self.segments:
            return
        meta = {"format": FORMAT, "fingerprint": self._key, "bearingdae_version": __version__,
                "stats": self.stats}
        if getattr(self, "_inputs", None):
            meta["inputs"] = self._inputs
        if self.segments:
            meta["segments"] = self.segments
        steps = self._maxima()
        extra = {} if steps is None else {"extremes": steps}
        try:
            _atomic_savez(self.path, **extra, **tap_rows(self.X), peaks=self._peak_rows(),
                          t=np.array(self.T, dtype=float),
                          y=np.array(self.Y, dtype=float).reshape(len(self.T), -1)
                          if self.T else np.empty((0, self._size)),
                          yp=np.array(self.YP, dtype=float).reshape(len(self.T), -1)
                          if self.T else np.empty((0, self._size)),
                          meta=np.array(json.dumps(meta)))
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

    def _load(self, size: int, t_out: np.ndarray | None = None) -> None:
        shown = shown_path(self.path)
        try:
            with np.load(self.path, allow_pickle=False) as z:
                meta = json.loads(str(z["meta"]))
                t, y, yp = np.array(z["t"]), np.array(z["y"]), np.array(z["yp"])
                peaks = np.array(z["peaks"]) if "peaks" in z else None
                maxima = np.array(z["extremes"]) if "extremes" in z else None
                taps = np.array(z["taps"]) if "taps" in z else None
        except Exception as exc:  # a foreign or damaged file: say which and what to do
            raise CheckpointError(
                f"checkpoint '{shown}' cannot be read ({type(exc).__name__}: "
                f"{str(exc)[:100]}); delete it to start the run afresh") from None
        if not isinstance(meta, dict):
            raise CheckpointError(f"checkpoint '{shown}' is damaged: its metadata is a JSON "
                                  f"{type(meta).__name__}, not an object; delete it to start "
                                  "afresh")
        if meta.get("format") != FORMAT or meta.get("fingerprint") != self._key:
            changed = _changed_input(meta.get("inputs"), getattr(self, "_inputs", {}))
            if changed:
                raise CheckpointError(
                    f"checkpoint '{shown}' was written with other contents of {changed}: "
                    "resuming would continue the old run under the new file; delete the "
                    "checkpoint, or run without --resume to start afresh")
            raise CheckpointError(
                f"checkpoint '{shown}' was written by a different run (scene, solver, output "
                f"times or bearingdae version differ); delete it, or run without --resume to "
                "overwrite it")
        segments = meta.get("segments", [])
        if not (isinstance(segments, list) and all(
                isinstance(g, dict) and isinstance(g.get("samples"), int) and g["samples"] > 0
                for g in segments)):
            raise CheckpointError(f"checkpoint '{shown}' is damaged: its list of segment files "
                                  "is not valid; delete it to start afresh")
        first = 0
        for index, seg in enumerate(segments, 1):  # each read and checked, none kept
            problem = _segment_problem(self.path, index, seg["samples"], first, self._key,
                                       size, t_out)
            if problem:
                raise CheckpointError(f"checkpoint '{shown}' is damaged ({problem}); delete it "
                                      "and its segment files to start afresh")
            first += seg["samples"]
        problem = _inconsistent(t, y, yp, size, None if t_out is None else t_out[first:],
                                meta.get("stats", {}), empty_ok=bool(segments)) \
            or _peaks_problem(peaks, t.size) or _maxima_problem(maxima) \
            or taps_problem(taps, t.size)
        if problem:
            raise CheckpointError(f"checkpoint '{shown}' is damaged ({problem}); delete it to "
                                  "start afresh")
        self.T, self.Y, self.YP = list(map(float, t)), list(y), list(yp)
        self.P = list(peaks) if peaks is not None else [np.full(len(PEAKS), np.nan)] * t.size
        self.X = list(taps) if taps is not None else [None] * t.size
        self._held_maxima = maxima
        self.segments = segments
        self.stats = meta.get("stats", {})

    def discard(self) -> None:
        """Remove the checkpoint and its segment files (after the result has been saved)."""
        for p in [self.path] + [segment_path(self.path, i)
                                for i in range(1, len(self.segments) + 1)]:
            try:
                p.unlink()
            except FileNotFoundError:
                pass


def _changed_input(held, now: dict) -> str:
    """'the file 'P' ('KEY')' of the first input file whose contents (SHA-256) differ between a
    checkpoint's ``held`` record and the scene's ``now`` ('' if none, or the checkpoint keeps
    no record: one written before the record was kept gets the general message)."""
    if not isinstance(held, dict):
        return ""
    for key, (path, digest) in sorted(now.items()):
        was = held.get(key)
        if not (isinstance(was, list) and len(was) == 2) or was[1] != digest:
            return f"the file '{shown_path(path)}' ('{key}')"
    return ""


class Checkpointed(Solver):
    """Any :class:`~bearingdae.solvers.base.Solver` with checkpoints: ``Checkpointed(IDA(),
    Checkpoint(path, resume=True))``.

    Every sample of the inner run goes to ``checkpoint.sample`` (``on_sample`` of the inner
    solver), which writes the file as it goes; the file is written once more when the run stops.
    With ``checkpoint.resume`` and a checkpoint of the same run (fingerprint) on disk, its
    samples are handed on first and the inner solver continues from the last one
    (``t_start``). Counters of all segments are summed; ``resumed_from_s`` and ``segments``
    say that the run was resumed.
    """

    def __init__(self, solver: Solver, checkpoint: Checkpoint):
        if not isinstance(solver, Solver):
            raise TypeError(f"solver: expected a bearingdae Solver, got {type(solver).__name__}")
        if not isinstance(checkpoint, Checkpoint):
            raise TypeError(f"checkpoint: expected a Checkpoint, got "
                            f"{type(checkpoint).__name__}")
        self.solver, self.checkpoint = solver, checkpoint
        self._extra: dict = {}

    @property
    def name(self) -> str:  # type: ignore[override]
        return self.solver.name

    @property
    def locates_edges(self) -> bool:  # type: ignore[override]
        return self.solver.locates_edges  # the inner solver's root finding does it

    def describe(self) -> dict:
        d = dict(self.solver.describe())
        d["solver_description"] = d["solver_description"] + " (checkpointed)"
        return d

    def dataset_attrs(self, model, solution) -> dict:
        return self.solver.dataset_attrs(model, solution)

    def extra_stats(self) -> dict:
        return dict(self._extra)

    def error_estimate(self, n_samples: int):
        if self.checkpoint.resumed_from_s is not None:
            return None  # the earlier segment's estimates were not kept
        return self.solver.error_estimate(n_samples)

    def _run(self, model, y0, yp0, t_out, t_start, emit):
        ck = self.checkpoint
        d = self.solver.describe()
        held = ck.begin(fingerprint(model.scene, t_out, d["solver"],
                                    json.dumps(d["options"], sort_keys=True, default=str)),
                        model.size, t_out, model.scene.input_files())
        before = dict(ck.stats)
        if ck.held_steps is not None and self._extremes_from is not None:
            from ..system.extremes import Extremes

            size = Extremes(model.layout.rollers, model.geometry.slices, 0.0).maxima().size
            if ck.held_steps[0].size != size:
                raise CheckpointError(f"checkpoint '{shown_path(ck.path)}' is damaged (step "
                                      f"extremes of size {ck.held_steps[0].size}, expected "
                                      f"{size}); delete it to start afresh")
        self._extra = {}
        start, y_start, yp_start = t_start, y0, yp0
        ck.taps = lambda: model.ring_taps
        # a dynamic ring's replayed samples are filtered with the taps they were sampled with,
        # which the solver then continues (system/taps.py)
        restored = None
        if held and model.layout.ring_dynamic and getattr(self.solver, "ring_taps", False):
            from ..system.taps import RingTaps

            restored = model.ring_taps = RingTaps(model)
        for t, y, yp, rows in held.samples():
            if restored is not None and rows is not None:
                restored.restore(rows)
            emit(t, y, yp)
        if held:
            start, y_start, yp_start = held.last
            ck._t_last = float(start)
        model.ring_taps_carried = restored
        rest = t_out[t_out > start] if held else t_out

        # the inner solver's step extremes: each sample's interval peaks and the maxima
        ck.extremes = lambda: getattr(self.solver, "_extremes", None)

        from ..util.ctrl_c import ctrl_c_deferred

        def hook(t, y, yp):
            # a Ctrl-C waits until the sample is in the record and the checkpoint alike: landing
            # between the two it left the checkpoint a sample the record lacked
            with ctrl_c_deferred():
                try:
                    emit(t, y, yp)
                finally:  # (an error on the way: the checkpoint keeps the sample all the same)
                    ck.sample(t, y, yp)

        res = None
        try:
            if rest.size == 0:  # the checkpoint already holds the whole run
                if ck.held_steps is not None and self._extremes_from is not None:
                    # its step extremes and peaks, as kept: nothing is integrated to fold
                    # them into, and without them the results fell back to the samples
                    from ..system.extremes import Extremes

                    self._extremes = Extremes(model.layout.rollers, model.geometry.slices,
                                              self._extremes_from)
                    self._extremes.absorb(*ck.held_steps)
                return True, "completed", None
            res = self.solver.integrate(model, y_start, yp_start, rest, t_start=start,
                                        on_sample=hook, extremes_from=self._extremes_from,
                                        keep_samples=self._keep_samples)
            self._extremes = res.extremes
            if res.extremes is not None and held:
                if ck.held_steps is not None:  # the part before: its steps, as kept
                    res.extremes.absorb(*ck.held_steps)
                else:  # a checkpoint without them: the part before from its samples
                    res.extremes.steps_from = max(res.extremes.t_from, start)
            return res.success, res.message, res.failure_time_s
        finally:
            model.ring_taps_carried = None  # (taken by a solver that started)
            merged = _merge_stats(before, res.stats if res is not None else {})
            ck.stats = merged
            ck.write()
            for key in asdict(self.counters):
                setattr(self.counters, key, int(merged.get(key, 0)))
            self._extra = {k: v for k, v in merged.items()
                           if k not in asdict(self.counters)
                           and k not in ("output_samples", "wall_time_s")}
            if "wall_time_s" in merged:
                self._extra["wall_time_s_all_segments"] = merged["wall_time_s"]
            if ck.resumed_from_s is not None:
                self._extra["resumed_from_s"] = ck.resumed_from_s


def _merge_stats(before: dict, now: dict) -> dict:
    """The statistics of the segments of a resumed run (solvers/base.merge_statistics), with
    their count."""
    from ..solvers.base import merge_statistics

    out = merge_statistics(before, now)
    if before:
        out["segments"] = int(before.get("segments", 1)) + 1
    return out


def _atomic_savez(path: Path, **arrays) -> None:
    """np.savez through atomic.atomic_write: a reader or a killed writer never sees a partial
    file at ``path``."""
    with atomic_write(path) as tmp, open(tmp, "wb") as fh:
        np.savez(fh, **arrays)
