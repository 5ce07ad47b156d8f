"""The passes compiled apart (the roller end-flanges, system/flange.py; the cage centre,
system/whirl.py; the EHL rolling resistance, system/rolling_resistance.py; mixed lubrication,
system/mixed.py) as the kernels call them: compiled only for a scene that switches one on.

Stage: system (DAE model). The work tuple ``d`` ends with a marker (system/model.py
``optional_marker``): None when the scene switches none of these effects on, True otherwise
(told before the model is built by system/effects.scene_has_optional, from the declarations
that compile apart). Each step below is a numba overload chosen by the marker's *type*: for
None it is empty, so a kernel specialised for such a scene never types or compiles those
passes (docs/performance.md, "Cold start"); for True it is the code the kernels always ran,
each pass taken where the parameters switch it on (P[P_FL] > 0.5: flanges, P[P_WH] > 0.5:
whirl, P[P_RR] > 0.5: rolling resistance, P[P_MX] > 0.5: mixed lubrication). The marker is
None exactly when every one of these switches is off, so the None specialisation skips only
passes that would not run: the same numbers, bit for bit. (One "on" type for the four: a
scene with one of them compiles the others' passes too, as a scene with defects does.)
"""

from __future__ import annotations

import numpy as np
from numba import types
from numba.extending import overload

from .flange import (FLANGE_PARAM_NAMES, P_FLANGE_OFFSET, flange_jacobian,
                     flange_jacobian_algebraic, flange_pass)
from .mixed import mixed_slopes, mixed_tractions
from .rolling_resistance import (RR_PARAM_NAMES, rolling_resistance_jacobian,
                                 rolling_resistance_pass)
from .whirl import WHIRL_PARAM_NAMES, whirl_jacobian, whirl_pass

P_FL = P_FLANGE_OFFSET  #: the flange parameters P[P_FL:], P[P_FL] > 0.5: flanges
P_WH = P_FL + len(FLANGE_PARAM_NAMES)  #: the whirl parameters P[P_WH:], P[P_WH] > 0.5: whirl
P_RR = P_WH + len(WHIRL_PARAM_NAMES)  #: the rolling resistance's P[P_RR:], P[P_RR] > 0.5: on
P_MX = P_RR + len(RR_PARAM_NAMES)  #: mixed lubrication's P[P_MX:], P[P_MX] > 0.5: mixed


def optional_marker(P: np.ndarray):
    """The work tuple's last entry for parameters ``P``: None when no effect compiled apart
    is switched on, else True."""
    return True if any(P[i] > 0.5 for i in (P_FL, P_WH, P_RR, P_MX)) else None


def _none(marker) -> bool:
    return isinstance(marker, types.NoneType)


# The stubs are never called from Python; in compiled code the overloads below replace them
# (numba IR, inlined: the code of the True case is what the kernels had in place).
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
    if _none(marker):
        return lambda marker, yl, yg, w_ring, P, axial_load, resl, resg, contrib: None

    def impl(marker, yl, yg, w_ring, P, axial_load, resl, resg, contrib):
        if P[P_FL] > 0.5:  # roller end-flange contacts (system/flange.py); none: skipped
            flange_pass(yl, yg, w_ring, P[P_FL:], axial_load, resl, resg, contrib,
                        np.empty((0, 4, 4)))
    return impl


@overload(whirl_rows, inline="always")
def _whirl_rows(marker, yl, yg, ypg, w_ring, P, fp, resg):
    if _none(marker):
        return lambda marker, yl, yg, ypg, w_ring, P, fp, resg: None

    def impl(marker, yl, yg, ypg, w_ring, P, fp, resg):
        if P[P_WH] > 0.5:  # the cage centre's rows (system/whirl.py); no whirl: skipped
            whirl_pass(yl, yg, ypg, w_ring, P[P_WH:], fp, resg, np.empty(0))
    return impl


@overload(optional_jacobian, inline="always")
def _optional_jacobian(marker, yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd):
    if _none(marker):
        return lambda marker, yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd: None

    def impl(marker, yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd):
        if P[P_FL] > 0.5:  # roller end-flange contacts (system/flange.py)
            flange_jacobian(yl, yg, w_ring, P[P_FL:], S, RS, lmap, gmap, mass, Jd)
        if P[P_WH] > 0.5:  # the cage centre (system/whirl.py)
            whirl_jacobian(yl, yg, w_ring, P[P_WH:], S, RS, lmap, gmap, Jd)
    return impl


@overload(flange_jacobian_block, inline="always")
def _flange_jacobian_block(marker, yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd):
    if _none(marker):
        return lambda marker, yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd: None

    def impl(marker, yl, yg, w_ring, P, S, RS, lmap, gmap, mass, Jd):
        if P[P_FL] > 0.5:  # roller end-flange contacts (system/flange.py): the same entries
            flange_jacobian_algebraic(yl, yg, w_ring, P[P_FL:], S, RS, lmap, gmap, mass, Jd)
    return impl


def _compiled_apart(pass_fn, name: str):
    """The step ``name(marker, *args)`` for the kernels: ``pass_fn(*args)`` where the marker is
    True or a defect table; no code where it is None (``pass_fn`` then never typed). Not
    inlined: numba's inliner takes no ``*args``; the call costs nothing next to the pass, and
    a scene without the effect has none. The callers test the effect's switch."""
    def step(marker, *args):
        raise NotImplementedError("compiled code only")

    @overload(step)
    def _choose(marker, *args):
        if _none(marker):
            return lambda marker, *args: None
        return lambda marker, *args: pass_fn(*args)

    step.__name__ = step.__qualname__ = name
    return step


#: EHL rolling resistance (system/rolling_resistance.py): the residual's pass, the Jacobian's
rolling_resistance_rows = _compiled_apart(rolling_resistance_pass, "rolling_resistance_rows")
rolling_resistance_block = _compiled_apart(rolling_resistance_jacobian,
                                           "rolling_resistance_block")
#: mixed lubrication (system/mixed.py), inside the contact passes' branch ``P[P_MX] > 0.5``
#: (the film and the asperities replace the traction law there): tractions, their slopes
mixed_traction_rows = _compiled_apart(mixed_tractions, "mixed_traction_rows")
mixed_slope_rows = _compiled_apart(mixed_slopes, "mixed_slope_rows")
