"""
Rating life, oil film and power loss
====================================

The three numbers a bearing engineer reads off any bearing analysis, from the paper's baseline
bearing (yang20: 800 N radial load, 3 N·m moment, 2000 r/min): the ISO/TS 16281 reference
rating life (converged in laminae), the EHL film parameter λ = h_min/σ of every loaded slice,
and where the power goes. A quasi-static solve gives the life and the film at once; a short
dynamic run adds the power loss by source and the inner ring's drive power that balances it:
1 warm-up cage revolution, then a quarter revolution recorded at 5000 samples per revolution
(the drive power swings at the rollers' spin frequencies, so its integral needs dense samples).
"""

import matplotlib.pyplot as plt

from bearingdae import load_scene, simulate, solve_static

scene = load_scene("yang20_baseline", overrides={
    "numerics.warmup_cage_revolutions": 1.0, "numerics.cage_revolutions": 0.25,
    "numerics.samples_per_cage_revolution": 5000})
static = solve_static(scene)
print(f"L10r = {static['reference_rating_life_L10r_h'].item():.4g} h at 2000 r/min, "
      f"equivalent load {static['equivalent_reference_load_N'].item():.4g} N, "
      f"C = {static['basic_dynamic_load_rating_N'].item():.4g} N")
print(f"thinnest film: λ = {float(static.lambda_ratio.min()):.3g}")

# %%
# The film parameter of each slice of the most loaded roller, inner and outer race: λ < 1
# means the asperities touch (boundary lubrication); the films are isothermal, fully flooded
# estimates (upper bounds at speed, docs/theory.md).

most_loaded = int(static.contact_force.sum(("slice", "race")).argmax("roller"))
lam = static.lambda_ratio.isel(roller=most_loaded)

run = simulate(scene, progress=False)
mean_loss = run.power_loss_W.mean("time").sortby(run.power_loss_W.mean("time"))

fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11, 3.8), layout="constrained")
for race in lam.race.values:
    lam.sel(race=race).plot(ax=ax0, x="slice_position", marker="o", label=str(race))
ax0.axhline(1.0, color="k", ls="--", lw=1)
ax0.set(title=f"λ along roller {int(static.roller[most_loaded])}", ylabel="λ = h_min/σ")
ax0.legend()
ax1.barh([str(s) for s in mean_loss.loss_source.values], mean_loss.values)
ax1.set(xscale="log", xlabel="mean power loss [W]", title="where the power goes")
plt.show()

# %%
# Energy balance over the recorded window: the work the inner ring's drive does equals the
# energy the losses dissipate plus the change of the bodies' kinetic energy (docs/theory.md;
# at steady state the last term averages out).

t = run.time.values
drive_J = float(run.drive_power_W.integrate("time"))
lost_J = float(run.power_loss_W.sum("loss_source").integrate("time"))
stored_J = float(run.kinetic_energy_J[-1] - run.kinetic_energy_J[0])
print(f"over {t[-1] - t[0]:.4g} s: drive {drive_J:.4g} J = losses {lost_J:.4g} J "
      f"+ kinetic {stored_J:+.4g} J (imbalance {drive_J - lost_J - stored_J:+.2g} J)")
print(f"L10r of the run (averaged over its samples): "
      f"{run['reference_rating_life_L10r_h'].item():.4g} h")
