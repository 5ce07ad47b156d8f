"""Numba's kernel cache is cleared when any source of the package changes (util/kernel_cache.py).

References: numba's own cache locators (numba.core.caching: the in-tree ``__pycache__``, the
``NUMBA_CACHE_DIR`` subfolder from ``_CacheLocator.get_suitable_cache_subpath``), and a
package tree built here: a change of one file clears the cache files of every folder and keeps
everything else; an unchanged tree keeps them.
"""

from __future__ import annotations

import os
from pathlib import Path

from bearingdae.util import kernel_cache as kc


def _tree(root: Path) -> Path:
    pkg = root / "pkg"
    (pkg / "sub" / "__pycache__").mkdir(parents=True)
    (pkg / "__pycache__").mkdir()
    (pkg / "__init__.py").write_text("x = 1\n")
    (pkg / "sub" / "law.py").write_text("def f(q):\n    return q\n")
    (pkg / "sub" / "kernel.py").write_text("from .law import f\n")
    return pkg


def _cache_files(folder: Path) -> None:
    for name in ("kernel.f-1.py311.nbi", "kernel.f-1.py311.1.nbc"):
        (folder / name).write_bytes(b"machine code")
    (folder / "kernel.cpython-311.pyc").write_bytes(b"bytecode")


def test_a_change_of_any_source_clears_every_folders_kernels(tmp_path):
    pkg = _tree(tmp_path)
    env = {"XDG_CACHE_HOME": str(tmp_path / "user")}
    kc.invalidate_stale(pkg, env)  # the first look writes the stamp
    for folder in (pkg / "__pycache__", pkg / "sub" / "__pycache__"):
        _cache_files(folder)
    assert kc.invalidate_stale(pkg, env) == 0  # unchanged sources: kept
    assert len(list((pkg / "sub" / "__pycache__").glob("*.nb*"))) == 2
    # the law changes, the kernel's own file does not (what numba's key misses)
    law = pkg / "sub" / "law.py"
    law.write_text("def f(q):\n    return 2 * q\n")
    os.utime(law, ns=(law.stat().st_atime_ns, law.stat().st_mtime_ns + 10**9))
    assert kc.invalidate_stale(pkg, env) == 4
    for folder in (pkg / "__pycache__", pkg / "sub" / "__pycache__"):
        assert not list(folder.glob("*.nb*"))
        assert (folder / "kernel.cpython-311.pyc").exists()  # Python's own cache stays
    assert kc.invalidate_stale(pkg, env) == 0


def test_numba_cache_dir_is_where_numba_puts_the_kernels(tmp_path):
    """With NUMBA_CACHE_DIR the folders are numba's own subpaths of it."""
    from numba.core.caching import _CacheLocator

    pkg = _tree(tmp_path)
    custom = tmp_path / "numba-cache"
    env = {"NUMBA_CACHE_DIR": str(custom)}
    (stamp, folders), = kc.cache_roots(pkg, env)
    expected = {custom / _CacheLocator.get_suitable_cache_subpath(str(f / "x.py"))
                for f in (pkg, pkg / "sub")}
    assert set(folders) == expected and stamp.parent == custom
    kc.invalidate_stale(pkg, env)
    for folder in folders:
        folder.mkdir(parents=True, exist_ok=True)
        _cache_files(folder)
    (pkg / "__init__.py").write_text("x = 2  # longer\n")
    assert kc.invalidate_stale(pkg, env) == 4


def test_the_installed_package_is_stamped():
    """Importing bearingdae stamped its kernel cache with its sources' stamp."""
    import bearingdae  # noqa: F401

    stamps = [s for s, _ in kc.cache_roots() if s.exists()]
    assert stamps and all(s.read_text() == kc.sources_stamp() for s in stamps)
