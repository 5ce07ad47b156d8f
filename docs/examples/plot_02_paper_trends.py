"""
The paper's trends: speed, radial load and moment
=================================================

Yang et al. (2024) vary the inner-ring speed (Figs 18-20), the radial load (conclusion 2)
and the moment (Figs 21-24) on the yang20 bearing and describe how roller slip, skew and the
roller-cage force follow. Three small sweeps reproduce the trends; each is a
:class:`~bearingdae.studies.sweep.Sweep` built from a dict (the same keys as a sweep file),
and the three run together so that a run common to two sweeps is computed once.

Reduced settings: 3 points per axis (the bundled sweeps in ``cases/paper/`` have 4-5),
0.5 warm-up + 0.5 recorded cage revolutions (they use 1 + 1.25), 100 samples per revolution,
run in this process (``scheduler="synchronous"``; see the dask example for a cluster).
The full set is ``bearingdae paper -o paper/`` (docs: validation).
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from bearingdae.studies.sweep import run_sweeps, sweep_from_dict

reduced = {"numerics.warmup_cage_revolutions": 0.5, "numerics.cage_revolutions": 0.5,
           "numerics.samples_per_cage_revolution": 100}
axes = {
    "speed": ({"operating.radial_load_N": 800.0, "operating.moment_Nm": 3.0},
              "operating.speed_rpm", [2000.0, 6000.0, 14000.0]),
    "radial load": ({"operating.speed_rpm": 6000.0, "operating.moment_Nm": 3.0},
                    "operating.radial_load_N", [400.0, 800.0, 1600.0]),
    "moment": ({"operating.speed_rpm": 6000.0, "operating.radial_load_N": 400.0},
               "operating.moment_Nm", [0.0, 3.0, 10.0]),
}
sweeps = [sweep_from_dict({"title": f"yang20 {name} sweep", "base": "yang20_baseline",
                           "overrides": {**fixed, **reduced}, "axes": {key: values}},
                          name=name.replace(" ", "_"))
          for name, (fixed, key, values) in axes.items()]
out = Path(tempfile.mkdtemp())
results = run_sweeps(sweeps, [out / f"{sw.name}.nc" for sw in sweeps],
                     scheduler="synchronous", progress=False)

# %%
# One column per sweep, one row per summary (each summary is one function of
# ``bearingdae.analysis.summary``, computed over the recorded window):

rows = [("load_weighted_slip_m_s", 1.0, "load-weighted slip [m/s]"),
        ("skew_amplitude_rad", 1e3, "skew amplitude [mrad]"),
        ("peak_cage_force_N", 1.0, "peak pocket force [N]")]
fig, axs = plt.subplots(len(rows), len(results), figsize=(11, 7.5), layout="constrained",
                        sharey="row")
for j, ds in enumerate(results):
    (dim,) = [d for d in ds.dims if d in ds.coords and "scene_key" in ds[d].attrs]
    for i, (name, scale, label) in enumerate(rows):
        ax = axs[i, j]
        ax.plot(ds[dim], ds[name] * scale, "ko-")
        ax.grid(alpha=0.3)
        if j == 0:
            ax.set_ylabel(label)
        if i == len(rows) - 1:
            ax.set_xlabel(f"{dim} [{ds[dim].attrs['units']}]")
fig.suptitle("yang20: trends against speed (800 N, 3 N·m), radial load (6000 r/min, 3 N·m) "
             "and moment (6000 r/min, 400 N)", fontsize=10)
plt.show()

# %%
# What the paper claims and what these runs show, in numbers:

for ds in results:
    (dim,) = [d for d in ds.dims if d in ds.coords and "scene_key" in ds[d].attrs]
    slip = np.round(ds.load_weighted_slip_m_s.values, 4)
    print(f"{dim:15s} {ds[dim].values} -> load-weighted slip {slip} m/s, "
          f"skew amplitude {np.round(ds.skew_amplitude_rad.values * 1e3, 2)} mrad")
