"""Cage whirl outputs of a dynamic run (theory.md §17): the cage centre, the land's force on the
cage, and the whirl's summary attributes (whirl ratio, orbit radius over the guidance clearance
and its trend).

Stage: solver output -> **analysis**. The land force is the kernel's own law
(system/whirl.land_state at each recorded state), so the outputs satisfy the equations the
solver solved.
"""

from __future__ import annotations

import numpy as np

#: name -> (dims after time, units, long_name)
WHIRL_VARIABLES = {
    "cage_center": (("direction",), "m", "cage centre displacement from the bearing axis "
                    "(radial: along the radial-load line; tangential: 90° ahead of it in the "
                    "direction of rotation)"),
    "cage_land_force": ((), "N", "magnitude of the guiding land's force on the cage (film and "
                        "contact; 0 for a roller-guided cage)"),
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
