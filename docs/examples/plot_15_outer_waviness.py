"""
Outer-race waviness and its classic rule
========================================

The bundled case ``defects/outer_waviness``: the paper's bearing (Z = 20 rollers) with a
10 µm diametral preload, so that every roller carries load, a light 200 N radial load and
the inner ring as a body; the outer race has a sinusoidal form error of 0.5 µm. By the rule
of Wardle (1988) and Yhland (1992) (docs/theory.md §22) an order q = kZ ± 1 pushes the ring
round a circle of radius about the amplitude at kZ f_c (f_c the cage frequency), and any
other order leaves that line to the load zone's small stiffness variation. Here order 21
(= Z + 1) against order 17. Reduced window: 0.5 recorded cage revolutions.
"""

import matplotlib.pyplot as plt

from bearingdae import load_scene, simulate
from bearingdae.analysis.spectrum import amplitude_spectrum
from bearingdae.plots.plot_spectrum import draw_spectrum

runs = {}
for q in (21, 17):
    scene = load_scene("defects/outer_waviness", overrides={
        "waviness[0].order": q, "numerics.warmup_cage_revolutions": 0.2,
        "numerics.cage_revolutions": 0.5})
    runs[q] = simulate(scene, progress=False)

# %%
# The time signal
# ---------------
# The ring's radial displacement about its mean: with order 21 it swings by about the
# waviness amplitude at Z f_c (~300 Hz); with order 17 the rollers' pushes cancel at every
# instant and the ring barely moves.

fig, ax = plt.subplots(figsize=(10, 3.8), layout="constrained")
for q, ds in runs.items():
    rec = ds.sel(time=ds.time >= ds.record_start_s.item())
    x = rec.ring_displacement.sel(direction="radial")
    ax.plot((rec.time - rec.time[0]) * 1e3, (x - x.mean()) * 1e6, lw=1.0, label=f"order {q}")
ax.set(xlabel="time in the recorded window [ms]", ylabel="radial displacement [µm]")
ax.legend()

# %%
# The contact force
# -----------------
# One roller's outer-race contact force over its orbit: the waviness raises and lowers it q
# times per orbit (a force variation, not a drop: every roller stays loaded).

fig, ax = plt.subplots(figsize=(10, 3.8), layout="constrained")
for q, ds in runs.items():
    rec = ds.sel(time=ds.time >= ds.record_start_s.item())
    force = rec.contact_force.sel(race="outer").isel(roller=0).sum("slice")
    ax.plot((rec.time - rec.time[0]) * 1e3, force, lw=1.0, label=f"order {q}")
ax.set(xlabel="time in the recorded window [ms]", ylabel="roller 1, outer contact [N]")
ax.legend()

# %%
# The spectra
# -----------
# The displacement spectrum with the characteristic frequencies marked: order 21 puts a line
# of about 0.5 µm at the roller pass Z f_c (tests/validation/test_waviness_rule.py holds it
# within 20 % and order 17's line at least 20 dB below); the envelope spectrum below is the
# page every defect gallery shows, with the defect frequencies marked.

for q, ds in runs.items():
    spec = amplitude_spectrum(ds, "ring_displacement").sel(direction="radial")
    zfc = float(ds.defect_frequency_bpfo_Hz)
    print(f"order {q}: radial line at Z f_c = {zfc:.1f} Hz: "
          f"{float(spec.sel(frequency=zfc, method='nearest')) * 1e9:.3g} nm")
fig, axes = plt.subplots(2, 1, figsize=(10, 8), layout="constrained")
draw_spectrum(axes[0], runs[21], "ring_displacement", fmax=1500.0)
draw_spectrum(axes[1], runs[21], "ring_acceleration", fmax=1500.0, envelope=True)
plt.show()
