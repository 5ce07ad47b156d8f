"""Python API arguments that stand for scene keys, checked by the scene schema's own ranges
(pipeline stage 1, scene): one definition of each range for the scene file, ``--set`` and the
option classes of the solvers (``NewmarkOptions``).
"""

from __future__ import annotations

import math
import numbers

from .errors import _show
from .schema import _SECTIONS, allowed_range


def newmark_beta_min(gamma: float) -> float:
    """Smallest Newmark β that keeps the linear scheme unconditionally stable for this γ:
    β ≥ (γ + 1/2)²/4 (with γ ≥ 1/2; Hughes, The Finite Element Method, 9.1)."""
    return 0.25 * (gamma + 0.5) ** 2


def check_argument(key: str, value, argument: str):
    """A Python API argument that carries the meaning of the scene key ``key`` (e.g.
    ``NewmarkOptions.step_s`` and ``numerics.newmark_step_s``), checked against that key's type
    and range, so both are checked by the one definition above. Returns the value as the key's
    type (float, int or bool); raises TypeError (wrong type) or ValueError (not finite, out of
    range) naming ``argument``, the value (cut to ~100 characters) and the allowed range."""
    sec, _, name = key.partition(".")
    field = _SECTIONS[sec].model_fields[name]
    kinds = set(getattr(field.annotation, "__args__", (field.annotation,))) - {type(None)}
    real = isinstance(value, numbers.Real) and not isinstance(value, bool)
    rng = allowed_range(key)
    where = f" (as the scene key {key})"
    if kinds == {bool}:
        if not isinstance(value, bool) and type(value).__name__ != "bool_":
            raise TypeError(f"{argument} = {_show(value)}: expected True or False, got "
                            f"{type(value).__name__}{where}")
        return bool(value)
    if kinds == {int}:
        if not (isinstance(value, numbers.Integral) and not isinstance(value, bool)):
            raise TypeError(f"{argument} = {_show(value)}: expected an integer in {rng}, got "
                            f"{type(value).__name__}{where}")
        value = int(value)
    else:
        if not real:
            raise TypeError(f"{argument} = {_show(value)}: expected a number in {rng}, got "
                            f"{type(value).__name__}{where}")
        try:
            value = float(value)
        except OverflowError:  # an integer beyond float range
            raise ValueError(f"{argument} = {_show(value)}: outside the allowed range {rng}"
                             f"{where}") from None
        if not math.isfinite(value):
            raise ValueError(f"{argument} = {_show(value)}: must be a finite number in {rng}"
                             f"{where}")
    for c in field.metadata:
        for attr, ok in (("gt", lambda b: value > b), ("ge", lambda b: value >= b),
                         ("lt", lambda b: value < b), ("le", lambda b: value <= b)):
            bound = getattr(c, attr, None)
            if bound is not None and not ok(bound):
                raise ValueError(f"{argument} = {_show(value)}: outside the allowed range {rng}"
                                 f"{where}")
    return value
