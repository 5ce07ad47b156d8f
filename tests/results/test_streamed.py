"""A streamed run (results/streamed_record.py, results/streamed_netcdf.py,
api.simulate_to_file) writes the file an in-memory run would: every variable and coordinate bit for bit, the same attributes; and a
run interrupted (Ctrl-C) or killed (SIGKILL) while streaming loses no computed sample and
leaves no file at its target."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from bearingdae import SimulationError, load_scene, save, simulate
from bearingdae.cli import main
from bearingdae.run import checkpoint as checkpoint_module, segments
from bearingdae.run.checkpoint import Checkpoint, checkpoint_path
from bearingdae.results import streamed_netcdf as stream

ROOT = Path(__file__).resolve().parents[2]
CASE = "yang20_baseline"
#: short, with the default moment (skew, edge loading), a warm-up and several blocks
SCENE = {"numerics.warmup_cage_revolutions": 0.05, "numerics.cage_revolutions": 0.3}
#: a block of 16 samples: the 61 recorded samples come in 4 blocks, the last one short
BLOCK = 16
#: attributes that differ between any two runs (the clock)
CLOCK = {"history"}
CLOCK_STATISTICS = {"wall_time_s", "setup_wall_s", "wall_time_s_all_segments"}
#: the rating life's power means are sums over blocks: equal to round-off, not bit for bit
SUMMED = {"reference_rating_life_L10r_Mrev", "reference_rating_life_L10r_h",
          "equivalent_reference_load_N", "reference_rating_life_L10r_slices_Mrev",
          "reference_rating_life_L10r_error_Mrev"}


@pytest.fixture
def small_blocks(monkeypatch):
    monkeypatch.setattr(stream, "BLOCK_SAMPLES", BLOCK)


def quiet(fn, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kwargs)


def assert_same_result(mem: xr.Dataset, ds: xr.Dataset) -> None:
    """Every variable and coordinate equal bit for bit (values, dims, dtype, attributes), and
    every global attribute but the clock's; the summed life to 1e-12."""
    assert set(mem.variables) == set(ds.variables)
    for name in mem.variables:
        a, b = mem[name], ds[name]
        assert a.dims == b.dims, name
        if a.dtype.kind in "OUS":  # labels: a file gives them back as objects
            assert list(map(str, a.values.ravel())) == list(map(str, b.values.ravel())), name
            continue
        assert a.dtype == b.dtype, name
        if name in SUMMED:  # the life's sums, block by block
            assert b.item() == pytest.approx(a.item(), rel=1e-12), name
        elif name not in CLOCK_STATISTICS:
            assert np.array_equal(a.values, b.values, equal_nan=a.dtype.kind == "f"), name
        assert a.attrs.keys() == b.attrs.keys(), name
        for key, value in a.attrs.items():  # (a flag's flag_values is an array)
            assert np.array_equal(value, b.attrs[key]), (name, key)
    assert set(mem.attrs) - CLOCK == set(ds.attrs) - CLOCK
    for key in set(mem.attrs) - CLOCK - {"wall_time_s"}:
        x, y = mem.attrs[key], ds.attrs[key]
        if key == "solver_statistics":
            x, y = ({k: v for k, v in json.loads(s).items() if k not in CLOCK_STATISTICS}
                    for s in (x, y))
        if key in SUMMED:
            assert y == pytest.approx(x, rel=1e-12), key
        else:
            assert x == y, key


@pytest.mark.parametrize("precision", ["float64", "float32"])
def test_streamed_file_is_the_in_memory_dataset(tmp_path, small_blocks, precision):
    """simulate(scene) in memory, saved by save(), against simulate(scene, output=path):
    the same variables, coordinates, attributes and encodings (chunking apart)."""
    scene = load_scene(CASE, {**SCENE, "output.precision": precision})
    mem = quiet(simulate, scene, progress=False)
    saved = save(mem, tmp_path / "memory.nc")
    streamed = tmp_path / "streamed.nc"
    ds = quiet(simulate, scene, progress=False, output=streamed)
    try:
        assert ds.sizes["time"] == mem.sizes["time"] > 3 * BLOCK  # several blocks
        with xr.open_dataset(saved, decode_timedelta=False) as ref:
            ref.load()
            ds.load()
            assert_same_result(ref, ds)
            for name in ref.variables:  # as save() encodes them
                for key in ("dtype", "_FillValue", "zlib", "complevel", "coordinates"):
                    assert str(ref[name].encoding.get(key)) == str(ds[name].encoding.get(key)), \
                        (name, key)
            assert set(ds.encoding["unlimited_dims"]) == {"time"}
            assert ds.cage_speed.encoding["chunksizes"] == (BLOCK,)
        if precision == "float64":
            assert_same_result(mem, ds)
    finally:
        ds.close()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["memory.nc", "streamed.nc"]


def test_samples_that_wait_for_the_projection_give_the_same_file(tmp_path, small_blocks,
                                                                 monkeypatch):
    """A cold start with a second process (solvers/sundials/precompile.py) compiles the
    projection of the samples there while the integration goes on; the samples wait for it
    (results/streamed_record.py) and go through in order once it is there. The file is the
    one of a run whose projection was ready, bit for bit; no block is projected before the
    wait, and none waits once the projection is there."""
    from bearingdae.results import streamed_record
    from bearingdae.solvers.sundials import precompile

    scene = load_scene(CASE, SCENE)
    ready = quiet(simulate, scene, progress=False, output=tmp_path / "ready.nc")
    looks, waited, blocks = [], [], []
    busy_for = 45  # samples: the warm-up's and more than two blocks of the record
    monkeypatch.setattr(precompile, "projection_pending", lambda: True)
    monkeypatch.setattr(precompile, "projection_compiling",
                        lambda: looks.append(1) or len(looks) < busy_for)
    monkeypatch.setattr(precompile, "wait_projection", lambda: waited.append(len(looks)) or True)
    block = streamed_record.StreamedRecord._block

    def watched(self, *args, **kwargs):
        blocks.append(len(waited))
        return block(self, *args, **kwargs)

    monkeypatch.setattr(streamed_record.StreamedRecord, "_block", watched)
    ds = quiet(simulate, scene, progress=False, output=tmp_path / "waited.nc")
    try:
        assert waited == [busy_for] and len(looks) == busy_for  # once, then no more looks
        assert len(blocks) > 3 and all(blocks)  # every block after the wait
        assert ds.sizes["time"] > busy_for
        assert_same_result(ready, ds)
    finally:
        ds.close()
        ready.close()


def test_streamed_failure_keeps_warmup_and_record(tmp_path, small_blocks, monkeypatch):
    """Ctrl-C after 40 samples (warm-up and two blocks of the record): the partial file holds
    every sample computed, the warm-up's first, equal bit for bit to those of the completed
    run; nothing is at the target. The in-memory run's SimulationError holds the same. Resumed,
    the complete file replaces the partial one (left beside it, it would read as the latest)."""
    scene = load_scene(CASE, SCENE)
    full = quiet(simulate, scene, progress=False)
    real = Checkpoint.sample

    def after_40(self, t, y, yp):
        real(self, t, y, yp)
        if len(self.T) == 40:
            raise KeyboardInterrupt

    monkeypatch.setattr(Checkpoint, "sample", after_40)
    target = tmp_path / "run.nc"
    with pytest.raises(SimulationError, match="interrupted by the user") as streamed:
        quiet(simulate, scene, progress=False, output=target,
              checkpoint=Checkpoint(tmp_path / "s.npz"))
    with pytest.raises(SimulationError) as memory:
        quiet(simulate, scene, progress=False, checkpoint=Checkpoint(tmp_path / "m.npz"))
    assert not target.exists()
    ds, mem = streamed.value.dataset, memory.value.dataset
    try:
        ds.load()
        assert ds.sizes["time"] == 40 and ds.attrs["solver_status"] == "failed"
        assert float(ds.time[0]) == 0.0 < ds["record_start_s"].item() < float(ds.time[-1])
        assert_same_result(mem, ds)
        later = ds.time.values >= full["record_start_s"].item()
        assert later.sum() > BLOCK
        np.testing.assert_array_equal(ds.contact_force.values[later],
                                      full.contact_force.values[:later.sum()])
    finally:
        ds.close()
    assert (tmp_path / "run_partial.nc").exists()
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".part")]
    # resumed to its end, the run is at the target and the partial file it supersedes is gone
    monkeypatch.setattr(Checkpoint, "sample", real)
    quiet(simulate, scene, progress=False, output=target,
          checkpoint=Checkpoint(tmp_path / "s.npz", resume=True)).close()
    assert target.exists() and not (tmp_path / "run_partial.nc").exists()


def test_checkpoint_segments_bound_what_it_holds_and_resume_in_order(tmp_path, monkeypatch):
    """With segments of 7 samples a checkpoint of 30 samples holds 2 in memory and in its
    file, names 4 segment files, and hands all 30 back in order; a damaged segment is
    refused by name; discard removes them all."""
    monkeypatch.setattr(segments, "SEGMENT_SAMPLES", 7)
    monkeypatch.setattr(checkpoint_module, "SEGMENT_SAMPLES", 7)
    path = tmp_path / "r.nc.checkpoint.npz"
    t_out = np.arange(40) * 0.5
    ck = Checkpoint(path, every_samples=3)
    assert ck.begin("key", 3, t_out) == [] or not ck.begin("key", 3, t_out)
    rng = np.random.default_rng(1)
    states = rng.random((30, 2, 3))
    for k in range(30):
        ck.sample(t_out[k], states[k, 0], states[k, 1])
        assert len(ck.T) < 7
    ck.write()
    assert [p.name for p in sorted(tmp_path.iterdir())] == [
        "r.nc.checkpoint.00001.npz", "r.nc.checkpoint.00002.npz",
        "r.nc.checkpoint.00003.npz", "r.nc.checkpoint.00004.npz", "r.nc.checkpoint.npz"]
    again = Checkpoint(path, resume=True)
    held = again.begin("key", 3, t_out)
    assert len(held) == 30 and again.resumed_from_s == t_out[29]
    back = list(held)
    np.testing.assert_array_equal([t for t, _, _ in back], t_out[:30])
    np.testing.assert_array_equal(np.array([y for _, y, _ in back]), states[:, 0])
    np.testing.assert_array_equal(np.array([yp for _, _, yp in back]), states[:, 1])
    np.savez(tmp_path / "r.nc.checkpoint.00002.npz", t=np.zeros(7), y=np.zeros((7, 3)),
             yp=np.zeros((7, 3)), meta=np.array("{}"))
    with pytest.raises(checkpoint_module.CheckpointError, match="00002.npz"):
        Checkpoint(path, resume=True).begin("key", 3, t_out)
    again.discard()
    assert list(tmp_path.iterdir()) == []


KILLED = """
import sys
from bearingdae.results import streamed_netcdf as stream
from bearingdae.run import checkpoint, segments
stream.BLOCK_SAMPLES = 16
segments.SEGMENT_SAMPLES = checkpoint.SEGMENT_SAMPLES = 40
from bearingdae.cli import main
sys.exit(main(sys.argv[1:]))
"""


def test_sigkill_during_a_streamed_run_loses_nothing_computed(tmp_path, small_blocks,
                                                              monkeypatch):
    """SIGKILL once the stream has written blocks and the checkpoint a segment: nothing at
    the target; --resume writes the complete file (the killed run's temporary removed), whose
    samples up to the resume point are the uninterrupted run's bit for bit."""
    monkeypatch.setattr(segments, "SEGMENT_SAMPLES", 40)
    monkeypatch.setattr(checkpoint_module, "SEGMENT_SAMPLES", 40)
    sets = [f"--set={k}={v}" for k, v in {**SCENE, "numerics.cage_revolutions": 1.0}.items()]
    args = ["run", CASE, "--no-plot", "--no-progress", "--checkpoint-every=5", *sets]
    ref = tmp_path / "ref.nc"
    assert quiet(main, [*args, "-o", str(ref)]) == 0
    target = tmp_path / "run.nc"
    env = dict(os.environ, PYTHONPATH=str(ROOT), OMP_NUM_THREADS="1")
    p = subprocess.Popen([sys.executable, "-c", KILLED, *args, "-o", str(target)], env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    second = segments.segment_path(checkpoint_path(target), 2)
    while p.poll() is None and not second.exists():
        time.sleep(0.05)
    assert p.poll() is None, p.communicate()[1][-2000:]  # still running: a segment written
    temporaries = [q for q in tmp_path.iterdir() if q.name.startswith(".run.nc.")]
    assert temporaries  # the stream's file, under its temporary name
    p.send_signal(signal.SIGKILL)
    p.communicate()
    assert not target.exists() and not (tmp_path / "run_partial.nc").exists()
    assert quiet(main, [*args, "-o", str(target), "--resume"]) == 0
    assert not [q for q in tmp_path.iterdir() if q.name.endswith(".part")]
    assert not checkpoint_path(target).exists() and not second.exists()
    with xr.open_dataset(target) as ds, xr.open_dataset(ref) as full:
        stats = json.loads(ds.attrs["solver_statistics"])
        resumed = stats["resumed_from_s"]
        assert ds.sizes["time"] == full.sizes["time"]
        before = ds.time.values <= resumed
        assert before.sum() >= 60  # two segments of 40 (warm-up samples among them)
        for name in ("cage_speed", "contact_force", "skew_angle", "cage_force"):
            np.testing.assert_array_equal(ds[name].values[before],
                                          full[name].values[before], err_msg=name)


def test_sigint_during_a_streamed_run_keeps_every_sample(tmp_path):
    """A real Ctrl-C (SIGINT) once the stream has written blocks: status 130, nothing at the
    target, and the partial file holds exactly the samples the checkpoint holds (every sample
    computed, the warm-up's first)."""
    sets = [f"--set={k}={v}" for k, v in {**SCENE, "numerics.cage_revolutions": 1.0}.items()]
    target = tmp_path / "run.nc"
    args = ["run", CASE, "--no-plot", "--no-progress", *sets, "-o", str(target)]
    env = dict(os.environ, PYTHONPATH=str(ROOT), OMP_NUM_THREADS="1")
    p = subprocess.Popen([sys.executable, "-c", KILLED, *args], env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    first = segments.segment_path(checkpoint_path(target), 1)
    while p.poll() is None and not first.exists():
        time.sleep(0.05)
    assert p.poll() is None, p.communicate()[1][-2000:]
    p.send_signal(signal.SIGINT)
    _, err = p.communicate()
    assert p.returncode == 130, err[-2000:]
    assert "Traceback" not in err and not target.exists()
    from bearingdae.system.model import build_model

    size = build_model(load_scene(CASE, SCENE)).size
    held = Checkpoint(checkpoint_path(target), resume=True)
    with np.load(checkpoint_path(target)) as z:
        key = json.loads(str(z["meta"]))["fingerprint"]
    times = np.array([t for t, _, _ in held.begin(key, size)])
    with xr.open_dataset(tmp_path / "run_partial.nc") as ds:
        assert ds.attrs["solver_status"] == "failed"
        np.testing.assert_array_equal(ds.time.values, times)
    assert not [q for q in tmp_path.iterdir() if q.name.endswith(".part")]


def test_a_long_line_is_drawn_as_its_envelope():
    """envelope(): a line up to PLOT_POINTS samples as it is; a longer one as each bin's
    minimum and maximum in time order, every peak and trough kept, at most PLOT_POINTS."""
    from bearingdae.plots.figure_common import PLOT_POINTS, envelope

    for n in (601, PLOT_POINTS, PLOT_POINTS + 1, 60_001, 123_457):
        t = np.arange(n) * 1e-5
        y = np.sin(np.arange(n) / 37.0)
        y[n // 3], y[2 * n // 3] = 5.0, -7.0  # one-sample spikes
        te, ye = envelope(t, y)
        if n <= PLOT_POINTS:
            assert te is t and ye is y
            continue
        assert te.size <= PLOT_POINTS and np.all(np.diff(te) >= 0)
        assert ye.max() == 5.0 and ye.min() == -7.0
        assert set(te) <= set(t)


def test_a_figure_reads_a_long_series_in_pieces(monkeypatch):
    """plotting._read: the values of a selection whatever the piece length."""
    from bearingdae.plots import plotting

    da = xr.DataArray(np.arange(50.0).reshape(25, 2), dims=("time", "end"))
    monkeypatch.setattr(plotting, "READ_SAMPLES", 4)
    np.testing.assert_array_equal(plotting._read(da), da.values)
    np.testing.assert_array_equal(plotting._read(da.isel(end=1)), da.values[:, 1])


def test_a_block_the_disk_refuses_moves_the_file_with_what_it_holds(tmp_path, small_blocks,
                                                                       monkeypatch):
    """The third block's append fails as on a full disk: the file moves to the fallback
    folder with the two blocks written, the run goes on there, and the kept file is the
    complete result (the in-memory run's variables); nothing is left in the target folder
    but the checkpoint."""
    import errno

    from bearingdae.api import simulate_to_file

    scene = load_scene(CASE, SCENE)
    mem = quiet(simulate, scene, progress=False)
    target_dir, fallback_dir = tmp_path / "out", tmp_path / "fallback"
    target_dir.mkdir(), fallback_dir.mkdir()
    real = stream.StreamWriter._append

    def full_at_third(self, ds):
        if self.target.parent == target_dir and self.samples >= 2 * self.block:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real(self, ds)

    monkeypatch.setattr(stream.StreamWriter, "_append", full_at_third)
    ck = Checkpoint(checkpoint_path(target_dir / "run.nc"))
    result = quiet(simulate_to_file, scene, target_dir / "run.nc", progress=False,
                   checkpoint=ck, fallback=lambda p: fallback_dir / Path(p).name)
    assert result.success and result.path == fallback_dir / "run.nc"
    assert result.problems == [f"cannot write '{target_dir / 'run.nc'}': No space left on "
                               "device"]
    assert sorted(p.name for p in target_dir.iterdir()) == ["run.nc.checkpoint.npz"]
    with xr.open_dataset(result.path, decode_timedelta=False) as ds:
        ds.load()
        for name in mem.data_vars:
            if name in SUMMED:  # the life's sums, block by block
                assert ds[name].item() == pytest.approx(mem[name].item(), rel=1e-12), name
            elif name not in CLOCK_STATISTICS:
                assert np.array_equal(mem[name].values, ds[name].values,
                                      equal_nan=mem[name].dtype.kind == "f"), name


def test_a_short_records_figure_is_the_files(tmp_path, small_blocks):
    """A record short enough keeps the overview's variables: the figure drawn from them is
    the figure drawn from the file, pixel for pixel."""
    import matplotlib.image

    from bearingdae.api import simulate_to_file
    from bearingdae.plots.plotting import overview
    from bearingdae.results.streamed_netcdf import open_streamed

    result = quiet(simulate_to_file, load_scene(CASE, SCENE), tmp_path / "r.nc",
                   progress=False)
    assert result.figure is not None and result.figure.sizes["time"] == result.samples
    a = overview(result.figure, tmp_path / "memory.png")
    with open_streamed(result.path) as ds:
        b = overview(ds, tmp_path / "file.png")
    np.testing.assert_array_equal(matplotlib.image.imread(a), matplotlib.image.imread(b))
