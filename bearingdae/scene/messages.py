"""Validation messages: pydantic errors -> one line per key with value, range and unit hint.

Pipeline stage 1 (scene): :func:`_format_validation` turns a pydantic ``ValidationError`` into the
text of a :class:`~bearingdae.scene.errors.SceneError`; :func:`_unit_hint` suggests the fix when an
out-of-range value fits the range in a commonly slipped unit (metres written into ``_mm``).
"""

from __future__ import annotations

import math
import re
import typing
from typing import Any

from pydantic import ValidationError

from .errors import _dedupe, _show
from .schema import _SECTIONS, ARRAY_SECTIONS, allowed_range

#: The table members of union keys (a number or a table): their names appear in error locations.
_TABLES = {"SpeedRamp", "LoadTable", "MomentTable"}


def _format_validation(exc: ValidationError, origin: str,
                       known: dict[str, str] | None = None) -> str:
    """The message of ``exc``; ``known``: ranges that depend on another key, by unindexed key
    (``"defects.roller"``), as the scene decides them (scene/defects.known_ranges)."""
    lines = [f"invalid scene ({origin}):"]
    known = known or {}
    errors = exc.errors()
    # A union (speed_rpm: float | SpeedRamp) reports every member; keep the member the input
    # was meant for: a table -> the ramp's errors, anything else -> the number's.
    ramp = [e for e in errors if _TABLES & set(e["loc"])]
    if ramp and len(ramp) < len(errors):
        meant_ramp = {tuple(p for p in e["loc"] if p not in _TABLES)[:2]
                      for e in ramp if e["type"] != "model_type"}
        errors = [e for e in errors if not (
            (_TABLES & set(e["loc"]) and e["type"] == "model_type")
            or ("float" in e["loc"] and tuple(e["loc"][:2]) in meant_ramp))]
    for err in errors:
        # Union members (float | SpeedRamp) add their type name to the location: drop it.
        parts = [str(p) for p in err["loc"] if p not in {"float", "int", "str"} | _TABLES]
        if len(parts) > 2 and parts[0] in ARRAY_SECTIONS and parts[1].isdigit():
            parts = [f"{parts[0]}[{parts[1]}]", *parts[2:]]  # defects[0].depth_um
        loc = ".".join(parts)
        value = _show(err.get("input"))
        msg = err["msg"].removeprefix("Value error, ")
        rng = known.get(re.sub(r"\[\d+\]", "", loc)) or allowed_range(loc)
        rng = f" (allowed range {rng})" if rng else ""
        if err["type"] == "missing":
            choices = _choices(loc)
            allowed = rng or (f" (allowed: {choices})" if choices else "")
            lines.append(f"  - '{loc}' is required but missing{allowed}.")
        elif err["type"] == "finite_number":
            lines.append(f"  - '{loc}' = {value}: must be a finite number, not NaN or inf{rng}.")
        elif err["type"] in ("float_type", "int_type", "string_type", "bool_type", "model_type",
                             "int_from_float", "literal_error", "list_type", "dict_type"):
            lines.append(f"  - '{loc}' = {value}: wrong type or value; {msg[0].lower() + msg[1:]}"
                         f"{rng}.")
        else:
            if err["type"] in _RANGE_ERRORS and rng:
                # pydantic prints bounds as 0.00000000000001; the range says it once, as 1e-14.
                lines.append(f"  - '{loc}' = {value}: outside the allowed range "
                             f"{allowed_range(loc)}."
                             f"{_unit_hint(loc, err.get('input'))}")
                continue
            lines.append(f"  - '{loc}' = {value}: {msg[0].lower() + msg[1:].rstrip('.')}{rng}.")
    return "\n".join(_dedupe(lines))


def _choices(loc: str) -> str:
    """"'outer', 'inner' or 'roller'" for a Literal key, ``""`` for any other."""
    sec, _, name = loc.partition(".")
    model = ARRAY_SECTIONS.get(sec.partition("[")[0]) or _SECTIONS.get(sec)
    field = model.model_fields.get(name) if model is not None else None
    if field is None or typing.get_origin(field.annotation) is not typing.Literal:
        return ""
    values = [repr(v) for v in typing.get_args(field.annotation)]
    return values[0] if len(values) == 1 else f"{', '.join(values[:-1])} or {values[-1]}"


_RANGE_ERRORS = ("greater_than", "greater_than_equal", "less_than", "less_than_equal")

#: Unit suffix of a key name -> (unit a value is often written in by mistake, factor from that
#: unit to the key's unit). Used to suggest the fix when a value is out of range.
UNIT_NAMES = {"_mm": "mm", "_um": "µm", "_nm": "nm", "_GPa": "GPa", "_kg_m3": "kg/m³",
              "_Pa_s": "Pa s"}
UNIT_SLIPS = {
    "_mm": (("m", 1e3), ("µm", 1e-3)),
    "_um": (("m", 1e6), ("mm", 1e3), ("nm", 1e-3)),
    "_nm": (("m", 1e9), ("µm", 1e3)),
    "_GPa": (("Pa", 1e-9), ("MPa", 1e-3)),
    "_kg_m3": (("g/cm³", 1e3),),
    "_Pa_s": (("mPa s (cP)", 1e-3),),
}


def in_field_range(key: str, value: float) -> bool:
    """True when ``value`` satisfies the Field bounds of the dotted ``key``."""
    sec, _, name = key.partition(".")
    for c in _SECTIONS[sec].model_fields[name].metadata:
        for attr, ok in (("gt", lambda b: value > b), ("ge", lambda b: value >= b),
                         ("lt", lambda b: value < b), ("le", lambda b: value <= b)):
            bound = getattr(c, attr, None)
            if bound is not None and not ok(bound):
                return False
    return True


def _unit_hint(key: str, value: Any) -> str:
    """' The key is in mm: 0.004 m is 4 mm.' when ``value`` fits the range in a slipped unit."""
    sec, _, name = key.partition(".")
    if sec not in _SECTIONS or name not in _SECTIONS[sec].model_fields:
        return ""
    if not isinstance(value, (int, float)) or isinstance(value, bool):
        return ""
    try:
        v = float(value)
    except OverflowError:  # an integer beyond float range: no unit makes it fit
        return ""
    if not math.isfinite(v):
        return ""
    for suffix, slips in UNIT_SLIPS.items():
        if name.endswith(suffix):
            unit = UNIT_NAMES[suffix]
            for wrong, factor in slips:
                fixed = v * factor
                if in_field_range(key, fixed):
                    return (f" The key is in {unit}: if {_show(value)} is in {wrong}, write "
                            f"{fixed:.6g}.")
    return ""
