"""Scene errors: :class:`SceneError` and the value printing every scene message uses.

Pipeline stage 1 (scene); the lowest module of ``bearingdae.scene``: the other modules raise
:class:`SceneError` and print offending values with :func:`_show`.
"""

from __future__ import annotations

import difflib
import math
from typing import Any, Iterable


class SceneError(ValueError):
    """A scene file or override is invalid. The message names the key, value and allowed range."""


def _show(value: Any, limit: int = 100) -> str:
    """``repr`` for messages: at most ``limit`` characters, and never raising (Python refuses
    to print integers beyond 4300 digits and values nested deeper than its recursion limit)."""
    try:
        text = repr(value)
    except ValueError:
        if not isinstance(value, int):
            raise
        text = f"<integer of about {int(value.bit_length() * math.log10(2)) + 1} digits>"
    except RecursionError:
        text = f"<{type(value).__name__} nested too deeply to print>"
    return text if len(text) <= limit else text[: limit - 4] + " ..."


def _clip(text: str, limit: int = 100) -> str:
    """Text the user typed, for a message: at most ``limit`` characters."""
    text = str(text)
    return text if len(text) <= limit else text[: limit - 4] + " ..."


def _dedupe(lines: list[str]) -> list[str]:
    seen, out = set(), []
    for line in lines:
        if line not in seen:
            seen.add(line)
            out.append(line)
    return out


def close_matches(word: Any, candidates: Iterable[str], n: int = 1,
                  cutoff: float = 0.6) -> list[str]:
    """``difflib.get_close_matches`` ignoring case: a candidate equal to ``word`` but for case
    comes first (``numerics.Atol`` -> ``numerics.atol``); the candidates are returned as
    written."""
    folded: dict[str, str] = {}
    for c in candidates:
        folded.setdefault(c.casefold(), c)
    w = str(word).casefold()
    if w in folded:
        return [folded[w]]
    return [folded[m] for m in difflib.get_close_matches(w, list(folded), n=n, cutoff=cutoff)]
