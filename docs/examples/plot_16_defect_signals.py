"""
Signals for learning: a sweep over a spall's size
=================================================

A classifier or a diagnostic method needs labelled fault signals, and measured ones are
scarce. A sweep whose axes are defect keys gives them: here the bundled outer-race spall
(``defects/outer_spall``) at three depths, the ring acceleration of every run stored in the
sweep file along ``sample`` (``[sweep] signals``), labelled by its axes. A full data set
adds axes (``"defects[0].length_mm"``, ``"operating.speed_rpm"``,
``"operating.radial_load_N"``) and runs on a dask cluster like any sweep (the "sweep on a
dask cluster" example). Reduced window: 0.3 recorded cage revolutions per run, one after
another in this process (``scheduler="synchronous"``).
"""

import tempfile
import time
from pathlib import Path

import matplotlib.pyplot as plt
import xarray as xr

from bearingdae.studies.sweep import run_sweep, sweep_from_dict

sweep = sweep_from_dict({
    "title": "outer spall: depth",
    "base": "defects/outer_spall",
    "overrides": {"numerics.warmup_cage_revolutions": 0.05,
                  "numerics.cage_revolutions": 0.3},
    "axes": {"defects[0].depth_um": [1.0, 3.0, 20.0]},
    "sweep": {"signals": ["ring_acceleration"]},
}, name="spall_depth")

out = Path(tempfile.mkdtemp()) / "spall_depth.nc"
t0 = time.perf_counter()
run_sweep(sweep, out, scheduler="synchronous", progress=False)
elapsed = time.perf_counter() - t0

# %%
# The file holds the signals as one array over the axes, samples and directions; each point
# has its time since the start of its recorded window (``signal_time``) and its run's file.

ds = xr.open_dataset(out)
print(ds.ring_acceleration.sizes)
points = ds.sizes["depth_um"]
print(f"{points} runs, {elapsed / points:.1f} s of wall time per point on the machine that "
      f"built this page (kernels from numba's cache); the signals take "
      f"{ds.ring_acceleration.nbytes / points / 1e3:.0f} kB per point "
      f"({ds.sizes['sample']} samples x 2 directions, float64); the sweep file "
      f"{out.stat().st_size / 1e6:.2f} MB with the summaries")

# %%
# A spall deeper than the rollers' deflection (a few µm at 800 N) unloads each roller that
# crosses it completely, and the ring rings at each crossing; a shallow one only lowers the
# rollers' load and the ring barely notices.

fig, axes = plt.subplots(3, 1, figsize=(10, 7), layout="constrained", sharex=True,
                         sharey=True)
for ax, depth in zip(axes, ds.depth_um.values):
    point = ds.sel(depth_um=depth)
    ax.plot(point.signal_time * 1e3, point.ring_acceleration.sel(direction="tangential"),
            lw=0.6)
    ax.set(title=f"depth {depth:g} µm", ylabel="tangential [m/s²]")
axes[-1].set(xlabel="time in the recorded window [ms]")
plt.show()
