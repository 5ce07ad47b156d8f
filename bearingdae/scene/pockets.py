"""Whether the cage's pockets fit (pipeline stage 1): Z pockets of width D_w + c_p on the cage's
inner circumference (scene/parameters.py's cage annulus). A pocket clearance in µm written
into the mm key is the usual cause of a refusal.
"""

from __future__ import annotations

import math

from .errors import SceneError
from .parameters import cage_annulus


def _pocket_room_mm(rollers: int, dm_mm: float, dw_mm: float, length_mm: float) -> tuple:
    """(the largest pocket clearance [mm], the cage's inner radius [mm]) of Z pockets of width
    D_w + c_p on the cage's inner circumference (parameters.py)."""
    r_i, _, _ = cage_annulus(0.5 * dm_mm, dw_mm, length_mm)
    return 2.0 * math.pi * r_i / rollers - dw_mm, r_i


def pockets_fit(rollers: int, dm_mm: float, dw_mm: float, length_mm: float,
                 cp_mm: float) -> bool:
    """Whether a pocket clearance passes :func:`check_pockets_fit`."""
    room, _ = _pocket_room_mm(rollers, dm_mm, dw_mm, length_mm)
    return not (room > 0.0 and cp_mm >= room)


def check_pockets_fit(rollers: int, dm_mm: float, dw_mm: float, length_mm: float, cp_mm: float,
                       origin: str) -> None:
    """Z pockets of width D_w + c_p must fit the cage's inner circumference (parameters.py).

    A pocket clearance in µm written into the mm key (100 for 0.1 mm) is caught here. A bearing
    whose rollers alone fill the cage (a full complement) is left to the dynamic model, which
    needs the cage: its static solve does not.
    """
    room, r_i = _pocket_room_mm(rollers, dm_mm, dw_mm, length_mm)
    if not pockets_fit(rollers, dm_mm, dw_mm, length_mm, cp_mm):
        raise SceneError(
            f"invalid scene ({origin}):\n  - 'cage.pocket_clearance_mm' = {cp_mm!r}: {rollers} "
            f"pockets of {dw_mm:g} mm + c_p do not fit the cage's inner circumference "
            f"({2 * math.pi * r_i:.4g} mm); allowed range [0, {room:.4g}) mm." + (
                f" If it was written in µm, write {cp_mm * 1e-3:.6g}."
                if cp_mm * 1e-3 < room else ""))
