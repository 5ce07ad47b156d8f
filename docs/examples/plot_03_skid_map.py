"""
A skid map
==========

"At which load does my bearing skid at this speed?" :func:`bearingdae.studies.skidmap.run_skidmap`
runs a speed x radial-load grid, each point warmed up until its cage speed is steady
(``numerics.until_steady``) from the torque-balance skid start, and maps the steady cage
slip 1 - mean cage speed / epicyclic speed, with the skid boundary (cage slip = 1 %) in red.

The Harris bearing (36 rollers, 64 µm clearance, pure radial load) skids at light load.
Reduced settings: a 3 x 3 grid, 3 slices per roller (default 10), steady-state blocks of
half a cage revolution and 0.25 recorded revolutions, in this process
(``scheduler="synchronous"``). The full maps: docs, "Skid maps".
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

from bearingdae.studies.skidmap import run_skidmap

out = Path(tempfile.mkdtemp()) / "harris36_skidmap.nc"
ds, paths = run_skidmap(
    "paper/harris36_5000rpm", speeds_rpm=[2000, 4000, 6000], loads_N=[500, 1000, 4000],
    output=out, scheduler="synchronous", progress=False,
    overrides={"numerics.slices": 3, "numerics.steady_block_cage_revolutions": 0.5,
               "numerics.cage_revolutions": 0.25})
print((ds.cage_slip_ratio * 100).round(2).to_pandas())
print("steady at every point:", bool((ds.steady_state_reached == 1).all()))

# %%
# The map's figure, as ``bearingdae skidmap`` writes it beside the NetCDF file:

fig, ax = plt.subplots(figsize=(7, 5), layout="constrained")
png = next(p for p in paths if p.suffix == ".png")  # beside the map and sweep files
ax.imshow(plt.imread(png))
ax.set_axis_off()
plt.show()
