"""Runs that several test modules read, computed once per test session.

The baseline over 1 warm-up + 24 recorded cage revolutions (IDA at the scene's rtol 1e-6) is
read by three slow modules: tests/solvers/test_newmark.py (IDA's side of the Newmark
cross-check), tests/validation/test_statistical_equivalence.py (its statistics against the
documented run) and tests/validation/test_cage_whirl.py (the rotating-only cage's mean speed,
the whirling cage's reference). Each computed it (the last one over 20 revolutions): three
runs of the same scene, of which two are now saved.

Under xdist the modules may run on different workers: :func:`shared_simulate` keeps the run
in a file of the session's folder (tests/conftest.py gives every worker the same), keyed by
the scene (its complete TOML) and the solver. A worker holds an exclusive ``flock`` on the
key's lock while it computes; another that needs the same run waits for it and reads the
file. The file is a pickle of the Dataset, so every reader gets the computing worker's
Dataset exactly (the code is the same within a session). Outside xdist (no folder) the
session-scoped fixture of tests/conftest.py keeps it in memory.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import pickle
import warnings
from pathlib import Path

#: the long baseline: 1 warm-up (the scene's default) + 24 recorded cage revolutions, i.e.
#: 8 windows of 3 revolutions; max_steps for Newmark's 2 µs steps over it
LONG_BASELINE = ("yang20_baseline", {"numerics.cage_revolutions": 24.0,
                                     "numerics.max_steps": 2_000_000})


def long_baseline_scene():
    from bearingdae import load_scene

    case, overrides = LONG_BASELINE
    return load_scene(case, overrides)


def _simulate(scene, solver: str):
    from bearingdae import simulate

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # λ < 1 on the baseline (boundary lubrication)
        return simulate(scene, solver=solver, progress=False)


def shared_simulate(scene, folder: Path | None, solver: str = "ida"):
    """``simulate(scene, solver=solver)``, computed once by the workers sharing ``folder``
    (None: computed here)."""
    if folder is None:
        return _simulate(scene, solver)
    folder.mkdir(parents=True, exist_ok=True)
    key = hashlib.sha1(f"{solver}\n{scene.to_toml(complete=True)}".encode()).hexdigest()[:20]
    path = folder / f"{key}.pickle"
    fd = os.open(folder / f"{key}.lock", os.O_CREAT | os.O_WRONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)  # released at the process's exit, too
        if path.exists():
            with open(path, "rb") as f:
                return pickle.load(f)
        ds = _simulate(scene, solver)
        partial = path.with_suffix(".partial")
        with open(partial, "wb") as f:
            pickle.dump(ds, f, protocol=pickle.HIGHEST_PROTOCOL)
        os.replace(partial, path)  # a reader never sees half a file
        return ds
    finally:
        os.close(fd)
