"""
A sweep on a dask cluster
=========================

A sweep runs one base scene over the outer product of its axes; every run is one task on a
dask cluster. Here the cluster is a :class:`dask.distributed.LocalCluster` of two worker
processes started by hand (one thread each, as the sweeps want: BLAS and OpenMP pinned to
one thread), and the sweep attaches to it by its address, as it would to a remote cluster
(``bearingdae sweep FILE --scheduler tcp://HOST:8786``). Without ``scheduler=``,
:func:`~bearingdae.studies.sweep.run_sweep` starts such a local cluster itself.

Reduced settings: 2 x 2 runs of 0.25 + 0.5 cage revolutions at 6 slices.
"""

import os
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
from dask.distributed import LocalCluster

from bearingdae.studies.sweep import PINNED_ENV, run_sweep, sweep_from_dict

sweep = sweep_from_dict({
    "title": "yang20: speed x radial load",
    "base": "yang20_baseline",
    "overrides": {"numerics.slices": 6, "numerics.warmup_cage_revolutions": 0.25,
                  "numerics.cage_revolutions": 0.5,
                  "numerics.samples_per_cage_revolution": 100},
    "axes": {"operating.speed_rpm": [2000.0, 8000.0],
             "operating.radial_load_N": [400.0, 1600.0]},
}, name="speed_load")
print(f"{len(sweep.points)} runs on axes {[a.key for a in sweep.axes]}")

os.environ.update(PINNED_ENV)  # the workers inherit the pinned BLAS/OpenMP threads
out = Path(tempfile.mkdtemp()) / "speed_load.nc"
# dashboard_address=":0": the scheduler's web server on a free port (with None it still
# takes 8787, and warns when another cluster on the machine holds that port)
with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                  dashboard_address=":0") as cluster:
    print("scheduler:", cluster.scheduler_address)
    ds = run_sweep(sweep, out, scheduler=cluster.scheduler_address, progress=False)

print(ds.status.values)
print("runs kept for a restart in", ds.attrs.get("run_directory", out.with_name("speed_load_runs")))

# %%
# The sweep Dataset has the axes as dimensions; xarray plots a summary against them.

fig, ax = plt.subplots(figsize=(6.5, 4), layout="constrained")
(ds.cage_slip_ratio * 100).plot.line(ax=ax, x="radial_load_N", hue="speed_rpm", marker="o")
ax.set(ylabel="cage slip [%]", xlabel="radial load [N]",
       title="steady cage slip over the recorded window")
plt.show()
