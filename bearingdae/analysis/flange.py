"""Roller end-flange outputs of a dynamic run (theory.md §16): per roller end the normal and
axial flange forces, the sliding speed and the axial force on the inner ring's flanges; the
friction power of all flange contacts; the catalogue's permissible axial load as a plausibility
check.

Stage: solver output -> **analysis**. The per-contact values are those the DAE kernel uses
(system/flange.flange_state at each recorded state), so the outputs satisfy the equations the
solver solved.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..system.flange import flange_values
from ..system.layout import GLOBAL, LOCAL

#: name -> (dims after time, units, long_name)
FLANGE_VARIABLES = {
    "flange_force": (("roller", "end"), "N", "normal force of the roller end-flange contacts "
                     "at the roller end (both rings' flanges)"),
    "flange_axial_force": (("roller", "end"), "N", "axial component of the flange force on the "
                           "roller end (magnitude, both rings' flanges)"),
    "inner_flange_axial_force": (("roller", "end"), "N", "axial force of the inner ring's "
                                 "flange on the roller end, along +X (sums to the axial load)"),
    "flange_slip_velocity": (("roller", "end"), "m s-1", "sliding speed at the end's loaded "
                             "flange contact, flange surface minus roller surface, along the "
                             "direction of rotation"),
    "flange_friction_power": ((), "W", "friction power of all roller end-flange contacts"),
    "roller_axial_position": (("roller",), "m", "roller axial position along +X (0: centred "
                              "between the flanges)"),
    "ring_axial_displacement": ((), "m", "inner ring axial displacement along +X"),
    "applied_axial_load": ((), "N", "external axial force applied to the inner ring along +X "
                           "(the axial load history)"),
}


#: the catalogue's rules of the permissible axial load, attribute -> (rule's name, what it
#: limits); the permissible axial load is the smallest (physics/flange.py, theory.md §16)
AXIAL_LOAD_RULES = {
    "thermal_axial_load_limit_N": ("thermal F_ap (SKF)", "heat of the flange contact"),
    "flange_strength_limit_N": ("flange strength", "a constantly acting axial load"),
    "radial_axial_load_limit_N": ("0.5 F_r", "a single-row bearing: F_a <= 0.5 F_r"),
}


def _rating_and_speed(scene) -> tuple[float, float]:
    """(C0 [N] of ISO 76, the speed [r/min] the thermal limit is taken at: a ramp's largest)."""
    from ..physics.flange import basic_static_load_rating

    b, op = scene.bearing, scene.operating
    C0 = basic_static_load_rating(b.rollers, b.roller_diameter_m, b.roller_length_m,
                                  b.pitch_diameter_m)
    return C0, op.speed_rpm if isinstance(op.speed_rpm, float) else max(op.speed_rpm[1])


def axial_limits(scene) -> dict[str, float]:
    """The catalogue's limits of the axial load [N] (:data:`AXIAL_LOAD_RULES`' keys) at the
    scene's operating point (the largest speed of a ramp, the radial load's magnitude)."""
    from ..physics.flange import flange_strength_limit, permissible_axial_load

    b, op = scene.bearing, scene.operating
    C0, n = _rating_and_speed(scene)
    Fr = abs(op.radial_load_N)
    # the thermal formula falls below 0 at high speed and radial load: no axial load then
    return {"thermal_axial_load_limit_N": max(0.0, permissible_axial_load(
                C0, n, b.bore_m * 1e3, b.outer_diameter_m * 1e3, Fr)),
            "flange_strength_limit_N": flange_strength_limit(b.outer_diameter_m),
            "radial_axial_load_limit_N": 0.5 * Fr}


def binding_rule(limits: dict[str, float]) -> str:
    """The attribute of the smallest limit (the first of :data:`AXIAL_LOAD_RULES` on a tie)."""
    return min(AXIAL_LOAD_RULES, key=lambda k: limits[k])


def permissible_axial_load_text(attrs) -> str:
    """'400 N (0.5 F_r binds; thermal F_ap (SKF) 6695 N, flange strength 2424 N)': the
    permissible axial load, the rule that binds, the others in brackets (from a result's
    attributes)."""
    if "permissible_axial_load_rule" not in attrs:  # a file written before: its thermal limit
        return (f"{float(attrs['permissible_axial_load_N']):.4g} N (SKF, thermal), flange "
                f"strength {float(attrs['flange_strength_limit_N']):.4g} N")
    keys = [k for k in AXIAL_LOAD_RULES if k in attrs]
    bind = min(keys, key=lambda k: float(attrs[k]))
    others = ", ".join(f"{AXIAL_LOAD_RULES[k][0]} {float(attrs[k]):.4g} N"
                       for k in keys if k != bind)
    return (f"{float(attrs[bind]):.4g} N ({AXIAL_LOAD_RULES[bind][0]} binds"
            + (f"; {others})" if others else ")"))


def axial_capacity_attrs(scene) -> dict:
    """The permissible axial load of the catalogue (physics/flange.py): the smallest of its
    rules (:data:`AXIAL_LOAD_RULES`), the rule that binds and each rule's value; and the check
    of the scene's axial load (its largest value, a history) against it; warns
    (PlausibilityWarning) when it is exceeded."""
    from .guards import PlausibilityWarning

    b, op = scene.bearing, scene.operating
    C0, n = _rating_and_speed(scene)
    limits = axial_limits(scene)
    bind = binding_rule(limits)
    limit = limits[bind]
    Fa = op.axial_load_max_N
    if Fa > limit:
        warnings.warn(
            f"axial load {Fa:g} N exceeds the permissible axial load {limit:.4g} N of the "
            f"catalogue ({AXIAL_LOAD_RULES[bind][0]}; thermal F_ap = "
            f"{limits['thermal_axial_load_limit_N']:.4g} N at {n:g} r/min, flange strength "
            f"{limits['flange_strength_limit_N']:.4g} N, 0.5 F_r = "
            f"{limits['radial_axial_load_limit_N']:.4g} N; docs/theory.md §16): the flange "
            "contact would overheat or wear; lower 'operating.axial_load_N'",
            PlausibilityWarning, stacklevel=3)
    return {"flange_type": b.flanges.type, "axial_load_N": op.axial_load_N,
            "static_load_rating_C0_N": C0, "permissible_axial_load_N": limit,
            "permissible_axial_load_rule": AXIAL_LOAD_RULES[bind][0], **limits}


def static_with_flanges(scene, sol, azimuth_rad=None):
    """The static solution ``sol`` of the slice contacts replaced by the quasi-static state
    with flanges (solvers/flange_static.py), and the flange variables of that state:
    (solution, {name: DataArray}). ``azimuth_rad``: the rollers' azimuths (default: the
    initial ones; the model's state starts there)."""
    from dataclasses import replace

    import xarray as xr

    from ..physics.equilibrium import contact_state
    from ..solvers.algebraic import static_state
    from ..system.layout import RING
    from ..system.model import build_model

    model = build_model(scene)
    if azimuth_rad is not None:  # the initial state is solved at the geometry's azimuths
        model = replace(model, geometry=replace(model.geometry, azimuth0_rad=np.asarray(
            azimuth_rad, dtype=float)))
    y, full_l, full_g, rows = static_state(model)
    u = full_l[:, LOCAL.index("radial_position")]
    beta = full_l[:, LOCAL.index("tilt")]
    ring = full_g[[GLOBAL.index(n) for n in RING]]
    prob = sol.problem
    cs = contact_state(u, beta, ring, prob.azimuth_rad, prob.contact)
    sol = replace(sol, z=np.concatenate([u, beta, ring]), contact=cs,
                  relative_residual=rows)
    v = flange_values(model, np.zeros(1), full_l[None], full_g[None])
    end = ("end", ["a", "b"], {"long_name": "roller end (a: x = +L/2, b: x = -L/2)"})
    out = {}
    for name, (dims, units, long_name) in FLANGE_VARIABLES.items():
        out[name] = xr.DataArray(v[name][0], dims=dims,
                                 coords={"end": end} if "end" in dims else None,
                                 attrs={"units": units, "long_name": long_name})
    return sol, out
