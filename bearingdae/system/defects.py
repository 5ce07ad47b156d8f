"""Local defects and waviness in the DAE (theory.md §4): the slice approaches lose the
separation of physics/defects.py, in the residual, the analytic Jacobians and the static solve.

Stage: system (DAE model). A scene with ``[[defects]]`` or ``[[waviness]]`` carries one more
work array, the defect table (:func:`defect_table`), and it is the work tuple's marker
(system/optional.py): an array marker selects the code below, while None or True (a scene
without defects) selects empty steps, so such a scene's kernels never type or compile any of
it and compute exactly what they did before.

The table: row 0 holds the shaft angle θ_s of the last evaluation (the defect pass writes it,
the Jacobian's slopes read it), then one row per entry (columns ``C_*``): kind (0 defect,
1 waviness), race (0 inner, 1 outer: the slice arrays' race index), the defect's centre angle
[rad] and its surface radius [m], half length, ramp, reachable depth, half width [m]; the
waviness order, phase [rad] and amplitude [m].

Per roller j, slice λ and race: δ ← δ - h(φ, x_λ) with φ = θX,j on the outer race and
θX,j - θ_s(t) on the inner; dδ/dθX gains -dh/dφ (the analytic Jacobian's ``defect_slopes``).
"""

from __future__ import annotations

import numpy as np
from numba import njit, types
from numba.extending import overload

from ..physics.defects import (defect_depth, defect_separation, edge_ramp,
                               waviness_separation, width_share)
from ..physics.loads import shaft_angle
from .layout import LOCAL

A_TH = LOCAL.index("azimuth")
(C_KIND, C_RACE, C_CENTRE, C_RADIUS, C_HALF, C_RAMP, C_DEPTH, C_HALF_WIDTH, C_ORDER,
 C_PHASE, C_AMPLITUDE) = range(11)
COLUMNS = 11
RACE = {"inner": 0, "outer": 1}


def defect_table(scene, geometry) -> np.ndarray | None:
    """The defect table of a scene (see the module docstring), None without defects."""
    if not scene.defects and not scene.waviness:
        return None
    g = geometry
    radius = {"inner": g.inner_race_radius_m, "outer": g.outer_race_radius_m}
    rows = [np.zeros(COLUMNS)]
    for d in scene.defects:
        row = np.zeros(COLUMNS)
        row[C_KIND], row[C_RACE], row[C_CENTRE] = 0.0, RACE[d.surface], d.angle_rad
        row[C_RADIUS], row[C_HALF] = radius[d.surface], 0.5 * d.length_m
        row[C_RAMP] = edge_ramp(d.edge_m, d.length_m)
        row[C_DEPTH] = defect_depth(d.depth_m, d.length_m, g.roller_radius_m)
        row[C_HALF_WIDTH] = 0.5 * d.width_m
        rows.append(row)
    for w in scene.waviness:
        row = np.zeros(COLUMNS)
        row[C_KIND], row[C_RACE] = 1.0, RACE[w.surface]
        row[C_ORDER], row[C_PHASE], row[C_AMPLITUDE] = w.order, w.phase_rad, w.amplitude_m
        rows.append(row)
    return np.array(rows)


@njit(inline="always", error_model="numpy")
def _entry(D, e, phi, xl, w):
    """(h, dh/dφ) [m, m/rad] of entry e at surface angle φ and slice centre x_λ (width w)."""
    if D[e, C_KIND] < 0.5:
        h, dh = defect_separation(phi, D[e, C_CENTRE], D[e, C_RADIUS], D[e, C_HALF],
                                  D[e, C_RAMP], D[e, C_DEPTH])
        a = width_share(xl, w, D[e, C_HALF_WIDTH])
        return h * a, dh * a
    return waviness_separation(phi, D[e, C_ORDER], D[e, C_AMPLITUDE], D[e, C_PHASE])


@njit(inline="always", error_model="numpy")
def separations(D, th, xl, w):
    """(h_i, dh_i/dθX, h_o, dh_o/dθX): the summed separations of a slice of the roller at orbit
    angle θX on both races, with the shaft angle of the table's row 0."""
    hi = dhi = ho = dho = 0.0
    shaft = D[0, 0]
    for e in range(1, D.shape[0]):
        if D[e, C_RACE] < 0.5:
            h, dh = _entry(D, e, th - shaft, xl, w)
            hi += h
            dhi += dh
        else:
            h, dh = _entry(D, e, th, xl, w)
            ho += h
            dho += dh
    return hi, dhi, ho, dho


@njit(cache=True, error_model="numpy")
def defect_pass(t, yl, x, w, ramp_t, ramp_w, D, q):
    """The slice approaches q (Z, k, race) of residual.kinematics_pass lose the separations;
    the shaft angle at t into the table's row 0."""
    D[0, 0] = shaft_angle(t, ramp_t, ramp_w)
    for j in range(yl.shape[0]):
        th = yl[j, A_TH]
        for lam in range(x.shape[0]):
            hi, _, ho, _ = separations(D, th, x[lam], w)
            q[j, lam, 0] -= hi
            q[j, lam, 1] -= ho


def separation_arrays(scene, geometry, t: float, azimuth_rad, ramp_t, ramp_w) -> tuple | None:
    """(h_i, h_o), each (Z, k) [m], of the rollers at ``azimuth_rad`` at time t, for the
    static solve (solvers/static.py; ``ramp_t, ramp_w``: the ring speed law's points); None
    for a scene without defects."""
    D = defect_table(scene, geometry)
    if D is None:
        return None
    x = np.asarray(geometry.x_m, float)
    q = np.zeros((len(azimuth_rad), x.size, 2))
    yl = np.zeros((len(azimuth_rad), len(LOCAL)))
    yl[:, A_TH] = azimuth_rad
    defect_pass(float(t), yl, x, float(geometry.slice_width_m), np.asarray(ramp_t, float),
                np.asarray(ramp_w, float), D, q)
    return -q[..., 0], -q[..., 1]


def _is_table(marker) -> bool:
    return isinstance(marker, types.Array)


# The stubs are never called from Python; in compiled code the overloads replace them.
def defect_rows(marker, t, yl, x, w, ramp_t, ramp_w, q):
    raise NotImplementedError("compiled code only")


def defect_slopes(marker, th, xl, w, kqi, kqo, Fiq, Foq, dF):
    raise NotImplementedError("compiled code only")


@overload(defect_rows, inline="always")
def _defect_rows(marker, t, yl, x, w, ramp_t, ramp_w, q):
    if not _is_table(marker):
        return lambda marker, t, yl, x, w, ramp_t, ramp_w, q: None

    def impl(marker, t, yl, x, w, ramp_t, ramp_w, q):
        defect_pass(t, yl, x, w, ramp_t, ramp_w, marker, q)
    return impl


@overload(defect_slopes, inline="always")
def _defect_slopes(marker, th, xl, w, kqi, kqo, Fiq, Foq, dF):
    """dF rows (analytic Jacobian: 0 Q_i, 1 Q_o, 2 M_i, 3 M_o, 4 ΣF_i, 5 ΣF_o, 6 Σx(F_i + F_o))
    gain, along θX, the slice loads' slopes through the separations: dq/dθX = -k_q dh/dθX,
    and the tractions' through their loads (dF/dq)."""
    if not _is_table(marker):
        return lambda marker, th, xl, w, kqi, kqo, Fiq, Foq, dF: None

    def impl(marker, th, xl, w, kqi, kqo, Fiq, Foq, dF):
        _, dhi, _, dho = separations(marker, th, xl, w)
        ei = -kqi * dhi
        eo = -kqo * dho
        dF[0, A_TH] += ei
        dF[1, A_TH] += eo
        dF[2, A_TH] += xl * ei
        dF[3, A_TH] += xl * eo
        dF[4, A_TH] += Fiq * ei
        dF[5, A_TH] += Foq * eo
        dF[6, A_TH] += xl * (Fiq * ei + Foq * eo)
    return impl
