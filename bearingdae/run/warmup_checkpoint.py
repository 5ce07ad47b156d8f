"""The warm-up's checkpoint (run/steady.py): the state, block means, solver statistics and
thermal coupling after each block, written atomically beside the run's checkpoint
(``run.nc.checkpoint.npz`` -> ``run.nc.warmup.npz``), and read back only by the same scene
(its identity with its input files) and bearingdae version, every field checked.

A dynamic ring's taps (system/taps.py) of the last intervals before the block's end are kept
too: the record's first samples are filtered over them, so a record recomputed after a resume
is filtered as the uninterrupted one (without them its first samples fell back to the
triangle mean).
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..system.taps import TAP_COLUMNS

#: 2: the ring taps (``taps``) are kept; a file of format 1 lacks them, and is read only by a
#: run that keeps no taps (no dynamic ring, or a solver that does not tap it)
FORMAT = 2


@dataclass
class Run:
    """Warm-up bookkeeping (resumable state)."""

    t: float
    y: np.ndarray
    yp: np.ndarray
    means: list = field(default_factory=list)
    stats: dict = field(default_factory=dict)
    segments: int = 0
    coupling: dict = field(default_factory=dict)  #: state of run/thermal_coupling.py
    #: a dynamic ring's taps the next segment continues: rows (t [s], δ_r [m], δ_t [m])
    #: (system/taps.py), none without a dynamic ring or a solver that taps it
    taps: np.ndarray = field(default_factory=lambda: np.empty((0, TAP_COLUMNS)))


def fingerprint(model, solver=None) -> str:
    """Hash of what makes a warm-up: the scene (its text and input files), the solver's name
    and settings (``solver.describe()``: a warm-up resumed under another integrator, linear
    solver or tolerance factor would continue one run with another's state) and the version."""
    from .. import __version__

    h = hashlib.sha256()
    parts = [model.scene.identity(), "until_steady", __version__]
    if solver is not None:
        d = solver.describe()
        parts += [str(d["solver"]), json.dumps(d["options"], sort_keys=True, default=str)]
    for part in parts:
        h.update(part.encode("utf-8") + b"\0")
    return h.hexdigest()


def save(path: Path, key: str, run: Run, inputs: dict | None = None) -> None:
    from ..util.atomic import atomic_write

    meta = {"format": FORMAT, "fingerprint": key, "means": run.means, "stats": run.stats,
            "segments": run.segments, "t": run.t}
    if run.coupling:
        meta["coupling"] = run.coupling
    if inputs:  # the scene's input files (Scene.input_files): to name one that changed
        meta["inputs"] = {k: list(v) for k, v in inputs.items()}
    with atomic_write(path) as tmp, open(tmp, "wb") as fh:
        np.savez(fh, y=run.y, yp=run.yp, taps=np.asarray(run.taps, dtype=float),
                 meta=np.array(json.dumps(meta)))


def load(path: Path, key: str, size: int, horizon: float = np.inf,
          inputs: dict | None = None, taps_needed: bool = True) -> Run | None:
    """The warm-up of ``path`` if it is this run's (``key``, a state of ``size``), every field
    checked; else a CheckpointError naming what differs. ``taps_needed``: the run continues a
    dynamic ring's taps; without them a file of format 1 (which lacks its taps, and nothing
    else) is as good as one of this format."""
    from .checkpoint import CheckpointError

    try:
        with np.load(path, allow_pickle=False) as z:
            meta = json.loads(str(z["meta"]))
            y, yp = np.array(z["y"]), np.array(z["yp"])
            taps = np.array(z["taps"]) if "taps" in z else None
    except Exception as exc:
        raise CheckpointError(f"warm-up checkpoint '{path}' cannot be read "
                              f"({type(exc).__name__}: {exc}); delete it to start afresh") \
            from None
    if not isinstance(meta, dict):
        raise CheckpointError(f"warm-up checkpoint '{path}' is damaged: its metadata is not a "
                              "JSON object; delete it to start afresh")
    form = meta.get("format")
    if form == 1 and not taps_needed and taps is None:
        form, taps = FORMAT, np.empty((0, TAP_COLUMNS))
    if form != FORMAT and isinstance(form, int) and not isinstance(form, bool) \
            and meta.get("fingerprint") == key:
        raise CheckpointError(f"warm-up checkpoint '{path}' is of format {form}, this "
                              f"bearingdae reads format {FORMAT} (it also keeps the ring's "
                              "taps); delete it to start afresh, or run without --resume")
    if form != FORMAT or meta.get("fingerprint") != key or y.shape != (size,):
        from .checkpoint import _changed_input

        changed = _changed_input(meta.get("inputs"), inputs or {})
        if changed:
            raise CheckpointError(f"warm-up checkpoint '{path}' was written with other "
                                  f"contents of {changed}: resuming would continue the old "
                                  "warm-up under the new file; delete it, or run without "
                                  "--resume")
        raise CheckpointError(f"warm-up checkpoint '{path}' was written by a different run "
                              "(scene, solver or bearingdae version differ); delete it, or run "
                              "without --resume")
    t, means, stats, segments = (meta.get(k) for k in ("t", "means", "stats", "segments"))
    problem = ""
    if isinstance(t, bool) or not isinstance(t, (int, float)) or not np.isfinite(t) \
            or not 0 <= t <= horizon * (1 + 1e-9):
        problem = f"its time {t!r:.100} is not a time between 0 and the run's horizon"
    elif not (isinstance(means, list) and all(isinstance(m, (int, float))
                                              and not isinstance(m, bool) for m in means)):
        problem = "its block means are not a list of numbers"
    elif not isinstance(stats, dict) or isinstance(segments, bool) \
            or not isinstance(segments, int) or segments < 0:
        problem = "its solver statistics or segment count are not what a run writes"
    elif not (y.dtype.kind == yp.dtype.kind == "f" and y.shape == yp.shape
              and np.all(np.isfinite(y)) and np.all(np.isfinite(yp))):
        problem = "its state is not finite"
    elif taps is None:
        problem = "it keeps no ring taps"
    else:
        problem = _taps_problem(taps, float(t))
    if problem:
        raise CheckpointError(f"warm-up checkpoint '{path}' is damaged ({problem}); delete it "
                              "to start afresh")
    coupling = meta.get("coupling") or {}
    return Run(float(t), y, yp, list(means), dict(stats), int(segments),
               coupling if isinstance(coupling, dict) else {}, taps)


def _taps_problem(taps: np.ndarray, t_s: float) -> str:
    """What is wrong with a warm-up checkpoint's ring taps ('' if nothing): rows (t, δ_r,
    δ_t) of finite floats, their times increasing and none after the state's time ``t_s``."""
    if not (taps.dtype.kind == "f" and taps.ndim == 2 and taps.shape[1] == TAP_COLUMNS):
        return f"its ring taps are not rows of {TAP_COLUMNS} numbers"
    if not np.all(np.isfinite(taps)):
        return "its ring taps are not finite"
    if taps.shape[0] and (np.any(np.diff(taps[:, 0]) <= 0) or taps[-1, 0] > t_s):
        return "its ring taps' times do not increase up to the state's time"
    return ""


def warmup_path(checkpoint) -> Path | None:
    """The warm-up checkpoint beside a :class:`bearingdae.run.checkpoint.Checkpoint`'s file
    (``run.nc.checkpoint.npz`` -> ``run.nc.warmup.npz``), or None without a checkpoint."""
    if checkpoint is None:
        return None
    p = Path(checkpoint.path)
    return p.with_name(p.name.removesuffix(".checkpoint.npz") + ".warmup.npz")
