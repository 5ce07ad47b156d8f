"""
Work-precision: error against wall time
=======================================

How much wall time does each solver need for a given error? The study runs every solver
over a ladder of tolerances (IDA, the scipy peers) or steps (Newmark-β), takes IDA at its
tightest tolerance as the reference (confirmed by the next-tightest run) and measures the
error of each run against it. ``bearingdae workprecision`` runs the full ladders of every
solver; here the short ones (``quick=True``) of IDA and Newmark-β, one timed run per rung,
over the first 0.05 cage revolutions of the baseline (the command's default window is 0.2).
``solvers=("newmark", "scipy-BDF", "scipy-LSODA")`` adds scipy's integrators.
"""

import math

import matplotlib.pyplot as plt

from bearingdae import load_scene
from bearingdae.studies import workprecision as wp

scene = load_scene("yang20_baseline", overrides={"numerics.warmup_cage_revolutions": 0.0,
                                                 "numerics.cage_revolutions": 0.05})
st = wp.study(scene, repeat=1, quick=True, solvers=("newmark",),
              progress=False)

for r in st.runs:
    error = r.errors.get("cage_speed_rel_rms", math.nan)
    note = " (reference)" if r.is_reference else ("" if r.status == "ok" else f" {r.status}")
    print(f"{r.label:28s} {r.wall_s:7.3f} s  cage-speed error {error:9.2e}{note}")

# %%
# Each solver's rungs as one line; the reference has no error of its own (it is the
# reference), and errors below the agreement of the two tightest IDA runs (dotted) are
# not resolved.

fig, ax = plt.subplots(figsize=(6.5, 4.5), layout="constrained")
for solver in dict.fromkeys(r.solver for r in st.runs):
    ok = [r for r in st.runs if r.solver == solver and r.status == "ok" and not r.is_reference]
    ax.loglog([r.errors["cage_speed_rel_rms"] for r in ok], [r.wall_s for r in ok], "o-",
              label=solver)
    for r in ok:
        ax.annotate(f"{r.value:g}", (r.errors["cage_speed_rel_rms"], r.wall_s), fontsize=7,
                    xytext=(4, 4), textcoords="offset points")
ax.axvline(st.floor["cage_speed_rel_rms"], color="0.5", ls=":", label="reference floor")
ax.set(xlabel="cage speed error (relative RMS against the reference)",
       ylabel="integrator wall time [s]", title="yang20 baseline, first 0.05 cage revolutions")
ax.legend()
plt.show()
