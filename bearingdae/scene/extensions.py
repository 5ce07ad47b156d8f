"""The switch and keys of an effect declared outside the package (pipeline stage 1).

An effect written in the user's own module (system/extensions.register_effect) brings its
scene keys as one pydantic section (a ``_Section`` whose ``model_config`` names its switch, as
``[ring]``'s does) and its switch as one field of ``[physics]``. :func:`register_section` adds
both to the checked input (:class:`~bearingdae.scene.schema.SceneInput`, ``[physics]``) and to
the section table, so the generic rules read them as any other: an unknown key is refused
with the closest one, a key given without its switch is refused (scene/switches.py), ``--set
<section>.<key>`` works, ``bearingdae keys`` lists them. :func:`with_extensions` leaves the
section of a switch that is off out of the scene's TOML (a default scene keeps its text) and
hands the checked sections of the switches that are on to the SI scene
(``Scene.extensions``).
"""

from __future__ import annotations

import dataclasses

from pydantic.fields import FieldInfo

from .histories import _Section
from .schema import _SECTIONS, SceneInput
from .sections.output import switch_on
from .sections.physics import PhysicsInput

#: {switch: section name} of every registered section (the switch names its section)
REGISTERED: dict[str, str] = {}


def _add_field(model, name: str, annotation, info: FieldInfo) -> None:
    model.__pydantic_fields__[name] = info
    model.__annotations__[name] = annotation
    model.model_rebuild(force=True)


def register_section(switch: str, section: type[_Section], effect: str,
                     description: str) -> None:
    """Add the switch ``physics.<switch>`` (true: on; default off, left out of the TOML) and
    the section ``[<switch>]`` of the keys ``section`` declares (each read by that switch
    alone) to the scene's checked input. ``effect`` names the effect in messages."""
    if switch in REGISTERED:
        return  # (the same module imported again)
    if switch in _SECTIONS or switch in PhysicsInput.model_fields:
        raise ValueError(f"register_section: '{switch}' is already a section or a switch")
    own = (section.model_config.get("json_schema_extra") or {}).get("switch")
    if own != switch:
        raise ValueError(f"register_section: [{switch}]'s model_config must name its switch "
                         f"(json_schema_extra={{'switch': '{switch}'}}), got {own!r}")
    _add_field(PhysicsInput, switch, bool | None, FieldInfo(
        annotation=bool | None, default=None, description=description,
        json_schema_extra={"on": True, "effect": effect}))
    _add_field(SceneInput, switch, section, FieldInfo(annotation=section,
                                                      default=section()))
    # the input's default [physics] has the new switch too
    SceneInput.__pydantic_fields__["physics"].default = PhysicsInput()
    SceneInput.model_rebuild(force=True)
    _SECTIONS[switch] = section
    REGISTERED[switch] = switch


def unregister_section(switch: str) -> None:
    """Undo :func:`register_section` (a test's effect, registered for that test alone)."""
    if REGISTERED.pop(switch, None) is None:
        return
    for model, name in ((PhysicsInput, switch), (SceneInput, switch)):
        model.__pydantic_fields__.pop(name, None)
        model.__annotations__.pop(name, None)
        model.model_rebuild(force=True)
    SceneInput.__pydantic_fields__["physics"].default = PhysicsInput()
    SceneInput.model_rebuild(force=True)
    _SECTIONS.pop(switch, None)


def with_extensions(scene, m):
    """The SI scene ``scene`` of the checked input ``m`` with the registered sections whose
    switch is on (``Scene.extensions``); the sections of the switches that are off left out of
    its TOML (their keys, all at their defaults: refused otherwise by scene/switches.py)."""
    if not REGISTERED:
        return scene
    on = {}
    for switch, section in REGISTERED.items():
        if switch_on(m.physics, switch):
            on[switch] = getattr(m, section)
        else:
            scene.source.pop(section, None)
    return dataclasses.replace(scene, extensions=on) if on else scene
