"""
The baseline run, read with xarray
==================================

Run the paper's baseline bearing (yang20: 20 rollers, 800 N radial load, 3 N·m moment,
2000 r/min), write it to NetCDF and read it back with :func:`xarray.open_dataset`, as any
later analysis would. Reduced window: 1 warm-up + 1.25 recorded cage revolutions (the
default records 3), so that roller 1 completes one orbit.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import xarray as xr

from bearingdae import load_scene, save, simulate

scene = load_scene("yang20_baseline", overrides={"numerics.cage_revolutions": 1.25})
path = save(simulate(scene), Path(tempfile.mkdtemp()) / "yang20_baseline.nc")

ds = xr.open_dataset(path)
print(ds.title)
print(dict(ds.sizes))

# %%
# Labelled dimensions make the selections read like the question: the cage speed against
# the pure-rolling (epicyclic) speed, roller 1's inner-race load summed over its slices,
# and the slice loads along roller 1 where it carried its peak load.

epicyclic = ds["epicyclic_cage_speed_rad_s"].item()
inner_1 = ds.contact_force.sel(race="inner", roller=1)
peak_time = inner_1.sum("slice").idxmax("time")

fig, (ax0, ax1, ax2) = plt.subplots(1, 3, figsize=(13, 3.8), layout="constrained")
ds.cage_speed.plot(ax=ax0, label="cage")
ax0.axhline(epicyclic, color="k", ls="--", lw=1, label="epicyclic (pure rolling)")
ax0.set_title("cage speed")
ax0.legend()
ax1.plot(np.degrees(ds.roller_azimuth.sel(roller=1) % (2 * np.pi)),
         inner_1.sum("slice"), ".", ms=2)
ax1.set(xlabel="azimuth of roller 1 from the load line [deg]",
        ylabel="inner-race load of roller 1 [N]", title="load over one orbit")
inner_1.sel(time=peak_time).plot(ax=ax2, x="slice_position", marker="o")
ax2.set(title="slice loads at the peak")
plt.show()

# %%
# The scene that ran travels with the result (``scene_toml``), as do the solver's name,
# settings and statistics:

print(ds.attrs["solver"], ds.attrs["rtol"], ds.attrs["atol"])
print(ds.attrs["scene_toml"][:300])
ds.close()
