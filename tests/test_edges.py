"""The edges of a run (issue 13): output that cannot be written, progress, titles, an
unreachable scheduler, plots of short sweeps, and the small ones.

Every command-line test asserts the exit status, that the message names the thing (path,
key, address), and that no traceback reaches the user. The full disk is simulated twice: by
a writer that raises ``OSError(ENOSPC)`` (always), and by a real tmpfs that fills up (when
this process may mount one, i.e. as root; skipped otherwise). Runs are a tenth of a cage
revolution, about 1 s once the kernels are compiled: these tests check the machinery.
"""

from __future__ import annotations

import errno
import io
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from bearingdae import progress as progress_mod
from bearingdae.cli import main

ROOT = Path(__file__).resolve().parents[1]
SHORT = ["--set", "numerics.warmup_cage_revolutions=0", "--set", "numerics.cage_revolutions=0.1"]
TINY_SWEEP = """
title = "tiny"
base = "yang20_baseline"
[overrides]
"numerics.warmup_cage_revolutions" = 0.0
"numerics.cage_revolutions" = 0.05
"numerics.samples_per_cage_revolution" = 100
[axes]
"operating.speed_rpm" = [2000, 4000]
[sweep]
figures = [18, 19, 20]
"""


def cli(*args: str, env: dict | None = None, timeout: float = 600) -> subprocess.CompletedProcess:
    """The command line in a process of its own (what a user sees, tracebacks included)."""
    return subprocess.run([sys.executable, "-m", "bearingdae.cli", *args], capture_output=True,
                          text=True, timeout=timeout,
                          env={**os.environ, "PYTHONPATH": str(ROOT), "OMP_NUM_THREADS": "1",
                               **(env or {})})


def no_traceback(text: str) -> None:
    assert "Traceback" not in text and "Exception ignored" not in text, text[-3000:]


@pytest.fixture
def fallback_dir(tmp_path, monkeypatch):
    """$TMPDIR of this process: where a result that cannot be written is kept."""
    d = tmp_path / "fallback"
    d.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(d))
    return d


def enospc_under(folder: Path, monkeypatch) -> None:
    """Every NetCDF write into ``folder`` fails as on a full disk (after writing part of the
    file); writes elsewhere (the fallback folder) work."""
    real = xr.Dataset.to_netcdf

    def to_netcdf(self, path=None, *args, **kwargs):
        if path is not None and Path(path).parent == folder:
            Path(path).write_bytes(b"CDF\x01" + b"\0" * 1000)
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real(self, path, *args, **kwargs)

    monkeypatch.setattr(xr.Dataset, "to_netcdf", to_netcdf)


def mount_tmpfs(where: Path, options: str) -> None:
    where.mkdir()
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(where)],
                       capture_output=True, text=True)
    if r.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here ({r.stderr.strip() or 'not root'}); the "
                    "monkeypatched-writer tests cover the same path")


@pytest.fixture
def tmpfs(tmp_path):
    mounted = []

    def make(name: str, options: str) -> Path:
        where = tmp_path / name
        mount_tmpfs(where, options)
        mounted.append(where)
        return where

    yield make
    for where in mounted:
        subprocess.run(["umount", "-l", str(where)], capture_output=True)


# ------------------------------------------------------------------------------------------
# Item 2: output that cannot be written
# ------------------------------------------------------------------------------------------
def test_run_into_a_directory_is_refused_before_computing(tmp_path, capsys):
    folder = tmp_path / "results"
    folder.mkdir()
    assert main(["run", "-o", f"{folder}/", *SHORT]) == 2
    out, err = capsys.readouterr()
    assert f"'{folder}' is a directory" in err
    assert "wall time" not in out  # nothing was computed
    assert sorted(p.name for p in tmp_path.iterdir()) == ["results"]  # no checkpoint beside it
    no_traceback(err)


@pytest.mark.parametrize("command", ["run", "static", "sweep", "plot"])
def test_unwritable_output_is_refused_before_computing(tmp_path, capsys, command):
    """A target under a path that is a file (root can write anywhere else: chmod would not
    stop it) is refused with exit status 2 before anything runs."""
    blocker = tmp_path / "not_a_folder"
    blocker.write_text("a file")
    target = blocker / "out.nc"
    if command == "sweep":
        sweep = tmp_path / "s.toml"
        sweep.write_text(TINY_SWEEP)
        args = ["sweep", str(sweep), "-o", str(target), "--scheduler", "synchronous"]
    elif command == "plot":
        from bearingdae import load_scene, save, solve_static

        source = save(solve_static(load_scene("yang20_baseline")), tmp_path / "s.nc")
        args = ["plot", str(source), "--figure", "12", "-o", str(blocker / "f.png")]
    else:
        args = [command, "-o", str(target), *SHORT]
    assert main(args) == 2
    out, err = capsys.readouterr()
    assert f"'{blocker}' is a file, not a folder" in err, err
    assert "wall time" not in out and "Newton iterations" not in out
    no_traceback(err)


@pytest.mark.parametrize("command", ["run", "static", "sweep"])
def test_read_only_file_system_is_refused_before_computing(tmp_path, tmpfs, command):
    ro = tmpfs("ro", "ro,size=1m")
    if command == "sweep":
        sweep = tmp_path / "s.toml"
        sweep.write_text(TINY_SWEEP)
        args = ["sweep", str(sweep), "-o", str(ro / "x.nc"), "--scheduler", "synchronous"]
    else:
        args = [command, "-o", str(ro / "x.nc"), *SHORT]
    r = cli(*args)
    assert r.returncode == 2, r.stderr
    assert f"cannot write '{ro / 'x.nc'}': Read-only file system" in r.stderr
    no_traceback(r.stderr + r.stdout)


def test_full_disk_after_computing_keeps_the_result(tmp_path, capsys, monkeypatch,
                                                    fallback_dir):
    """The run finishes, the NetCDF write fails with ENOSPC: one line naming the path and "No
    space left on device", status 1, the result in the fallback file, the checkpoint kept;
    with room again, --resume writes the same result without integrating again."""
    target_dir = tmp_path / "out"
    target_dir.mkdir()
    target = target_dir / "run.nc"
    enospc_under(target_dir, monkeypatch)
    assert main(["run", "-o", str(target), "--no-progress", *SHORT]) == 1
    out, err = capsys.readouterr()
    no_traceback(err)
    assert f"cannot write '{target}': No space left on device" in err
    kept = list(fallback_dir.glob("bearingdae-*-run.nc"))
    assert len(kept) == 1 and f"kept in '{kept[0]}'" in err
    assert not target.exists() and not list(target_dir.glob(".*.part"))
    checkpoint = target_dir / "run.nc.checkpoint.npz"
    assert checkpoint.exists() and "--resume" in err
    with xr.open_dataset(kept[0]) as ds:
        result = ds.load()
    assert result.sizes["time"] > 10 and np.isfinite(result.cage_speed).all()

    monkeypatch.undo()  # the disk has room again
    assert main(["run", "-o", str(target), "--no-progress", "--no-plot", "--resume",
                 *SHORT]) == 0
    with xr.open_dataset(target) as ds:
        resumed = ds.load()
    stats = json.loads(resumed.attrs["solver_statistics"])
    assert stats["resumed_from_s"] == pytest.approx(float(result.time[-1]))
    np.testing.assert_array_equal(resumed.cage_speed.values, result.cage_speed.values)
    assert not checkpoint.exists()


def test_full_disk_of_static_keeps_the_result(tmp_path, capsys, monkeypatch, fallback_dir):
    target_dir = tmp_path / "out"
    target_dir.mkdir()
    enospc_under(target_dir, monkeypatch)
    assert main(["static", "-o", str(target_dir / "s.nc")]) == 1
    _, err = capsys.readouterr()
    no_traceback(err)
    assert f"cannot write '{target_dir / 's.nc'}': No space left on device" in err
    (kept,) = fallback_dir.glob("bearingdae-*-s.nc")
    with xr.open_dataset(kept) as ds:
        assert ds.contact_force.sum() > 0


def test_a_really_full_tmpfs(tmp_path, tmpfs):
    """The same on a real file system that fills up during the run: the checkpoint writes
    fail (the run goes on), the NetCDF write fails (netCDF4 says only "HDF error"; the message
    says the disk is full), the result goes to $TMPDIR. A tmpfs full from the start is refused
    before computing."""
    full = tmpfs("full", "size=512k")
    fallback = tmp_path / "fallback"
    fallback.mkdir()
    args = ["run", "-o", str(full / "x.nc"), "--no-progress", "--set",
            "numerics.warmup_cage_revolutions=0", "--set", "numerics.cage_revolutions=0.3"]
    r = cli(*args, env={"TMPDIR": str(fallback)})
    no_traceback(r.stderr + r.stdout)
    assert r.returncode == 1, r.stderr
    assert f"cannot write '{full / 'x.nc'}': No space left on device" in r.stderr
    (kept,) = fallback.glob("bearingdae-*-x.nc")
    with xr.open_dataset(kept) as ds:
        assert ds.sizes["time"] > 10
    for p in full.iterdir():  # the kept checkpoint; then fill the disk to the last byte
        p.unlink()
    try:
        with open(full / "filler", "wb") as fh:
            while True:
                fh.write(b"\0" * 4096)
                fh.flush()
    except OSError:
        pass
    r = cli(*args, env={"TMPDIR": str(fallback)})
    assert r.returncode == 2 and "No space left on device" in r.stderr, r.stderr
    assert "wall time" not in r.stdout
    no_traceback(r.stderr)


@pytest.fixture(scope="module")
def short_sweep(tmp_path_factory):
    """A two-run sweep whose runs are shorter than one orbit (summaries, no orbit curves)."""
    d = tmp_path_factory.mktemp("short_sweep")
    (d / "s.toml").write_text(TINY_SWEEP)
    from bearingdae.sweep import run_sweep

    run_sweep(d / "s.toml", d / "short.nc", scheduler="synchronous", progress=False)
    return d / "short.nc"


def test_plot_write_failure_is_one_line(tmp_path, capsys, monkeypatch, short_sweep):
    from matplotlib.figure import Figure

    def full(self, fname, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(Figure, "savefig", full)
    target = tmp_path / "f.png"
    assert main(["plot", str(short_sweep), "--figure", "trends", "-o", str(target)]) == 1
    _, err = capsys.readouterr()
    assert f"cannot write '{target}': No space left on device" in err
    assert not target.exists()
    no_traceback(err)


# ------------------------------------------------------------------------------------------
# Item 3: an unreachable scheduler
# ------------------------------------------------------------------------------------------
def test_unreachable_scheduler_is_one_line(tmp_path):
    sweep = tmp_path / "s.toml"
    sweep.write_text(TINY_SWEEP)
    t0 = time.monotonic()
    r = cli("sweep", str(sweep), "-o", str(tmp_path / "x.nc"), "--scheduler",
            "tcp://127.0.0.1:1", "--scheduler-timeout", "2", "--no-progress")
    waited = time.monotonic() - t0
    no_traceback(r.stderr + r.stdout)
    assert r.returncode == 1, r.stderr
    errors = [ln for ln in r.stderr.splitlines() if ln.startswith("bearingdae:")]
    assert len(errors) == 1, r.stderr
    assert "'tcp://127.0.0.1:1' within 2 s" in errors[0] and "--scheduler-timeout" in errors[0]
    assert "CancelledError" not in r.stderr
    assert waited < 29, waited  # the timeout given, not the 30 s default


def test_scheduler_timeout_must_be_positive(tmp_path, capsys):
    sweep = tmp_path / "s.toml"
    sweep.write_text(TINY_SWEEP)
    assert main(["sweep", str(sweep), "--scheduler-timeout", "0"]) == 2
    assert "--scheduler-timeout 0.0: must be > 0 s" in capsys.readouterr().err


# ------------------------------------------------------------------------------------------
# Item 4: plots of short sweeps, and of a directory
# ------------------------------------------------------------------------------------------
def test_plot_of_a_sweep_shorter_than_one_orbit_skips_the_orbit_figures(short_sweep, capsys):
    assert main(["plot", str(short_sweep)]) == 0  # the trends figure is drawn
    out, err = capsys.readouterr()
    no_traceback(err)
    for number in (18, 19, 20):
        assert f"figure {number} skipped: needs the one-orbit curves" in err, err
        assert not short_sweep.with_name(f"short_fig{number}.png").exists()
    assert "shorter than one orbit" in err
    assert short_sweep.with_name("short_trends.png").exists()
    # asked for explicitly, the figure is an error naming it
    assert main(["plot", str(short_sweep), "--figure", "20"]) == 2
    assert "figure 20: needs the one-orbit curves" in capsys.readouterr().err


def test_plot_of_a_directory_says_so(tmp_path, capsys):
    assert main(["plot", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert f"'{tmp_path}' is a directory" in err and "does not exist" not in err
    no_traceback(err)
