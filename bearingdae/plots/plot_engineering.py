"""The engineering figure of a result file: power loss, oil film and where the life is spent.

Pipeline: plots (reads a static or dynamic Dataset only; analysis/engineering.py wrote the
variables and attributes it draws). ``bearingdae plot FILE --figure engineering``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from ..physics import life
from .figure_common import closed_on_failure


def lamina_damage(ds: xr.Dataset) -> np.ndarray:
    """(q_e/q_c)^(9/2) per slice and race (slice, race): each slice's share of the ISO/TS
    16281 sum on the result's slices, whose power -8/9 is ``reference_rating_life_L10r_slices_
    Mrev`` (physics/life.py; the exponents the file records), recomputed from the file."""
    q = ds.contact_force.values
    axes = (0, 1) if "time" in ds.contact_force.dims else 0
    rollers, slices = ds.sizes["roller"], ds.sizes["slice"]
    C = ds.attrs["basic_dynamic_load_rating_N"]
    import tomllib

    b = tomllib.loads(ds.attrs["scene_toml"])["bearing"]  # γ = D_w / d_m of the stored scene
    dm = b.get("pitch_diameter_mm", 0.5 * (b["outer_diameter_mm"] + b["bore_mm"]))
    pitch_ratio = b["roller_diameter_mm"] / dm
    length = b["roller_length_mm"] * 1e-3
    width = length / slices
    qc_i, qc_o = life.lamina_ratings(C, rollers, pitch_ratio, width, length)
    f = (life.edge_stress_factors(slices) if ds.attrs.get("edge_stress_factors", 1)
         else np.ones(slices))
    p_i = ds.attrs.get("rating_life_exponent_inner", life.EXPONENT_ROTATING_RING)
    p_o = ds.attrs.get("rating_life_exponent_outer", life.EXPONENT_STATIONARY_RING)
    qe_i = life.equivalent_lamina_load(f * q[..., 0], p_i, axes)
    qe_o = life.equivalent_lamina_load(f * q[..., 1], p_o, axes)
    return np.stack([(qe_i / qc_i) ** 4.5, (qe_o / qc_o) ** 4.5], axis=-1)


@closed_on_failure
def engineering_figure(ds: xr.Dataset, path: str | Path) -> Path:
    """Three panels: mean power loss by source (dynamic runs), minimum λ per race (over time,
    or per roller for a static solve), and each lamina's share of the rating-life sum."""
    from .plotting import _plt, save_figure

    if "reference_rating_life_L10r_Mrev" not in ds.attrs or "contact_force" not in ds:
        raise ValueError("the file has no rating life or slice loads (written by bearingdae "
                         "0.1 static/run with the engineering outputs)")
    plt = _plt()
    fig, ax = plt.subplots(1, 3, figsize=(14, 4.2), constrained_layout=True)
    a = ax[0]
    if "power_loss_W" in ds and ds.sizes.get("time", 0):
        mean = ds.power_loss_W.mean("time")
        names = [str(s) for s in ds.source.values]
        a.barh(names, mean.values * 1e3, color="tab:red")
        if "drive_power_W" in ds:  # output.variables may keep the loss alone
            a.axvline(float(ds.drive_power_W.mean()) * 1e3, color="k", ls="--", lw=0.8)
        if (mean.values > 0).all():  # the sources span decades
            a.set_xscale("log")
        a.set(xlabel="mean power loss [mW]", title=f"power loss {float(mean.sum()) * 1e3:.4g} "
              f"mW (dashed: drive power)")
    else:
        a.text(0.5, 0.5, "power loss: dynamic runs only", ha="center", transform=a.transAxes)
        a.set_axis_off()
    a = ax[1]
    if "lambda_ratio" in ds and np.isfinite(ds.lambda_ratio.values).any():
        lam = ds.lambda_ratio
        for race in lam.race.values:
            one = lam.sel(race=race)
            if "time" in one.dims:
                m = one.min(("roller", "slice"), skipna=True)
                a.plot(ds.time.values * 1e3, m, lw=0.9, label=f"{race} race")
                a.set(xlabel="time [ms]")
            else:
                m = one.min("slice", skipna=True)
                a.plot(m.roller.values, m, "o-", ms=3, lw=0.9, label=f"{race} race")
                a.set(xlabel="roller")
        a.axhline(1.0, color="r", ls="--", lw=0.8)
        a.set(ylabel="minimum λ = h_min / σ", title="oil film (λ < 1: boundary lubrication)")
        a.legend(fontsize=8)
    else:
        a.text(0.5, 0.5, "no film (standstill)", ha="center", transform=a.transAxes)
    a = ax[2]
    damage = lamina_damage(ds)
    share = damage / damage.sum()
    s = ds.slice.values
    a.bar(s - 0.2, share[:, 0] * 100, 0.4, label="inner ring")
    a.bar(s + 0.2, share[:, 1] * 100, 0.4, label="outer ring")
    a.set(xlabel="slice", ylabel="share of the life sum on the slices [%]",
          title=f"L10r {ds.attrs['reference_rating_life_L10r_Mrev']:.4g} million rev")
    a.legend(fontsize=8)
    fig.suptitle(ds.attrs.get("title", "bearingdae"), fontsize=10)
    return save_figure(fig, path)
