"""
Friction torque against the catalogue
=====================================

The paper's bearing (yang20) under a 2000 N radial load at three speeds, run twice: with the
paper's model (every switch at its default) and with EHL rolling resistance and mixed
lubrication on (``[physics] rolling_resistance = true``, ``lubrication = "mixed"``). Beside
them the SKF catalogue model at the same points, from the table the user guide's section
"Friction, power loss and temperature against the catalogue" is built on
(``docs/data/catalogue_friction.csv``, written by ``tools/catalogue_friction.py``, whose
catalogue column is the model typed in ``tools/skf_friction.py``).

Short runs to keep the gallery quick: half a warm-up cage revolution from the torque-balance
start and a quarter revolution recorded (the user guide's table runs each point until
steady); the friction torque is the window mean of the power loss summed over its sources,
over the inner ring's speed, without the oil-air mixture's drag (orbit drag and churning):
the catalogue's moment for oil-air lubrication has no drag term.
"""

import csv
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from bearingdae import load_scene, simulate
from bearingdae.studies.friction import DRAG_SOURCES

LOAD_N = 2000.0
SPEEDS_RPM = (500.0, 2000.0, 6000.0)
MODELS = {"paper's model": {},
          "rolling resistance + mixed lubrication": {"physics.rolling_resistance": True,
                                                     "physics.lubrication": "mixed"}}
window = {"operating.moment_Nm": 0.0, "operating.radial_load_N": LOAD_N,
          "numerics.initial_speeds": "torque_balance",
          "numerics.warmup_cage_revolutions": 0.5, "numerics.cage_revolutions": 0.25}


def friction_torque_N_mm(ds):
    """Window mean of Σ power loss / inner-ring speed [N·mm] over every source but the drag
    (trapezoids over the record)."""
    t = ds.time.values
    dim = next(d for d in ds.friction_torque_N_m.dims if d != "time")
    friction = ds.friction_torque_N_m.drop_sel({dim: list(DRAG_SOURCES)}).sum(dim)
    return 1e3 * np.trapezoid(friction.values, t) / (t[-1] - t[0])


torque = {name: [friction_torque_N_mm(simulate(load_scene(
    "yang20_baseline", {**window, **switches, "operating.speed_rpm": n}), progress=False))
    for n in SPEEDS_RPM] for name, switches in MODELS.items()}

# %%
# The catalogue's values at the same points, from the committed table (its ``skf_N_mm``
# column), and the comparison.

here = Path(__file__).parent if "__file__" in globals() else Path.cwd()
with open(here.parent / "data" / "catalogue_friction.csv", newline="") as f:
    table = [r for r in csv.DictReader(f)
             if r["bearing"] == "yang20" and float(r["radial_load_N"]) == LOAD_N]
skf_speeds = [float(r["speed_rpm"]) for r in table]
skf = [float(r["skf_N_mm"]) for r in table]

for name, values in torque.items():
    ratios = [v / np.interp(n, skf_speeds, skf) for n, v in zip(SPEEDS_RPM, values)]
    print(f"{name:40s}", "  ".join(f"{n:5.0f} r/min: {v:.3g} N·mm ({r:.2g} x SKF)"
                                   for n, v, r in zip(SPEEDS_RPM, values, ratios)))

fig, ax = plt.subplots(figsize=(6.5, 4), layout="constrained")
ax.plot(skf_speeds, skf, "k-", label="SKF catalogue model")
for (name, values), marker in zip(torque.items(), ("o", "s")):
    ax.plot(SPEEDS_RPM, values, marker, label=name)
ax.set(yscale="log", xlabel="inner ring speed [r/min]",
       ylabel="friction torque without drag [N·mm]",
       title=f"yang20, {LOAD_N:.0f} N radial load")
ax.legend()
plt.show()
