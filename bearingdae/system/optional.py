"""The passes of the optional bodies (roller end-flanges, system/flange.py; the cage centre,
system/whirl.py) as the kernels call them: compiled only for a scene that assembles them.

Stage: system (DAE model). The work tuple ``d`` ends with a marker (system/model.py
``optional_marker``): None when the scene has neither flanges nor a whirling cage, True
otherwise (told before the model is built by system/effects.scene_has_optional, from the
declarations that compile apart). Each step below is a numba overload chosen by the marker's *type*: for None it is
empty, so a kernel specialised for such a scene never types or compiles the flange and whirl
passes (a default run compiles ~11 s of CPU less: docs/performance.md, "Cold start"); for
True it is the code the kernels always ran, the pass taken where the parameters switch it
on (P[P_FL] > 0.5: flanges, P[P_WH] > 0.5: whirl). The marker is None exactly when both
switches are off, so the None specialisation skips only passes that would not run: the same
numbers, bit for bit.
"""

from __future__ import annotations

import numpy as np
from numba import types
from numba.extending import overload

from .flange import (FLANGE_PARAM_NAMES, P_FLANGE_OFFSET, flange_jacobian,
                     flange_jacobian_algebraic, flange_pass)
from .whirl import whirl_jacobian, whirl_pass

P_FL = P_FLANGE_OFFSET  #: the flange parameters P[P_FL:], P[P_FL] > 0.5: flanges
P_WH = P_FL + len(FLANGE_PARAM_NAMES)  #: the whirl parameters P[P_WH:], P[P_WH] > 0.5: whirl


def optional_marker(P: np.ndarray):
    """The work tuple's last entry for parameters ``P``: None when neither optional body is
    switched on, else True."""
    return True if (P[P_FL] > 0.5 or P[P_WH] > 0.5) else None


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
