"""Signals for learning: a sweep whose axes are defect keys (``defects[0].depth_um``) stores
each point's time series (studies/sweep/signals.py).

References: the scene each run was built from (its ``scene_toml``, read back here) for the
labels; the run's own file, sample by sample, for the stored signal.
"""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
import xarray as xr

from bearingdae.scene import SceneError
from bearingdae.studies.sweep import run_sweep, sweep_from_dict

SWEEP = {
    "title": "outer spall: depth x load",
    "base": "defects/outer_spall",
    "overrides": {"numerics.cage_revolutions": 0.05, "numerics.warmup_cage_revolutions": 0.0,
                  "numerics.samples_per_cage_revolution": 1000},
    "axes": {"defects[0].depth_um": [1.0, 20.0], "operating.radial_load_N": [800.0]},
    "sweep": {"signals": ["ring_acceleration"]},
}


def test_defect_keys_are_sweep_axes():
    sweep = sweep_from_dict(SWEEP, name="spall")
    assert [a.dim for a in sweep.axes] == ["depth_um", "radial_load_N"]
    assert [p.scene.defects[0].depth_m for p in sweep.points] == pytest.approx([1e-6, 20e-6])


def test_a_signal_that_is_not_a_time_series_is_refused():
    with pytest.raises(SceneError, match="sweep.signals"):
        sweep_from_dict({**SWEEP, "sweep": {"signals": ["contact_force_max"]}})


@pytest.mark.slow
def test_the_sweep_stores_each_points_signal_labelled_by_its_axes(tmp_path):
    """Synchronous (the machinery, not the cluster, is under test: tests/studies/
    test_sweep.py runs a LocalCluster)."""
    out = tmp_path / "signals.nc"
    run_sweep(sweep_from_dict(SWEEP, name="spall"), out, scheduler="synchronous",
              progress=False)
    with xr.open_dataset(out) as ds:
        a = ds.ring_acceleration
        assert a.dims == ("depth_um", "radial_load_N", "sample", "direction")
        assert ds.signal_time.dims == ("depth_um", "radial_load_N", "sample")
        assert a.attrs["units"] == "m s-2"
        assert list(ds.depth_um.values) == [1.0, 20.0]
        assert ds.depth_um.attrs["scene_key"] == "defects[0].depth_um"
        for depth in ds.depth_um.values:
            point = ds.sel(depth_um=depth, radial_load_N=800.0)
            with xr.open_dataset(out.parent / str(point.run_file.values)) as run:
                scene = tomllib.loads(run.attrs["scene_toml"])
                assert scene["defects"][0]["depth_um"] == depth  # the label is the input
                start = float(run.record_start_s)
                rec = run.ring_acceleration.sel(time=run.time >= start)
                assert rec.sizes["time"] == point.sizes["sample"]
                np.testing.assert_array_equal(point.ring_acceleration.values,
                                              rec.transpose("time", "direction").values)
                np.testing.assert_allclose(point.signal_time.values,
                                           rec.time.values - start, rtol=0, atol=1e-15)
