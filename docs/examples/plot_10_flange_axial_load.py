"""
Axial load on an NJ bearing: flange forces, skew and flange friction
====================================================================

The paper's baseline bearing (yang20, 800 N radial load, 3 N·m, 2000 r/min) as an NJ type:
the outer ring has two flanges, the inner ring one, and the inner ring carries an axial load
(docs/theory.md §16). Each roller is pinched between the inner ring's flange at its -x end and
the outer ring's at its +x end; the flange friction skews it. Two axial loads, 200 N and
1000 N; reduced window: 0.3 warm-up + 0.5 recorded cage revolutions.
"""

import warnings

import matplotlib.pyplot as plt
import numpy as np

from bearingdae import load_scene, simulate

runs = {}
for Fa in (200.0, 1000.0):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # 1000 N is above the catalogue's 0.5 F_r: it warns
        runs[Fa] = simulate(load_scene("yang20_nj_axial", overrides={
            "operating.axial_load_N": Fa, "numerics.warmup_cage_revolutions": 0.3,
            "numerics.cage_revolutions": 0.5}))
for Fa, ds in runs.items():
    carried = float(ds.inner_flange_axial_force.sum(("roller", "end")).mean())
    print(f"{Fa:6.0f} N: carried by the inner-ring flanges {carried:.3f} N, flange friction "
          f"{float(ds.flange_friction_power.mean()):.2f} W, skew RMS "
          f"{1e3 * float(np.sqrt((ds.skew_angle ** 2).mean())):.2f} mrad")

# %%
# Left: the flange force on both ends of roller 1 over its orbit (end b against the inner
# ring's flange, end a against the outer ring's). Right: its skew angle; the flange friction's
# skewing moment grows with the axial load.

fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11, 4.2), layout="constrained")
for Fa, ds in runs.items():
    az = np.degrees(np.mod(ds.roller_azimuth.sel(roller=1), 2 * np.pi))
    for end, ls in (("a", "-"), ("b", "--")):
        ax0.plot(az, ds.flange_force.sel(roller=1, end=end), ls, lw=0.8,
                 label=f"{Fa:.0f} N, end {end}")
    ax1.plot(az, 1e3 * ds.skew_angle.sel(roller=1), ".", ms=2, label=f"{Fa:.0f} N")
ax0.set(xlabel="roller azimuth [deg]", ylabel="flange force [N]", title="roller 1")
ax1.set(xlabel="roller azimuth [deg]", ylabel="skew angle [mrad]", title="roller 1")
ax0.legend(fontsize=8)
ax1.legend()
