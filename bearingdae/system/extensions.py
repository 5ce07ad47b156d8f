"""Effects declared outside the package: one law and one declaration in the user's own module
(system layer; docs/adding-an-effect.md).

:func:`register_effect` takes an :class:`~bearingdae.system.effect.Effect` and hands it to the
generic machinery, no file of the package changed:

* its switch ``physics.<switch>`` and its keys, the pydantic section ``[<switch>]`` it declares
  (``section``; scene/extensions.py): refused without the switch, left out of the scene's TOML
  while the switch is off;
* its parameters, after every other's in the kernel's parameter vector
  (system/effects.param_names); ``parameters(scene, geometry, context)`` gives their values;
* its passes, ``passes = (rows, block)``, two numba-jitted functions the kernels call where
  the scene switches the effect on (the work tuple's marker, system/optional.py):

  - ``rows(yl, ypl, yg, ypg, w_ring, PE, resl, resg)`` adds its terms to the full residual
    rows, per roller ``resl`` (Z, len(LOCAL)) and global ``resg`` (len(GLOBAL)), from the
    unscaled full states (system/layout.py's LOCAL and GLOBAL order), the inner ring's speed
    [rad/s] and its own parameters ``PE``; it runs after every other pass, so it adds (+=);
  - ``block(yl, yg, w_ring, PE, S, RS, lmap, gmap, Jd)`` adds the derivatives of those terms
    to the scaled iteration matrix Jd (compact rows and columns: d(row)/d(column) times
    S[column] / RS[row]; ``lmap``/``gmap`` give each compact unknown's full index). Its terms
    must leave the algebraic rows alone (the projection onto them does not call it);
* its power sources with their heat partition, ``power``, its output variables
  (``variables``: {name: (dims after time, units, long_name)}, their values from ``values``).

A scene with such an effect compiles its own kernels (numba cannot cache code that calls the
user's functions: every process compiles them once; numba calls such first-class functions
experimental) and cannot have defects or waviness.
"""

from __future__ import annotations

import warnings
from functools import lru_cache

from numba import NumbaExperimentalFeatureWarning, njit

from . import effects
from .effect import Effect


def register_effect(effect: Effect) -> Effect:
    """Register ``effect`` (see the module's docstring); returns it. Registering the same
    declaration again (its module imported twice) does nothing."""
    from ..scene.extensions import register_section
    from ..scene.sections.output import OUTPUT_VARIABLES

    if effect in effects.EXTENSIONS:
        return effect
    taken = {e.name for e in effects.EFFECTS}
    if effect.name in taken or effect.switch is None or effect.section is None:
        raise ValueError(f"register_effect: '{effect.name}' needs a name of its own (taken: "
                         f"{sorted(taken)}), a switch and the section of its keys")
    clash = set(effect.params) & set(effects.param_names())
    if clash or len(effect.passes) != 2 or effect.unknowns or effect.compiled_apart:
        raise ValueError(f"register_effect: '{effect.name}' needs parameters of its own "
                         f"(taken: {sorted(clash)}), passes = (rows, block) and no unknowns")
    register_section(effect.switch, effect.section, effect.name, effect.switch_description)
    # the kernels call its passes as first-class functions, which numba calls experimental at
    # every compilation: said once here, in the docs, not in every run's output
    warnings.filterwarnings("ignore", message=".*First-class function type feature",
                            category=NumbaExperimentalFeatureWarning)
    for name in effect.variables or {}:
        OUTPUT_VARIABLES[name] = effect.switch
    effects.add_extension(effect)
    return effect


def unregister_effect(effect: Effect) -> None:
    """Undo :func:`register_effect` (a test's effect, registered for that test alone)."""
    from ..scene.extensions import unregister_section
    from ..scene.sections.output import OUTPUT_VARIABLES

    if effect not in effects.EXTENSIONS:
        return
    effects.remove_extension(effect)
    for name in effect.variables or {}:
        OUTPUT_VARIABLES.pop(name, None)
    unregister_section(effect.switch)


def marker_entry(scene):
    """The extensions' passes of a scene, as the kernels call them (system/optional.py's
    marker, its entry ``EXTENSION``): (rows, block) of every extension the scene switches on, each
    with its own parameters; None without."""
    on = tuple(e for e in effects.EXTENSIONS if effects.is_on(e, scene))
    if not on:
        return None
    if scene.defects or scene.waviness:
        raise ValueError(f"the effect '{on[0].name}' (registered from outside the package) "
                         "cannot run with defects or waviness; leave one of them off")
    return _composed(tuple((e.passes, effects.param_slice(e).start) for e in on))


@lru_cache(maxsize=None)
def _composed(passes: tuple) -> tuple:
    """(rows, block) calling each extension's own with its parameters P[start:], in order:
    the same functions for the same extensions (the kernels then compile once)."""
    rows = block = None
    for (own_rows, own_block), start in passes:
        rows, block = _then_rows(rows, own_rows, start), _then_block(block, own_block, start)
    return rows, block


def _then_rows(before, own, start):
    if before is None:
        @njit
        def rows(yl, ypl, yg, ypg, w_ring, P, resl, resg):
            own(yl, ypl, yg, ypg, w_ring, P[start:], resl, resg)
    else:
        @njit
        def rows(yl, ypl, yg, ypg, w_ring, P, resl, resg):
            before(yl, ypl, yg, ypg, w_ring, P, resl, resg)
            own(yl, ypl, yg, ypg, w_ring, P[start:], resl, resg)
    return rows


def _then_block(before, own, start):
    if before is None:
        @njit
        def block(yl, yg, w_ring, P, S, RS, lmap, gmap, Jd):
            own(yl, yg, w_ring, P[start:], S, RS, lmap, gmap, Jd)
    else:
        @njit
        def block(yl, yg, w_ring, P, S, RS, lmap, gmap, Jd):
            before(yl, yg, w_ring, P, S, RS, lmap, gmap, Jd)
            own(yl, yg, w_ring, P[start:], S, RS, lmap, gmap, Jd)
    return block
