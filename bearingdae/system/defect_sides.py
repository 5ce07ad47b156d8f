"""Sharp defect edges located by IDA's root finding (``numerics.defect_edges = "locate"``).

Stage: system (DAE model). With "smooth" (the default) every defect edge is a C¹ ramp of at
least physics/defects.EDGE_MIN_M and nothing here is used. With "locate", an edge the smooth
model would ramp over that least length (``edge_mm`` below it: a sharp edge) stays sharp: the
defect table (system/defects.py) marks such an entry with a ramp of 0, and its separation is
D inside the defect and 0 outside (physics/defects.sharp_separation), a jump of the residual.
A stated longer ramp is smooth already and keeps its profile (no root).

How the jump is crossed: each sharp entry's side (inside or outside) at each of its contacts
is a flag of the table, frozen while IDA steps, so that IDA integrates a residual that is
smooth between crossings and whose Jacobian has no ramp term. IDA's root finding
(solvers/ida_edges.py, the compiled root function of solvers/sundials/roots.py) watches the
gaps g = l/2 - |s| of :func:`edge_gaps` (physics/defects.edge_gap: positive inside) and stops
where one changes sign; there the side is set from the crossing's direction and IDA restarts
(IDAReInit, order 1, IDACalcIC for the algebraic unknowns the jump moves).

The flags: row 0 column :data:`FROZEN` of the table is 1 while IDA's integration freezes the
sides (0 otherwise: every other evaluation, the static solve and a residual from Python, takes
the side from the position, :func:`side`); column :data:`ENTRIES` holds the number of entries
E. After the E entry rows come Z side rows, one per roller j; column 2(e - 1) + p holds entry
e's side at contact p (p = 0: a race defect's one contact, or a roller defect's point at the
outer race; p = 1: a roller defect's point at the inner race). The root functions, in the
order of :func:`edge_gaps` (roller, entry, contact), are one per sharp entry and contact of
each roller it can touch.
"""

from __future__ import annotations

import contextlib

import numpy as np
from numba import njit

from ..physics.compiled import helper
from ..physics.defects import edge_gap
from ..physics.loads import shaft_angle

#: row 0 of the table: the shaft angle (column 0), the frozen flag, the number of entries
FROZEN, ENTRIES = 1, 2
#: the defect table's columns (system/defects.py) read here
C_KIND, C_RACE, C_CENTRE, C_RADIUS, C_HALF, C_RAMP, C_ROLLER = 0, 1, 2, 3, 4, 5, 11


@helper
def contact_angle(D, e, p, th, phi, shaft):
    """The surface angle [rad] of entry e's contact p for a roller at orbit angle θX and spin
    angle φ (system/defects.py): θX - θ_s on the inner race, θX on the outer, -φ (p = 0, at the
    outer race) or π - φ (p = 1, at the inner race) on a roller."""
    if D[e, C_RACE] < 0.5:
        return th - shaft
    if D[e, C_RACE] < 1.5:
        return th
    return -phi if p == 0 else np.pi - phi


@helper
def is_sharp(D, e):
    """Entry e is a defect whose edges are located (a ramp of 0: system/defects.defect_table)."""
    return D[e, C_KIND] < 0.5 and D[e, C_RAMP] <= 0.0


@helper
def touches(D, e, j):
    """Entry e can meet roller j: a race defect every roller, a roller defect its own."""
    return D[e, C_RACE] < 1.5 or D[e, C_ROLLER] < -0.5 or abs(D[e, C_ROLLER] - j) < 0.5


@helper
def gap(D, e, p, th, phi, shaft):
    """physics/defects.edge_gap of entry e's contact p [m]."""
    return edge_gap(contact_angle(D, e, p, th, phi, shaft), D[e, C_CENTRE], D[e, C_RADIUS],
                    D[e, C_HALF])


@helper
def side(D, e, p, j, th, phi, shaft):
    """1 inside sharp entry e at contact p of roller j, else 0: the frozen flag while IDA
    integrates, else the position's."""
    if D[0, FROZEN] > 0.5:
        return D[1 + int(D[0, ENTRIES]) + j, 2 * (e - 1) + p]
    return 1.0 if gap(D, e, p, th, phi, shaft) > 0.0 else 0.0


@njit(cache=True, error_model="numpy")
def edge_gaps(D, th, phi, shaft, g):
    """The root functions: every sharp entry's gap at each contact of each roller it meets
    (the order of the module docstring) into g; returns their number (g may be longer; a g of
    length 0 only counts)."""
    k = 0
    E = int(D[0, ENTRIES])
    for j in range(th.shape[0]):
        for e in range(1, E + 1):
            if is_sharp(D, e) and touches(D, e, j):
                for p in range(1 if D[e, C_RACE] < 1.5 else 2):
                    if k < g.shape[0]:
                        g[k] = gap(D, e, p, th[j], phi[j], shaft)
                    k += 1
    return k


@njit(cache=True, error_model="numpy")
def crossing(D, Z, k):
    """(roller, entry, contact) of root function k (the order of :func:`edge_gaps`)."""
    n = 0
    E = int(D[0, ENTRIES])
    for j in range(Z):
        for e in range(1, E + 1):
            if is_sharp(D, e) and touches(D, e, j):
                for p in range(1 if D[e, C_RACE] < 1.5 else 2):
                    if n == k:
                        return j, e, p
                    n += 1
    return -1, -1, -1


def has_sharp(table) -> bool:
    """Whether a defect table has an entry whose edges are located (``table``: a model's
    ``defect_table``, None without defects)."""
    return isinstance(table, np.ndarray) and bool(np.any((table[1:, C_KIND] < 0.5)
                                                         & (table[1:, C_RAMP] <= 0.0)))


def roller_state(model, y) -> tuple[np.ndarray, np.ndarray]:
    """(θX, φ) [rad] of every roller from the scaled compact state y (φ 0 where the layout has
    no spin angles)."""
    from .layout import LOCAL, SPIN_ANGLE

    Z, nl = model.layout.rollers, model.layout.n_local
    out = []
    for name in ("azimuth", SPIN_ANGLE):
        a = LOCAL.index(name)
        where = np.flatnonzero(np.asarray(model.layout.local_map) == a)
        if where.size:
            i = np.arange(Z) * nl + where[0]
            out.append(np.asarray(y, float)[i] * model.scale[i])
        else:
            out.append(np.zeros(Z))
    return out[0], out[1]


def freeze_sides(model, t: float, y) -> int:
    """Set every sharp entry's side from the state (t, y) and freeze the sides (the residual
    reads the flags from now on); returns the number of root functions."""
    D = model.defect_table
    th, phi = roller_state(model, y)
    shaft = shaft_angle(float(t), model.ramp_t, model.ramp_w)
    g = np.zeros(edge_gaps(D, th, phi, shaft, np.zeros(0)))
    edge_gaps(D, th, phi, shaft, g)
    D[0, FROZEN] = 0.0
    for k in range(g.size):
        j, e, p = crossing(D, th.size, k)
        D[1 + int(D[0, ENTRIES]) + j, 2 * (e - 1) + p] = 1.0 if g[k] > 0.0 else 0.0
    D[0, FROZEN] = 1.0
    return g.size


def set_side(model, k: int, inside: bool) -> tuple[int, int, int]:
    """Root function k crossed: its side becomes inside (True) or outside; returns its
    (roller, entry, contact)."""
    D = model.defect_table
    j, e, p = crossing(D, model.layout.rollers, k)
    D[1 + int(D[0, ENTRIES]) + j, 2 * (e - 1) + p] = 1.0 if inside else 0.0
    return j, e, p


def thaw_sides(model) -> None:
    """The sides from the positions again (after IDA's integration)."""
    model.defect_table[0, FROZEN] = 0.0


@contextlib.contextmanager
def positional_sides(model):
    """The sides from the positions while the block runs, IDA's frozen flag put back after: a
    streamed record projects its samples while IDA integrates (results/streamed_record.py),
    and a sample's side is its own position's, not the one IDA froze at its current time
    (the record a run writes as it goes equals the one projected after the run)."""
    D = model.defect_table
    if not has_sharp(D):
        yield
        return
    frozen = D[0, FROZEN]
    D[0, FROZEN] = 0.0
    try:
        yield
    finally:
        D[0, FROZEN] = frozen
