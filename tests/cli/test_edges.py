"""The edges of a run: output that cannot be written, progress, titles, an
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

from bearingdae.run import progress as progress_mod
from bearingdae.cli import main

ROOT = Path(__file__).resolve().parents[2]
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
def test_unwritable_output_is_refused_before_computing(tmp_path, capsys, command, request):
    """A target under a path that is a file (root can write anywhere else: chmod would not
    stop it) is refused with exit status 2 before anything runs."""
    blocker = tmp_path / "not_a_folder"
    blocker.write_text("a file")
    target = blocker / "out.nc"
    if command == "sweep":
        sweep = tmp_path / "s.toml"
        sweep.write_text(TINY_SWEEP)
        args = ["sweep", str(sweep), "-o", str(target), "--scheduler", "synchronous"]
    elif command == "plot":  # (a sweep file: plot draws from run and sweep files)
        source = request.getfixturevalue("short_sweep")
        args = ["plot", str(source), "--figure", "trends", "-o", str(blocker / "f.png")]
    else:
        args = [command, "-o", str(target), *SHORT]
    assert main(args) == 2
    out, err = capsys.readouterr()
    assert f"'{blocker}' is a file, not a folder" in err, err
    assert "wall time" not in out and "Newton iterations" not in out
    no_traceback(err)


@pytest.mark.parametrize("command", ["run", "static", "sweep", "plot"])
def test_read_only_file_system_is_refused_before_computing(tmp_path, tmpfs, command, request):
    ro = tmpfs("ro", "ro,size=1m")
    target = ro / "x.nc"
    if command == "sweep":
        sweep = tmp_path / "s.toml"
        sweep.write_text(TINY_SWEEP)
        args = ["sweep", str(sweep), "-o", str(target), "--scheduler", "synchronous"]
    elif command == "plot":
        source = request.getfixturevalue("short_sweep")
        target = ro / "f.png"
        args = ["plot", str(source), "--figure", "trends", "-o", str(target)]
    else:
        args = [command, "-o", str(target), *SHORT]
    r = cli(*args)
    assert r.returncode == 2, r.stderr
    assert f"cannot write '{target}': Read-only file system" in r.stderr
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


def test_a_failed_write_leaves_no_netcdf_file_open(tmpfs):
    """A NetCDF write that fails on a full disk closes its file before it reports. Left to
    Python's cyclic collector (xarray's open file sits in a cycle with the exception's frames),
    it closed at a random later moment, on whichever thread ran then, maybe while the stream
    writer's thread was in HDF5, which is not thread-safe: in 9 of 35 runs of the test above's
    first command, the fallback copy failed with "HDF error" or the process crashed."""
    import gc

    import netCDF4

    from bearingdae.results.netcdf import save
    from bearingdae.results.streamed_netcdf import StreamWriter

    def open_files():  # without collecting: what the collector would close later
        # (type(): isinstance would ask a dead weak proxy among the objects for its class)
        return [f for f in gc.get_objects()
                if issubclass(type(f), netCDF4.Dataset) and f.isopen()]

    full = tmpfs("small", "size=64k")
    noise = np.random.default_rng(0).standard_normal((600, 200))  # ~1 MB that zlib cannot shrink
    ds = xr.Dataset({"v": (("time", "x"), noise)}, coords={"time": np.arange(600.0)})
    assert open_files() == []
    with pytest.raises((OSError, RuntimeError)):
        save(ds, full / "a.nc")
    assert open_files() == []
    writer = StreamWriter(full / "b.nc", block=600)
    writer.append(ds)  # written by the writer's thread
    with pytest.raises(OSError, match="No space left on device"):
        writer.settle()
    assert open_files() == []
    writer.abandon()
    assert sorted(p.name for p in full.iterdir()) == []


@pytest.fixture(scope="module")
def short_sweep(tmp_path_factory):
    """A two-run sweep whose runs are shorter than one orbit (summaries, no orbit curves)."""
    d = tmp_path_factory.mktemp("short_sweep")
    (d / "s.toml").write_text(TINY_SWEEP)
    from bearingdae.studies.sweep import run_sweep

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


@pytest.mark.parametrize("command", ["sweep", "paper", "paper --trends", "skidmap"])
@pytest.mark.parametrize("seconds", ["0", "-1", "inf", "nan", "1e300"])
def test_scheduler_timeout_is_finite_positive_seconds(tmp_path, capsys, command, seconds):
    """Every command that reaches a scheduler refuses a wait that is not a finite number of
    seconds in (0, a day] in one line, status 2, before any run (inf was a traceback)."""
    sweep = tmp_path / "s.toml"
    sweep.write_text(TINY_SWEEP)
    args = {"sweep": ["sweep", str(sweep)], "paper": ["paper", "-o", str(tmp_path / "p")],
            "paper --trends": ["paper", "--trends", "-o", str(tmp_path / "p")],
            "skidmap": ["skidmap", "yang20_baseline", "--speeds", "1000", "--loads", "100",
                        "-o", str(tmp_path / "m.nc")]}[command]
    assert main([*args, f"--scheduler-timeout={seconds}"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"--scheduler-timeout {float(seconds)!r}" in err[0], err
    assert "finite number of seconds in (0, 86400]" in err[0]
    assert not (tmp_path / "p" / "runs").exists() or not any((tmp_path / "p" / "runs").iterdir())


def test_paper_trends_waits_the_timeout_it_is_given(tmp_path):
    r = cli("paper", "--trends", "-o", str(tmp_path / "p"), "--scheduler", "tcp://127.0.0.1:1",
            "--scheduler-timeout", "2", "--no-progress", "--no-figures")
    no_traceback(r.stderr + r.stdout)
    errors = [ln for ln in r.stderr.splitlines() if ln.startswith("bearingdae:")]
    assert r.returncode == 1 and len(errors) == 1, r.stderr
    assert "'tcp://127.0.0.1:1' within 2 s" in errors[0]  # not the 30 s default


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


# ------------------------------------------------------------------------------------------
# Item 5: titles show the values that ran
# ------------------------------------------------------------------------------------------
def test_titles_show_the_values_set(tmp_path, capsys, monkeypatch):
    from matplotlib.figure import Figure

    titles = []
    real_savefig = Figure.savefig

    def savefig(self, *args, **kwargs):
        titles.append(self.get_suptitle())
        return real_savefig(self, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", savefig)
    out = tmp_path / "h.nc"
    assert main(["static", "harris36_static", "-o", str(out), "--set",
                 "operating.radial_load_N=8000"]) == 0
    printed = capsys.readouterr().out.splitlines()[0]
    assert printed.endswith("[set: operating.radial_load_N = 8000]"), printed
    with xr.open_dataset(out) as ds:
        assert ds.attrs["title"].endswith("[set: operating.radial_load_N = 8000]")
        assert ds["radial_load_N"].item() == 8000.0
    run = tmp_path / "r.nc"
    assert main(["run", "-o", str(run), "--no-progress", *SHORT]) == 0
    with xr.open_dataset(run) as ds:
        assert "numerics.cage_revolutions = 0.1" in ds.attrs["title"]
    assert titles and "numerics.cage_revolutions = 0.1" in titles[-1]  # the overview PNG
    # without overrides the case's own title is kept as written
    from bearingdae import load_scene

    assert load_scene("harris36_static").title == "harris36: 12000 N, 5000 r/min"


# ------------------------------------------------------------------------------------------
# Item 6: progress a person can read
# ------------------------------------------------------------------------------------------
class Clock:
    def __init__(self):
        self.now = 1000.0

    def __call__(self):
        return self.now


def test_progress_without_a_terminal_is_a_line_per_tenth(monkeypatch):
    clock = Clock()
    monkeypatch.setattr(progress_mod.time, "monotonic", clock)
    stream = io.StringIO()
    bar = progress_mod.SimulationProgress(0.25, stream=stream)
    assert not bar.tty
    for t in np.linspace(0.0, 0.25, 801):  # 801 samples, as the default run's 802
        clock.now += 0.05
        bar.update(float(t))
    bar.close()
    lines = stream.getvalue().splitlines()
    assert "\r" not in stream.getvalue()
    # a line as soon as the integration moves (the second sample: on a cold start the first
    # sign that compiling is over), then one per tenth
    assert lines[0].startswith("simulated time 0.0003/0.2500 s (0 %)"), lines[0]
    assert [ln.split("(")[1].split(" %")[0] for ln in lines[1:]] == [str(10 * k) for k in
                                                                     range(1, 11)]
    # half done after 20 s of integration: 20 s left (the rate since the first sample)
    assert lines[5].endswith("0:20 elapsed, about 0:20 left"), lines[5]
    assert lines[-1].startswith("simulated time 0.2500/0.2500 s (100 %)")


def test_eta_only_once_it_means_something(monkeypatch):
    clock = Clock()
    monkeypatch.setattr(progress_mod.time, "monotonic", clock)
    bar = progress_mod.SimulationProgress(1.0, stream=io.StringIO())
    clock.now += 25.0  # the first sample comes after compiling
    bar.update(0.0)
    clock.now += 1.0
    bar.update(0.01)
    assert bar.eta_s(0.01) is None  # 1 % done, 1 s of integration: nothing to say yet
    clock.now += 1.0
    assert bar.eta_s(0.2) is None  # 2 s since the first sample: still too early
    clock.now += 2.0
    eta = bar.eta_s(0.2)  # 20 % in 4 s since the first sample: 16 s left, compiling excluded
    assert eta == pytest.approx(16.0)


def test_progress_on_a_terminal_is_a_bar_with_a_late_eta(monkeypatch):
    clock = Clock()
    monkeypatch.setattr(progress_mod.time, "monotonic", clock)
    stream = io.StringIO()
    bar = progress_mod.SimulationProgress(1.0, stream=stream, tty=True)
    bar.update(0.0)
    clock.now += 1.0
    bar.update(0.01)
    early = stream.getvalue()
    assert "simulated time" in early and "ETA" not in early
    clock.now += 9.0
    bar.update(0.5)
    bar.close()
    assert ", ETA 0:10]" in stream.getvalue() and ", ," not in stream.getvalue()


def test_a_terminal_is_recognised_by_its_size():
    """Default detection: a pseudo-terminal with a size gets the bar; one that reports 0 x 0
    (the pty of `script` piped, docker -t), where tqdm shows nothing, and a pipe get lines."""
    import fcntl
    import struct
    import termios

    master, slave = os.openpty()
    with os.fdopen(slave, "w") as tty, os.fdopen(master, "rb", buffering=0):
        fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 0, 0, 0, 0))
        sized_zero = progress_mod.SimulationProgress(1.0, stream=tty)
        assert not sized_zero.tty and sized_zero._bar is None
        fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 30, 100, 0, 0))
        sized = progress_mod.SimulationProgress(1.0, stream=tty)
        assert sized.tty and sized._bar is not None
        sized.close()
    assert not progress_mod.SimulationProgress(1.0, stream=io.StringIO()).tty


def test_cold_kernel_cache_is_detected(tmp_path):
    """Cold: a numba cache folder without the kernels (a fresh process pointed at an empty
    NUMBA_CACHE_DIR); warm: this process, after a run has compiled and cached them."""
    from bearingdae import load_scene, simulate

    simulate(load_scene("yang20_baseline", {"numerics.warmup_cage_revolutions": 0,
                                            "numerics.cage_revolutions": 0.02}))
    assert progress_mod.kernels_cold() is False and progress_mod.compile_notice() is None
    code = "from bearingdae.run.progress import compile_notice; print(compile_notice())"
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       env={**os.environ, "PYTHONPATH": str(ROOT),
                            "NUMBA_CACHE_DIR": str(tmp_path)})
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("compiling kernels (first run only, ~"), r.stdout


def test_run_piped_prints_lines_not_a_redrawn_bar(tmp_path):
    r = cli("run", "-o", str(tmp_path / "r.nc"), "--no-plot", *SHORT)
    assert r.returncode == 0, r.stderr
    no_traceback(r.stderr)
    assert "\r" not in r.stderr
    progress_lines = [ln for ln in r.stderr.splitlines() if ln.startswith("simulated time")]
    assert 5 <= len(progress_lines) <= 12, r.stderr


# ------------------------------------------------------------------------------------------
# Item 7: the small ones
# ------------------------------------------------------------------------------------------
def test_sweep_accepts_set(tmp_path, capsys):
    sweep = tmp_path / "s.toml"
    sweep.write_text(TINY_SWEEP)
    out = tmp_path / "x.nc"
    assert main(["sweep", str(sweep), "-o", str(out), "--scheduler", "synchronous",
                 "--no-progress", "--set", "numerics.slices=4"]) == 0
    assert "[set: numerics.slices = 4]" in capsys.readouterr().out
    with xr.open_dataset(out) as ds:
        run_file = out.parent / str(ds.run_file.values.ravel()[0])
        assert ds.attrs["title"].endswith("[set: numerics.slices = 4]")
    with xr.open_dataset(run_file) as run:
        assert run.sizes["slice"] == 4


@pytest.mark.parametrize("command", ["sweep", "paper", "paper --trends"])
def test_set_on_sweeps_names_the_argument(tmp_path, capsys, command):
    sweep = tmp_path / "s.toml"
    sweep.write_text(TINY_SWEEP)
    first = [str(sweep)] if command == "sweep" else ["-o", str(tmp_path / "p")]
    command, *extra = command.split()
    first += extra
    assert main([command, *first, "--set", "operating.speed_rpm=3000"]) == 2
    err = capsys.readouterr().err
    assert "--set operating.speed_rpm=3000: 'operating.speed_rpm' is an axis" in err, err
    assert main([command, *first, "--set", "numerics.slics=4"]) == 2
    err = capsys.readouterr().err
    assert "--set" in err and "Did you mean 'numerics.slices'?" in err, err
    no_traceback(err)


@pytest.mark.parametrize("command", ["run", "static", "sweep", "plot", "workprecision"])
def test_ctrl_c_gives_status_130_in_every_command(tmp_path, capsys, monkeypatch, command,
                                                  short_sweep):
    """Ctrl-C while each command works: status 130 and one line (a run keeps its samples)."""
    def interrupt(*args, **kwargs):
        raise KeyboardInterrupt

    if command == "run":
        from bearingdae.run.checkpoint import Checkpoint

        real = Checkpoint.sample

        def after_4(self, t, y, yp):
            real(self, t, y, yp)
            if len(self.T) == 4:
                raise KeyboardInterrupt

        monkeypatch.setattr(Checkpoint, "sample", after_4)
        args = ["run", "-o", str(tmp_path / "r.nc"), "--no-progress", "--no-plot", *SHORT]
    elif command == "static":
        monkeypatch.setattr("bearingdae.solve_static", interrupt)
        args = ["static", "-o", str(tmp_path / "s.nc")]
    elif command == "sweep":
        monkeypatch.setattr("bearingdae.studies.sweep.run_sweep", interrupt)
        sweep = tmp_path / "s.toml"
        sweep.write_text(TINY_SWEEP)
        args = ["sweep", str(sweep), "-o", str(tmp_path / "w.nc")]
    elif command == "plot":
        monkeypatch.setattr("bearingdae.plots.plotting.figure", interrupt)
        args = ["plot", str(short_sweep), "--figure", "trends", "-o", str(tmp_path / "t.png")]
    else:
        monkeypatch.setattr("bearingdae.studies.workprecision.study", interrupt)
        args = ["workprecision", "-o", str(tmp_path)]
    assert main(args) == 130
    err = capsys.readouterr().err
    no_traceback(err)
    assert "interrupted" in err
    if command == "run":
        assert (tmp_path / "r_partial.nc").exists()


def test_set_errors_name_the_set_argument(capsys):
    assert main(["static", "harris36_static", "--set", "operating.radial_load_N=-5"]) == 2
    err = capsys.readouterr().err
    assert "invalid scene (--set operating.radial_load_N=-5)" in err, err
    assert "harris36_static.toml" not in err and "site-packages" not in err
    no_traceback(err)


def test_invalid_speed_is_one_error_line(capsys):
    assert main(["static", "--set", "operating.speed_rpm=-5"]) == 2
    err = capsys.readouterr().err
    items = [ln for ln in err.splitlines() if ln.startswith("  - ")]
    assert len(items) == 1 and "'operating.speed_rpm' = -5" in items[0], err
    assert "SpeedRamp" not in err
    # a ramp that is wrong gets the ramp's message, not the number's
    assert main(["static", "--set",
                 "operating.speed_rpm={times_s = [0, 1], values_rpm = [0, -3]}"]) == 2
    err = capsys.readouterr().err
    items = [ln for ln in err.splitlines() if ln.startswith("  - ")]
    assert len(items) == 1 and "values_rpm" in items[0], err


def test_unknown_sweep_axis_suggests_a_key_of_its_section(tmp_path, capsys):
    sweep = tmp_path / "s.toml"
    sweep.write_text(TINY_SWEEP.replace('"operating.speed_rpm"', '"operating.nosuch_key"'))
    assert main(["sweep", str(sweep)]) == 2
    err = capsys.readouterr().err
    assert "unknown scene key 'operating.nosuch_key'" in err
    assert "Did you mean 'operating'" not in err and "operating.radial_load_N" in err, err
    sweep.write_text(TINY_SWEEP.replace('"operating.speed_rpm"', '"operating.sped_rpm"'))
    assert main(["sweep", str(sweep)]) == 2
    assert "Did you mean 'operating.speed_rpm'?" in capsys.readouterr().err


def test_partial_files_are_removed_after_a_successful_resume(tmp_path, capsys, monkeypatch):
    from bearingdae.run.checkpoint import Checkpoint

    real = Checkpoint.sample

    def after_4(self, t, y, yp):
        real(self, t, y, yp)
        if len(self.T) == 4:
            raise KeyboardInterrupt

    target = tmp_path / "r.nc"
    with monkeypatch.context() as m:
        m.setattr(Checkpoint, "sample", after_4)
        assert main(["run", "-o", str(target), "--no-progress", *SHORT]) == 130
    partial = [tmp_path / "r_partial.nc", tmp_path / "r_partial.png"]
    assert all(p.exists() for p in partial)
    assert main(["run", "-o", str(target), "--no-progress", "--resume", *SHORT]) == 0
    out = capsys.readouterr().out
    assert not any(p.exists() for p in partial)
    assert target.exists() and target.with_suffix(".png").exists()
    assert "removed" in out and "r_partial.nc" in out


def test_cases_copy_starts_a_case_of_ones_own(tmp_path, capsys):
    mine = tmp_path / "my_case.toml"
    assert main(["cases", "--copy", "yang20_baseline", str(mine)]) == 0
    assert "bearingdae run" in capsys.readouterr().out
    from bearingdae import load_scene
    from bearingdae.scene import resolve_case

    assert mine.read_bytes() == resolve_case("yang20_baseline").read_bytes()
    assert load_scene(mine).title == load_scene("yang20_baseline").title
    # edited, the copy's title states its own load (the case's title is generated from its
    # operating point: scene/titles.py)
    mine.write_text(mine.read_text().replace("radial_load_N = 800.0", "radial_load_N = 2000.0"))
    assert load_scene(mine).title == "yang20 baseline: 2000 N, 3 N·m, 2000 r/min"
    assert main(["cases", "--copy", "yang20_baseline", str(mine)]) == 2  # never overwrites
    assert "exists already" in capsys.readouterr().err
    assert main(["cases", "--copy", "no_such_case", str(tmp_path / "x.toml")]) == 2
    assert "no_such_case" in capsys.readouterr().err


# ------------------------------------------------------------------------------------------
# Item 8: output precision
# ------------------------------------------------------------------------------------------
def test_float32_output_halves_the_file_within_float32_rounding(tmp_path):
    from bearingdae import load_scene, save, simulate

    scene = load_scene("yang20_baseline", {"numerics.warmup_cage_revolutions": 0,
                                           "numerics.cage_revolutions": 0.1,
                                           "output.precision": "float32"})
    assert scene.output_precision == "float32"
    ds = simulate(scene)
    small = save(ds, tmp_path / "f32.nc")  # from the Dataset's output_precision attribute
    full = save(ds, tmp_path / "f64.nc", precision="float64")
    assert small.stat().st_size < 0.7 * full.stat().st_size
    with xr.open_dataset(small) as back:
        assert back.time.dtype == np.float64  # coordinates keep float64
        for name, var in ds.data_vars.items():
            if var.dtype.kind != "f":
                continue
            assert back[name].dtype == np.float32, name
            x, y = var.values, back[name].values.astype(float)
            # float32 rounds to nearest: |error| <= 2^-24 |x| (unit roundoff); nan (a film on an
            # unloaded slice) stays nan
            assert np.array_equal(np.isnan(x), np.isnan(y)), name
            x, y = x[~np.isnan(x)], y[~np.isnan(x)]
            assert np.all(np.abs(y - x) <= 2.0 ** -24 * np.abs(x) + 1e-300), name
    assert load_scene("yang20_baseline").output_precision == "float64"  # the default


def test_sweep_piped_prints_a_line_per_run(tmp_path):
    sweep = tmp_path / "s.toml"
    sweep.write_text(TINY_SWEEP)
    r = cli("sweep", str(sweep), "-o", str(tmp_path / "x.nc"), "--scheduler", "synchronous")
    assert r.returncode == 0, r.stderr
    no_traceback(r.stderr)
    assert "\r" not in r.stderr
    assert [ln for ln in r.stderr.splitlines() if ln.startswith("sweep:")] == [
        "sweep: 1/2 runs done, 0 failed", "sweep: 2/2 runs done, 0 failed"]


def test_sundials_unavailable_is_one_line_not_a_traceback(tmp_path, capsys, monkeypatch):
    """A broken scikit-sundae installation (the compiled IDA core cannot bind its SUNDIALS):
    status 1 and one line that says so, naming the cause, no traceback, no file written."""
    from bearingdae.solvers.ida import IDA
    from bearingdae.solvers.sundials.library import SundialsUnavailable

    def unavailable(*args, **kwargs):
        raise SundialsUnavailable("libsundials_ida not found among the loaded libraries")

    monkeypatch.setattr(IDA, "_run", unavailable)
    target = tmp_path / "r.nc"
    status = main(["run", "-o", str(target), "--no-progress", "--no-plot", *SHORT])
    err = capsys.readouterr().err
    assert status == 1
    assert "SUNDIALS unavailable" in err and "libsundials_ida" in err
    no_traceback(err)
    assert not target.exists()


def test_a_reader_that_goes_away_ends_the_command_quietly(capsys, monkeypatch):
    """stdout closed by its reader (``bearingdae keys | head -1``): BrokenPipeError on the next
    print; status 1, no traceback, no error line."""
    import bearingdae.cli as cli_mod

    def closed_stdout(args):
        raise BrokenPipeError(32, "Broken pipe")

    monkeypatch.setattr(cli_mod, "_keys", closed_stdout)
    assert main(["keys"]) == 1
    assert capsys.readouterr().err == ""


def test_resume_on_a_complete_result_leaves_it_as_it_is(tmp_path, capsys):
    """--resume where the run is complete (its file, no checkpoint) says so and exits 0 with
    the file byte for byte as it was; a file of another scene, or not a run file at all, is
    refused in one line (exit 2) and left alone: --resume never replaces a file."""
    target = tmp_path / "r.nc"
    assert main(["run", "-o", str(target), "--no-progress", "--no-plot", *SHORT]) == 0
    before = target.read_bytes()
    capsys.readouterr()
    assert main(["run", "-o", str(target), "--no-progress", "--no-plot", "--resume",
                 *SHORT]) == 0
    out, err = capsys.readouterr()
    assert "a complete run of this scene; nothing to resume" in out and "wall time" not in out
    assert target.read_bytes() == before
    assert main(["run", "-o", str(target), "--no-progress", "--no-plot", "--resume", *SHORT,
                 "--set", "operating.radial_load_N=900"]) == 2
    err = capsys.readouterr().err
    assert "another scene" in err and len(err.strip().splitlines()) == 1
    no_traceback(err)
    assert target.read_bytes() == before
    foreign = tmp_path / "f.nc"
    foreign.write_bytes(b"not a netcdf file")
    assert main(["run", "-o", str(foreign), "--no-progress", "--no-plot", "--resume",
                 *SHORT]) == 2
    err = capsys.readouterr().err
    assert "not a result file" in err and foreign.read_bytes() == b"not a netcdf file"
    no_traceback(err)


def test_resume_after_a_kill_during_the_png_write_draws_it(tmp_path):
    """A run killed while it wrote its overview PNG (the NetCDF complete, the checkpoint
    removed) left no PNG and the write's temporary; `--resume` said "nothing to resume" and
    left both so. Now it draws the PNG from the file and removes the dead writer's temporary."""
    from bearingdae.util.atomic import _host_tag

    target = tmp_path / "run.nc"
    r = cli("run", "-o", str(target), "--no-plot", "--no-progress", *SHORT)
    assert r.returncode == 0, r.stderr
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True).stdout.strip()
    stale = tmp_path / f".run.png.{dead}-{_host_tag()}.abc12345.part"
    stale.write_bytes(b"\x89PNG half")  # what SIGKILL during the write leaves
    r = cli("run", "-o", str(target), "--resume", "--no-progress", *SHORT)
    no_traceback(r.stderr + r.stdout)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "run.png").stat().st_size > 1000 and not stale.exists()
    assert "nothing to resume" in r.stdout and "the overview was missing" in r.stdout


def test_an_interrupted_warm_up_in_blocks_says_what_it_kept_and_resumes(tmp_path, capsys,
                                                                          monkeypatch):
    """``until_steady`` keeps its own warm-up checkpoint (``OUT.nc.warmup.npz``), not the
    record's: interrupted in its third block the run says that file is kept, and
    ``--resume`` says it resumes the warm-up from it (it said "no checkpoint ...; starting
    from t = 0" and, interrupted, nothing of a checkpoint)."""
    from bearingdae.run import progress

    real = progress.mark_first_sample
    calls = []

    def sample_then_stop():  # (called at every sample) Ctrl-C in the third block
        real()
        calls.append(1)
        if len(calls) == 25:
            raise KeyboardInterrupt

    target = tmp_path / "r.nc"
    blocks = ["--set", "numerics.until_steady=true", "--set", "numerics.steady_tolerance=0.1",
              "--set", "numerics.steady_block_cage_revolutions=0.05", "--set",
              "numerics.warmup_cage_revolutions=0.2", "--set", "numerics.cage_revolutions=0.05",
              "--no-plot", "--no-progress"]
    with monkeypatch.context() as m:
        m.setattr(progress, "mark_first_sample", sample_then_stop)
        assert main(["run", "-o", str(target), *blocks]) == 130
    err = capsys.readouterr().err
    warm = tmp_path / "r.nc.warmup.npz"
    assert warm.exists() and f"warm-up checkpoint {warm} kept; continue with --resume" in err
    assert main(["run", "-o", str(target), "--resume", *blocks]) == 0
    err = capsys.readouterr().err
    assert f"resuming the warm-up from {warm}" in err and "starting from t = 0" not in err
    assert target.exists() and not warm.exists()


def test_a_ctrl_c_while_a_sample_is_handed_on_keeps_record_and_checkpoint_alike(tmp_path,
                                                                                monkeypatch):
    """A SIGINT that arrives while a sample is on its way to the record (the streamed file)
    lands after the sample has reached both the record and the checkpoint: the partial file
    and the checkpoint hold the same samples, so that the resume continues where the file
    ends (before, the checkpoint kept the sample and the file did not: a race that failed
    tests/results/test_streamed.py's real Ctrl-C once in a loaded full tier)."""
    import signal

    from bearingdae.results.streamed_record import StreamedRecord
    from bearingdae.run.checkpoint import checkpoint_path

    real = StreamedRecord.__call__
    seen = []

    def signal_first(self, t, y, yp):  # the SIGINT arrives before the record takes sample 10
        seen.append(t)
        if len(seen) == 10:
            os.kill(os.getpid(), signal.SIGINT)
        real(self, t, y, yp)

    target = tmp_path / "r.nc"
    with monkeypatch.context() as m:
        m.setattr(StreamedRecord, "__call__", signal_first)
        assert main(["run", "-o", str(target), "--no-progress", "--no-plot", *SHORT]) == 130
    with np.load(checkpoint_path(target)) as z:
        held = np.array(z["t"])
    with xr.open_dataset(tmp_path / "r_partial.nc") as ds:
        np.testing.assert_array_equal(ds.time.values, held)
    assert held.size == 10
