"""Slopes of the scalar laws in the analytic Jacobian's rows (system/jacobian_analytic.py):
the three drag laws, each a function of one speed, and the dynamic ring's own terms.

The drag laws (orbit drag, roller-end and cage-side churning) are tabulated piecewise in Re:
their slopes are a central difference of that one scalar function, which costs nothing next
to the slice loop.
"""

from __future__ import annotations

from numba import njit

from ..physics.lubricant import cage_side_churning, orbit_drag_force, roller_end_churning
from .param_vector import P_CRI, P_CRO, P_L, P_MUO, P_R, P_RHO, P_RM
from .residual import G_DR, G_DT, G_GR, G_GT, G_VR, G_VT, G_WR, G_WT

DRAG_RELATIVE_STEP = 1e-6


# One function per law, each inlined as numba IR into its one call site: one function with the
# law as a literal argument (``kind``) was either a specialisation per kind (compiled on its own)
# or, inlined, all three laws typed and lowered at each of its three call sites.
@njit(inline="always")
def orbit_drag_slope(speed, P):
    """Central-difference slope of the orbit drag (physics/lubricant.orbit_drag_force)."""
    h = DRAG_RELATIVE_STEP * max(abs(speed), 1.0)
    Rm, r, L = P[P_RM], P[P_R], P[P_L]
    fp = orbit_drag_force(speed + h, Rm, 2.0 * r, L, P[P_RHO], P[P_MUO])
    fm = orbit_drag_force(speed - h, Rm, 2.0 * r, L, P[P_RHO], P[P_MUO])
    return (fp - fm) / (2.0 * h)


@njit(inline="always")
def roller_end_slope(speed, P):
    """Central-difference slope of the roller-end churning (physics/lubricant.py)."""
    h = DRAG_RELATIVE_STEP * max(abs(speed), 1.0)
    fp = roller_end_churning(speed + h, P[P_R], P[P_RHO], P[P_MUO])
    fm = roller_end_churning(speed - h, P[P_R], P[P_RHO], P[P_MUO])
    return (fp - fm) / (2.0 * h)


@njit(inline="always")
def cage_side_slope(speed, P):
    """Central-difference slope of the cage-side churning (physics/lubricant.py)."""
    h = DRAG_RELATIVE_STEP * max(abs(speed), 1.0)
    fp = cage_side_churning(speed + h, P[P_CRI], P[P_CRO], P[P_RHO], P[P_MUO])
    fm = cage_side_churning(speed - h, P[P_CRI], P[P_CRO], P[P_RHO], P[P_MUO])
    return (fp - fm) / (2.0 * h)


@njit(inline="always")
def _ring_own_slope(g, h, k_sup, c_sup):
    """d(own terms of global row g)/d(global unknown h) of the dynamic ring's rows
    (residual.dynamic_ring_rows): -1 for δ' - v along v; -dF_s/dδ = k and -dF_s/dv = c
    (physics/ring.support_force) in the momentum rows."""
    if (g == G_DR and h == G_VR) or (g == G_DT and h == G_VT) or (
            g == G_GR and h == G_WR) or (g == G_GT and h == G_WT):
        return -1.0
    if (g == G_VR and h == G_DR) or (g == G_VT and h == G_DT):
        return k_sup
    if (g == G_VR and h == G_VR) or (g == G_VT and h == G_VT):
        return c_sup
    return 0.0
