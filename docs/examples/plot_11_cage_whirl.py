"""
Cage whirl: a stable and an unstable land-guided cage
=====================================================

The baseline bearing (yang20) with a whirling cage (``physics.cage_whirl = true``,
docs/theory.md §17) riding on an outer-ring land of 0.09 mm diametral clearance, at
10 000 r/min. Under the baseline's 800 N and 3 N·m the roller set's net pocket force pushes the
cage towards the land, whose film holds it at a steady eccentricity (ε ≈ 0.93): stable. Without load nothing holds it: the land's
short-bearing film drives the classic half-frequency whirl (Newkirk & Taylor 1925), whose orbit
grows from the centre until the cage rides on the land. Window: 1 warm-up + 8 recorded cage
revolutions each.
"""

import warnings

import matplotlib.pyplot as plt
import numpy as np

from bearingdae import load_scene, simulate

base = {"physics.cage_whirl": True, "cage.guidance": "outer-land",
        "cage.land_clearance_mm": 0.09, "operating.speed_rpm": 10000.0,
        "numerics.warmup_cage_revolutions": 1.0, "numerics.cage_revolutions": 8.0}
runs = {}
for label, loads in (("800 N, 3 N·m", {}),
                     ("no load", {"operating.radial_load_N": 0.0, "operating.moment_Nm": 0.0})):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        runs[label] = simulate(load_scene("yang20_baseline", overrides={**base, **loads}))
for label, ds in runs.items():
    print(f"{label:>13}: whirl ratio {float(ds.cage_whirl_ratio):+.3f}, orbit radius / "
          f"clearance {float(ds.cage_orbit_radius_over_clearance):.3f} (trend "
          f"{float(ds.cage_orbit_radius_over_clearance_trend_per_revolution):+.4f} per "
          "revolution)")

# %%
# Left: the cage centre's orbit in the land clearance (dashed). Right: the orbit radius over
# the clearance against cage revolutions; the unloaded cage's grows.

fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11, 4.6), layout="constrained")
for label, ds in runs.items():
    c = 1e6 * ds.cage_center.values
    ax0.plot(c[:, 0], c[:, 1], lw=0.8, label=label)
    t = ds.time.values
    rev = np.cumsum(np.r_[0.0, np.diff(t) * ds.cage_speed.values[1:]]) / (2 * np.pi)
    ax1.plot(rev, np.hypot(c[:, 0], c[:, 1]) / (1e6 * ds["cage_guidance_clearance_m"].item()),
             lw=0.8, label=label)
C = 1e6 * runs["no load"]["cage_guidance_clearance_m"].item()
th = np.linspace(0, 2 * np.pi, 361)
ax0.plot(C * np.cos(th), C * np.sin(th), "k--", lw=0.8, label="land clearance")
ax0.set_aspect("equal")
ax0.set(xlabel="radial [µm]", ylabel="tangential [µm]", title="cage centre")
ax1.set(xlabel="cage revolutions in the record", ylabel="orbit radius / land clearance [1]",
        title="orbit radius")
ax0.legend(fontsize=8)
ax1.legend()
