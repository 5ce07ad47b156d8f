"""Local defects and waviness in the DAE (theory.md §4): the slice approaches lose the
separation of physics/defects.py, in the residual, the analytic Jacobians and the static solve.

Stage: system (DAE model). A scene with ``[[defects]]`` or ``[[waviness]]`` carries one more
work array, the defect table (:func:`defect_table`), and the work tuple's marker holds it
(system/optional.py, its entry ``DEFECTS``): a marker with a table selects the code below,
while one without (None, or a tuple whose entry is None: a scene without defects) selects
empty steps, so such a scene's kernels never type or compile any of it and compute exactly
what they did before.

The table: row 0 holds the shaft angle θ_s of the last evaluation (the defect pass writes it,
the Jacobian's slopes read it) and the number of entries (column 2; column 1 and the rows
after the entries: the sides of sharp edges, system/defect_sides.py), then one row per entry
(columns ``C_*``): kind (0 defect, 1 waviness), surface (0 inner race, 1 outer race: the slice
arrays' race index; 2 a roller), the defect's centre angle [rad] and its surface radius [m], half length, ramp, reachable depth,
half width [m]; the waviness order, phase [rad] and amplitude [m]; the roller it sits on (-1:
every roller, as roller waviness); a roller defect's reachable depth at its inner contact (the
column before: at its outer one, the race's own: each reach with the curvature of both
surfaces, physics/defects.py).

Per roller j, slice λ and race: δ ← δ - h(φ, x_λ) with φ = θX,j on the outer race and
θX,j - θ_s(t) on the inner; dδ/dθX gains -dh/dφ (the analytic Jacobian's ``defect_slopes``).
A roller's surface: the roller turns by its spin angle φ_j (φ_j' = ω_j, the spin speed relative
to the orbiting frame, system/layout.py's ``spin_angle``) in the frame that orbits with it,
where its outer contact sits at the angle 0 and its inner one at π; the point of its surface at
angle a (``angle_deg``: 0 faces the outer race at t = 0) meets the outer race where a = -φ_j and
the inner race where a = π - φ_j, each once per roller revolution. Its separation adds to both
contacts, with slopes -dh/da along φ_j. The residual's row φ_j' - ω_j (:func:`spin_angle_rows`)
and its Jacobian (:func:`spin_angle_slopes`) compile with the defect table only.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numba.extending import overload

from ..physics.compiled import helper
from ..physics.defects import (EDGE_MIN_M, defect_depth, defect_separation, edge_ramp,
                               waviness_separation, width_share)
from ..physics.loads import shaft_angle
from .defect_sides import ENTRIES, side
from .layout import LOCAL, SPIN_ANGLE
from .optional import DEFECTS, compiles

A_TH, A_W, A_PHI = (LOCAL.index(n) for n in ("azimuth", "spin_speed", SPIN_ANGLE))
(C_KIND, C_RACE, C_CENTRE, C_RADIUS, C_HALF, C_RAMP, C_DEPTH, C_HALF_WIDTH, C_ORDER,
 C_PHASE, C_AMPLITUDE, C_ROLLER, C_DEPTH_INNER) = range(13)
COLUMNS = 13
RACE = {"inner": 0, "outer": 1, "roller": 2}


def has_roller_surface(scene) -> bool:
    """Whether a defect or waviness entry sits on a roller: the model then carries the rollers'
    spin angles (system/layout.py)."""
    return any(e.surface == "roller" for e in (*scene.defects, *scene.waviness))


def defect_table(scene, geometry) -> np.ndarray | None:
    """The defect table of a scene (see the module docstring), None without defects."""
    if not scene.defects and not scene.waviness:
        return None
    g = geometry
    radius = {"inner": g.inner_race_radius_m, "outer": g.outer_race_radius_m,
              "roller": g.roller_radius_m}
    # "locate": a sharp edge (one the least ramp would smooth) keeps no ramp (defect_sides.py)
    locate = scene.dynamics.defect_edges == "locate"
    entries = len(scene.defects) + len(scene.waviness)
    width = max(COLUMNS, 2 * entries)
    rows = [np.zeros(width)]
    rows[0][ENTRIES] = entries
    for d in scene.defects:
        row = np.zeros(width)
        row[C_KIND], row[C_RACE], row[C_CENTRE] = 0.0, RACE[d.surface], d.angle_rad
        row[C_RADIUS], row[C_HALF] = radius[d.surface], 0.5 * d.length_m
        sharp = locate and d.edge_m < (EDGE_MIN_M if d.least_ramp_m is None else d.least_ramp_m)
        row[C_RAMP] = 0.0 if sharp else edge_ramp(d.edge_m, d.length_m, d.least_ramp_m)
        # the reachable depth at the contact the entry meets (physics/defects.py): a race's
        # with the roller; a roller's with the outer race (C_DEPTH) and the inner (C_DEPTH_INNER)
        r = g.roller_radius_m
        if d.surface == "roller":
            row[C_DEPTH] = defect_depth(d.depth_m, d.length_m, r, True,
                                        g.outer_race_radius_m, False)
            row[C_DEPTH_INNER] = defect_depth(d.depth_m, d.length_m, r, True,
                                              g.inner_race_radius_m, True)
        else:
            row[C_DEPTH] = row[C_DEPTH_INNER] = defect_depth(
                d.depth_m, d.length_m, radius[d.surface], d.surface == "inner", r, True)
        row[C_HALF_WIDTH] = 0.5 * d.width_m
        row[C_ROLLER] = d.roller
        rows.append(row)
    for w in scene.waviness:
        row = np.zeros(width)
        row[C_KIND], row[C_RACE] = 1.0, RACE[w.surface]
        row[C_ORDER], row[C_PHASE], row[C_AMPLITUDE] = w.order, w.phase_rad, w.amplitude_m
        row[C_ROLLER] = -1.0  # a roller's waviness: every roller's
        rows.append(row)
    if locate and any(r[C_KIND] < 0.5 and r[C_RAMP] <= 0.0 for r in rows[1:]):
        rows += [np.zeros(width) for _ in range(g.rollers)]  # the sides (defect_sides.py)
    return np.array(rows)


@helper
def _entry(D, e, phi, xl, w, j, p, th, rphi, shaft):
    """(h, dh/dφ) [m, m/rad] of entry e at surface angle φ and slice centre x_λ (width w); a
    sharp entry (ramp 0, numerics.defect_edges = "locate") on its side at contact p of roller j
    (orbit angle θX, spin angle φ_j: defect_sides.side)."""
    if D[e, C_KIND] < 0.5:
        depth = D[e, C_DEPTH_INNER] if p == 1 else D[e, C_DEPTH]  # (p 1: a roller's inner
        if D[e, C_RAMP] > 0.0:                                    # contact)
            h, dh = defect_separation(phi, D[e, C_CENTRE], D[e, C_RADIUS], D[e, C_HALF],
                                      D[e, C_RAMP], depth)
        else:
            h, dh = depth * side(D, e, p, j, th, rphi, shaft), 0.0
        a = width_share(xl, w, D[e, C_HALF_WIDTH])
        return h * a, dh * a
    return waviness_separation(phi, D[e, C_ORDER], D[e, C_AMPLITUDE], D[e, C_PHASE])


@helper
def separations(D, j, th, phi, xl, w):
    """(h_i, dh_i/dθX, h_o, dh_o/dθX, dh_i/dφ, dh_o/dφ): the summed separations of a slice of
    roller j (orbit angle θX, spin angle φ) on both races, with the shaft angle of the table's
    row 0."""
    hi = dhi = ho = dho = dhi_phi = dho_phi = 0.0
    shaft = D[0, 0]
    for e in range(1, int(D[0, ENTRIES]) + 1):
        if D[e, C_RACE] < 0.5:
            h, dh = _entry(D, e, th - shaft, xl, w, j, 0, th, phi, shaft)
            hi += h
            dhi += dh
        elif D[e, C_RACE] < 1.5:
            h, dh = _entry(D, e, th, xl, w, j, 0, th, phi, shaft)
            ho += h
            dho += dh
        elif D[e, C_ROLLER] < -0.5 or abs(D[e, C_ROLLER] - j) < 0.5:  # on roller j
            h, dh = _entry(D, e, -phi, xl, w, j, 0, th, phi, shaft)  # its point at the outer
            ho += h                                                  # contact ...
            dho_phi -= dh
            h, dh = _entry(D, e, np.pi - phi, xl, w, j, 1, th, phi, shaft)  # ... the inner one
            hi += h
            dhi_phi -= dh
    return hi, dhi, ho, dho, dhi_phi, dho_phi


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def defect_pass(t, yl, x, w, ramp_t, ramp_w, D, q):
    """The slice approaches q (Z, k, race) of residual.kinematics_pass lose the separations;
    the shaft angle at t into the table's row 0."""
    D[0, 0] = shaft_angle(t, ramp_t, ramp_w)
    for j in range(yl.shape[0]):
        th, phi = yl[j, A_TH], yl[j, A_PHI]
        for lam in range(x.shape[0]):
            hi, _, ho, _, _, _ = separations(D, j, th, phi, x[lam], w)
            q[j, lam, 0] -= hi
            q[j, lam, 1] -= ho


def separation_arrays(scene, geometry, t: float, azimuth_rad, ramp_t, ramp_w,
                      spin_angle_rad=None, table=None) -> tuple | None:
    """(h_i, h_o), each (Z, k) [m], of the rollers at ``azimuth_rad`` (and spin angles
    ``spin_angle_rad``, 0 if not given: their reference at t = 0) at time t, for the static
    solve (solvers/static.py; ``ramp_t, ramp_w``: the ring speed law's points); None for a
    scene without defects. ``table``: a model's own defect table (its frozen sides of sharp
    edges, defect_sides.py), else the scene's."""
    D = defect_table(scene, geometry) if table is None else table
    if D is None:
        return None
    x = np.asarray(geometry.x_m, float)
    q = np.zeros((len(azimuth_rad), x.size, 2))
    yl = np.zeros((len(azimuth_rad), len(LOCAL)))
    yl[:, A_TH] = azimuth_rad
    if spin_angle_rad is not None:
        yl[:, A_PHI] = spin_angle_rad
    defect_pass(float(t), yl, x, float(geometry.slice_width_m), np.asarray(ramp_t, float),
                np.asarray(ramp_w, float), D, q)
    return -q[..., 0], -q[..., 1]


def _is_table(marker) -> bool:
    """Whether the marker (a numba type) holds a defect table: the code below compiles."""
    return compiles(marker, DEFECTS)


# The stubs are never called from Python; in compiled code the overloads replace them.
def defect_rows(marker, t, yl, x, w, ramp_t, ramp_w, q):
    raise NotImplementedError("compiled code only")


def defect_slopes(marker, j, th, phi, xl, w, kqi, kqo, Fiq, Foq, dF):
    raise NotImplementedError("compiled code only")


def spin_angle_rows(marker, yl, ypl, res):
    raise NotImplementedError("compiled code only")


def spin_angle_slopes(marker, JR):
    raise NotImplementedError("compiled code only")


@overload(defect_rows, inline="always")
def _defect_rows(marker, t, yl, x, w, ramp_t, ramp_w, q):
    if not _is_table(marker):
        return lambda marker, t, yl, x, w, ramp_t, ramp_w, q: None

    def impl(marker, t, yl, x, w, ramp_t, ramp_w, q):
        defect_pass(t, yl, x, w, ramp_t, ramp_w, marker[DEFECTS], q)
    return impl


@overload(defect_slopes, inline="always")
def _defect_slopes(marker, j, th, phi, xl, w, kqi, kqo, Fiq, Foq, dF):
    """dF rows (analytic Jacobian: 0 Q_i, 1 Q_o, 2 M_i, 3 M_o, 4 ΣF_i, 5 ΣF_o, 6 Σx(F_i + F_o))
    gain, along θX and the spin angle φ, the slice loads' slopes through the separations:
    dq/dθX = -k_q dh/dθX (the same along φ), and the tractions' through their loads (dF/dq)."""
    if not _is_table(marker):
        return lambda marker, j, th, phi, xl, w, kqi, kqo, Fiq, Foq, dF: None

    def impl(marker, j, th, phi, xl, w, kqi, kqo, Fiq, Foq, dF):
        _, dhi, _, dho, dhi_phi, dho_phi = separations(marker[DEFECTS], j, th, phi, xl, w)
        _add_slopes(dF, A_TH, -kqi * dhi, -kqo * dho, xl, Fiq, Foq)
        _add_slopes(dF, A_PHI, -kqi * dhi_phi, -kqo * dho_phi, xl, Fiq, Foq)
    return impl


@helper
def _add_slopes(dF, col, ei, eo, xl, Fiq, Foq):
    """The slice's load slopes (ei, eo) along unknown ``col`` into dF's rows."""
    dF[0, col] += ei
    dF[1, col] += eo
    dF[2, col] += xl * ei
    dF[3, col] += xl * eo
    dF[4, col] += Fiq * ei
    dF[5, col] += Foq * eo
    dF[6, col] += xl * (Fiq * ei + Foq * eo)


@overload(spin_angle_rows, inline="always")
def _spin_angle_rows(marker, yl, ypl, res):
    """The spin angles' rows φ_j' - ω_j into res (Z, len(LOCAL)); packed where the layout has
    them (a defect or waviness on a roller)."""
    if not _is_table(marker):
        return lambda marker, yl, ypl, res: None

    def impl(marker, yl, ypl, res):
        for j in range(yl.shape[0]):
            res[j, A_PHI] = ypl[j, A_PHI] - yl[j, A_W]
    return impl


@overload(spin_angle_slopes, inline="always")
def _spin_angle_slopes(marker, JR):
    """d(φ_j' - ω_j)/dω_j = -1 into a roller's block JR (its y' slope is the mass 1)."""
    if not _is_table(marker):
        return lambda marker, JR: None

    def impl(marker, JR):
        JR[A_PHI, A_W] = -1.0
    return impl
