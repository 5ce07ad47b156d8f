"""``physics.friction_model``: one key for the whole friction model (pipeline stage 1).

``"paper"`` (the default, also when absent): the paper's friction, every switch as the scene
sets it. ``"full"``: the friction model a user can defend against the catalogues (docs/
theory.md §19-21), i.e. the switches of :data:`FULL` (Biboulet & Houpert's rolling resistance,
with ``lubricant.inlet_film_um`` if given; mixed lubrication; the steady thermal network),
each unless the scene sets that switch itself: an explicit switch wins. The conversion
(scene/convert.py) applies it first, so the rest of the package sees ordinary switches, and
records the switches it set among the resolved values (the complete TOML states them).
"""

from __future__ import annotations

#: the switches ``friction_model = "full"`` sets ({physics key: value})
FULL = {"rolling_resistance": "biboulet_houpert", "lubrication": "mixed", "thermal": "steady"}


def apply_friction_model(m):
    """(the checked input with the switches of ``physics.friction_model`` set, {physics key:
    value} of those it set); unchanged with ``"paper"`` or without the key."""
    physics = m.physics
    if physics.friction_model != "full":
        return m, {}
    update = {k: v for k, v in FULL.items() if k not in physics.model_fields_set}
    return m.model_copy(update={"physics": physics.model_copy(update=update)}), update


def rolling_law(value) -> bool | str:
    """The SI value of ``physics.rolling_resistance``: False (off) or the law's name (``true``
    is Biboulet & Houpert's)."""
    if value is True:
        return "biboulet_houpert"
    return value or False
