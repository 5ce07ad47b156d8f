"""Atomic file writes: the one recipe of every file bearingdae writes (NetCDF results,
checkpoints, sweep failure records, PNG figures).

:func:`atomic_write` yields a hidden temporary path beside the target; when the block succeeds
the file is fsynced, given the ordinary file mode and ``os.replace``-d onto the target, and on
any failure it is removed. A reader, or a writer killed at any moment, therefore never sees a
partial file at the target path.

A write that fails because the file system is full is reported as ``OSError(ENOSPC)`` whatever
the writer raised (netCDF4 says only "NetCDF: HDF error"); :func:`check_writable` tells before
any computing whether a target can be written at all (a directory, a read-only file system, a
folder that is a file), and :func:`write_failure` says in one line what went wrong.

Only SIGKILL (or a power cut) can leave the temporary behind. Its name carries the writer:
``.<target>.<pid>-<host>.<random>.part`` (host: 8 hex digits of a hash of the host name). Every
later write to the same target first removes its stale temporaries (:func:`remove_stale`): those
of this host whose writer process no longer exists, and any older than ``STALE_AFTER_S``
(a writer on another host sharing the folder, a reused PID, or a name without a writer from an
older version). A live writer's temporary is never touched: a write takes seconds, far below
``STALE_AFTER_S``, and its PID is alive.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import os
import re
import shutil
import socket
import tempfile
import time
from pathlib import Path

#: A temporary older than this is stale whoever wrote it (a NetCDF write takes seconds).
STALE_AFTER_S = 24 * 3600.0


def _host_tag() -> str:
    return hashlib.sha256(socket.gethostname().encode("utf-8", "replace")).hexdigest()[:8]


#: Longest file name (bytes) of the usual file systems (NAME_MAX of Linux and macOS).
NAME_MAX = 255
#: What a temporary's name adds to its target's: "." before, then ".<pid>-<host>.<random>.part"
#: (pid up to 7 digits, host 8, mkstemp's random part 8).
_TEMPORARY_EXTRA = 1 + 1 + 7 + 1 + 8 + 1 + 8 + len(".part")


def short_name(name: str, room: int = NAME_MAX) -> str:
    """``name`` when its UTF-8 form fits in ``room`` bytes; else its beginning, ``~`` and 12 hex
    digits of a hash of the whole name (the same name always gives the same short one)."""
    raw = name.encode("utf-8", "surrogateescape")
    if len(raw) <= room:
        return name
    tag = "~" + hashlib.sha256(raw).hexdigest()[:12]
    return raw[: room - len(tag)].decode("utf-8", "ignore") + tag


def fit_name(path: str | Path, tail: str = "") -> Path:
    """``path`` with its name shortened to :data:`NAME_MAX` bytes if needed, keeping ``tail``
    (the end a writer added, such as ``.checkpoint.npz``), for files named after a target whose
    own name is legal but long (225-255 characters)."""
    path = Path(path)
    if len(path.name.encode("utf-8", "surrogateescape")) <= NAME_MAX:
        return path
    head = path.name[: len(path.name) - len(tail)] if tail and path.name.endswith(tail) \
        else path.name
    tail = path.name[len(head):]
    return path.with_name(short_name(head, NAME_MAX - len(tail.encode("utf-8", "surrogateescape")))
                          + tail)


def temporary_prefix(path: Path) -> str:
    """The name prefix of this process's temporaries of ``path``. A target name too long to
    take the writer's tag within NAME_MAX is shortened (:func:`short_name`)."""
    return f".{_temporary_stem(path)}.{os.getpid()}-{_host_tag()}."


def _temporary_stem(path: Path) -> str:
    return short_name(path.name, NAME_MAX - _TEMPORARY_EXTRA)


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, owned by another user
        return True
    except OverflowError:  # not a PID of this system
        return False
    return True


def remove_stale(path: str | Path, now: float | None = None) -> list[Path]:
    """Remove the stale temporaries of ``path`` (rule in the module docstring); returns them.
    Temporaries of other targets in the same folder are never touched."""
    path = Path(path)
    name = re.escape(_temporary_stem(path))
    # mkstemp's random part is [a-z0-9_]: the patterns cannot match another target's names
    # (e.g. run.nc.checkpoint.npz's temporaries for target run.nc).
    with_writer = re.compile(rf"^\.{name}\.(\d+)-([0-9a-f]{{8}})\.[a-z0-9_]+\.part$")
    without_writer = re.compile(rf"^\.{re.escape(path.name)}\.[a-z0-9_]+\.part$")  # before the
    # writer was named
    now = time.time() if now is None else now
    host = _host_tag()
    removed = []
    try:
        entries = list(os.scandir(path.parent if str(path.parent) else "."))
    except OSError:
        return removed
    for entry in entries:
        m = with_writer.match(entry.name)
        if not m and not without_writer.match(entry.name):
            continue
        try:
            old = now - entry.stat(follow_symlinks=False).st_mtime > STALE_AFTER_S
            dead = bool(m) and m.group(2) == host and not _pid_alive(int(m.group(1)))
            if (old or dead) and entry.is_file(follow_symlinks=False):
                os.unlink(entry.path)
                removed.append(Path(entry.path))
        except OSError:  # vanished meanwhile (another writer cleaned it), or not ours to remove
            pass
    return removed


@contextlib.contextmanager
def atomic_write(path: str | Path):
    """Yield a temporary path beside ``path``; when the block succeeds, fsync it, give it the
    ordinary file mode and ``os.replace`` it onto ``path``; on any failure remove it. Stale
    temporaries of ``path`` left by killed writers are removed first. The temporary's name does
    not end in the target's suffix: writers that infer a format from it need it given."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    remove_stale(path)
    fd, tmp = tempfile.mkstemp(prefix=temporary_prefix(path), suffix=".part", dir=path.parent)
    os.close(fd)
    try:
        yield tmp
        with open(tmp, "rb") as fh:
            os.fsync(fh.fileno())
        os.chmod(tmp, default_mode())  # mkstemp makes 0600; a result file is an ordinary file
        os.replace(tmp, path)
    except BaseException as exc:
        # Measured on a full tmpfs: netCDF4 raises RuntimeError("NetCDF: HDF error") with 0
        # bytes free; the free space is looked at before the temporary is removed.
        full = isinstance(exc, Exception) and _disk_full(path.parent, exc)
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if full:
            raise OSError(errno.ENOSPC, f"{os.strerror(errno.ENOSPC)} (the writer said: "
                          f"{type(exc).__name__}: {exc})", str(path)) from exc
        raise


#: A failed write with less than this free on the file system is taken for a full disk
#: (measured on a full tmpfs: netCDF4 raised RuntimeError("NetCDF: HDF error") or
#: PermissionError, never ENOSPC).
FULL_DISK_FREE_BYTES = 1 << 20
#: Less than this free before computing: the target is refused as full (no result fits).
NO_ROOM_BYTES = 64 << 10


def _free_bytes(folder: Path) -> int | None:
    try:
        return shutil.disk_usage(folder).free
    except OSError:
        return None


def _disk_full(folder: Path, exc: BaseException) -> bool:
    """True when ``exc`` (a writer's error other than ENOSPC) came with a full disk."""
    if isinstance(exc, OSError) and exc.errno == errno.ENOSPC:
        return False  # says so already
    free = _free_bytes(folder)
    return free is not None and free < FULL_DISK_FREE_BYTES


class OutputNotWritable(ValueError):
    """The output location cannot take a file (a directory, a read-only file system, a folder
    that is a file). Raised before anything is computed; the message names the path and why."""


def check_writable(path: str | Path) -> Path:
    """Check, before computing, that ``path`` can be written the way :func:`atomic_write`
    writes it: the target is not a directory, its folder exists or can be made, and a file can
    be created there (a probe temporary, removed at once). Raises :class:`OutputNotWritable`.
    Creates missing folders of the path (as the write itself would)."""
    path = Path(path)
    try:
        if path.is_dir():
            example = path / ("result" + (path.suffix or ".nc"))
            raise OutputNotWritable(f"output '{shown_path(path)}' is a directory; give a file "
                                    f"name, e.g. '{shown_path(example)}'")
        folder = path.parent
        ancestor = folder
        while not ancestor.exists() and ancestor != ancestor.parent:
            ancestor = ancestor.parent
        if not ancestor.is_dir():
            raise OutputNotWritable(f"cannot write '{shown_path(path)}': '{shown_path(ancestor)}' "
                                    "is a file, not a folder")
        folder.mkdir(parents=True, exist_ok=True)
        free = _free_bytes(folder)
        if free is not None and free < NO_ROOM_BYTES:
            raise OutputNotWritable(f"cannot write '{shown_path(path)}': "
                                    f"{os.strerror(errno.ENOSPC)} ({free} bytes free in "
                                    f"'{shown_path(folder)}')")
        fd, probe = tempfile.mkstemp(prefix=temporary_prefix(path), suffix=".part", dir=folder)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise OutputNotWritable(f"cannot write '{shown_path(path)}': {exc.strerror or exc}"
                                f"{_where(exc, path)}") from None
    except ValueError as exc:  # NUL byte in the name
        if isinstance(exc, OutputNotWritable):
            raise
        raise OutputNotWritable(f"cannot write '{shown_path(path)}': {exc}") from None
    return path


def shown_path(path: str | Path, limit: int = 100) -> str:
    """A path for a message: as given, with its middle cut when longer than ``limit``."""
    text = str(path)
    if len(text) <= limit:
        return text
    keep = (limit - 5) // 2
    return f"{text[:keep]} ... {text[-keep:]}"


def same_file(a: str | Path, b: str | Path) -> bool:
    """True when ``a`` and ``b`` name one file: by device and inode where both exist (symlinks
    and hard links included), else by their resolved paths."""
    try:
        return os.path.samefile(a, b)
    except (OSError, ValueError):
        pass
    try:
        return os.path.realpath(a) == os.path.realpath(b)
    except (OSError, ValueError):
        return False


def refuse_aliases(outputs, inputs=()) -> None:
    """Refuse, before computing, an output that is one of the inputs under any name (``./x``,
    a symlink, a hard link) or another output of the same command: ``outputs`` and ``inputs``
    are ``(what, path)`` pairs (a ``None`` path is skipped). Raises
    :class:`OutputNotWritable` naming both."""
    outputs = [(what, Path(p)) for what, p in outputs if p is not None]
    for i, (what, out) in enumerate(outputs):
        for in_what, inp in inputs:
            if inp is not None and same_file(out, inp):
                raise OutputNotWritable(
                    f"{what} '{shown_path(out)}' is the {in_what} '{shown_path(inp)}': writing "
                    f"it would destroy the {in_what}; give another output name")
        for other_what, other in outputs[:i]:
            if same_file(out, other):
                raise OutputNotWritable(
                    f"the {other_what} and the {what} would both be '{shown_path(out)}'; give "
                    "another output name")


def _where(exc: OSError, path: Path) -> str:
    name = exc.filename
    shown = name and str(name) != str(path) and ".part" not in str(name)
    return f" ('{shown_path(name)}')" if shown else ""


def write_failure(exc: BaseException, path: str | Path) -> str:
    """One line saying which write failed and why (``strerror`` such as "No space left on
    device"), for a failure after the result was computed."""
    if isinstance(exc, OSError) and exc.strerror:
        return f"cannot write '{shown_path(path)}': {exc.strerror}"
    return f"cannot write '{shown_path(path)}': {type(exc).__name__}: {exc}"


def default_mode() -> int:
    """0666 minus the process umask: the mode open() would have given the file."""
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask
