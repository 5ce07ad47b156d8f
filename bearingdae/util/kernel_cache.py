"""Numba's on-disk kernel cache, keyed by the *contents* of the package's sources.

Numba stamps a cached kernel with its own file only (0.68: a hash of that file's contents;
older releases: its modification time and size). The kernels inline laws and read constants
from other modules (physics/, the parameter offsets of system/residual.py): after a change of
one of those and not of the kernel's file, numba would load the old machine code and compute
with the old physics, silently (measured: a kernel cached before a parameter was added
ignored ``physics.lubrication = "mixed"``).

So the package's kernels live in a folder of their own, named by one SHA-256 of every ``.py``
file's relative path and contents (:func:`sources_hash`)::

    <root>/<hash>/<package folder>/<kernel>.nbi, .nbc

``<root>``: ``$NUMBA_CACHE_DIR/bearingdae`` when that is set, else the user's cache folder
(``$XDG_CACHE_HOME`` or ``~/.cache``) ``/bearingdae/kernels``; a folder in the temporary
directory when neither can be written. Numba still keys each entry on the numba version, the
CPU and the signature (its index), and :class:`PackageLocator` stamps it with the hash.

* Reinstalling the same sources (``pip install .`` again, new modification times, another
  path) finds the same folder: every kernel is kept.
* Each process hashes the sources when its first kernel module is imported (:func:`install`,
  called by the ``__init__`` of physics/, system/ and solvers/) and reads and writes only the
  folder of that hash: a process started before an edit keeps to the old folder, so a changed
  source never meets an old kernel, whichever process compiled it. A kernel decorated after
  a source changed under the process (a module imported after an edit) is cached in a folder
  of that process alone, deleted at its exit: never shared, and the hash's folder untouched.
* Numba writes each kernel's entry as soon as that kernel has compiled (index and data under a
  temporary name, then renamed): an interrupted compile keeps the kernels that finished.
* Folders of other hashes not used for ``PRUNE_AFTER_S`` are deleted beyond the ``KEEP`` most
  recently used (:func:`prune`); using a folder touches it.
* The first compile of a kernel group in a process prints one line to stderr naming it
  (numba's "numba:compile" event, which fires on a cache miss): a module that declares
  ``KERNEL_GROUP`` (e.g. "flanges") is a group wherever its kernels compile; otherwise the
  module of the outermost compile names it ("system/residual.py"), unless the caller has
  announced the compiling itself (:func:`quiet`: the run's own notice, run/progress.py).
  Printed where a person watches (:func:`notices`: the command line, and ``simulate`` where
  it shows its progress); quiet otherwise.

Importing this module is standard library only (the command line starts in milliseconds);
:func:`install` imports numba. Nothing here raises: a cache that cannot be set up is left to
numba's own locators.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1]
#: folders of other hashes kept, most recently used first, whatever their age
KEEP = 4
#: a folder of another hash used within this time is kept (another process may use it) [s]
PRUNE_AFTER_S = 7 * 24 * 3600.0

#: registered packages: resolved folder -> (cache folder of its hash, hash, {file: (size, mtime_ns)})
_PACKAGES: dict[str, tuple[Path, str, dict[str, tuple[int, int]]]] = {}
_ANNOUNCED: set[str] = set()  #: kernel groups whose first compile this process announced
_QUIET: list[bool] = [False]  #: a caller announces the compiling itself (run/progress.py)
#: the notices are printed: where a person watches (the command line; simulate() with its
#: progress shown); a script's simulate(progress=False) stays quiet
_NOTICES: list[bool] = [False]


def _sources(package: Path) -> list[Path]:
    """The package's ``.py`` files, sorted."""
    return sorted(p for p in package.rglob("*.py") if "__pycache__" not in p.parts)


def sources_hash(package: Path = PACKAGE) -> tuple[str, dict[str, tuple[int, int]]]:
    """SHA-256 of every ``.py`` file's relative path and contents (modification times play
    no part), and each file's (size, mtime_ns) when it was read (to notice a later edit)."""
    h, seen = hashlib.sha256(), {}
    for path in _sources(package):
        st = path.stat()
        h.update(path.relative_to(package).as_posix().encode() + b"\0")
        h.update(hashlib.sha256(path.read_bytes()).digest())
        seen[os.path.realpath(path)] = (st.st_size, st.st_mtime_ns)
    return h.hexdigest(), seen


def cache_root(environ=os.environ) -> Path:
    """Where the hash folders live (module docstring)."""
    custom = environ.get("NUMBA_CACHE_DIR")
    if custom:
        return Path(custom) / "bearingdae"
    base = environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache")
    return Path(base) / "bearingdae" / "kernels"


def _writable_root(environ) -> Path | None:
    for root in (cache_root(environ),
                 Path(tempfile.gettempdir()) / f"bearingdae-kernels-{os.getuid()}"):
        try:
            root.mkdir(parents=True, exist_ok=True)
            tempfile.TemporaryFile(dir=root).close()
            return root
        except OSError:
            continue
    return None


def prune(root: Path, keep_name: str, now: float | None = None) -> list[Path]:
    """Delete the hash folders of ``root`` other than ``keep_name`` that are neither among the
    ``KEEP`` most recently used nor used within ``PRUNE_AFTER_S``; returns what was deleted."""
    now = time.time() if now is None else now
    try:
        others = sorted((p for p in root.iterdir() if p.is_dir() and p.name != keep_name),
                        key=lambda p: p.stat().st_mtime, reverse=True)
    except OSError:
        return []
    deleted = []
    for old in others[KEEP:]:
        try:
            if now - old.stat().st_mtime > PRUNE_AFTER_S:
                shutil.rmtree(old)
                deleted.append(old)
        except OSError:
            pass
    return deleted


def install(package: Path = PACKAGE, environ=os.environ) -> Path | None:
    """Cache the kernels of ``package`` in the folder of its sources' hash (idempotent, once
    per package and process); returns that folder, or None when numba keeps its own way.
    First the vector width they compile for (util/vector_width.py): it must be chosen before
    numba builds its CPU target, which the first kernel decorated after this does."""
    try:
        from .vector_width import apply

        apply(environ)
    except Exception:  # noqa: BLE001 - numba's own features then, as they always were
        pass
    key = os.path.realpath(package)
    if key in _PACKAGES:
        return _PACKAGES[key][0]
    try:
        digest, seen = sources_hash(Path(key))
        root = _writable_root(environ)
        if root is None:
            return None
        folder = root / digest[:32]
        fresh = not folder.exists()
        folder.mkdir(exist_ok=True)
        os.utime(folder)  # last used: now (prune keeps it)
        if fresh:
            prune(root, folder.name)
        _PACKAGES[key] = (folder, digest, seen)
        _register_with_numba()
        return folder
    except Exception:  # noqa: BLE001 - numba's own locators then cache as they always did
        _PACKAGES.pop(key, None)
        return None


def notices(on: bool) -> None:
    """Print the first-compile notices (on) or not (off, the default)."""
    _NOTICES[0] = bool(on)


def quiet(on: bool) -> None:
    """While on, the per-group compile notice is not printed (the caller has announced the
    compiling with a notice of its own)."""
    _QUIET[0] = bool(on)


def _owner(py_file: str) -> tuple[str, str] | None:
    """(package key, path relative to it) of a registered package's file, else None."""
    real = os.path.realpath(py_file)
    for key in _PACKAGES:
        if real.startswith(key + os.sep):
            return key, os.path.relpath(real, key)
    return None


def _place(key: str, rel: str) -> tuple[str, str]:
    """(cache folder, stamp) of a kernel in the file ``rel`` of the package ``key``: the hash's
    folder and the hash; when a source of the package changed after the hash was taken (a
    module imported after an edit), a folder of this process alone, deleted at its exit, so
    that what it compiles is never shared, nor disturbs the hash's folder."""
    folder, digest, seen = _PACKAGES[key]
    for path, sig in seen.items():
        try:
            st = os.stat(path)
        except OSError:
            break
        if (st.st_size, st.st_mtime_ns) != sig:
            break
    else:
        return str(folder / os.path.dirname(rel)), digest
    if not _CHANGED:
        import atexit

        _CHANGED.append(tempfile.mkdtemp(prefix="bearingdae-kernels-changed-"))
        atexit.register(shutil.rmtree, _CHANGED[0], True)
    return os.path.join(_CHANGED[0], os.path.dirname(rel)), f"{digest} changed"


_CHANGED: list[str] = []  #: this process's own folder once its sources changed under it


_registered: list[bool] = [False]


def _register_with_numba() -> None:
    if _registered[0]:
        return
    from numba.core import caching, event

    class PackageLocator(caching._CacheLocator):
        """A registered package's kernels in the folder of its sources' hash."""

        def __init__(self, py_func, key, rel):
            self._lineno = py_func.__code__.co_firstlineno
            self._path, self._source_stamp = _place(key, rel)

        def get_cache_path(self):
            return self._path

        def get_source_stamp(self):
            return self._source_stamp

        def get_disambiguator(self):
            return str(self._lineno)

        @classmethod
        def from_function(cls, py_func, py_file):
            owner = _owner(py_file)
            if owner is None:
                return None
            self = cls(py_func, *owner)
            try:
                self.ensure_cache_path()
            except OSError:
                return None
            return self

    class CompileNotice(event.Listener):
        """numba's "numba:compile" event (a cache miss: numba is about to compile): at the
        outermost compile of a registered package's kernel, one line per group and process."""

        depth = 0

        def on_start(self, ev):
            self.depth += 1
            _announce(ev.data.get("dispatcher"), outermost=self.depth == 1)

        def on_end(self, ev):
            self.depth = max(self.depth - 1, 0)

    caching.CacheImpl._locator_classes.insert(0, PackageLocator)
    event.register("numba:compile", CompileNotice())
    _registered[0] = True


def group_of(module_name: str) -> str:
    """The kernel group of a module: its ``KERNEL_GROUP``, else its file's path."""
    module = sys.modules.get(module_name)
    name = getattr(module, "KERNEL_GROUP", None)
    if name:
        return str(name)
    return module_name.split(".", 1)[-1].replace(".", "/") + ".py"


def _notice(group: str) -> str:
    return (f"compiling the {group} kernels (first use only; later runs load them from "
            "the cache)")


def _announce(dispatcher, outermost: bool) -> None:
    """Print the notice of ``dispatcher``'s kernel group, once per group and process: a named
    group (``KERNEL_GROUP``) wherever it compiles, else the module of the outermost compile
    unless the caller announced the compiling itself (:func:`quiet`)."""
    if not _NOTICES[0]:
        return
    try:
        py_func = dispatcher.py_func
        if _owner(py_func.__code__.co_filename) is None:
            return
        named = getattr(sys.modules.get(py_func.__module__), "KERNEL_GROUP", None)
        if not named and (not outermost or _QUIET[0]):
            return
        group = group_of(py_func.__module__)
    except Exception:  # noqa: BLE001 - a notice is not worth a failure
        return
    if group not in _ANNOUNCED:
        _ANNOUNCED.add(group)
        print(f"bearingdae: {_notice(group)}", file=sys.stderr, flush=True)
