"""Dotted-key overrides (``--set operating.radial_load_N=400``) and unknown-key messages.

Pipeline stage 1 (scene): applied to the parsed TOML dict before validation; unknown sections
and keys are reported with the closest valid key (``Did you mean ...?``).
"""

from __future__ import annotations

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


def _apply_override(data: dict, key: str, value: Any, origin: str | None = None) -> None:
    what = "--set key" if origin else "override"
    if not isinstance(key, str):
        raise SceneError(f"override key {_show(key)} must be a dotted string such as "
                         "'operating.radial_load_N'")
    parts = key.split(".")
    if len(parts) == 1 and parts[0] == "title":
        data["title"] = value
        return
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
