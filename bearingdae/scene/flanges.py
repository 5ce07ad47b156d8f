"""Flanges (ribs) of the scene: bearing type, rib and roller-end geometry, axial load
(pipeline stage 1; theory.md §16). Checked input -> the frozen :class:`Flanges` in SI.

Which ring has which flanges (catalogue designations, e.g. SKF / Schaeffler):

    NU   outer ring two flanges, inner ring none      no axial load
    N    inner ring two flanges, outer ring none      no axial load
    NJ   outer ring two, inner ring one (at -x)       axial load on the inner ring along +X
    NUP  outer ring two, inner ring two               axial load either way

The roller end touches a flange at the distance e from the roller axis (towards that ring):
a spherical end of radius R_e on a rib inclined by α touches where its normal is inclined by α,
e = R_e sin α (Harris & Kotzalas, *Advanced Concepts of Bearing Technology*, 5th ed., ch. 1,
"roller end-flange contact"); a flat end touches the rib's rim, e = r - h_f. The contact must lie
on the rib face between its rim (r - h_f) and the roller's corner (r - r_k).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: flanges of each type: (inner at +x end a, inner at -x end b, outer at a, outer at b)
TYPE_FLANGES = {"NU": (0, 0, 1, 1), "N": (1, 1, 0, 0), "NJ": (0, 1, 1, 1), "NUP": (1, 1, 1, 1)}
DEFAULT_ANGLE_DEG = 0.5
DEFAULT_HEIGHT_FRACTION = 0.2  #: flange height / D_w
DEFAULT_CORNER_FRACTION = 0.05  #: corner radius / D_w
DEFAULT_CLEARANCE_MM = 0.02
DEFAULT_FRICTION = 0.05
END_RADIUS_MAX_MM = 1e5  #: the range of bearing.roller_end_radius_mm (scene/sections/bearing.py)



@dataclass(frozen=True)
class Flanges:
    """Roller end-flange contact geometry in SI (``Bearing.flanges``; None: no flanges)."""

    type: str
    angle_rad: float  #: rib inclination α
    height_m: float  #: h_f
    roller_end: str  #: "flat" | "spherical"
    end_radius_m: float  #: R_e (spherical ends)
    corner_radius_m: float  #: r_k
    clearance_m: float  #: axial play of a roller between the flanges of one ring
    friction: float  #: sliding friction coefficient μ_f
    contact_height_m: float  #: e, distance of the contact point from the roller axis
    contact_radius_m: float  #: radius of the Hertz point contact (R_e, or r_k for flat ends)

    @property
    def present(self) -> tuple[int, int, int, int]:
        """(inner a, inner b, outer a, outer b): 1 where a flange exists."""
        return TYPE_FLANGES[self.type]

    @property
    def axial_load_directions(self) -> str:
        return {"NU": "none", "N": "none", "NJ": "+X only", "NUP": "both"}[self.type]


def check_flanges(b, axial, origin: str, roller_diameter_mm: float):
    """(Flanges or None, resolved values in mm) from the checked ``[bearing]`` input ``b`` and
    the axial load ``axial`` = (key, times [s] or None, values [N]): a constant (one value,
    times None) or every row of its history, each checked against the bearing type; raises
    SceneError with the field, value, allowed range and fix."""
    from .errors import SceneError

    def fail(key: str, value, rule: str):
        raise SceneError(f"invalid scene ({origin}): '{key}' = {value!r}: {rule}.")

    key, times, values = axial
    values = np.asarray(values, dtype=float)  # a history's: millions of values, vectorised

    def fail_axial(bad, rule: str):
        """One line for the first value of the axial load that ``bad`` (a vectorised test)
        refuses."""
        i = int(np.flatnonzero(bad(values))[0])
        if times is None:
            fail(key, float(values[i]), rule)
        raise SceneError(f"invalid scene ({origin}): '{key}' = {float(values[i])!r} at t = "
                         f"{float(times[i]):.9g} s (of its history): {rule}.")

    loaded = bool(np.any(values != 0.0))
    if b.type is None:  # its keys were refused without it (scene/switches.py)
        if loaded:
            fail_axial(lambda v: v != 0.0, "the flangeless bearing carries no axial load; "
                       "set bearing.type = \"NJ\" (F_a >= 0) or \"NUP\", or the load to 0")
        return None, {}
    if b.type in ("NU", "N") and loaded:
        fail_axial(lambda v: v != 0.0, f"an {b.type} bearing carries no axial load "
                   "(allowed: 0); use type NJ or NUP")
    if b.type == "NJ" and values.min() < 0.0:
        fail_axial(lambda v: v < 0.0, "an NJ bearing carries axial load along +X only "
                   "(allowed range [0, 1e8] N; its inner-ring flange is at the -x end); use NUP")
    Dw = roller_diameter_mm
    r = 0.5 * Dw
    angle = b.flange_angle_deg if b.flange_angle_deg is not None else DEFAULT_ANGLE_DEG
    h = b.flange_height_mm if b.flange_height_mm is not None else DEFAULT_HEIGHT_FRACTION * Dw
    rk = (b.roller_corner_radius_mm if b.roller_corner_radius_mm is not None
          else DEFAULT_CORNER_FRACTION * Dw)
    end = b.roller_end or "spherical"
    if not rk < h < r:
        key = "flange_height_mm" if b.flange_height_mm is not None else "roller_corner_radius_mm"
        fail(f"bearing.{key}", getattr(b, key), f"the flange height must lie between the "
             f"corner radius {rk:g} mm and the roller radius {r:g} mm (allowed ({rk:g}, {r:g}))")
    sin_a = math.sin(math.radians(angle))
    Re = b.roller_end_radius_mm
    if end == "spherical":
        # the end radius (given, or by default the one touching mid flange face) lies in
        # roller_end_radius_mm's range, the result file's complete TOML states it: R_e sin α
        # at least r - h_f (given) or r - (h_f + r_k)/2 (default) needs α at least this
        mid = r - 0.5 * (h + rk)
        reach = mid if Re is None else r - h
        if not reach <= END_RADIUS_MAX_MM * sin_a:
            least = math.degrees(math.asin(min(1.0, reach / END_RADIUS_MAX_MM)))
            what = ("the default roller end radius (r - (h_f + r_k)/2)/sin α" if Re is None
                    else "a roller end radius touching the flange face, (r - h_f)/sin α or more,")
            fail("bearing.flange_angle_deg", angle, f"too small a rib angle: {what} exceeds "
                 f"roller_end_radius_mm's range (0, {END_RADIUS_MAX_MM:g}] mm (allowed range "
                 f"[{least:.6g}, 10] at this roller and flange height); or use "
                 "roller_end = \"flat\"")
    if end == "spherical":
        lo, hi = (r - h) / sin_a, (r - rk) / sin_a  # end radii touching the rib face
        if Re is None:
            Re = mid / sin_a
        elif not lo <= Re <= hi:
            fail("bearing.roller_end_radius_mm", Re, f"the end-flange contact R_e sin α must "
                 f"lie on the flange face (allowed range [{lo:.4g}, {hi:.4g}] mm at "
                 f"flange_angle_deg = {angle:g}, flange_height_mm = {h:g})")
        e, rc = Re * sin_a, Re
    else:
        if Re is not None:
            fail("bearing.roller_end_radius_mm", Re, "applies to spherical ends only; set "
                 "bearing.roller_end = \"spherical\" or drop the key")
        if rk <= 0.0:
            fail("bearing.roller_corner_radius_mm", rk, "a flat end's edge contact needs a "
                 "corner radius > 0")
        e, rc, Re = r - h, rk, math.inf
    clearance = b.flange_clearance_mm if b.flange_clearance_mm is not None else (
        DEFAULT_CLEARANCE_MM)
    friction = b.flange_friction if b.flange_friction is not None else DEFAULT_FRICTION
    mm = 1e-3
    fl = Flanges(type=b.type, angle_rad=math.radians(angle), height_m=h * mm, roller_end=end,
                 end_radius_m=Re * mm, corner_radius_m=rk * mm, clearance_m=clearance * mm,
                 friction=friction, contact_height_m=e * mm, contact_radius_m=rc * mm)
    resolved = {"flange_angle_deg": angle, "flange_height_mm": h, "roller_end": end,
                "roller_corner_radius_mm": rk, "flange_clearance_mm": clearance,
                "flange_friction": friction}
    if end == "spherical":
        resolved["roller_end_radius_mm"] = Re
    return fl, resolved
