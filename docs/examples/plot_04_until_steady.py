"""
Until steady, and the skid start
================================

A fixed warm-up cannot know when a skidding cage has settled: at light load the Harris
bearing's cage spins down from the pure-rolling start over tens of revolutions. With
``numerics.until_steady = true`` the warm-up runs in blocks until the block-mean cage speed
stops changing (criterion: user guide, "Until steady"), and
``numerics.initial_speeds = "torque_balance"`` starts the cage and rollers near their skid
speeds, so that few blocks are needed. The Dataset records how it went.

Reduced settings: 3 slices per roller (default 10), blocks of half a cage revolution
(default 1), 0.5 recorded revolutions; the pure-rolling start is shown over 2 revolutions.
"""


import matplotlib.pyplot as plt
import numpy as np

from bearingdae import load_scene, simulate

common = {"operating.radial_load_N": 500.0, "numerics.slices": 3}
steady = simulate(load_scene("paper/harris36_5000rpm", overrides={
    **common, "numerics.until_steady": True, "numerics.initial_speeds": "torque_balance",
    "numerics.steady_block_cage_revolutions": 0.5, "numerics.cage_revolutions": 0.5}))
rolling = simulate(load_scene("paper/harris36_5000rpm", overrides={
    **common, "numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 2.0}))

for name in ("steady_state_reached", "warmup_cage_revolutions_used", "steady_last_change",
             "steady_remaining_estimate"):
    print(f"{name:30s} {steady[name].item()}")

# %%
# The block means of the warm-up settle within the tolerance (0.1 % of the epicyclic speed)
# after a few blocks; from the pure-rolling start the cage is still far from that speed
# after two revolutions.

epicyclic = steady["epicyclic_cage_speed_rad_s"].item()
means = steady.steady_block_means.values
block = 0.5
fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(12, 4), layout="constrained")
ax0.plot(block * np.arange(1, len(means) + 1), means / epicyclic, "ko-",
         label="block means, torque-balance start")
ax0.set(xlabel="warm-up [cage revolutions]", ylabel="cage speed / epicyclic",
        title=f"until steady: {len(means)} blocks")
ax0.legend()
ax1.plot(rolling.time, rolling.cage_speed / epicyclic, label="pure-rolling start")
ax1.plot(steady.time, steady.cage_speed / epicyclic, label="torque-balance start, steady")
ax1.set(xlabel="time [s]", ylabel="cage speed / epicyclic",
        title="Harris bearing, 500 N, 5000 r/min")
ax1.legend()
plt.show()
