"""Cage whirl keys of the scene (pipeline stage 1; theory.md §17): ``[physics] cage_whirl`` and
the guidance keys of ``[cage]``, checked -> the SI values of :class:`~bearingdae.scene.si.Cage`.

Defaults: a roller-guided cage (the pockets alone hold its centre); a land-guided cage rides
with a diametral clearance of half the pocket clearance (so that the land, not the pockets,
guides it) on rims as wide as the cage's side rims, (cage width - roller length) / 2 each.
"""

from __future__ import annotations

from .parameters import cage_annulus
from .sections.contact import LAND_CLEARANCE_MIN_MM, LAND_WIDTH_MIN_MM

#: the [cage] keys that only a land-guided cage reads (a whirling cage's keys are refused
#: without it by scene/switches.py, from their fields' metadata)
LAND_KEYS = ("land_clearance_mm", "land_width_mm", "land_friction")


def check_whirl(m, origin: str, pocket_clearance_mm: float, pitch_diameter_mm: float,
                roller_diameter_mm: float, roller_length_mm: float) -> tuple[dict, dict]:
    """(SI keyword values for Cage, resolved values in mm for the complete TOML) from the
    checked input ``m``; raises SceneError with the field, value, allowed range and fix."""
    from .errors import SceneError

    def fail(key: str, value, rule: str):
        raise SceneError(f"invalid scene ({origin}): '{key}' = {value!r}: {rule}.")

    c = m.cage
    on = bool(m.physics.cage_whirl)
    if not on:  # its keys were refused without it (scene/switches.py)
        return {}, {}
    if not m.physics.cage:
        fail("physics.cage_whirl", True, "needs the cage; set physics.cage = true or "
             "physics.cage_whirl = false")
    guidance = c.guidance or "roller"
    if guidance == "roller":
        given = [k for k in LAND_KEYS if getattr(c, k) is not None]
        if given:
            fail(f"cage.{given[0]}", getattr(c, given[0]), "applies to a land-guided cage; "
                 "set cage.guidance = \"outer-land\" or \"inner-land\", or drop the key")
        return {"mass_kg": c.mass_kg, "guidance": guidance}, {"guidance": guidance}
    _, _, width = cage_annulus(0.5 * pitch_diameter_mm, roller_diameter_mm, roller_length_mm)
    rim = 0.5 * (width - roller_length_mm)
    b = c.land_width_mm if c.land_width_mm is not None else rim
    if b > rim:
        fail("cage.land_width_mm", b, f"wider than the cage's side rim (allowed range "
             f"[{LAND_WIDTH_MIN_MM:g}, {rim:.4g}] mm: (cage width {width:.4g} mm - roller "
             "length) / 2)")
    if b < LAND_WIDTH_MIN_MM:  # the default, the rim, can be narrower
        fail("cage.land_width_mm", b, f"the default (the cage's side rim) is below "
             f"{LAND_WIDTH_MIN_MM:g} mm; give a width in [{LAND_WIDTH_MIN_MM:g}, 100] mm")
    cl = c.land_clearance_mm if c.land_clearance_mm is not None else 0.5 * pocket_clearance_mm
    if cl < LAND_CLEARANCE_MIN_MM:  # the default, half the pocket clearance, can be smaller
        fail("cage.land_clearance_mm", cl, f"the default (half the pocket clearance) is below "
             f"{LAND_CLEARANCE_MIN_MM:g} mm; give a clearance in [{LAND_CLEARANCE_MIN_MM:g}, "
             "10] mm")
    mm = 1e-3
    return ({"mass_kg": c.mass_kg, "guidance": guidance, "land_clearance_m": cl * mm,
             "land_width_m": b * mm, "land_friction": c.land_friction},
            {"guidance": guidance, "land_clearance_mm": cl, "land_width_mm": b})
