"""Atomic writes: the overview PNG is written like the NetCDF results, and the
hidden temporaries a SIGKILLed writer leaves are removed by the next write to the same target.

* An exception in the middle of saving a figure leaves no PNG (and no temporary) at the target,
  and an older PNG there intact.
* Stale temporaries: the rule of bearingdae/util/atomic.py (this host's dead writer, or older than
  STALE_AFTER_S) on hand-made names, and end to end: a process SIGKILLed inside ``save`` leaves
  its temporary; the next ``save`` and the next ``bearingdae static`` to that target remove it.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from bearingdae.util import atomic
from bearingdae.util.atomic import STALE_AFTER_S, remove_stale, temporary_prefix
from bearingdae.cli import main
from bearingdae.plots.plotting import overview
from bearingdae.results import save

ROOT = Path(__file__).resolve().parents[2]
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def small_run() -> xr.Dataset:
    """A Dataset shaped like a dynamic run (what overview() reads), made by hand."""
    t = np.linspace(0.0, 1e-3, 6)
    rollers = np.arange(1, 4)
    ds = xr.Dataset(
        {"cage_speed": ("time", 90 + t * 1e3, {"units": "rad s-1", "long_name": "cage"}),
         "orbit_speed": (("time", "roller"), np.ones((6, 3)), {"units": "rad s-1",
                                                             "long_name": "orbit"})},
        coords={"time": ("time", t, {"units": "s", "long_name": "time"}),
                "roller": ("roller", rollers, {"units": "1", "long_name": "roller number"})},
        attrs={"title": "hand-made"})
    return ds


def leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.endswith(".part"))


def test_overview_png_is_complete(tmp_path):
    path = overview(small_run(), tmp_path / "run.png")
    assert path.read_bytes()[:8] == PNG_MAGIC
    assert leftovers(tmp_path) == []
    assert path.stat().st_mode & 0o777 == atomic.default_mode()


def test_error_while_saving_the_overview_leaves_no_png(tmp_path, monkeypatch):
    """The PNG writer writes the PNG signature and part of the image, then fails (as on a full
    disk): the exception reaches the caller; nothing at the target path, no temporary left; an
    older PNG at the target is kept byte for byte."""
    from matplotlib.figure import Figure

    def half_written(self, fname, **kwargs):
        with open(fname, "wb") as fh:
            fh.write(PNG_MAGIC + b"\0" * 4096)
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Figure, "savefig", half_written)
    target = tmp_path / "run.png"
    with pytest.raises(OSError, match="No space left"):
        overview(small_run(), target)
    assert not target.exists()
    assert leftovers(tmp_path) == []

    target.write_bytes(b"older complete figure")
    with pytest.raises(OSError, match="No space left"):
        overview(small_run(), target)
    assert target.read_bytes() == b"older complete figure"
    assert leftovers(tmp_path) == []


def dead_pid() -> int:
    """The PID of a process that has ended (and been reaped)."""
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


def test_stale_rule_on_hand_made_temporaries(tmp_path):
    target = tmp_path / "run.nc"
    host = temporary_prefix(target).rsplit("-", 1)[1].rstrip(".")
    other_host = "0123abcd" if host != "0123abcd" else "89abcdef"
    dead = dead_pid()
    names = {
        f".run.nc.{dead}-{host}.a1b2c3d4.part": "removed",        # this host, writer gone
        f".run.nc.{os.getpid()}-{host}.live0001.part": "kept",    # this host, writer alive
        f".run.nc.{dead}-{other_host}.recent01.part": "kept",     # another host, recent
        f".run.nc.{dead}-{other_host}.old00001.part": "old",      # another host, 2 days old
        ".run.nc.abcd_123.part": "kept",                           # writer unknown, recent
        ".run.nc.efgh_456.part": "old",                            # writer unknown, old
        f".run.nc.checkpoint.npz.{dead}-{host}.zz99yy88.part": "kept",  # another target
        f".run2.nc.{dead}-{host}.zz99yy88.part": "kept",           # another target
        f"run.nc.{dead}-{host}.nodot000.part": "kept",             # not hidden: not ours
    }
    now = time.time()
    for name, fate in names.items():
        p = tmp_path / name
        p.write_bytes(b"x")
        if fate == "old":
            os.utime(p, (now - 2 * STALE_AFTER_S, now - 2 * STALE_AFTER_S))
    removed = sorted(p.name for p in remove_stale(target))
    assert removed == sorted(n for n, f in names.items() if f in ("removed", "old"))
    assert leftovers(tmp_path) == sorted(n for n, f in names.items() if f == "kept")


SAVE_LOOP = """
import sys, numpy as np, xarray as xr
from bearingdae.results import save
ds = xr.Dataset({"a": (("t", "x"), np.random.default_rng(1).random((1500, 1500)),
                       {"units": "1", "long_name": "noise"})})
print("ready", flush=True)
while True:
    save(ds, sys.argv[1], complevel=1)
"""


def kill_inside_save(target: Path, tries: int = 5) -> list[str]:
    """SIGKILL a process looping over save(target) once its temporary exists; returns the
    temporaries it left (retries if the write finished between the look and the kill)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    for _ in range(tries):
        p = subprocess.Popen([sys.executable, "-c", SAVE_LOOP, str(target)], env=env,
                             stdout=subprocess.PIPE, text=True)
        try:
            assert p.stdout.readline().strip() == "ready"
            deadline = time.monotonic() + 60
            while not leftovers(target.parent) and time.monotonic() < deadline:
                time.sleep(0.005)
            p.send_signal(signal.SIGKILL)
        finally:
            p.kill()
            p.wait(timeout=60)
            p.stdout.close()
        left = leftovers(target.parent)
        if left:
            assert all(n.startswith(f".{target.name}.{p.pid}-") for n in left), left
            return left
    pytest.fail(f"no temporary left after {tries} SIGKILLs inside save()")


def test_next_save_removes_the_temporary_of_a_killed_writer(tmp_path):
    target = tmp_path / "big.nc"
    assert kill_inside_save(target)
    save(small_run(), target)
    assert leftovers(tmp_path) == []
    with xr.open_dataset(target) as ds:
        assert ds.sizes["time"] == 6


def test_next_cli_write_removes_the_temporary_of_a_killed_writer(tmp_path, capsys):
    target = tmp_path / "static.nc"
    assert kill_inside_save(target)
    assert main(["static", "yang20_baseline", "-o", str(target)]) == 0
    assert leftovers(tmp_path) == []
    with xr.open_dataset(target) as ds:
        assert "contact_force" in ds


@pytest.mark.parametrize("length", [10, 223, 224, 255])
def test_temporaries_of_long_names_fit_and_are_cleaned(tmp_path, length):
    """A legal target name of up to 255 bytes: its temporary fits in 255 bytes (shortened by a
    hash only when it must be, so names up to 223 bytes keep the old form), a write works,
    and a dead writer's temporary of that target is removed by the next write."""
    target = tmp_path / ("é" * ((length - 3) // 2) + "x" * ((length - 3) % 2) + ".nc")
    assert len(target.name.encode()) == length
    prefix = temporary_prefix(target)
    assert len(prefix.encode()) + 8 + len(".part") <= atomic.NAME_MAX
    assert (prefix.startswith(f".{target.name}.")) == (length <= 223)
    dead = tmp_path / prefix.replace(f".{os.getpid()}-", ".9999999-").__add__("abcd1234.part")
    dead.write_bytes(b"partial")
    with atomic.atomic_write(target) as tmp:
        Path(tmp).write_bytes(b"whole")
    assert target.read_bytes() == b"whole" and not dead.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == [target.name]


def test_fit_name_keeps_the_tail_and_short_names():
    short = Path("/x/run.nc.checkpoint.npz")
    assert atomic.fit_name(short, ".checkpoint.npz") == short
    long = Path("/x/" + "r" * 250 + ".nc.checkpoint.npz")
    fitted = atomic.fit_name(long, ".checkpoint.npz")
    assert fitted.name.endswith(".checkpoint.npz") and len(fitted.name.encode()) == 255
    assert fitted == atomic.fit_name(long, ".checkpoint.npz")  # the same name every time
    assert fitted != atomic.fit_name(Path("/x/" + "r" * 249 + "s.nc.checkpoint.npz"),
                                     ".checkpoint.npz")


def test_aliases_of_an_input_are_refused(tmp_path):
    scene = tmp_path / "s.toml"
    scene.write_text("x")
    (tmp_path / "link.nc").symlink_to(scene)
    os.link(scene, tmp_path / "hard.nc")
    for out in (scene, tmp_path / "." / "s.toml", tmp_path / "link.nc", tmp_path / "hard.nc"):
        with pytest.raises(atomic.OutputNotWritable, match="is the scene file"):
            atomic.refuse_aliases([("output", out)], [("scene file", scene)])
    atomic.refuse_aliases([("output", tmp_path / "new.nc")], [("scene file", scene)])
    with pytest.raises(atomic.OutputNotWritable, match="would both be"):
        atomic.refuse_aliases([("output", tmp_path / "a.png"), ("PNG", tmp_path / "a.png")])
