"""Local defects and waviness of the scene (pipeline stage 1; theory.md §4): the entries of
``[[defects]]`` and ``[[waviness]]`` checked against the bearing -> the SI values of
:class:`Defect` and :class:`Waviness` (the laws: physics/defects.py).

Checks (each a one-line SceneError naming the key, its value and the allowed range): a defect
no wider than the roller (its length, which the slices span), shorter than its
surface's circumference (else it is off the race: it would overlap itself), ramps at most half
its length; ``roller`` given for a roller's surface only (and there required), within
0..Z-1 (no Field bounds: the range depends on ``bearing.rollers``).

A defect or waviness on a roller brings the rollers' spin angles into the model
(system/layout.py); roller waviness is the same form error on every roller.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Defect:
    """One local defect in SI: ``surface`` "outer" | "inner" | "roller", its centre's angle on
    that surface [rad], the roller index (-1: a race), length along the rolling direction,
    width across it, depth and edge ramp [m]. ``least_ramp_m``: the ramp a sharp edge is
    smoothed over (None: physics/defects.EDGE_MIN_M); no TOML key sets it, a study of the
    least ramp itself replaces it (studies/workprecision/edges.sharper)."""

    surface: str
    angle_rad: float
    roller: int
    length_m: float
    width_m: float
    depth_m: float
    edge_m: float
    least_ramp_m: float | None = None


@dataclass(frozen=True)
class Waviness:
    """One waviness harmonic in SI: extra separation amplitude_m · cos(order φ + phase_rad)."""

    surface: str
    order: int
    amplitude_m: float
    phase_rad: float


def surface_diameters_mm(pitch_diameter_mm: float, roller_diameter_mm: float) -> dict:
    """Diameter [mm] of each rolling surface: the raceways at d_m ± D_w, the roller D_w."""
    return {"outer": pitch_diameter_mm + roller_diameter_mm,
            "inner": pitch_diameter_mm - roller_diameter_mm, "roller": roller_diameter_mm}


def roller_range(rollers: int) -> str:
    """The allowed range of a defect's ``roller`` on a bearing of ``rollers`` rollers."""
    return f"[0, {rollers - 1}] for the bearing's {rollers} rollers"


def known_ranges(data) -> dict[str, str]:
    """The dependent ranges (sections/defects.DEPENDENT_RANGES) that the raw scene ``data``
    (preset resolved) decides, by unindexed key: for the messages of the schema's own checks
    (a roller index of the wrong type), which run before the scene is converted."""
    from .messages import in_field_range

    bearing = data.get("bearing") if isinstance(data, dict) else None
    z = bearing.get("rollers") if isinstance(bearing, dict) else None
    if type(z) is not int or not in_field_range("bearing.rollers", z):
        return {}  # no valid Z (its own line says why): the range stays in terms of Z
    return {"defects.roller": roller_range(z)}


def check_defects(m, origin: str, rollers: int, pitch_diameter_mm: float,
                  roller_diameter_mm: float, roller_length_mm: float
                  ) -> tuple[tuple[Defect, ...], tuple[Waviness, ...]]:
    """(defects, waviness) in SI from the checked input ``m``; raises SceneError."""
    from .errors import SceneError

    def fail(key: str, value, rule: str):
        raise SceneError(f"invalid scene ({origin}): '{key}' = {value!r}: {rule}.")

    diameters = surface_diameters_mm(pitch_diameter_mm, roller_diameter_mm)
    mm = 1e-3
    defects = []
    for i, d in enumerate(m.defects):
        key = f"defects[{i}]"
        if d.on == "roller":
            if d.roller is None:
                raise SceneError(f"invalid scene ({origin}): '{key}.roller' is required for "
                                 f"on = \"roller\" but missing (allowed range "
                                 f"{roller_range(rollers)}).")
            if not 0 <= d.roller < rollers:
                fail(f"{key}.roller", d.roller, f"outside the allowed range "
                     f"{roller_range(rollers)}")
        elif d.roller is not None:
            fail(f"{key}.roller", d.roller, f"applies to a defect on a roller only (on = "
                 f"\"{d.on}\"); drop the key")
        if d.width_mm > roller_length_mm:
            fail(f"{key}.width_mm", d.width_mm, f"wider than the roller; allowed range "
                 f"(0, {roller_length_mm:g}] mm (the roller length)")
        around = math.pi * diameters[d.on]
        if d.length_mm >= around:
            fail(f"{key}.length_mm", d.length_mm, f"longer than the {d.on} surface's "
                 f"circumference, off the {'roller' if d.on == 'roller' else 'race'}; "
                 f"allowed range (0, {around:.4g}) mm")
        if d.edge_mm > 0.5 * d.length_mm:
            fail(f"{key}.edge_mm", d.edge_mm, f"the two ramps exceed the length; allowed range "
                 f"[0, {0.5 * d.length_mm:g}] mm (half of length_mm)")
        defects.append(Defect(d.on, math.radians(d.angle_deg),
                              -1 if d.roller is None else d.roller, d.length_mm * mm,
                              d.width_mm * mm, d.depth_um / 1e6, d.edge_mm * mm))
    waviness = []
    for i, w in enumerate(m.waviness):
        waviness.append(Waviness(w.on, w.order, w.amplitude_um / 1e6,
                                 math.radians(w.phase_deg)))
    return tuple(defects), tuple(waviness)

