"""Cold start: compile part of a run's kernels in a second process while this one compiles the
rest (docs/performance.md, "Cold start").

Stage: solvers (compiled IDA core), start-up only. On the first run after installation numba
compiles every kernel the run needs before its integration starts, and numba compiles in one
thread at a time (a global lock). When the Jacobian callback is not in numba's cache
(``callbacks.compile_aside``), :func:`start` launches ``python -c "...aside.child(kind,
optional, scene)"``: that child compiles the linear solver's operations and the Jacobian
callback, says so (a pipe of its own), then (given the run's scene) the projection of the
samples (aside.py), and writes numba's cache (``cache=True``: index and data files are written
to a temporary name and renamed, so a reader never sees half a file). Meanwhile this process
loads its modules, computes the initial state (the residual) and compiles the residual callback
and the per-step extremes hook. When IDA needs the Jacobian, :func:`wait` waits for the child's
word, and ``callbacks.compiled`` then loads what it compiled from the cache; the integration
starts while the child compiles the projection, which the samples wait for
(:func:`wait_projection`; results/streamed_record.py keeps them until then). The machine
code is the same as if compiled here (same source, same LLVM, same CPU); it is also what every
later (warm) run loads, so cold and warm runs compute the same numbers.

The child is started only when a CPU is idle (:func:`_spare_cpu`; ``BEARINGDAE_COMPILE_ASIDE``
= 1 / 0 forces it on / off; ``python benchmarks/run.py cold-start --serial`` compares both).
Anything unexpected (the child fails, is killed, or takes longer than ``WAIT_LIMIT_S``) falls
back to compiling in this process, as before: never an error.
"""

from __future__ import annotations

import atexit
import os
import pickle
import select
import subprocess
import sys
import tempfile
from pathlib import Path

#: callbacks compiled in a child process, by kind ("analytic", "fd"): the child
_CHILDREN: dict[str, subprocess.Popen] = {}
#: the child still compiling the projection of the samples after its word (one at a time),
#: and the file that handed it the scene
_PROJECTION: list = []
#: what the child writes to its word pipe once the Jacobian callback is in the cache
READY = b"jacobian compiled"
#: the block-arrow linear solver's operations the child leaves to this process, which
#: compiles them as its IDA session builds the solver, before it needs the Jacobian
#: (session.py): the factorisation, ~1.3 s of the child's ~12 s; the two shares then end
#: together (measured with a trace of both processes, docs/performance.md "Cold start")
PARENT_LINSOL_OPS = ("setup",)
#: longest wait for a child before compiling here instead [s] (a cold compile takes ~15 s on idle CPUs)
WAIT_LIMIT_S = 300.0
#: the directory that holds the ``bearingdae`` package (the child imports the same files, so
#: it writes the cache entries this process reads)
_PACKAGE_PARENT = str(Path(__file__).resolve().parents[3])


def _cpus() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def _others_running() -> int | None:
    """Processes runnable right now besides this one (/proc/loadavg), None when unknown."""
    try:
        with open("/proc/loadavg") as f:
            return max(int(f.read().split()[3].split("/")[0]) - 1, 0)
    except (OSError, ValueError, IndexError):
        return None


def _spare_cpu(busy_ok: bool = False) -> bool:
    """Whether a second process would get a CPU of its own: at least 2 CPUs and, unless
    ``BEARINGDAE_COMPILE_ASIDE`` says "1" (always) or "0" (never), no other process running
    on the CPU it needs now and a 1-minute load average below CPUs - 0.5 (a run that just
    ended counts there, another job's steady work too). Why both tests: with the machine to
    itself the child cuts the time to the first moving progress by about a third; with another
    job running it makes it slower (the pair spends ~20 % more CPU than one process and only
    takes turns with the other job).
    ``busy_ok``: skip the load test (a sweep about to occupy every CPU anyway)."""
    setting = os.environ.get("BEARINGDAE_COMPILE_ASIDE", "auto").strip().lower()
    cpus = _cpus()
    if setting == "0" or cpus < 2:
        return False
    if setting == "1" or busy_ok:
        return True
    others = _others_running()
    try:
        load = os.getloadavg()[0]
    except OSError:
        load = 0.0
    return (others is None or others <= cpus - 2) and load < cpus - 0.5


def start(kind: str, busy_ok: bool = False, optional: str = "", scene=None) -> bool:
    """Compile the C callback ``kind`` in a child process if a CPU is idle (the caller,
    ``callbacks.compile_aside``, has checked that it is not cached; ``busy_ok``: see
    :func:`_spare_cpu`; ``optional``: the effects compiled apart that the scene switches on,
    system/optional.pattern_tag's string, "d" after it with defects, "" for none; ``scene``:
    the run's scene, whose projection of the samples the child compiles next, None for none).
    True when a child was started (``callbacks.compiled`` waits for it)."""
    if kind in _CHILDREN or _PROJECTION or not _python() or not _spare_cpu(busy_ok):
        return False
    scene_file = _scene_file(scene)
    code = ("import sys; sys.path.insert(0, sys.argv[1]); "
            "from bearingdae.solvers.sundials.aside import child; "
            "child(sys.argv[2], sys.argv[3], sys.argv[4], int(sys.argv[5]))")
    word_in, word_out = os.pipe()  # the child's word: a pipe of its own, not its output
    try:
        # Same process group: a Ctrl-C at the terminal ends the child as well; no output (a
        # failure there only means this process compiles the rest itself).
        child = subprocess.Popen([sys.executable, "-c", code, _PACKAGE_PARENT, kind,
                                  optional or "0", scene_file or "", str(word_out)],
                                 stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                 stderr=subprocess.DEVNULL, close_fds=True,
                                 pass_fds=(word_out,))
    except (OSError, ValueError):
        os.close(word_in)
        _remove(scene_file)
        return False
    finally:
        os.close(word_out)  # the child holds its own copy: its exit closes the pipe
    child.word = word_in
    _CHILDREN[kind] = child
    if scene_file:
        _PROJECTION.extend((child, scene_file))
    return True


def _python() -> bool:
    """Whether this process's executable is a Python interpreter that ``-c`` runs code with:
    not in an application that embeds Python (its ``sys.executable`` is the application)."""
    name = os.path.basename(sys.executable or "").lower()
    return name.startswith("python") or name.startswith("pypy")


def _scene_file(scene) -> str | None:
    """The scene pickled into a temporary file for the child (None: no scene, or one that
    does not pickle: the child then leaves the projection to this process)."""
    if scene is None:
        return None
    try:
        fd, path = tempfile.mkstemp(prefix="bearingdae-scene-", suffix=".pickle")
        with os.fdopen(fd, "wb") as f:
            pickle.dump(scene, f, protocol=pickle.HIGHEST_PROTOCOL)
        return path
    except Exception:  # noqa: BLE001 - any failure: the projection compiles here
        return None


def _remove(path: str | None) -> None:
    if path:
        try:
            os.unlink(path)
        except OSError:
            pass


def running(kind: str) -> bool:
    """A child was started for ``kind`` and not waited for yet."""
    return kind in _CHILDREN


def wait(kind: str) -> bool:
    """Wait for the child compiling ``kind`` (if any) to have it in the cache; True when it
    said so (or, with no projection to compile, ended successfully)."""
    child = _CHILDREN.pop(kind, None)
    if child is None:
        return False
    try:
        if _word(child) and projection_pending():
            return True  # (it goes on with the projection)
        ok = child.wait(timeout=WAIT_LIMIT_S) == 0
        if not ok:
            _drop_projection()
        return ok
    except subprocess.TimeoutExpired:
        _end(child)
        _drop_projection()
        return False
    except BaseException:  # Ctrl-C while waiting: the child goes too
        _end(child)
        _drop_projection()
        raise


def _word(child: subprocess.Popen) -> bool:
    """Wait (at most ``WAIT_LIMIT_S``) for the child's word that the Jacobian callback is in
    the cache; False when it ended without it, or took too long (then it is ended)."""
    fd = getattr(child, "word", None)
    if fd is None:
        return False
    child.word = None  # read and closed here, whatever happens
    try:
        ready, _, _ = select.select([fd], [], [], WAIT_LIMIT_S)
        said = bool(ready) and os.read(fd, 64).strip() == READY
    finally:
        os.close(fd)
    if not ready:
        _end(child)
    return said


def projection_pending() -> bool:
    """A child compiles (or is to compile) the projection of this run's samples: the first
    samples wait for it (:func:`wait_projection`) instead of compiling it here."""
    return bool(_PROJECTION)


def projection_compiling() -> bool:
    """The child is still compiling the projection (a look, no wait)."""
    return bool(_PROJECTION) and _PROJECTION[0].poll() is None


def wait_projection() -> bool:
    """Wait for the child compiling the projection (if any); True when it finished
    successfully (the projection is then in numba's cache)."""
    if not _PROJECTION:
        return False
    try:
        return _PROJECTION[0].wait(timeout=WAIT_LIMIT_S) == 0
    except subprocess.TimeoutExpired:
        return False
    finally:  # (a child still at work, after a timeout or a Ctrl-C here, is ended)
        _drop_projection()


def _drop_projection() -> None:
    """Forget the child compiling the projection: ended if still at work, its scene removed."""
    if _PROJECTION:
        child, scene_file = _PROJECTION
        _PROJECTION.clear()
        _end(child)
        _remove(scene_file)


def _end(child: subprocess.Popen) -> None:
    if child.poll() is None:
        child.kill()
        child.wait()
    fd = getattr(child, "word", None)
    if fd is not None:
        os.close(fd)
        child.word = None


@atexit.register
def _end_all() -> None:
    """No child outlives this process (a run that failed before IDA started)."""
    while _CHILDREN:
        _end(_CHILDREN.popitem()[1])
    _drop_projection()
