"""What a bearing engineer reads off a result: rating life, oil film and power loss.

Pipeline: analysis (post-processing of a static solve's or a dynamic run's slice loads, speeds
and forces; nothing here enters the DAE). The laws are in physics/life.py (ISO/TS 16281,
ISO 281), physics/film.py (line-contact EHL) and physics/power.py (power loss by source);
this module picks their inputs out of a result and labels the outputs:

* Dataset attributes ``reference_rating_life_L10r_Mrev``, ``reference_rating_life_L10r_h``,
  ``equivalent_reference_load_N``, ``basic_dynamic_load_rating_N`` (and where it came from),
  ``edge_stress_factors``, the laminae and the error estimate (analysis/rating_life.py);
* variables ``film_thickness_central``, ``film_thickness_min``, ``lambda_ratio`` per
  (time,) roller, slice, race (nan where a slice carries no load);
* dynamic runs: ``power_loss_W`` and ``friction_torque_N_m`` (time, source), the inner
  ring's ``drive_torque_N_m``, ``drive_power_W`` and the ``kinetic_energy_J`` E of
  physics/power.py (time): over a window, mean drive power = mean Σ power loss + ΔE / duration
  (the energy balance; tests/analysis/test_engineering.py).

A dynamic run's life takes the standard's power means of the slice loads over every recorded
sample and every roller, corrected to converged laminae (analysis/rating_life.py).
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from ..physics import film, power
from ..physics.kinematics import rolling_sums
# the rating life (analysis/rating_life.py); streamed runs import its sums from here
from .rating_life import (  # noqa: F401
    converged_life, dynamic_life_attrs, equivalent_loads, lamina_power_sums, mean_speed_rpm,
    rating, slice_life, static_life_attrs, summed_life_attrs)

#: A slice carrying less than this fraction of the largest slice load (same sample) gets no
#: film (its load is contact-onset regularisation residue, docs/theory.md §5, or nearly so).
FILM_LOADED_FRACTION = 1e-3


def _var(dims, data, units, long_name, **extra):
    """A labelled variable; ``units`` None for a label coordinate (no units, as CF has it)."""
    attrs = ({} if units is None else {"units": units}) | {"long_name": long_name, **extra}
    return xr.Variable(dims, np.asarray(data), attrs)


def film_variables(scene, geometry, contact_force_N, ring_rad_s, orbit_rad_s, spin_rad_s,
                   dims) -> dict:
    """Film and λ variables; speeds broadcast against (..., roller) of the slice loads."""
    g, e = geometry, scene.engineering
    sum_i, sum_o = rolling_sums(np.asarray(ring_rad_s)[..., None], orbit_rad_s, spin_rad_s,
                                g.roller_radius_m, g.inner_race_radius_m, g.outer_race_radius_m)
    u = 0.5 * np.stack([sum_i, sum_o], axis=-1)[..., None, :]  # (..., roller, 1, race)
    radius = np.array([g.reduced_radius_inner_m, g.reduced_radius_outer_m])
    q = np.asarray(contact_force_N)
    peak = q.max(axis=(-3, -2, -1), keepdims=True)
    q = np.where((q > FILM_LOADED_FRACTION * peak) & (u != 0.0), q, 0.0)  # rolling contacts
    h_c, h_min = film.line_contact_film(q / g.slice_width_m, radius, u,
                                        scene.lubricant.viscosity_Pa_s,
                                        e.pressure_viscosity_Pa_inv,
                                        film.reduced_modulus(g.compliance_m2_N))
    lam = film.film_parameter(h_min, e.roughness_m)
    note = ("isothermal, fully flooded line contact (Pan & Hamrock 1989); no inlet shear "
            "heating or starvation factor")
    nan = "no film: the slice carries no load or does not roll"
    return {
        "film_thickness_central": _var(dims, h_c, "m", "central EHL film thickness",
                                       comment=note, nan_meaning=nan),
        "film_thickness_min": _var(dims, h_min, "m", "minimum EHL film thickness",
                                   comment=note, nan_meaning=nan),
        "lambda_ratio": _var(dims, lam, "1", "film parameter lambda = minimum film thickness "
                             "over composite RMS roughness", comment=note, nan_meaning=nan),
    }


def add_static(ds: xr.Dataset, scene, geometry) -> xr.Dataset:
    """Life (attributes) and film (variables) of a static solve, rollers at the epicyclic
    orbit speed with pure-rolling spin (the static solve's kinematics). The life is the
    standard's one position of the roller set, converged in laminae (analysis/rating_life.py);
    ``life.phase_positions = m`` > 0 (default 0: off) adds
    ``reference_rating_life_L10r_phase_averaged_Mrev``, the means over m positions within one
    roller pitch under the same loads (8 are converged to 0.1 % on yang20), the quasi-static
    counterpart of a dynamic run's life."""
    w = scene.operating.speed_rad_s_at(0.0)
    q = ds.contact_force.values
    n = scene.operating.speed_at(0.0)
    ds.attrs.update(static_life_attrs(scene, geometry, n))
    phases = scene.engineering.phase_positions
    if phases:  # off by default: each position is one more static solve per lamina count
        averaged = converged_life(scene, np.arange(phases) / phases)
        ds.attrs["reference_rating_life_L10r_phase_averaged_Mrev"] = averaged["laminae_Mrev"]
    orbit = np.full(geometry.rollers, geometry.epicyclic_orbit_speed(w))
    spin = np.full(geometry.rollers, geometry.pure_rolling_spin(w))
    return ds.assign(film_variables(scene, geometry, q, w, orbit, spin,
                                    ("roller", "slice", "race")))


def dynamic_variables(model, t, values: dict) -> tuple[dict, dict]:
    """(variables, attributes) of a dynamic run from the full sample arrays ``values`` (the
    names of results/dataset.py, before the ``output.variables`` selection)."""
    from ..system.residual import PARAM_NAMES

    scene, g = model.scene, model.geometry
    p = {n: float(model.params[PARAM_NAMES.index(n)]) for n in PARAM_NAMES}
    ring = np.asarray(values["inner_ring_speed"], dtype=float)
    orbit, spin = values["orbit_speed"], values["spin_speed"]
    q = values["contact_force"]
    speed_rpm = mean_speed_rpm(float(np.sum(ring)), t.size) if t.size else 0.0
    equivalent = (equivalent_loads(scene, g, q, (0, 1))  # the modified life's (given e_C)
                  if scene.lubricant.contamination_factor is not None and t.size else None)
    attrs = dynamic_life_attrs(scene, g, slice_life(scene, g, q, (0, 1)), t.size,
                               speed_rpm, equivalent) if t.size else {}
    data = film_variables(scene, g, q, ring, orbit, spin, ("time", "roller", "slice", "race"))

    from ..system.effects import active, sources

    F = values["traction_force"]
    P, drive = power_by_source(model, t, values)
    whirl = "cage_velocity" in values  # a whirling cage (docs/theory.md §17)
    loss = np.stack([P[s.name] for s in sources(scene)], axis=-1)
    orbit_inertia = p["mass"] * p["Rm"] ** 2 + (p["Ix"] if p["orbit_paper"] > 0.5 else 0.0)
    energy = 0.5 * (np.sum(orbit_inertia * orbit ** 2 + p["Ix"] * spin ** 2
                           + p["It"] * values["skew_rate"] ** 2, axis=-1)
                    + p["Ic"] * np.asarray(values["cage_speed"]) ** 2)
    if whirl:  # the cage's translation
        from ..system.residual import P_WH

        energy = energy + 0.5 * model.params[P_WH + 1] * np.sum(
            np.asarray(values["cage_velocity"]) ** 2, axis=-1)
    T_in = power.drive_torque(F[..., 0], g.inner_race_radius_m)
    for term in reversed(drive):  # the effects' terms, the last declared first (the order
        T_in = T_in + term        # the sum has always had: the same numbers, bit for bit)
    with np.errstate(divide="ignore", invalid="ignore"):
        torque = np.where(ring[:, None] != 0.0, loss / ring[:, None], np.nan)
    src = ("time", "loss_source")
    data.update({
        "power_loss_W": _var(src, loss, "W", "power loss by source"),
        "friction_torque_N_m": _var(src, torque, "N m", "friction torque by source, referred "
                                    "to the inner ring (power loss / inner-ring speed)",
                                    nan_meaning="the inner ring stands still"),
        "drive_torque_N_m": _var("time", T_in, "N m", "drive torque of the inner ring "
                                 "(reaction of the inner-race traction" + "".join(
                                     e.drive_note for e in active(scene)) + ")"),
        "drive_power_W": _var("time", ring * T_in, "W", "drive power of the inner ring"),
        "kinetic_energy_J": _var("time", energy, "J", "kinetic energy of rollers (orbit, "
                                 "spin, skew) and cage, as the equations of motion define it"),
    })
    return data, attrs


def power_by_source(model, t, values) -> tuple[dict, list]:
    """(power loss [W] by source (time,), the effects' drive-torque terms [N m]) of the
    samples' ``values`` (results/dataset.sample_values): system/effects.power_by_source."""
    from ..system.effects import power_by_source as by_source

    return by_source(model, t, values)


def source_coordinate(scene) -> xr.Variable:
    """The ``loss_source`` coordinate of a scene's run: the sources its effects declare."""
    from ..system.effects import sources

    declared = sources(scene)
    return _var("loss_source", np.array([s.name for s in declared]), None,
                "power loss source",
                description="; ".join(f"{s.name}: {s.long_name}" for s in declared))


def summary_lines(ds: xr.Dataset) -> list[str]:
    """Rating life, minimum λ and power loss of a result, as the CLI summaries print them."""
    lam = h = power = drive = None
    if "lambda_ratio" in ds and np.isfinite(ds.lambda_ratio.values).any():
        lam = float(np.nanmin(ds.lambda_ratio.values))
        if "film_thickness_min" in ds:  # output.variables may keep either alone
            h = float(np.nanmin(ds.film_thickness_min.values))
    energy_rate = None
    if "power_loss_W" in ds and ds.sizes.get("time", 0):
        power = dict(zip(map(str, ds.loss_source.values), ds.power_loss_W.mean("time").values))
        if "drive_power_W" in ds:
            drive = float(ds.drive_power_W.mean())
        if "kinetic_energy_J" in ds:
            t, E = ds.time.values, ds.kinetic_energy_J.values
            energy_rate = window_energy_rate((t[0], E[0]), (t[-1], E[-1]))
    from .result_variables import flat

    return engineering_lines(flat(ds), lam, h, power, drive, energy_rate)


def film_line(a: dict, lam: float, h_min: float) -> str:
    """The summary's 'minimum film' line: λ_min and h_min; below λ = 1 also where it occurs (the
    film check's finding in ``a['plausibility_warnings']``) and what it means for the model.
    The command line prints this line instead of the check's warning (analysis/guards.py)."""
    from .guards import LAMBDA_LIMIT

    film = f" (h_min {h_min * 1e6:.3g} µm)" if h_min is not None else ""  # (not kept)
    line = f"minimum film             λ = {lam:.3g}{film}"
    if not lam < LAMBDA_LIMIT:
        return line
    where = ""
    try:
        found = json.loads(a.get("plausibility_warnings", "[]"))
        where = next((f.get("where", "") for f in found if isinstance(f, dict)
                      and f.get("check") == "film_parameter"), "")
    except (TypeError, ValueError):  # a foreign or edited file: say it without the place
        pass
    at = f" at {where}" if where else ""
    if a.get("lubrication") == "mixed":  # docs/theory.md §20
        return (f"{line}{at}: below {LAMBDA_LIMIT:g} the asperities touch (boundary "
                "lubrication); the mixed-lubrication model is in use (physics.lubrication = "
                "\"mixed\": asperities carry a share of the load at the boundary friction)")
    return (f"{line}{at}: below {LAMBDA_LIMIT:g} the asperities touch (boundary lubrication); "
            "the EHL traction law assumes a full film (physics.lubrication = \"mixed\" "
            "models the asperities' share)")


#: the summary says how far the sampled means miss the energy balance when they miss it by more
#: than this fraction of the drive power
BALANCE_NOTE_FRACTION = 0.01


def engineering_lines(a: dict, lam, h_min, power: dict | None, drive,
                      energy_rate_W=None) -> list[str]:
    """:func:`summary_lines` from the numbers (a streamed run accumulates them): global
    attributes and 0-d variables ``a`` (result_variables.flat), the smallest λ and minimum
    film [m] (None: no film), the mean power loss per source [W] and the mean drive power [W]
    (None: no power; ``h_min`` and ``drive`` None alone: a file that keeps λ or the power loss
    without them, ``output.variables``), and the window's kinetic energy change over its
    duration [W] (None: not kept)."""
    lines = []
    if "reference_rating_life_L10r_Mrev" in a:
        hours = a["reference_rating_life_L10r_h"]
        hh = f", {hours:.4g} h" if np.isfinite(hours) else ""
        L = a["reference_rating_life_L10r_Mrev"]
        error = a.get("reference_rating_life_L10r_error_Mrev")
        laminae = (f"{a['rating_life_laminae']} laminae, ± {error / L:.1%}; "
                   if error is not None and np.isfinite(L) and L > 0 else "")
        lines.append(f"rating life L10r         {L:.4g} "
                     f"million rev{hh} (ISO/TS 16281, {laminae}P_ref "
                     f"{a['equivalent_reference_load_N']:.4g} N, C "
                     f"{a['basic_dynamic_load_rating_N']:.4g} N)")
        if a.get("rating_life_converged", 1) == 0 and np.isfinite(error):
            lines.append(f"rating life not converged: ± {error / L:.1%} at "
                         f"{a['rating_life_laminae']} laminae (the contact reaches the roller "
                         "ends; a crowned profile, bearing.profile, keeps it inside)")
        elif a.get("rating_life_converged", 1) == 0:
            lines.append(f"rating life not converged: the static solve on finer laminae "
                         f"failed; the life is that of {a['rating_life_laminae']} laminae")
        if "modified_rating_life_Lnmr_Mrev" in a:
            lines.append(modified_life_line(a))
    if lam is not None:
        lines.append(film_line(a, lam, h_min))
    if power is not None:
        total = float(sum(float(v) for v in power.values()))
        top = sorted(((float(v), str(k)) for k, v in power.items()), reverse=True)[:3]
        parts = ", ".join(f"{k} {v / total:.0%}" for v, k in top if total > 0)
        shown = f"; drive {drive:.4g} W" if drive is not None else ""
        lines.append(f"power loss (mean)        {total:.4g} W ({parts}){shown}")
        balance = balance_line(total, drive, energy_rate_W)
        if balance:
            lines.append(balance)
    return lines


def modified_life_line(a: dict) -> str:
    """The summary's line of the modified life L_nmr (beside L10r's): its value, hours, error
    and the κ it was computed at."""
    L, hours = a["modified_rating_life_Lnmr_Mrev"], a.get("modified_rating_life_Lnmr_h")
    hh = f", {hours:.4g} h" if hours is not None and np.isfinite(hours) else ""
    error = a.get("modified_rating_life_Lnmr_error_Mrev")
    err = (f" ± {error / L:.1%};" if error is not None and np.isfinite(L) and L > 0
           and np.isfinite(error) else "")
    ratio = (f", L_nmr/L10r {L / a['reference_rating_life_L10r_Mrev']:.3g}"
             if a.get("reference_rating_life_L10r_Mrev") else "")
    return (f"modified life L_nmr      {L:.4g} million rev{hh} (ISO 16281 with ISO 281's "
            f"a_ISO,{err} κ {a['kappa']:.3g}{ratio})")


def window_energy_rate(first, last) -> float | None:
    """ΔE/T [W] of a window from its first and last (time [s], kinetic energy [J]); None for
    a window without duration."""
    (t0, E0), (t1, E1) = first, last
    return float((E1 - E0) / (t1 - t0)) if t1 > t0 else None


def balance_line(loss_W: float, drive_W, energy_rate_W) -> str | None:
    """The line that says the sampled means miss the energy balance, or None. At every instant
    drive = Σ losses + dE/dt (physics/power.py, theory.md §9), so the means over the samples
    differ from the balance only by the mean of the sampled dE/dt against the window's ΔE/T:
    swings of the kinetic energy (pocket impacts, rollers entering the load zone) faster than
    the sampling. Denser sampling closes it."""
    if drive_W is None or energy_rate_W is None or not drive_W > 0:
        return None
    gap = drive_W - loss_W - energy_rate_W
    if not abs(gap) > BALANCE_NOTE_FRACTION * drive_W:
        return None
    return (f"energy balance           drive - losses - dE/dt = {gap:.3g} W ({gap / drive_W:.1%} "
            "of the drive): the means are over the samples, and the kinetic energy swings "
            "faster than they follow; more samples (numerics.samples_per_cage_revolution) "
            "close it")
