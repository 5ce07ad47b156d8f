"""The effect switches of a scene and the keys each one alone reads (pipeline stage 1).

A switch is a key (``physics.<name>``, or ``bearing.type`` for the flanges) whose field says
in its metadata which value switches its effect on (``on``) and what the effect is called
(``effect``). A key that one effect alone reads says so in its own field's metadata
(``switch``), or its section does for all of its keys (``model_config``'s
``json_schema_extra``); ``supplied_by`` names a switch under which another law supplies the
value (the key is then left out of the complete TOML). Nothing here lists an effect's keys: the
generic rules below read them off the section models, so a new key of an effect is one field.

* :func:`refuse_unswitched`: a key given without its switch is one SceneError naming the key,
  its value and the switch to set (it would be silently unused).
* :func:`switched_resolved`: the complete TOML's values of the keys of the switches that are
  on (given, or the SI dataclass's default).
"""

from __future__ import annotations

import dataclasses

from .errors import SceneError
from .schema import _SECTIONS
from .sections.output import switch_on
from .si import Lubricant

#: the SI dataclass whose defaults a section's switched keys take when not given
_SI_DEFAULTS = {"lubricant": Lubricant}


def switch_key(switch: str) -> str:
    """The dotted key of a switch (``flange``: ``bearing.type``)."""
    return "bearing.type" if switch == "flange" else f"physics.{switch}"


def _field(key: str):
    section, _, name = key.partition(".")
    return _SECTIONS[section].model_fields[name]


def _extra(field) -> dict:
    extra = field.json_schema_extra
    return extra if isinstance(extra, dict) else {}


def switch_effect(switch: str) -> str:
    """What the effect of a switch is called in messages (its field's ``effect``)."""
    return _extra(_field(switch_key(switch))).get("effect", switch_key(switch))


def switch_fix(switch: str) -> str:
    """The words that switch it on, e.g. ``set physics.thermal = "steady"``."""
    key = switch_key(switch)
    on = _extra(_field(key)).get("on", True)
    if on is True:
        value = "true"
    elif isinstance(on, (list, tuple)):
        value = ", ".join(f'"{v}"' for v in on[:-1]) + f' or "{on[-1]}"'
    else:
        value = f'"{on}"'
    return f"set {key} = {value}"


def switched_keys() -> dict[str, dict]:
    """{dotted key: {"switch": name, "supplied_by": name or None}} of every key that one
    switch alone reads, from the section models' metadata."""
    out = {}
    for section, model in _SECTIONS.items():
        whole = (model.model_config.get("json_schema_extra") or {}).get("switch")
        for name, field in model.model_fields.items():
            extra = _extra(field)
            switch = extra.get("switch", whole)
            if switch is not None:
                out[f"{section}.{name}"] = {"switch": switch,
                                            "supplied_by": extra.get("supplied_by")}
    return out


def keys_of(switch: str) -> tuple[str, ...]:
    """The dotted keys that the switch ``switch`` alone reads."""
    return tuple(k for k, v in switched_keys().items() if v["switch"] == switch)


def _given(m, key: str):
    """The value of ``key`` in the checked input ``m`` if given (differs from its default),
    else None."""
    section, _, name = key.partition(".")
    value = getattr(getattr(m, section), name)
    return None if value == _field(key).default else value


def _current(m, switch: str) -> str:
    section, _, name = switch_key(switch).partition(".")
    value = getattr(getattr(m, section), name)
    if value is None and _extra(_field(switch_key(switch))).get("on", True) is not True:
        return "not given"  # a choice left at its default (bearing.type: no flanges)
    return "false" if value is None or value is False else repr(value)


def present_when(condition: str):
    """The :class:`~bearingdae.scene.sections.output.PresentWhen` of an output variable's
    condition (its entry of OUTPUT_VARIABLES): declared in PRESENT_WHEN, else the switch of
    that name (its field's ``on`` value)."""
    from .sections.output import PRESENT_WHEN, PresentWhen

    if condition in PRESENT_WHEN:
        return PRESENT_WHEN[condition]
    fix = switch_fix(condition)
    return PresentWhen(
        lambda m: switch_on(m.physics, condition, m.bearing), fix.removeprefix("set "),
        lambda m: f"'{switch_key(condition)}' = {_current(m, condition)} removes it", fix)


def refuse_unswitched_outputs(m, origin: str) -> None:
    """SceneError for the first of ``output.variables`` whose condition (OUTPUT_VARIABLES,
    :func:`present_when`) does not hold: the variable, why it is absent and the setting that
    would make it exist."""
    from .schema import OUTPUT_VARIABLES

    for name in m.output.variables or []:
        condition = OUTPUT_VARIABLES[name]
        if condition is None:
            continue
        rule = present_when(condition)
        if not rule.holds(m):
            raise SceneError(
                f"invalid scene ({origin}): 'output.variables' asks for '{name}' but "
                f"{rule.unmet(m)}; drop it or {rule.fix}.")


def refuse_unswitched(m, origin: str) -> None:
    """SceneError (one line: the key, its value, the switch to set) for the first key given
    without the switch that alone reads it, or given (other than 0, which switches its law
    off) where the law of a switch that is on supplies it."""
    for key, rule in switched_keys().items():
        switch, supplier = rule["switch"], rule["supplied_by"]
        value = _given(m, key)
        if value is None:
            continue
        if not switch_on(m.physics, switch, m.bearing):
            raise SceneError(
                f"invalid scene ({origin}): '{key}' = {value!r}: is read by "
                f"{switch_effect(switch)} only ('{switch_key(switch)}' = "
                f"{_current(m, switch)}); {switch_fix(switch)} or drop the key.")
        if supplier and value != 0 and switch_on(m.physics, supplier, m.bearing):
            raise SceneError(
                f"invalid scene ({origin}): '{key}' = {value!r} is given but "
                f"'{switch_key(supplier)}' = {_current(m, supplier)} supplies it "
                f"({switch_effect(supplier)}); drop it (or set 0: the law off).")


def switched_resolved(m) -> dict[str, dict]:
    """{table: {name: value}}: the keys of the switches that are on, as the complete TOML
    records them (given, or the section's SI default), but those another law supplies under
    a switch that is on; only keys with SI defaults (:data:`_SI_DEFAULTS`)."""
    out: dict[str, dict] = {}
    for key, rule in switched_keys().items():
        section, _, name = key.partition(".")
        si = _SI_DEFAULTS.get(section)
        if si is None or not switch_on(m.physics, rule["switch"], m.bearing):
            continue
        if rule["supplied_by"] and switch_on(m.physics, rule["supplied_by"], m.bearing):
            continue
        defaults = {f.name: f.default for f in dataclasses.fields(si)}
        if name not in defaults:  # resolved by its effect's own check (scene/thermal_switch.py)
            continue
        value = getattr(getattr(m, section), name)
        out.setdefault(section, {})[name] = defaults[name] if value is None else value
    return out
