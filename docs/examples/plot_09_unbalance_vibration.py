"""
Vibration of a bearing under an unbalance load
==============================================

The paper's baseline bearing (yang20, 800 N radial load, 2000 r/min) with the inner ring as a
body (``physics.ring = "dynamic"``, docs/theory.md §15) and a 100 N unbalance turning with the
shaft (§14). The ring's orbit follows the rotating load; its spectrum shows the line at the
shaft frequency and the varying-compliance line at the roller-pass frequency Z f_cage, with the
bearing's characteristic frequencies marked. Reduced window: 0.25 warm-up + 1.5 recorded cage
revolutions at 400 samples per revolution, ring variables only.
"""


import matplotlib.pyplot as plt

from bearingdae import load_scene, simulate
from bearingdae.analysis.spectrum import amplitude_spectrum
from bearingdae.plots.plot_spectrum import draw_spectrum

scene = load_scene("yang20_baseline", overrides={
    "operating.moment_Nm": 0.0, "operating.unbalance_N": 100.0,
    "physics.ring": "dynamic", "ring.support_damping_N_s_m": 600.0,
    "numerics.warmup_cage_revolutions": 0.25, "numerics.cage_revolutions": 1.5,
    "numerics.samples_per_cage_revolution": 400,
    "output.variables": ["cage_speed", "ring_displacement", "ring_velocity",
                         "ring_acceleration", "applied_load"]})
ds = simulate(scene)
record = ds.sel(time=ds.time >= ds["record_start_s"].item())
frequencies = ds.characteristic_frequencies_Hz.to_series()
for name, f in frequencies.items():  # one per line: a dict would overflow the page
    print(f"{name:20s} {f:8.1f} Hz")

# %%
# The ring's centre orbits about its static position once per shaft revolution, pushed by
# the unbalance (left: displacement in µm; the load applied at each sample on the right).
# The orbit is drawn out along the tangential direction (the bearing is about nine times
# stiffer along the radial load than across it) and is not a smooth ellipse but a polygon
# with rounded corners: the rollers passing under the load change the bearing's compliance
# Z times per cage revolution, several times per shaft revolution, and the centre's path
# bends at each change.

fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11, 4.2), layout="constrained")
d = record.ring_displacement * 1e6
ax0.plot(d.sel(direction="radial"), d.sel(direction="tangential"), lw=0.8)
ax0.set(xlabel="radial displacement [µm]", ylabel="tangential displacement [µm]",
        title="ring orbit")
record.applied_load.plot.line(ax=ax1, x="time", hue="direction")
ax1.set_title("applied load (800 N + 100 N unbalance)")

# %%
# Spectra of the recorded window (Hann window, single-sided amplitude). The shaft line's
# amplitude is what a one-degree-of-freedom model with the bearing's compliance predicts
# (tests/validation/test_ring_vibration.py); the roller-pass line comes from the rollers
# passing under the load (varying compliance).

fig, axes = plt.subplots(2, 1, figsize=(10, 8), layout="constrained")
draw_spectrum(axes[0], ds, "ring_displacement")
draw_spectrum(axes[1], ds, "ring_acceleration")
spec = amplitude_spectrum(ds, "ring_displacement")
for name in ("shaft", "roller_pass_outer"):
    line = spec.sel(frequency=frequencies[name], method="nearest") * 1e9
    print(f"{name} ({frequencies[name]:.0f} Hz): radial {float(line[0]):.1f} nm, "
          f"tangential {float(line[1]):.1f} nm")

# %%
# The acceleration is recorded low-passed below the samples' Nyquist frequency (docs/theory.md
# §15: the filter's transfer function is in the variable's attributes), so the resonances of
# the ring above it do not fold back into the band. Its envelope spectrum (band-pass around the
# highest ring mode below 0.8 of Nyquist or, as here where the first mode lies above it, the
# record's top band, 0.4-0.8 of Nyquist; then the Hilbert envelope) shows how often the
# ringing is excited: the shaft and roller-pass lines. As ``bearingdae plot FILE --spectrum
# --envelope --log``.

print("ring natural frequencies [Hz]:", ds.ring_natural_frequencies_Hz.values)
print("recorded as:", ds.ring_acceleration.attrs["cell_methods"])
fig, ax = plt.subplots(figsize=(10, 4.5), layout="constrained")
draw_spectrum(ax, ds, "ring_acceleration", envelope=True, log=True)
