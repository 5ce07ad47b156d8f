"""Numba's on-disk kernel cache, invalidated when any source file of the package changes.

Numba keys a cached kernel on its *own* file's modification time and size only. The kernels
inline laws and read constants from other modules (physics/, the parameter offsets of
system/residual.py): after an update that changes one of those and not the kernel's file — a
``git pull`` in an editable install, an edit — numba loads the old machine code, and the run
computes with the old physics or reads a parameter at a shifted offset, silently (measured: a
kernel cached before a parameter was added ignored ``physics.lubrication = "mixed"``).

So at import the package compares one stamp of all its sources (each ``.py`` file's relative
path, size and modification time) with the stamp stored beside numba's cache files, and when
they differ deletes the package's cache files (``*.nbi``, ``*.nbc``) before any kernel is
loaded; the kernels then compile afresh (a cold start, docs/performance.md). Where numba puts
them (numba.core.caching's locators): ``NUMBA_CACHE_DIR`` when set, else each package folder's
``__pycache__`` and, where that is not writable, the user-wide cache folder. Standard library
only (the command line starts in milliseconds); never raises (a cache that cannot be checked
is left to numba).
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1]
STAMP_NAME = "bearingdae-sources.stamp"
_CACHE_SUFFIXES = (".nbi", ".nbc")


def _sources(package: Path) -> list[Path]:
    """The package's ``.py`` files, sorted (one walk of the tree per import)."""
    return sorted(package.rglob("*.py"))


def sources_stamp(package: Path = PACKAGE, files: list[Path] | None = None) -> str:
    """SHA-256 of every ``.py`` file's relative path, size and modification time [ns]."""
    h = hashlib.sha256()
    for path in _sources(package) if files is None else files:
        st = path.stat()
        h.update(f"{path.relative_to(package).as_posix()}\0{st.st_size}\0{st.st_mtime_ns}\n"
                 .encode())
    return h.hexdigest()


def _subpath(folder: Path) -> str:
    """numba's ``_CacheLocator.get_suitable_cache_subpath`` of a file in ``folder``."""
    path = os.path.abspath(folder)
    return "_".join([os.path.split(path)[-1], hashlib.sha1(path.encode()).hexdigest()])


def _user_cache_dir() -> Path:
    """numba's user-wide cache folder on Linux (``AppDirs("numba").user_cache_dir``: the XDG
    cache folder); on other systems numba's folder differs and stays numba's to manage."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache")
    return Path(base) / "numba"


def cache_roots(package: Path = PACKAGE, environ=os.environ,
                files: list[Path] | None = None) -> list[tuple[Path, list[Path]]]:
    """(stamp file, the cache folders it covers) for each place numba may keep the package's
    kernels."""
    folders = sorted({p.parent for p in (_sources(package) if files is None else files)})
    custom = environ.get("NUMBA_CACHE_DIR")
    if custom:
        root = Path(custom)
        return [(root / f"{_subpath(package)}.{STAMP_NAME}", [root / _subpath(f) for f in folders])]
    user = _user_cache_dir()
    return [(package / "__pycache__" / STAMP_NAME, [f / "__pycache__" for f in folders]),
            (user / f"{_subpath(package)}.{STAMP_NAME}", [user / _subpath(f) for f in folders])]


def invalidate_stale(package: Path = PACKAGE, environ=os.environ) -> int:
    """Delete the package's numba cache files wherever its stamp is missing or differs from
    the sources'; returns how many files were deleted. Never raises."""
    deleted = 0
    try:
        files = _sources(package)
        stamp = sources_stamp(package, files)
        for stamp_file, folders in cache_roots(package, environ, files):
            try:
                if stamp_file.read_text() == stamp:
                    continue
            except OSError:
                pass
            for folder in (f for f in folders if f.is_dir()):
                for path in folder.iterdir():
                    if path.suffix in _CACHE_SUFFIXES:
                        try:
                            path.unlink()
                            deleted += 1
                        except OSError:
                            pass
            try:
                from .atomic import atomic_write  # (only on a change: it imports more)

                with atomic_write(stamp_file) as tmp:
                    Path(tmp).write_text(stamp)
            except OSError:
                pass
    except Exception:  # noqa: BLE001 - the cache is numba's to handle if this cannot check it
        pass
    return deleted
