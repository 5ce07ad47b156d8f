"""
A spall on a roller
===================

The bundled case ``defects/roller_spall``: the paper's baseline (800 N, 2000 r/min) with the
inner ring as a body, a light preload (every roller loaded) and a spall 1 mm long and 20 µm
deep on roller 0 (docs/theory.md §4, §22). The model carries each roller's spin angle: the
spall meets the inner race and the outer race once each per revolution of the roller, so the
ring is struck at twice the roller spin frequency, 2×BSF. Below: the ring's acceleration over
time, roller 0's contact force on both races, and the envelope spectrum with the defect
frequencies marked, as ``bearingdae plot RUN.nc --spectrum --envelope`` draws it. Reduced
window: 2 recorded cage revolutions (bins of ~7.6 Hz, the ± FTF sidebands two bins off).
"""

import matplotlib.pyplot as plt

from bearingdae import load_scene, simulate
from bearingdae.analysis.spectrum_peaks import format_table, spectrum_peaks
from bearingdae.plots.plot_spectrum import draw_spectrum

scene = load_scene("defects/roller_spall", overrides={
    "numerics.warmup_cage_revolutions": 0.05, "numerics.cage_revolutions": 2.0})
ds = simulate(scene, progress=False)
rec = ds.sel(time=ds.time >= ds.record_start_s.item())
t_ms = (rec.time - rec.time[0]) * 1e3

# %%
# The time signal and the contact force
# -------------------------------------
# Each time the spall turns into a contact, the roller drops into it on the covered slices and
# the ring rings at its first mode. The strikes alternate between the inner and the outer race,
# half a roller revolution apart (~2.7 ms here), on whichever side of the ring the roller is.

fig, axes = plt.subplots(2, 1, figsize=(10, 6), layout="constrained", sharex=True)
for d in ("radial", "tangential"):
    axes[0].plot(t_ms, rec.ring_acceleration.sel(direction=d), lw=0.6, label=d)
axes[0].set(ylabel="ring acceleration [m/s²]", title="roller spall")
axes[0].legend(loc="upper right")
for race in ("inner", "outer"):
    q = rec.contact_force.isel(roller=0).sel(race=race, slice=5)  # a middle slice: under it
    axes[1].plot(t_ms, q, lw=0.9, label=f"{race} race")
axes[1].set(xlabel="time in the recorded window [ms]", ylabel="slice force of roller 0 [N]",
            xlim=(0.0, 20.0))
axes[1].legend(loc="upper right")

# %%
# The envelope spectrum
# ---------------------
# Band-passed around the ring's first mode and demodulated (analysis/spectrum.py), the ringing
# leaves how often it is struck: 2×BSF and its harmonics, with sidebands at 2×BSF ± FTF (the
# spalled roller goes round with the cage, through more and less loaded places, once per cage
# revolution). Without the preload the roller strikes only in the load zone, and the cage
# frequency itself can be the strongest envelope line (user guide, "Local defects and waviness").
# The table is that of ``bearingdae spectrum RUN.nc --envelope --peaks 6``.

fig, ax = plt.subplots(figsize=(10, 4.5), layout="constrained")
draw_spectrum(ax, ds, "ring_acceleration", fmax=1200.0, envelope=True)
print(format_table(spectrum_peaks(ds, 6, fmax_Hz=1200.0), "roller spall"))
plt.show()
