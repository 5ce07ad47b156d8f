"""
A spall on the outer race and on the inner race
===============================================

The bundled cases ``defects/outer_spall`` and ``defects/inner_spall``: the paper's baseline
(800 N, 2000 r/min) with the inner ring as a body and a spall 1.5 mm long and 20 µm deep,
deeper than the rollers' deflection, in the middle of the raceway (docs/theory.md §4, §22).
For each: the ring's acceleration over time, one roller's contact force as it crosses the
spall, and the envelope spectrum with the defect frequencies marked, as ``bearingdae plot
RUN.nc --spectrum --envelope`` draws it. Reduced windows: 0.5 recorded cage revolutions for
the outer spall, 1.5 for the inner one (its sidebands at ± the shaft speed need bins well
below 33 Hz).
"""

import matplotlib.pyplot as plt
import numpy as np

from bearingdae import load_scene, simulate
from bearingdae.analysis.spectrum_peaks import format_table, spectrum_peaks
from bearingdae.physics.geometry import make_geometry
from bearingdae.plots.plot_spectrum import draw_spectrum

runs = {}
for race, revolutions in (("outer", 0.5), ("inner", 1.5)):
    scene = load_scene(f"defects/{race}_spall", overrides={
        "numerics.warmup_cage_revolutions": 0.05, "numerics.cage_revolutions": revolutions})
    runs[race] = scene, simulate(scene, progress=False)

# %%
# The time signal
# ---------------
# Every roller that crosses the spall lets the ring fall into it and strike back at the exit:
# a burst of ringing at the ring's modes (printed below: the run's own, from the ring's mass
# and its static stiffness on the rollers, which the inner spall's preload raises). On the
# outer race the spall sits still in the load zone and every crossing strikes alike, at BPFO;
# on the inner race it turns with the shaft, and the strikes at BPFI rise and fall once per
# shaft revolution as it passes through the load zone.

for race, (scene, ds) in runs.items():
    print(f"{race}-race spall: the ring's modes [kHz]",
          np.round(np.sort(ds.ring_natural_frequencies_Hz.values) / 1e3, 1))

fig, axes = plt.subplots(2, 1, figsize=(10, 6), layout="constrained", sharex=True)
for ax, (race, (scene, ds)) in zip(axes, runs.items()):
    rec = ds.sel(time=ds.time >= ds.record_start_s.item())
    t_ms = (rec.time - rec.time[0]) * 1e3
    for d in ("radial", "tangential"):
        ax.plot(t_ms, rec.ring_acceleration.sel(direction=d), lw=0.6, label=d)
    ax.set(ylabel="ring acceleration [m/s²]", title=f"{race}-race spall")
axes[0].legend(loc="upper right")
axes[1].set(xlabel="time in the recorded window [ms]", xlim=(0.0, 40.0))

# %%
# The contact-force drop
# ----------------------
# A roller's force on the slices the spall covers falls to nothing for the time its contact
# point takes to cross the spall: length / (Ω R_o) on the outer race, length / ((ω_s − Ω) R_i)
# on the inner one, Ω the roller's orbit speed (tests/system/test_defect_rows.py holds it
# within 10 %). The shaded band has that width, centred on the drop.

def first_crossing(q, t):
    """(roller index, first, last sample) of the first short dip of a slice's force below
    half its roller's largest: a roller crossing the spall in the load zone (out of the load
    zone a roller stays unloaded for far longer than 2 ms)."""
    for r in range(q.sizes["roller"]):
        low = q.isel(roller=r).values < 0.5 * float(q.isel(roller=r).max())
        edges = np.flatnonzero(np.diff(low.astype(int)))
        for a, b in zip(edges[:-1], edges[1:]):
            if low[a + 1] and t[b] - t[a] < 2e-3:
                return r, a + 1, b
    raise ValueError("no roller crossed the spall in the window")


fig, axes = plt.subplots(1, 2, figsize=(11, 3.8), layout="constrained")
for ax, (race, (scene, ds)) in zip(axes, runs.items()):
    g = make_geometry(scene)
    rec = ds.sel(time=ds.time >= ds.record_start_s.item())
    t = rec.time.values
    q = rec.contact_force.sel(race=race, slice=5)  # a middle slice (of 1-10): under the spall
    roller, first, last = first_crossing(q, t)
    orbit = float(rec.orbit_speed.isel(roller=roller, time=slice(first, last + 1)).mean())
    if race == "outer":
        speed = orbit * g.outer_race_radius_m
    else:
        speed = (float(rec.inner_ring_speed.mean()) - orbit) * g.inner_race_radius_m
    expected = scene.defects[0].length_m / speed
    mid = 0.5 * (t[first] + t[last])
    window = (t > mid - 4 * expected) & (t < mid + 4 * expected)
    ax.plot((t[window] - mid) * 1e3, q.isel(roller=roller).values[window], lw=1.2)
    ax.axvspan(-0.5 * expected * 1e3, 0.5 * expected * 1e3, color="0.85", zorder=0)
    ax.set(xlabel="time from the middle of the drop [ms]", ylabel="slice force [N]",
           title=f"{race} race, roller {int(rec.roller[roller])}: length / rolling speed "
                 f"= {expected * 1e3:.2f} ms")
    print(f"{race}: force below half for {(last - first + 1) * (t[1] - t[0]) * 1e3:.2f} ms, "
          f"length / rolling speed {expected * 1e3:.2f} ms")

# %%
# The envelope spectrum
# ---------------------
# Band-passed around the ring's first mode and demodulated (analysis/spectrum.py), the
# ringing leaves how often it is struck: BPFO and its harmonics for the outer spall, BPFI
# with sidebands at BPFI ± f_s for the inner one. The markers are the defect frequencies from
# the run's own cage and roller speeds (slip included). The tables are those of ``bearingdae
# spectrum RUN.nc --envelope --peaks 5``.

fig, axes = plt.subplots(2, 1, figsize=(10, 8.5), layout="constrained")
for ax, (race, (scene, ds)) in zip(axes, runs.items()):
    draw_spectrum(ax, ds, "ring_acceleration", fmax=1200.0, envelope=True)
    print(format_table(spectrum_peaks(ds, 5, fmax_Hz=1200.0), f"{race} spall"), "\n")
plt.show()
