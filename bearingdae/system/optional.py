"""The passes compiled apart (the roller end-flanges, system/flange.py; the cage centre,
system/whirl.py; the EHL rolling resistance, system/rolling_resistance.py; mixed lubrication,
system/mixed.py; local defects and waviness, system/defects.py) as the kernels call them: each
compiled only for a scene that has it.

Stage: system (DAE model). The work tuple ``d`` ends with a marker (system/model.py
``optional_marker``): None when the scene has none of these, else a tuple (:func:`marker_of`)
with one entry per effect in :data:`APART` order, None where the scene leaves the effect off
and True where it switches it on (told before the model is built by
system/effects.apart_pattern, from the declarations that compile apart), then the passes of the
effects registered from outside the package (system/extensions.py; None without), then the
scene's defect table (system/defects.py; None without). Each step below is a numba overload
chosen by the marker's *type*: where the marker is None, or its effect's entry is, the step is
empty, so a kernel specialised for such a scene never types or compiles that effect's passes
(docs/performance.md, "Cold start"); where its entry is True, it is the code the kernels
always ran, the pass taken where the parameters switch it on (P[P_FL] > 0.5: flanges,
P[P_WH] > 0.5: whirl, P[P_RR] > 0.5: rolling resistance, P[P_MX] > 0.5: mixed lubrication).
An entry is None exactly when its switch is off, so a specialisation skips only passes that
would not run: the same numbers, bit for bit. A defect scene thus compiles the defects' passes
and those of the effects it switches on, no others. A kernel that runs only some effects'
passes takes the marker narrowed to their entries (:func:`mixed_marker`,
:func:`defect_marker`, :func:`flange_marker`): one specialisation of it serves every pattern
that leaves those effects off.
"""

from __future__ import annotations

import numpy as np
from numba import njit, types
from numba.extending import overload

from .flange import flange_jacobian, flange_jacobian_algebraic, flange_pass
from .mixed import mixed_slopes, mixed_tractions
from .rolling_resistance import rolling_resistance_jacobian, rolling_resistance_pass
from .whirl import whirl_jacobian, whirl_pass
from .param_vector import P_FL, P_MX, P_RR, P_WH

#: the effects compiled apart, by the parameter that switches each on: the marker's entries
#: in this order (system/effects.apart_pattern gives the same from the declarations)
APART = (P_FL, P_WH, P_RR, P_MX)
FLANGE, WHIRL, ROLLING_RESISTANCE, MIXED = range(len(APART))  #: their entries in the marker
#: the marker's entry after them: the passes of the effects registered from outside the
#: package (system/extensions.py), (residual pass, Jacobian block) as jitted functions, or None
EXTENSION = len(APART)
#: its last entry: the scene's defect table (system/defects.py), or None
DEFECTS = EXTENSION + 1
LENGTH = DEFECTS + 1  #: the marker's entries


def optional_marker(P: np.ndarray, extension=None, table=None):
    """The work tuple's last entry for parameters ``P``, the extensions' passes
    ``extension`` and the defect table ``table``: :func:`marker_of` of the effects compiled
    apart that ``P`` switches on."""
    return marker_of(tuple(bool(P[i] > 0.5) for i in APART), extension, table)


def marker_of(pattern, extension=None, table=None):
    """The marker of a scene whose effects compiled apart are on as ``pattern`` says (one
    bool per entry of :data:`APART`; None: none on) with the extensions' passes
    ``extension`` and the defect table ``table`` (None: none): None when it has none of
    these, else (True or None per effect, ``extension``, ``table``)."""
    if (pattern is None or not any(pattern)) and extension is None and table is None:
        return None
    pattern = pattern or (False,) * len(APART)
    return tuple(True if on else None for on in pattern) + (extension, table)


def marker_table(marker):
    """The defect table a model's marker holds (system/defects.py), None without."""
    return None if marker is None else marker[DEFECTS]


def pattern_tag(pattern: tuple) -> str:
    """``pattern`` (one bool per effect compiled apart) as a string of 0s and 1s."""
    return "".join("1" if on else "0" for on in pattern[:EXTENSION])


def _on(entry) -> bool:
    return entry is not None and entry is not False


def variant(optional):
    """The variant of the compiled callbacks (solvers/sundials/callbacks.py) for ``optional``:
    False (nothing compiled apart), else the marker's entries as the callbacks are named and
    compiled after them: the pattern of the effects compiled apart (one bool each in
    :data:`APART` order), the extensions' passes (None: none), whether the scene has defects.
    ``optional`` is one of these, a marker (:func:`marker_of`; True in place of its defect
    table will do), a pattern alone or followed by the extensions' passes, True (every effect
    compiled apart), "defects" (defects alone) or a string of 0s and 1s
    (:func:`pattern_tag`'s), followed by "d" for the pattern with defects."""
    if optional is None or optional is False or (isinstance(optional, str)
                                                  and set(optional) <= {"0"}):
        return False
    if isinstance(optional, str):
        if optional == "defects":
            optional = (False,) * len(APART) + (None, True)
        elif optional.endswith("d"):  # pattern_tag(...) + "d": that pattern with defects
            optional = tuple(c == "1" for c in optional[:-1]) + (None, True)
        else:
            optional = tuple(c == "1" for c in optional)
    elif optional is True:
        optional = (True,) * len(APART)
    optional = tuple(optional)
    if len(optional) not in (len(APART), EXTENSION + 1, LENGTH):
        raise ValueError(f"pattern {optional!r}: one entry per effect compiled apart "
                         f"({len(APART)}), then the extensions' passes and the defects")
    pattern = tuple(_on(o) for o in optional[:EXTENSION])
    extension = optional[EXTENSION] if len(optional) > EXTENSION else None
    defects = len(optional) > DEFECTS and _on(optional[DEFECTS])
    if not any(pattern) and extension is None and not defects:
        return False
    return pattern + (extension, defects)


def apart_marker(pattern, flag, extension, table):
    """The marker of :func:`marker_of` for the literal ``pattern`` (one bool per effect
    compiled apart), the extensions' passes ``extension`` and the defect table ``table``
    (None: none), its entries ``flag`` (a run-time True, typed as the bool ``model.data``
    holds) or None: compiled code only."""
    raise NotImplementedError("compiled code only")


@njit(inline="always")
def _entry_on(flag):
    return flag


@njit(inline="always")
def _entry_off(flag):
    return None


@overload(apart_marker, inline="always", prefer_literal=True)
def _apart_marker(pattern, flag, extension, table):
    if not all(isinstance(t, types.BooleanLiteral) for t in pattern.types):
        return None  # the pattern must be a compile-time constant
    on = [t.literal_value for t in pattern.types]
    if len(on) != 4:
        raise TypeError("apart_marker: one entry per effect of APART (4)")
    a, b, c, e = (_entry_on if o else _entry_off for o in on)
    return lambda pattern, flag, extension, table: (a(flag), b(flag), c(flag), e(flag),
                                                    extension, table)


def compiles(marker, entry: int) -> bool:
    """Whether the kernels typed with ``marker`` (a numba type) compile the passes at
    ``entry`` of the marker (an effect of :data:`APART`, :data:`EXTENSION` or
    :data:`DEFECTS`): a tuple whose entry is not None."""
    return (isinstance(marker, types.BaseTuple)
            and not isinstance(marker.types[entry], types.NoneType))


def _item(k: int):
    @njit(inline="always")
    def item(marker):
        return marker[k]
    return item


@njit(inline="always")
def _no_item(marker):
    return None


_ITEMS = tuple(_item(k) for k in range(LENGTH))  #: marker[k], inlined


def _narrowing(name: str, entries: tuple, doc: str):
    """The marker narrowed to its ``entries``, as a kernel that runs only their passes takes
    it: None where the marker has none of them, else the marker with its other entries None;
    from Python and in compiled code (an overload chosen by the marker's type). Why: one
    specialisation of such a kernel then serves every pattern that leaves those entries None
    (a cold compile of a pattern reuses the default scene's, from the same process or numba's
    cache, instead of typing and compiling the same code again: the roller blocks, ~3 s of
    CPU per pattern). The code is the same: a pass the marker leaves out has none either way."""
    def narrowed(marker):
        if marker is None or all(marker[k] is None for k in entries):
            return None
        return tuple(m if k in entries else None for k, m in enumerate(marker))

    @overload(narrowed, inline="always")
    def _narrowed(marker):
        if not any(compiles(marker, k) for k in entries):
            return lambda marker: None
        a, b, c, e, f, g = (_ITEMS[k] if k in entries else _no_item for k in range(LENGTH))
        return lambda marker: (a(marker), b(marker), c(marker), e(marker), f(marker),
                               g(marker))

    narrowed.__name__ = narrowed.__qualname__ = name
    narrowed.__doc__ = doc
    return narrowed


mixed_marker = _narrowing("mixed_marker", (MIXED,), """The marker narrowed to mixed
    lubrication, as the contact passes take it (the only effect compiled apart they run).""")
defect_marker = _narrowing("defect_marker", (DEFECTS,), """The marker narrowed to the defect
    table, as the Jacobian's roller blocks take it.""")
flange_marker = _narrowing("flange_marker", (FLANGE, DEFECTS), """The marker narrowed to the
    flanges and the defects, as the algebraic Jacobian block takes it (system/
    jacobian_algebraic.py; the projection's work tuple, jacobian_algebraic.algebraic_work).""")


def extension_rows(marker, yl, ypl, yg, ypg, w_ring, P, resl, resg):
    raise NotImplementedError("compiled code only")


def extension_block(marker, yl, yg, w_ring, P, S, RS, lmap, gmap, Jd):
    raise NotImplementedError("compiled code only")


@overload(extension_rows, inline="always")
def _extension_rows(marker, yl, ypl, yg, ypg, w_ring, P, resl, resg):
    """The extensions' residual pass (system/extensions.py) where the marker has one."""
    if not compiles(marker, EXTENSION):
        return lambda marker, yl, ypl, yg, ypg, w_ring, P, resl, resg: None
    return lambda marker, yl, ypl, yg, ypg, w_ring, P, resl, resg: marker[EXTENSION][0](
        yl, ypl, yg, ypg, w_ring, P, resl, resg)


@overload(extension_block, inline="always")
def _extension_block(marker, yl, yg, w_ring, P, S, RS, lmap, gmap, Jd):
    """The extensions' Jacobian block (system/extensions.py) where the marker has one."""
    if not compiles(marker, EXTENSION):
        return lambda marker, yl, yg, w_ring, P, S, RS, lmap, gmap, Jd: None
    return lambda marker, yl, yg, w_ring, P, S, RS, lmap, gmap, Jd: marker[EXTENSION][1](
        yl, yg, w_ring, P, S, RS, lmap, gmap, Jd)


# The stubs are never called from Python; in compiled code the overloads below replace them
# (numba IR, inlined: the code of an effect switched on is what the kernels had in place).
def flange_rows(marker, yl, yg, w_ring, P, axial_load, resl, resg, contrib):
    raise NotImplementedError("compiled code only")


def whirl_rows(marker, yl, yg, ypg, w_ring, P, fp, resg):
    raise NotImplementedError("compiled code only")


def optional_jacobian(marker, yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd):
    raise NotImplementedError("compiled code only")


def flange_jacobian_block(marker, yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd):
    raise NotImplementedError("compiled code only")


@overload(flange_rows, inline="always")
def _flange_rows(marker, yl, yg, w_ring, P, axial_load, resl, resg, contrib):
    if not compiles(marker, FLANGE):
        return lambda marker, yl, yg, w_ring, P, axial_load, resl, resg, contrib: None

    def impl(marker, yl, yg, w_ring, P, axial_load, resl, resg, contrib):
        if P[P_FL] > 0.5:  # roller end-flange contacts (system/flange.py); none: skipped
            flange_pass(yl, yg, w_ring, P[P_FL:], axial_load, resl, resg, contrib,
                        np.empty((0, 4, 4)))
    return impl


@overload(whirl_rows, inline="always")
def _whirl_rows(marker, yl, yg, ypg, w_ring, P, fp, resg):
    if not compiles(marker, WHIRL):
        return lambda marker, yl, yg, ypg, w_ring, P, fp, resg: None

    def impl(marker, yl, yg, ypg, w_ring, P, fp, resg):
        if P[P_WH] > 0.5:  # the cage centre's rows (system/whirl.py); no whirl: skipped
            whirl_pass(yl, yg, ypg, w_ring, P[P_WH:], fp, resg, np.empty(0))
    return impl


@overload(optional_jacobian, inline="always")
def _optional_jacobian(marker, yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd):
    fl, wh = compiles(marker, FLANGE), compiles(marker, WHIRL)
    if fl and wh:
        def impl(marker, yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd):
            if P[P_FL] > 0.5:  # roller end-flange contacts (system/flange.py)
                flange_jacobian(yl, yg, w_ring, P[P_FL:], S, RS, lmap, gmap, mass, Jd)
            if P[P_WH] > 0.5:  # the cage centre (system/whirl.py)
                whirl_jacobian(yl, yg, w_ring, P[P_WH:], S, RS, lmap, gmap, Jd)
    elif fl:
        def impl(marker, yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd):
            if P[P_FL] > 0.5:
                flange_jacobian(yl, yg, w_ring, P[P_FL:], S, RS, lmap, gmap, mass, Jd)
    elif wh:
        def impl(marker, yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd):
            if P[P_WH] > 0.5:
                whirl_jacobian(yl, yg, w_ring, P[P_WH:], S, RS, lmap, gmap, Jd)
    else:
        def impl(marker, yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd):
            return None
    return impl


@overload(flange_jacobian_block, inline="always")
def _flange_jacobian_block(marker, yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd):
    if not compiles(marker, FLANGE):
        return lambda marker, yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd: None

    def impl(marker, yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd):
        if P[P_FL] > 0.5:  # roller end-flange contacts (system/flange.py): the same entries
            flange_jacobian_algebraic(yl, yg, w_ring, P[P_FL:], S, RS, lmap, gmap, mass, Jd)
    return impl


def _compiled_apart(pass_fn, name: str, entry: int):
    """The step ``name(marker, *args)`` for the kernels: ``pass_fn(*args)`` where the marker
    compiles the effect at ``entry`` (:func:`compiles`); no code elsewhere (``pass_fn`` then
    never typed). Not
    inlined: numba's inliner takes no ``*args``; the call costs nothing next to the pass, and
    a scene without the effect has none. The callers test the effect's switch."""
    def step(marker, *args):
        raise NotImplementedError("compiled code only")

    @overload(step)
    def _choose(marker, *args):
        if not compiles(marker, entry):
            return lambda marker, *args: None
        return lambda marker, *args: pass_fn(*args)

    step.__name__ = step.__qualname__ = name
    return step


#: EHL rolling resistance (system/rolling_resistance.py): the residual's pass, the Jacobian's
rolling_resistance_rows = _compiled_apart(rolling_resistance_pass, "rolling_resistance_rows",
                                          ROLLING_RESISTANCE)
rolling_resistance_block = _compiled_apart(rolling_resistance_jacobian,
                                           "rolling_resistance_block", ROLLING_RESISTANCE)
#: mixed lubrication (system/mixed.py), inside the contact passes' branch ``P[P_MX] > 0.5``
#: (the film and the asperities replace the traction law there): tractions, their slopes
mixed_traction_rows = _compiled_apart(mixed_tractions, "mixed_traction_rows", MIXED)
mixed_slope_rows = _compiled_apart(mixed_slopes, "mixed_slope_rows", MIXED)
