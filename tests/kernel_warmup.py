"""Compile each switch pattern's kernels once per test session, shared by the xdist workers.

Every pattern of the effects compiled apart (system/optional.py: flanges, cage whirl, rolling
resistance, mixed lubrication, and a defect table) is a kernel family of its own: its first
use compiles what of the residual, the analytic Jacobian, the projection of the samples and the
IDA callbacks the default scene's kernels do not cover (12-18 s of CPU cold on a 2-CPU Xeon,
2026-11-30). numba's cache is shared on disk, but two processes that miss it at the same time
both compile: under ``-n 2`` the workers did so (measured: the
flange pattern's residual and Jacobian, 33 s of CPU, compiled at once for test_static.py and
test_fuzz_scene.py).

Here (tests/conftest.py, :func:`warm_patterns`) each worker of an xdist session, before its
first test, claims the patterns its session needs one at a time (a file linked to its name in a
folder of the session: the first worker to create it compiles that pattern, the other skips to
the next) and compiles a claimed one by a tiny run of a scene with it, holding an exclusive
``flock`` on the claim (taken before the claim appears); the two workers thus compile disjoint
halves at once. Then each waits (a shared ``flock``) for the patterns the other is still
compiling, and its tests load every kernel from the cache. A pattern already in the cache (a
warm session) costs one read of a cache index. The warm-up compiles what the tests would
compile anyway, the same machine code (numba's cache): no result changes, only when and where
it compiles.

:data:`PATTERNS` says, per pattern, which test modules need it (their source names its
switch): a session warms only the patterns of the modules it runs. A wrong guess costs time,
never a result: a pattern not warmed compiles in the test that needs it, as it would without
this file, and :func:`share_compiles` still keeps two workers from compiling it at once.
"""

from __future__ import annotations

import fcntl
import os
import tempfile
import warnings
from pathlib import Path

# the tiny run that compiles a pattern (a start, a few IDA steps, three samples projected):
# the one a sweep's client compiles a kernel variant by
from bearingdae.studies.sweep.cluster import _TINY

# an axial load needs a radial one to hold the rollers (the preset's scene has none; without it
# the flanges' quasi-static start does not converge and the pattern was never warmed)
_NJ = {"bearing.type": "NJ", "operating.axial_load_N": 200.0, "operating.radial_load_N": 800.0}
_WHIRL = {"physics.cage_whirl": True, "cage.guidance": "outer-land"}
_RR = {"physics.rolling_resistance": True}

#: pattern (system/optional.pattern_tag, or "defects") -> (overrides of a yang20 scene that
#: switch exactly it on, a regular expression: a test module whose source matches it needs the
#: pattern), the costliest first. The fast tier's runs need these (measured with numba's
#: "numba:compile" events); a pattern not listed compiles in its test, once per session
#: (:func:`share_compiles`).
PATTERNS: dict[str, tuple[dict, str]] = {
    "0000": ({}, r""),  # every module that runs anything
    "1000": (_NJ, r"\bNJ\b|\bNUP\b|flange|nj_axial|bundled"),
    "defects": ({"defects": [{"on": "inner", "angle_deg": 0.0, "length_mm": 1.5,
                              "width_mm": 8.0, "depth_um": 20.0}]}, r"defect|spall|waviness"),
    "0100": (_WHIRL, r"cage_whirl"),
    "0010": (_RR, r"rolling_resistance"),
    # last: a worker done with its share compiles it instead of waiting for the other's
    "0001": ({"physics.lubrication": "mixed"}, r"lubrication\W+mixed|=mixed\b"),
}


#: fewer modules than this: no warm-up (each pattern compiles in its first test, once per
#: session all the same); a few files of one subject seldom need the patterns the
#: expressions guess
WARM_MIN_MODULES = 5


def needed(nodeids) -> list[str]:
    """The patterns of :data:`PATTERNS` that a session running ``nodeids`` needs, in order:
    those whose expression a collected module's source matches."""
    import re

    root = Path(__file__).resolve().parents[1]
    modules = sorted({n.split("::", 1)[0] for n in nodeids})
    if len(modules) < WARM_MIN_MODULES:
        return []
    texts = []
    for module in modules:
        try:
            texts.append((root / module).read_text())
        except OSError:
            continue
    return [tag for tag, (_, pattern) in PATTERNS.items()
            if texts and any(re.search(pattern, t) for t in texts)]


def _cold(tag: str) -> bool:
    """Whether the pattern's IDA callbacks miss numba's cache (then its kernels do too)."""
    from bearingdae.solvers.sundials.callbacks import is_cold

    return is_cold("residual", tag) or is_cold("analytic", tag)  # (variant: "defects" too)


def pattern_scene(tag: str, numerics: dict | None = None):
    """The yang20 scene that switches on exactly pattern ``tag`` (``numerics``: more
    overrides)."""
    from bearingdae import scene_from_dict

    overrides, _ = PATTERNS[tag]
    data = {"bearing": {"preset": "yang20"}}
    if "defects" in overrides:
        data["defects"] = overrides["defects"]
        overrides = {}
    return scene_from_dict(data, {**(numerics or {}), **overrides})


def compile_pattern(tag: str) -> None:
    """Run a tiny scene of pattern ``tag``: its kernels compile (or load) into numba's cache."""
    from bearingdae import simulate

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        simulate(pattern_scene(tag, _TINY), progress=False)


def warm_patterns(tags, folder: Path) -> dict[str, str]:
    """Compile the patterns ``tags`` that no other worker of the session (sharing ``folder``)
    has claimed, then wait for those the others compile. Returns {pattern: what happened}."""
    folder.mkdir(parents=True, exist_ok=True)
    done: dict[str, str] = {}
    held = []
    for tag in tags:
        # the claim appears already locked: a file of this process, locked, then linked to
        # the claim's name (atomic; fails if another worker linked first)
        mine = folder / f".{tag}.{os.getpid()}"
        fd = os.open(mine, os.O_CREAT | os.O_WRONLY)
        fcntl.flock(fd, fcntl.LOCK_EX)
        try:
            os.link(mine, folder / f"{tag}.claim")
        except FileExistsError:
            os.close(fd)
            continue  # another worker compiles it
        finally:
            mine.unlink()
        held.append(fd)
        try:
            if _cold(tag):
                compile_pattern(tag)
                done[tag] = "compiled"
            else:
                done[tag] = "cached"
        except Exception as exc:  # noqa: BLE001 - the tests then compile it themselves
            done[tag] = f"failed: {exc!r}"
        finally:
            fcntl.flock(fd, fcntl.LOCK_UN)
    for fd in held:
        os.close(fd)
    for tag in tags:
        if tag in done:
            continue
        # the claiming worker holds LOCK_EX while compiling (released at its exit, too)
        claim = folder / f"{tag}.claim"
        try:
            fd = os.open(claim, os.O_RDONLY)
        except OSError:
            continue
        try:
            fcntl.flock(fd, fcntl.LOCK_SH)
            done[tag] = "waited"
        finally:
            os.close(fd)
    return done


def session_folder(run_id: str) -> Path:
    """The claims' folder of the xdist session ``run_id`` (every worker gets the same)."""
    return Path(tempfile.gettempdir()) / f"bearingdae-warmup-{os.getuid()}-{run_id}"


# --------------------------------------------------------------------------------------------
# One compile per kernel and session: a lock per specialisation, shared by the workers
# --------------------------------------------------------------------------------------------
_PACKAGE = str(Path(__file__).resolve().parents[1] / "bearingdae") + os.sep


def _lock_path(folder: Path, kind: str, py_func, sig) -> Path | None:
    """The lock file of the specialisation ``sig`` of the package's kernel ``py_func``; None
    for a function of another package (its compiles are not shared through the cache)."""
    import hashlib

    try:
        if not os.path.realpath(py_func.__code__.co_filename).startswith(_PACKAGE):
            return None
        key = f"{kind}:{py_func.__module__}.{py_func.__qualname__}:{sig}"
    except Exception:  # noqa: BLE001 - no lock: numba compiles as it always does
        return None
    return folder / (hashlib.sha1(key.encode()).hexdigest() + ".lock")


def _locked(path: Path | None, compile_, *args):
    """``compile_(*args)`` holding an exclusive ``flock`` on ``path`` (None: no lock), taken
    inside numba's own compiler lock (re-entrant: threads of one process take turns as numba
    makes them, and never hold file locks while waiting for it)."""
    from numba.core.compiler_lock import global_compiler_lock

    if path is None:
        return compile_(*args)
    with global_compiler_lock:
        try:
            fd = os.open(path, os.O_CREAT | os.O_WRONLY)
        except OSError:
            return compile_(*args)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)  # released at the process's exit, too
            return compile_(*args)
        finally:
            os.close(fd)


def share_compiles(folder: Path) -> None:
    """Make every compile of a cached kernel of the package take a lock of its own in
    ``folder`` (shared by the session's workers): a worker that needs a kernel another one is
    compiling waits for it, then numba loads it from the cache instead of compiling it again.
    Each lock is held by one compile (nested compiles take their callees' locks, in call
    order: the locks of a process follow its call graph down, so two processes never wait
    for each other in a circle)."""
    from numba.core import ccallback, dispatcher, sigutils
    from numba.core.caching import NullCache

    folder.mkdir(parents=True, exist_ok=True)
    compile_dispatcher = dispatcher.Dispatcher.compile
    compile_cfunc = ccallback.CFunc.compile

    def dispatcher_compile(self, sig):
        args, _ = sigutils.normalize_signature(sig)
        if tuple(args) in self.overloads or isinstance(self._cache, NullCache):
            return compile_dispatcher(self, sig)
        return _locked(_lock_path(folder, "jit", self.py_func, tuple(args)),
                       compile_dispatcher, self, sig)

    def cfunc_compile(self):
        if isinstance(self._cache, NullCache):
            return compile_cfunc(self)
        return _locked(_lock_path(folder, "cfunc", self._pyfunc, self._sig),
                       compile_cfunc, self)

    dispatcher.Dispatcher.compile = dispatcher_compile
    ccallback.CFunc.compile = cfunc_compile
