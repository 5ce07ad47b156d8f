"""Cage whirl outputs of a dynamic run (theory.md §17): the cage centre, the land's force on the
cage, and the whirl's summary attributes (whirl ratio, orbit radius over the guidance clearance
and its trend).

Stage: solver output -> **analysis**. The land force is the kernel's own law
(system/whirl.land_state at each recorded state), so the outputs satisfy the equations the
solver solved.
"""

from __future__ import annotations

import numpy as np

from ..system.layout import GLOBAL

#: name -> (dims after time, units, long_name)
WHIRL_VARIABLES = {
    "cage_center": (("direction",), "m", "cage centre displacement from the bearing axis "
                    "(radial: along the radial-load line; tangential: 90° ahead of it in the "
                    "direction of rotation)"),
    "cage_land_force": ((), "N", "magnitude of the guiding land's force on the cage (film and "
                        "contact; 0 for a roller-guided cage)"),
}


def whirl_values(model, t, full_g) -> dict[str, np.ndarray]:
    """The :data:`WHIRL_VARIABLES` of a run from the unscaled full global states (n, NG)."""
    from ..system.residual import P_WH
    from ..system.whirl import land_state

    PW = np.ascontiguousarray(model.params[P_WH:])
    n = full_g.shape[0]
    land = np.zeros((n, 4))
    for i in range(n):
        land_state(np.ascontiguousarray(full_g[i]), model.ring_speed(float(t[i])), PW, land[i])
    centre = np.stack([full_g[:, GLOBAL.index("cage_x")], full_g[:, GLOBAL.index("cage_y")]],
                      axis=-1)
    velocity = np.stack([full_g[:, GLOBAL.index("cage_vx")],
                         full_g[:, GLOBAL.index("cage_vy")]], axis=-1)
    # not outputs: the land's force vector and moment and the centre's velocity, for the power
    # accounting (analysis/engineering.py, whirl_powers)
    return {"cage_center": centre, "cage_land_force": np.hypot(land[:, 0], land[:, 1]),
            "cage_velocity": velocity, "cage_land_force_xy": land[:, :2],
            "cage_land_moment": land[:, 3]}


def whirl_powers(model, t, values) -> dict[str, np.ndarray]:
    """The power terms a whirling cage adds (docs/theory.md §17; W, per sample), from the
    recorded states and the kernel's laws: ``pocket_impact`` the pockets' work at the lead
    rates of the displaced pockets (Eq. 17.1: the extra -Σ F_cr Δv) and of their radial lips
    (-Σ F_ρ ρ̇); ``pocket_friction`` the roller-bar friction's work on the cage's radial sliding
    (-Σ f (ė·r̂ + ω_c e·t̂)); ``cage_land`` the land's loss -(F·ė + T (ω_c - ω_land)); and
    ``drive_torque`` the inner ring's extra drive (the land's moment T, inner land only)."""
    from ..physics.cage import pocket_force
    from ..physics.cage_guidance import pocket_displacement
    from ..system.residual import P_WH
    from ..system.whirl import (W_CDP, W_CR, W_EPSP, W_FP, W_INNER, W_KP, W_MUC, W_SPIN)

    PW = model.params[P_WH:]
    Z = model.geometry.rollers
    c = np.asarray(values["cage_center"])[:, None, :]
    v = np.asarray(values["cage_velocity"])[:, None, :]
    wc = np.asarray(values["cage_speed"], float)[:, None]
    tc = np.asarray(values["cage_angle"], float)[:, None]
    j = np.arange(Z)[None, :]
    dv = pocket_displacement(c[..., 0], c[..., 1], v[..., 0], v[..., 1], tc, wc, j, Z)[1]
    psi = tc + 2.0 * np.pi * j / Z
    cp, sp = np.cos(psi), np.sin(psi)
    e_r = c[..., 0] * cp + c[..., 1] * sp
    e_t = -c[..., 0] * sp + c[..., 1] * cp
    nu_r = v[..., 0] * cp + v[..., 1] * sp
    radial_rate = nu_r + wc * e_t  # d(e·r̂)/dt at the pocket
    F = np.asarray(values["cage_force"])
    Fcr = F[..., 0] + F[..., 1]
    om = np.asarray(values["spin_speed"])
    sg = om / np.sqrt(om * om + PW[W_SPIN] ** 2)
    f = -PW[W_MUC] * sg * Fcr
    F_rho = pocket_force(-e_r, -radial_rate, PW[W_CR], PW[W_KP], PW[W_CDP], PW[W_EPSP],
                         PW[W_FP])[0]
    land_speed = PW[W_INNER] * np.asarray(values["inner_ring_speed"], float)
    Fl = np.asarray(values["cage_land_force_xy"])
    T = np.asarray(values["cage_land_moment"])
    vc = np.asarray(values["cage_velocity"])
    return {
        "pocket_impact": -np.sum(Fcr * dv, axis=-1) + np.sum(F_rho * radial_rate, axis=-1),
        "pocket_friction": -np.sum(f * radial_rate, axis=-1),
        "cage_land": -(np.sum(Fl * vc, axis=-1) + T * (wc[:, 0] - land_speed)),
        "drive_torque": T * PW[W_INNER],
    }


def guidance_clearance_m(model) -> float:
    """The radial travel of the cage centre its guidance allows [m]: the land's radial clearance
    (half the diametral), or for a roller-guided cage the corner of the polygon the Z pockets'
    radial lips make, (c_p/2) / cos(π/Z) (a lip at ψ holds e·r̂_ψ ≤ c_p/2)."""
    cg = model.scene.cage
    if cg.guidance == "roller":
        return 0.5 * cg.pocket_clearance_m / np.cos(np.pi / model.geometry.rollers)
    return 0.5 * cg.land_clearance_m


def whirl_attrs(model, t, centre, cage_speed) -> dict:
    """Summary attributes of the cage whirl over the record (t (n,), centre (n, 2) [m],
    cage_speed (n,) [rad/s]): whirl ratio, orbit radius over the guidance clearance and its
    trend per cage revolution (> 0: growing orbit)."""
    t = np.asarray(t, float)
    centre = np.asarray(centre, float)
    clearance = guidance_clearance_m(model)
    out = {"cage_guidance": model.scene.cage.guidance,
           "cage_guidance_clearance_m": float(clearance)}
    if t.size < 3:
        return out
    phi = np.unwrap(np.arctan2(centre[:, 1], centre[:, 0]))
    radius = np.hypot(centre[:, 0], centre[:, 1])
    span = t[-1] - t[0]
    whirl = (phi[-1] - phi[0]) / span  # mean whirl speed of the centre [rad/s]
    speed = float(np.mean(cage_speed))
    revolutions = np.cumsum(np.r_[0.0, 0.5 * (cage_speed[1:] + cage_speed[:-1]) * np.diff(t)])
    revolutions /= 2.0 * np.pi
    ratio = radius / clearance
    trend = np.polyfit(revolutions, ratio, 1)[0] if revolutions[-1] > 0 else np.nan
    out.update({
        "cage_whirl_speed_rad_s": float(whirl),
        "cage_whirl_ratio": float(whirl / speed) if speed != 0 else float("nan"),
        "cage_orbit_radius_max_m": float(radius.max()),
        "cage_orbit_radius_over_clearance": float(ratio.mean()),
        "cage_orbit_radius_over_clearance_max": float(ratio.max()),
        "cage_orbit_radius_over_clearance_trend_per_revolution": float(trend),
    })
    return out
