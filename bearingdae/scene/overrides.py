"""Dotted-key overrides (``--set operating.radial_load_N=400``) and unknown-key messages.

Pipeline stage 1 (scene): applied to the parsed TOML dict before validation; unknown sections
and keys are reported with the closest valid key (``Did you mean ...?``).
"""

from __future__ import annotations

import re
from typing import Any, Mapping

import numpy as np

from .errors import SceneError, _clip, _show, close_matches
from .schema import _SECTIONS, ARRAY_SECTIONS, valid_keys
from .titles import DEFAULT_TITLE

def _title_with_overrides(title: Any, overrides: Mapping[str, Any]) -> Any:
    """The title followed by the values set: ``"harris36: 12 kN [set: operating.radial_load_N
    = 8000]"`` (a case title states its case's values; with overrides they no longer hold)."""
    if not isinstance(title, str):
        title = DEFAULT_TITLE if title is None else title
        if not isinstance(title, str):
            return title  # not a string: the validator names it
    def shown(v: Any) -> str:
        if isinstance(v, float):
            return f"{v:g}"
        return v if isinstance(v, str) else _show(v, 40)
    return f"{title} [set: " + ", ".join(f"{k} = {shown(v)}" for k, v in overrides.items()) + "]"


#: a key of one entry of an array of tables: ``defects[0].depth_um``
_ENTRY_KEY = re.compile(r"^([a-z_]+)\[(\d+)\]\.([A-Za-z0-9_]+)$")


def entry_key(key: str) -> tuple[str, int, str] | None:
    """``("defects", 0, "depth_um")`` for ``"defects[0].depth_um"``, a key of one entry of an
    array of tables; None for any other key (an unknown key name included: the caller's
    unknown-key message names it)."""
    m = _ENTRY_KEY.match(key) if isinstance(key, str) else None
    if m is None or m.group(1) not in ARRAY_SECTIONS:
        return None
    sec, index, name = m.group(1), int(m.group(2)), m.group(3)
    return (sec, index, name) if name in ARRAY_SECTIONS[sec].model_fields else None


def field_of(key: str):
    """The pydantic field of a dotted key (``operating.speed_rpm``, ``defects[0].depth_um``),
    None if there is none."""
    entry = entry_key(key)
    if entry is not None:
        return ARRAY_SECTIONS[entry[0]].model_fields[entry[2]]
    sec, _, name = key.partition(".")
    model = _SECTIONS.get(sec)
    return None if model is None else model.model_fields.get(name)


def _apply_entry_override(data: dict, key: str, value: Any) -> None:
    """Set one key of an existing entry of an array of tables (``defects[0].depth_um``)."""
    sec, index, name = entry_key(key)
    entries = data.get(sec, [])
    if not isinstance(entries, list) or not 0 <= index < len(entries) \
            or not isinstance(entries[index], dict):
        count = len(entries) if isinstance(entries, list) else 0
        have = f"indices 0..{count - 1}" if count else "none"
        raise SceneError(f"'{_clip(key)}': the scene has {count} [[{sec}]] "
                         f"entr{'y' if count == 1 else 'ies'} ({have}); a key can be set only "
                         f"on an entry the scene file gives")
    data[sec] = [dict(e) if isinstance(e, dict) else e for e in entries]
    data[sec][index][name] = value.item() if isinstance(value, np.generic) else value


def _apply_override(data: dict, key: str, value: Any, origin: str | None = None) -> None:
    what = "--set key" if origin else "override"
    if not isinstance(key, str):
        raise SceneError(f"override key {_show(key)} must be a dotted string such as "
                         "'operating.radial_load_N'")
    if entry_key(key) is not None:
        _apply_entry_override(data, key, value)
        return
    parts = key.split(".")
    if len(parts) == 1 and parts[0] in ("title", *ARRAY_SECTIONS):
        data[key] = value  # a whole array of tables: [] removes every entry (the validator
        return             # checks a list given here as one written in the file)
    if len(parts) != 2 or parts[0] not in _SECTIONS:
        raise SceneError(_unknown_message(key, what))
    sec, name = parts
    if name not in _SECTIONS[sec].model_fields:
        raise SceneError(_unknown_message(key, what))
    if isinstance(value, np.generic):
        value = value.item()
    data.setdefault(sec, {})
    if not isinstance(data[sec], dict):
        raise SceneError(f"[{sec}] must be a table, got {_show(data[sec])}")
    data[sec][name] = value


def _unknown_message(key: str, what: str = "key") -> str:
    sec, dot, name = key.partition(".")
    shown = _clip(key)  # the key as typed, cut for the message
    if dot and sec in _SECTIONS:  # a known section: suggest one of its keys, not the section
        names = list(_SECTIONS[sec].model_fields)
        close = close_matches(name, names, n=1, cutoff=0.5)
        hint = (f" Did you mean '{sec}.{close[0]}'?" if close else
                f" [{sec}] has: {', '.join(f'{sec}.{n}' for n in names)}.")
        return f"unknown {what} '{shown}'.{hint} Every key: bearingdae keys."
    if not dot and sec in _SECTIONS:  # a whole section (a nested table): name its keys,
        names = list(_SECTIONS[sec].model_fields)  # never the section itself as the fix
        return (f"unknown {what} '{shown}': [{sec}] is a section, set one key of it at a time, "
                f"e.g. '{sec}.{names[0]}' ([{sec}] has: "
                f"{', '.join(f'{sec}.{n}' for n in names)}). Every key: "
                "bearingdae keys.")
    close = [k for k in close_matches(key, valid_keys(), n=2, cutoff=0.5) if k != key][:1]
    if not close:  # same key name in the wrong section?
        leaf = key.split(".")[-1]
        close = [k for k in valid_keys() if k.split(".")[-1] == leaf][:1]
    hint = f" Did you mean '{close[0]}'?" if close else ""
    return f"unknown {what} '{shown}'.{hint} Every key: bearingdae keys."


def _check_unknown(data: Mapping[str, Any]) -> None:
    problems = []
    for sec, body in data.items():
        if sec == "title":
            continue
        if sec in ARRAY_SECTIONS:
            problems += _unknown_in_array(sec, body)
            continue
        if sec not in _SECTIONS:
            problems.append(_unknown_message(str(sec), "section"))
            continue
        if not isinstance(body, dict):
            problems.append(f"[{sec}] must be a table of keys, got {_show(body)}")
            continue
        for k in body:
            if k not in _SECTIONS[sec].model_fields:
                problems.append(_unknown_message(f"{sec}.{k}"))
    if problems:
        raise SceneError("\n".join(problems))


def _unknown_in_array(sec: str, body: Any) -> list[str]:
    """The problems of an array of tables (``[[defects]]``): not a list of tables, or an
    unknown key in an entry (with the closest key of the entry's model)."""
    if not isinstance(body, list) or not all(isinstance(e, dict) for e in body):
        return [f"[[{sec}]] must be an array of tables ([[{sec}]] headers, one per entry), "
                f"got {_show(body)}"]
    names = list(ARRAY_SECTIONS[sec].model_fields)
    out = []
    for i, entry in enumerate(body):
        for k in entry:
            if k not in names:
                close = close_matches(k, names, n=1, cutoff=0.5)
                hint = (f" Did you mean '{sec}[{i}].{close[0]}'?" if close else
                        f" [[{sec}]] has: {', '.join(names)}.")
                out.append(f"unknown key '{sec}[{i}].{_clip(str(k))}'.{hint}")
    return out
