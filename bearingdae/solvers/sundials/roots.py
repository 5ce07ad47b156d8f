"""IDA's root function for sharp defect edges, a compiled C callback (numba ``cfunc``).

Stage: solvers (compiled IDA core). With ``numerics.defect_edges = "locate"`` (system/
defect_sides.py) IDA watches, after every step, the gaps between each roller's contact and the
edges of each sharp defect; SUNDIALS calls

    IDARootFn: int g(sunrealtype t, N_Vector yy, N_Vector yp, sunrealtype* gout,
                     void* user_data)

with the same ``user_data`` as the residual (callbacks.py): the roller's orbit and spin angles
are unpacked from the scaled state (the work tuple's scales and local map), the shaft angle is
computed at t (the ring speed law's points), and system/defect_sides.edge_gaps writes the
gaps. Compiled only for a scene with such a defect (:func:`compiled`): a scene without
defects, or with "smooth", never types or loads it.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numba import cfunc, types

from ...physics.loads import shaft_angle
from ...system.defect_sides import edge_gaps
from ...system.layout import LOCAL, SPIN_ANGLE
from .callbacks import S_I, S_IN, S_N, S_OFF, _nvector, _slots, _table, _w1, _w2, _wi
from .memory import address, f64_at, i64_at

#: IDARootFn's C signature
ROOT_SIG = types.int32(types.float64, types.voidptr, types.voidptr, types.voidptr,
                       types.voidptr)
A_TH, A_PHI = LOCAL.index("azimuth"), LOCAL.index(SPIN_ANGLE)


def _edge_roots(t, yy, yp, gout, ud):
    U = _slots(ud)
    n, off = U[S_N], U[S_OFF]
    y = _nvector(yy, off, n)
    I = i64_at(U[S_I], (U[S_IN],))
    S, lmap = _w1(U, I, 3), _wi(U, I, 5)  # the work tuple's unknown scales and local map
    Z = _w2(U, I, 9).shape[0]  # (its per-roller unknowns: Z rows)
    nl = lmap.shape[0]
    th, phi = np.zeros(Z), np.zeros(Z)
    for j in range(Z):
        for a in range(nl):
            i = j * nl + a
            if lmap[a] == A_TH:
                th[j] = y[i] * S[i]
            elif lmap[a] == A_PHI:
                phi[j] = y[i] * S[i]
    D = _table(ud)
    shaft = shaft_angle(t, _w1(U, I, 7), _w1(U, I, 8))  # ramp_t, ramp_w
    k = edge_gaps(D, th, phi, shaft, np.zeros(0))
    edge_gaps(D, th, phi, shaft, f64_at(address(gout), (k,)))
    return 0


@lru_cache(maxsize=None)
def compiled():
    """The root function's C callback, compiled on first use (or loaded from numba's cache)."""
    return cfunc(ROOT_SIG, cache=True, error_model="numpy")(_edge_roots)
