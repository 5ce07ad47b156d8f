"""numba's compiler flags compared without rebuilding their dicts: numba's answers, less CPU.

Stage: util, applied once by physics/compiled.py before any kernel compiles; no physics here.

While it types a kernel, numba looks up each call's overload in a cache keyed by (typing
context, argument types, keyword types, compiler flags) (numba/core/typing/templates.py
``_get_impl``). A key's hash and equality test build ``values()``, a dict of every option
read through its property, twice per test: ~45 000 hashes and ~60 000 tests at a cold start,
~4 % of the compile CPU (docs/performance.md, "Cold start"). Here both give numba's own
answers faster:

- ``__hash__`` is ``hash(tuple(sorted(self.values())))``: sorting a dict sorts its keys, the
  names of the class's options, so the hash is one number per class; it is computed once.
- ``__eq__`` compares ``values()`` of both; an option not set reads as its default (the
  property numba's metaclass generates), so two configurations of one class are equal
  exactly when their set values, completed by the defaults, are. Another class (or a class
  whose option properties are not numba's own) takes numba's comparison.

Nothing else of numba changes; the flags, and so the machine code and the cache keys, are the
same (the cache indexes by the flags' ``summary``, not by their hash).
"""

from __future__ import annotations

from numba.core import targetconfig

_Config = targetconfig.TargetConfig
_numba_hash, _numba_eq = _Config.__hash__, _Config.__eq__
_hashes: dict[type, int] = {}
_defaults: dict[type, dict | None] = {}


def _class_defaults(cls) -> dict | None:
    """{option: default} of ``cls`` when every option reads through numba's generated
    property (``self._values.get(name, default)``), else None."""
    try:
        return _defaults[cls]
    except KeyError:
        pass
    out = {}
    for name, option in cls.options.items():
        prop = getattr(cls, name, None)
        if not (isinstance(prop, property) and prop.fget is not None
                and prop.fget.__qualname__.endswith("make_prop.<locals>.getter")):
            out = None
            break
        out[name] = option.default
    _defaults[cls] = out
    return out


def _hash(self) -> int:
    cls = type(self)
    try:
        return _hashes[cls]
    except KeyError:
        h = _hashes[cls] = _numba_hash(self)
        return h


def _eq(self, other):
    cls = type(self)
    if type(other) is not cls:
        return _numba_eq(self, other)
    # another numba may keep its values elsewhere: its own comparison then
    a, b = getattr(self, "_values", None), getattr(other, "_values", None)
    if not (isinstance(a, dict) and isinstance(b, dict)):
        return _numba_eq(self, other)
    if a == b:
        return True
    defaults = _class_defaults(cls)
    if defaults is None:
        return _numba_eq(self, other)
    return {**defaults, **a} == {**defaults, **b}  # values(): the same dicts


def apply() -> None:
    """Install the comparison (idempotent)."""
    _Config.__hash__ = _hash
    _Config.__eq__ = _eq
