"""Physical checks of a dynamic Dataset, recomputed from its variables only (not a test module).

Used by tests/robustness/test_extreme.py and benchmarks/stability.py. Each function returns numbers
(the caller decides what passes), so the benchmark can tabulate what the tests assert:

- :func:`nonfinite_variables`: every variable must be finite (no NaN/inf anywhere).
- :func:`algebraic_residual`: theory.md §5 (roller radial and tilt balance, inner-ring balance)
  recomputed from the slice contact forces, azimuths and orbit speeds in the Dataset, with the
  roller mass taken from the scene's raw dimensions — independent of system/ and physics/.
- :func:`speed_bounds`: kinematic bounds that hold for any bearing with a fixed outer ring and
  a driven inner ring: the cage and every roller centre orbit between 0 and the inner-ring speed,
  a roller's surface speed lies between 0 and the inner raceway's surface speed (nothing in the
  bearing moves faster; churning and pocket friction only slow rollers down); slice contact
  forces and pressures are >= 0 (compression only).
- :func:`kinematic_drift`: θ(t1) - θ(t0) against the trapezoid integral of the stored speed
  (θ' = ω is one of the DAE's equations), for the cage and every roller.
- :func:`power_balance`: the record's mean drive power, mean summed power loss and rate of
  change of the kinetic energy (energy balance: drive = losses + stored).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

RPM = 2.0 * np.pi / 60.0


def nonfinite_variables(ds: xr.Dataset) -> list[str]:
    """Names of data variables or coordinates holding any NaN or inf (NaN allowed where the
    variable states what it means, attribute ``nan_meaning``: no film on an unloaded slice)."""
    bad = []
    for name, var in ds.variables.items():
        if var.dtype.kind not in "fc":
            continue
        ok = (~np.isinf(var.values) if "nan_meaning" in var.attrs
              else np.isfinite(var.values))
        if not ok.all():
            bad.append(str(name))
    return bad


def roller_mass_kg(scene) -> float:
    """ρ π r² L from the scene's dimensions (theory.md §2), not from physics/geometry.py."""
    b = scene.bearing
    return scene.materials.density_kg_m3 * np.pi * (0.5 * b.roller_diameter_m) ** 2 * (
        b.roller_length_m)


def algebraic_residual(ds: xr.Dataset, scene) -> float:
    """Largest relative residual of theory.md §5 over all output times, rollers and equations.

    Forces are relative to the largest force in play (a load, a roller's contact load or its
    centrifugal force), moments to that force times the half roller length.
    """
    q = ds.contact_force
    qi, qo = q.sel(race="inner"), q.sel(race="outer")
    x = ds.slice_position
    phi = ds.roller_azimuth
    half = 0.5 * scene.bearing.roller_length_m
    Rm = 0.5 * scene.bearing.pitch_diameter_m
    Fc = roller_mass_kg(scene) * Rm * ds.orbit_speed**2
    if "applied_load" in ds:  # loads that change in time: as applied at each sample
        Fr, Ft = ds.applied_load.sel(direction="radial"), ds.applied_load.sel(direction="tangential")
        M = ds.applied_moment.sel(direction="radial")
        Mt = ds.applied_moment.sel(direction="tangential")
    else:
        Fr, Ft, M, Mt = scene.operating.loads
    Qi, Qo = qi.sum("slice"), qo.sum("slice")
    Mi = (x * qi).sum("slice")
    tilt = (x * (qi - qo)).sum("slice")
    if "inner_flange_axial_force" in ds:
        # roller end-flange contacts (theory.md §16): the flanges' tilting moment -ρ N_x on the
        # roller (ρ = +e outer ring side, -e inner), their share (R_m - e)(-N_x) of the ring's
        # moments, and the ring's axial balance F_a = Σ N_x (inner)
        e = scene.bearing.flanges.contact_height_m
        n_in = ds.inner_flange_axial_force
        n_out = (ds.flange_axial_force - abs(n_in)) * xr.DataArray([-1.0, 1.0], dims="end",
                                                                    coords={"end": ["a", "b"]})
        tilt = tilt - e * n_out.sum("end") + e * n_in.sum("end")
        Mi = Mi - (Rm - e) * n_in.sum("end")
        Fa = (ds.applied_axial_load if "applied_axial_load" in ds  # F_a(t) (theory.md §14)
              else scene.operating.axial_load_N)
        axial = (Fa - n_in.sum(("roller", "end"))) / max(scene.operating.axial_load_max_N, 1e-12)
    else:
        axial = xr.zeros_like(Qi)
    big = [float(np.max(np.abs(v))) for v in (Fr, Ft, M, Mt)]
    F = max(big[0], big[1], big[2] / half, big[3] / half, float(Qi.max()), float(Qo.max()),
            float(Fc.max()), 1e-12)
    eqs = [
        (Qi - Qo + Fc) / F,
        tilt / (F * half),
        axial,
    ]
    if "ring_acceleration" in ds:
        # a dynamic ring (theory.md §15): its momentum rows m a = F + F_s - Σ Q_i (cos φ, sin φ)
        # hold at each instant, but the Dataset records the acceleration low-passed over the
        # samples (analysis/vibration.py), not at the instant; tests/analysis/test_vibration.py
        # checks the filter. Its tilt rows carry an angular acceleration the Dataset does not
        # record. So only the rollers' rows are checked here.
        return max(float(abs(e).max()) for e in eqs)
    eqs += [
        (Fr - (Qi * np.cos(phi)).sum("roller")) / F,
        (Ft - (Qi * np.sin(phi)).sum("roller")) / F,
        (M - (Mi * np.cos(phi)).sum("roller")) / (F * half),
        (Mt - (Mi * np.sin(phi)).sum("roller")) / (F * half),
    ]
    return max(float(abs(e).max()) for e in eqs)


def speed_bounds(ds: xr.Dataset, scene) -> dict[str, float]:
    """Signed margins of the kinematic bounds (>= 0 when satisfied), relative to the largest
    inner-ring speed (surface speed for spin); for a bearing at rest, in rad/s and m/s.

    ``cage_low`` = min ω_c / ω_ref, ``cage_high`` = min (ω_i(t) - ω_c) / ω_ref, likewise
    ``orbit_low``/``orbit_high`` for every roller, ``spin_low``/``spin_high`` for ω_j r against
    [0, ω_i(t) R_i], and ``contact_force_min`` [N], ``contact_pressure_min`` [Pa].
    """
    b = scene.bearing
    r = 0.5 * b.roller_diameter_m
    Ri = 0.5 * b.pitch_diameter_m - r
    wi = ds.inner_ring_speed
    w_ref = float(wi.max())
    w_ref = w_ref if w_ref > 0 else 1.0
    out = {}
    if "cage_speed" in ds:
        wc = ds.cage_speed
        out["cage_low"] = float(wc.min()) / w_ref
        out["cage_high"] = float((wi - wc).min()) / w_ref
    Om = ds.orbit_speed
    out["orbit_low"] = float(Om.min()) / w_ref
    out["orbit_high"] = float((wi - Om).min()) / w_ref
    vs = ds.spin_speed * r
    out["spin_low"] = float(vs.min()) / (w_ref * Ri)
    out["spin_high"] = float((wi * Ri - vs).min()) / (w_ref * Ri)
    out["contact_force_min"] = float(ds.contact_force.min())
    out["contact_pressure_min"] = float(ds.contact_pressure.min())
    return out


def kinematic_drift(ds: xr.Dataset) -> float:
    """max |Δθ - ∫ω dt| / max(|Δθ|, 1e-12 rad) over the cage and every roller (trapezoid rule on
    the output samples; its own error is O(Δt²) times the angular acceleration)."""
    t = ds.time.values
    if t.size < 2:
        return 0.0
    pairs = [("roller_azimuth", "orbit_speed")]
    if "cage_angle" in ds:
        pairs.append(("cage_angle", "cage_speed"))
    worst = 0.0
    for ang, spd in pairs:
        a = ds[ang].values
        w = ds[spd].values
        integral = np.trapezoid(w, t, axis=0)
        delta = a[-1] - a[0]
        rel = np.abs(delta - integral) / np.maximum(np.abs(delta), 1e-12)
        worst = max(worst, float(np.max(rel)))
    return worst


def power_balance(ds: xr.Dataset) -> tuple[float, float, float]:
    """(drive, losses, stored) [W] over the record: the time means (trapezoids) of the drive
    power and of the power loss summed over its sources, and (E_end - E_start) / span of the
    kinetic energy."""
    t = ds.time.values
    span = t[-1] - t[0]
    drive = np.trapezoid(ds.drive_power_W.values, t) / span
    losses = np.trapezoid(ds.power_loss_W.sum("loss_source").values, t) / span
    stored = (ds.kinetic_energy_J.values[-1] - ds.kinetic_energy_J.values[0]) / span
    return float(drive), float(losses), float(stored)
