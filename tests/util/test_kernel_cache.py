"""Numba's kernel cache keyed by the package's source contents (util/kernel_cache.py).

References: a package typed here (``tinyk``: a law in one file, a kernel that inlines it in
another, registered with :func:`kernel_cache.install` as bearingdae registers itself), run in
fresh processes against numba's own hit/miss counters (``dispatcher.stats``) and the values
its kernels return; and bearingdae itself copied to a new path with new modification times.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

from bearingdae.util import kernel_cache as kc

ROOT = Path(__file__).resolve().parents[2]

INIT = ("from pathlib import Path\n"
        "from bearingdae.util.kernel_cache import install, notices\n"
        "install(Path(__file__).parent)\n"
        "notices(True)  # as the command line does\n")
KERNEL = ("from numba import njit\n"
          "from .law import SCALE\n"
          "KERNEL_GROUP = 'tiny'\n\n"
          "@njit(cache=True)\n"
          "def g(x):\n"
          "    return SCALE * x\n\n"
          "@njit(cache=True)\n"
          "def f(x):\n"
          "    return g(x) + 1.0\n\n"
          "@njit(cache=True)\n"
          "def broken(x):\n"
          "    return g(x) + 'text'\n")
#: f(1), then the cache hits and the misses of f and g together (numba's counters; a cached f
#: holds g: g is then neither loaded nor compiled)
REPORT = ("import tinyk.kern as k; v = k.f(1.0); "
          "h = lambda d: (sum(d.stats.cache_hits.values()), sum(d.stats.cache_misses.values())); "
          "print(v, *h(k.f), *h(k.g))")


def _package(where: Path, scale: str = "2.0") -> Path:
    pkg = where / "tinyk"
    pkg.mkdir(parents=True)
    (pkg / "__init__.py").write_text(INIT)
    (pkg / "law.py").write_text(f"SCALE = {scale}\n")
    (pkg / "kern.py").write_text(KERNEL)
    return pkg


def _env(where: Path, cache: Path) -> dict:
    return {**os.environ, "PYTHONPATH": os.pathsep.join([str(where), str(ROOT)]),
            "NUMBA_CACHE_DIR": str(cache)}


def _run(where: Path, cache: Path, code: str = REPORT):
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       env=_env(where, cache))
    assert r.returncode == 0, r.stderr
    value, f_hits, f_misses, g_hits, g_misses = r.stdout.split()
    return float(value), int(f_hits) + int(g_hits), int(f_misses) + int(g_misses), r.stderr


def _waiting(where: Path, cache: Path, before: str, after: str) -> subprocess.Popen:
    """A process that runs ``before``, says "ready", waits for a line, then runs ``after``
    and prints k.f(1)."""
    code = (f"import sys; {before}; print('ready', flush=True); sys.stdin.readline(); "
            f"{after + '; ' if after else ''}print(k.f(1.0), flush=True)")
    return subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=_env(where, cache))


def _release(a: subprocess.Popen, meanwhile) -> str:
    """Once ``a`` is ready, ``meanwhile()``, then let ``a`` go on; its output."""
    try:
        assert a.stdout.readline().strip() == "ready"
        meanwhile()
        out, err = a.communicate("go\n", timeout=600)
    finally:
        if a.poll() is None:
            a.kill()
    assert a.returncode == 0, err
    return out


def test_same_contents_at_new_times_and_paths_reuse_the_kernels(tmp_path):
    pkg, cache = _package(tmp_path / "a"), tmp_path / "cache"
    value, hits, misses, err = _run(tmp_path / "a", cache)
    assert (value, hits, misses) == (3.0, 0, 2)
    assert err.count("compiling the tiny kernels") == 1, err  # the group's first compile
    later = time.time() + 3600.0  # every file touched (a reinstall: new modification times)
    for path in pkg.rglob("*.py"):
        os.utime(path, (later, later))
    assert _run(tmp_path / "a", cache)[:3] == (3.0, 1, 0)
    copy = tmp_path / "b" / "tinyk"  # the same sources at another path, copied without times
    shutil.copytree(pkg, copy, copy_function=shutil.copy, ignore=shutil.ignore_patterns("__pycache__"))
    value, hits, misses, err = _run(tmp_path / "b", cache)
    assert (value, hits, misses) == (3.0, 1, 0) and "compiling" not in err, err


def test_an_edit_of_an_inlined_law_recompiles(tmp_path):
    """The kernel's own file is unchanged: numba's per-file stamp alone would load 2 x."""
    pkg, cache = _package(tmp_path), tmp_path / "cache"
    assert _run(tmp_path, cache)[:3] == (3.0, 0, 2)
    (pkg / "law.py").write_text("SCALE = 5.0\n")
    assert _run(tmp_path, cache)[:3] == (6.0, 0, 2)
    (pkg / "law.py").write_text("SCALE = 2.0\n")  # back: the first folder is still there
    assert _run(tmp_path, cache)[:3] == (3.0, 1, 0)


def test_a_process_started_before_an_edit_does_not_poison_the_cache(tmp_path):
    """Three processes: A imports the old sources and compiles after the edit; B compiled the
    new sources meanwhile; C (new sources, started last) gets B's kernels, never A's."""
    pkg, cache = _package(tmp_path), tmp_path / "cache"
    a = _waiting(tmp_path, cache, "import tinyk.kern as k", "")

    def b():
        (pkg / "law.py").write_text("SCALE = 5.0\n")  # the edit
        assert _run(tmp_path, cache)[:3] == (6.0, 0, 2)  # B

    out = _release(a, b)
    assert float(out) == 3.0  # A: its own (old) code, compiled now
    assert _run(tmp_path, cache)[:3] == (6.0, 1, 0)  # C: B's kernels


def test_a_module_imported_after_an_edit_keeps_its_kernels_to_itself(tmp_path):
    """A process hashed the sources, then imported the kernel after an edit: what it compiles
    (new law) is not loaded by a process of the old sources."""
    pkg, cache = _package(tmp_path), tmp_path / "cache"
    a = _waiting(tmp_path, cache, "import tinyk", "import tinyk.kern as k")
    out = _release(a, lambda: (pkg / "law.py").write_text("SCALE = 5.0\n"))
    assert float(out) == 6.0
    (pkg / "law.py").write_text("SCALE = 2.0\n")
    assert _run(tmp_path, cache)[:3] == (3.0, 0, 2)


def test_an_interrupted_compile_keeps_the_kernels_that_finished(tmp_path):
    """``broken`` fails while compiling after its callee ``g`` compiled: ``g`` is cached."""
    _package(tmp_path)
    cache = tmp_path / "cache"
    code = ("import tinyk.kern as k\n"
            "try:\n    k.broken(1.0)\nexcept Exception:\n    pass\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       env=_env(tmp_path, cache))
    assert r.returncode == 0, r.stderr
    value, hits, misses, err = _run(tmp_path, cache)
    assert value == 3.0 and (hits, misses) == (1, 1)  # g loaded, f compiled


def test_old_folders_are_pruned(tmp_path):
    now = time.time()
    old = now - kc.PRUNE_AFTER_S - 60.0
    ages = {f"h{k}": old - k for k in range(kc.KEEP + 3)}  # all old; h0 the most recent
    ages["recent"] = now - 60.0  # used a minute ago by another process
    for name, t in ages.items():
        (tmp_path / name).mkdir()
        (tmp_path / name / "x.nbi").write_bytes(b"")
        os.utime(tmp_path / name, (t, t))
    (tmp_path / "mine").mkdir()
    deleted = sorted(p.name for p in kc.prune(tmp_path, "mine", now))
    # kept: mine, and the KEEP most recently used of the others (recent, h0 .. h{KEEP-2})
    assert deleted == [f"h{k}" for k in range(kc.KEEP - 1, kc.KEEP + 3)]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        ["mine", "recent", *(f"h{k}" for k in range(kc.KEEP - 1))])


def test_bearingdae_copied_with_new_times_finds_the_same_folder(tmp_path):
    """The real package: a copy at another path with new modification times (what an install
    makes) hashes to the same folder; an edit of one file to another."""
    copy = tmp_path / "bearingdae"
    shutil.copytree(ROOT / "bearingdae", copy, copy_function=shutil.copy,
                    ignore=shutil.ignore_patterns("__pycache__"))
    assert kc.sources_hash(copy)[0] == kc.sources_hash(ROOT / "bearingdae")[0]
    law = copy / "physics" / "contact.py"
    law.write_text(law.read_text() + "\n")
    assert kc.sources_hash(copy)[0] != kc.sources_hash(ROOT / "bearingdae")[0]
