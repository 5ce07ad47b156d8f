"""
Exchanging a result through NetCDF
==================================

A result file is CF NetCDF: any tool that reads NetCDF finds the variables with their
``units`` and ``long_name``, and the scene, solver and provenance as global attributes.
Here a short run is written with :func:`bearingdae.save`, read back with the plain netCDF4
library (as a non-xarray tool would) and with xarray, and the two are compared.
"""

import json
import shutil
import subprocess
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import netCDF4
import numpy as np
import xarray as xr

from bearingdae import load_scene, save, simulate

scene = load_scene("yang20_baseline", overrides={"numerics.warmup_cage_revolutions": 0.25,
                                                 "numerics.cage_revolutions": 0.5})
path = save(simulate(scene), Path(tempfile.mkdtemp()) / "exchange.nc")

# %%
# Read with netCDF4: the CF attributes a reader needs are on every variable.

with netCDF4.Dataset(path) as nc:
    print("Conventions:", nc.Conventions)
    print("history:", nc.history)
    for name in ("time", "cage_speed", "skew_angle", "contact_force"):
        v = nc.variables[name]
        print(f"{name:14s} {str(v.dimensions):38s} units={v.units!r:10s} {v.long_name}")
    time = nc.variables["time"][:]
    cage = nc.variables["cage_speed"][:]
    cage_units = nc.variables["cage_speed"].units
    stats = json.loads(nc.solver_statistics)
print("solver statistics:", {k: stats[k] for k in list(stats)[:4]})

# %%
# ``ncdump -h`` (from netcdf-bin) shows the same header, if it is installed:

if shutil.which("ncdump"):
    header = subprocess.run(["ncdump", "-h", str(path)], capture_output=True, text=True).stdout
    print("\n".join(header.splitlines()[:25]))

# %%
# xarray reads the same file into labelled arrays; the values are identical.

ds = xr.open_dataset(path)
assert np.array_equal(ds.cage_speed.values, cage)
fig, ax = plt.subplots(figsize=(7, 3.5), layout="constrained")
ax.plot(time, cage, label="netCDF4")
ax.plot(ds.time, ds.cage_speed, "--", label="xarray")
ax.set(xlabel=f"time [{ds.time.attrs.get('units', 's')}]",
       ylabel=f"{ds.cage_speed.attrs['long_name']} [{cage_units}]")
ax.legend()
plt.show()
ds.close()
