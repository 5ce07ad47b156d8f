"""Quasi-static state of a bearing with flanges (theory.md §16): the algebraic unknowns — roller
radial positions and tilts, the rollers' axial positions, the inner ring's displacement, tilt
and axial displacement — solved together at given azimuths and speeds.

Stage: system (DAE model) -> **solvers**. The static Newton of solvers/static.py knows the
slice contacts only; it gives the radial state, then this Newton (on the algebraic rows of the
compiled DAE residual with the algebraic block of the analytic Jacobian, as the projection of
solvers/algebraic.py) adds the flange contacts, starting from the axial state of equal roller
shares: each roller carries F_a / Z, pinched between an inner-ring flange and the opposite
outer-ring flange.

A dynamic ring (theory.md §15) is solved with them: its displacement and tilt against its
momentum rows at rest (zero velocity and acceleration), so the ring starts in balance with the
flange forces' moment on it. Held at the flangeless equilibrium instead, it started out of
balance by that moment and rang about the balanced tilt (NJ at +300 N: 67 % of the mean tilt
peak to peak; an NUP under -300 N failed in IDA within 70 µs).
"""

from __future__ import annotations

import numpy as np

from ..physics.flange import point_contact_approach
from ..system.layout import GLOBAL, LOCAL, RING, RING_RATES
from ..system.model import Model
from .static import StaticConvergenceError

#: Newton iterations allowed for the flange settling: from the equal-share start < 15 under a
#: radial load of the order of the axial one; a lightly loaded roller crossing the clearance
#: takes a few hundred short steps (yang20 NJ, 10 N radial, 20 N axial, 200 r/min: 194)
SETTLE_MAX_ITERATIONS = 2000
#: the first iterations are the plain Newton (a fixed cap, no stall test), so every start that
#: converged within them, as all did before the cap could grow, settles where it did, bit for bit
PLAIN_ITERATIONS = 100
#: iterations in a row whose step the line search cut below 1e-6 of Newton's: no descent
STALL_ITERATIONS = 20
SETTLE_TOL = 1e-11  #: max |scaled algebraic row| at convergence
STEP_CAP = 2.0  #: largest first Newton update, in units of each unknown's scale
STEP_CAP_MAX = 1e4  #: the most the cap grows to (:func:`settle`)


class FlangeSettleError(StaticConvergenceError):
    """The quasi-static Newton with flanges did not converge (a static failure as any other:
    one line and exit status 1 from the program)."""


def axial_start(model: Model, t: float = 0.0) -> tuple[float, float]:
    """(roller axial position s, ring axial displacement δ_a) [m] of equal roller shares of
    the axial load at time t (its history, physics/loads.py)."""
    fl = model.scene.bearing.flanges
    Fa = float(model.loads_at(t)[4])
    half = 0.5 * fl.clearance_m
    if Fa == 0.0:
        return 0.0, 0.0
    from ..system.flange import F_K, P_FLANGE_OFFSET
    K = model.params[P_FLANGE_OFFSET + F_K]
    cos_a = np.cos(fl.angle_rad)
    Q = abs(Fa) / (model.geometry.rollers * cos_a)
    d_ax = float(point_contact_approach(Q, K)) / cos_a
    sign = 1.0 if Fa > 0 else -1.0
    return sign * (half + d_ax), sign * 2.0 * (half + d_ax)


def settle(model: Model, t: float, y: np.ndarray,
           ring_balance: bool = False) -> tuple[np.ndarray, int]:
    """Newton on every algebraic row of the scaled state y (differential unknowns held):
    (y, iterations). Step halving on the max-norm of the rows.

    ``ring_balance`` (a dynamic ring at rest, theory.md §15): the ring's displacement and tilt
    are solved too, against its momentum rows at zero velocity and acceleration (the ring's
    static balance, flange forces included); its velocities are held at their values (zero
    at a start). Without it the ring is held where y has it."""
    from ..system.residual import residual
    from .common import jacobian_filler

    rows_at, cols_at = _unknowns(model, ring_balance)
    jd, fill, _ = jacobian_filler(model, "analytic")
    yp = np.zeros(model.size)
    res = np.empty(model.size)

    def rows(z):
        residual(t, z, yp, res, model.data)
        return res[rows_at].copy()

    y = np.array(y, dtype=float)
    F = rows(y)
    cap = STEP_CAP
    stalled = 0
    for it in range(SETTLE_MAX_ITERATIONS):
        norm = np.abs(F).max()
        if norm <= SETTLE_TOL:
            return y, it
        fill(t, y, yp, 0.0, model.data, jd)
        try:
            step = np.linalg.solve(jd[0][np.ix_(rows_at, cols_at)], -F)
        except np.linalg.LinAlgError:  # a singular Jacobian: no Newton step from here
            step = np.full(F.shape, np.nan)
        if not np.all(np.isfinite(step)):
            raise FlangeSettleError(f"the quasi-static state with flanges did not converge: "
                                    f"singular or non-finite Newton step at iteration {it} "
                                    f"(max |row| = {norm:.3g} in scale units)")
        capped = np.abs(step).max() > cap
        step *= min(1.0, cap / max(np.abs(step).max(), 1e-300))
        lam = 1.0
        for _ in range(30):
            z = y.copy()
            z[cols_at] += lam * step
            Fz = rows(z)
            if np.all(np.isfinite(Fz)) and np.abs(Fz).max() < (1 - 1e-4 * lam) * norm:
                break
            lam *= 0.5
        y, F = z, Fz
        if it + 1 < PLAIN_ITERATIONS:
            continue
        # past the plain Newton, a capped step taken whole: the cap grows (a lightly loaded
        # roller crosses the clearance, hundreds of reference approaches, in a few steps); a
        # cut one: it shrinks
        cap = min(2.0 * cap, STEP_CAP_MAX) if capped and lam == 1.0 else \
            max(STEP_CAP, cap * lam)
        stalled = stalled + 1 if lam < 1e-6 else 0
        if stalled == STALL_ITERATIONS:
            raise FlangeSettleError(f"the quasi-static state with flanges did not converge: no "
                                    f"Newton step reduces the rows from iteration "
                                    f"{it + 1 - stalled} on (max |row| = {norm:.3g} in scale "
                                    f"units){_loads_text(model, t)}")
    raise FlangeSettleError(f"the quasi-static state with flanges did not converge in "
                            f"{SETTLE_MAX_ITERATIONS} Newton iterations (max |row| = "
                            f"{np.abs(F).max():.3g} in scale units){_loads_text(model, t)}")


def _loads_text(model: Model, t: float) -> str:
    """What held the rollers between the flanges when the settling failed, and what holds them
    better: the keys of the operating point, where the radial load is below the axial one
    (else nothing)."""
    op = model.scene.operating
    Fx, Fy, Mx, My, Fa = (float(v) for v in model.loads_at(t)[:5])
    if np.hypot(Fx, Fy) >= abs(Fa):
        return ""
    return (f"; operating.axial_load_N = {Fa:g} N on the flanges with a radial load of "
            f"{np.hypot(Fx, Fy):g} N (operating.radial_load_N), a moment of "
            f"{np.hypot(Mx, My):g} N m (operating.moment_Nm) at operating.speed_rpm = "
            f"{op.speed_rpm:g}: rollers this lightly held did not settle between the flanges; "
            f"a larger radial load lets them")


def _unknowns(model: Model, ring_balance: bool) -> tuple[np.ndarray, np.ndarray]:
    """(rows, unknowns) of :func:`settle`, compact indices: the algebraic rows and unknowns,
    with ``ring_balance`` (a dynamic ring) also the ring's momentum rows (``RING_RATES``) and
    its displacement and tilt (``RING``), in the same order (a square, regular block)."""
    lay = model.layout
    alg = np.flatnonzero(lay.algebraic)
    if not (ring_balance and lay.ring_dynamic):
        return alg, alg
    pairs = [(lay.index(rate), lay.index(pos)) for pos, rate in zip(RING, RING_RATES)
             if pos in lay.global_names]
    return (np.concatenate([alg, [r for r, _ in pairs]]),
            np.concatenate([alg, [c for _, c in pairs]]))


def with_flanges(model: Model, t: float, y: np.ndarray) -> np.ndarray:
    """The scaled state y (radial algebraic unknowns from the static Newton) with the axial
    unknowns started at equal shares and every algebraic unknown settled with the flanges; a
    dynamic ring's displacement and tilt with them, at rest (:func:`settle`'s
    ``ring_balance``).

    Continuation in the contact-onset smoothing ε (as the static Newton, solvers/static.py):
    the flange couple N_x 2e tilts every roller, and an unloaded roller only finds its balance
    with both raceways across the clearance (pinched diagonally); with the scene's ε (1 nm) the
    slice loads have no slope in the gap and Newton overshoots. Settled first with ε of the
    order of the reference approach, then with ε reduced by :data:`EPS_FACTOR` per stage."""
    from ..system.flange import F_EPS, P_FLANGE_OFFSET
    from ..system.residual import P_EPS

    lay = model.layout
    full_l, full_g = lay.unpack(y * model.scale)
    s, da = axial_start(model, t)
    full_l[:, LOCAL.index("axial_position")] = s
    full_g[GLOBAL.index("ring_axial")] = da
    y = lay.pack(full_l, full_g) / model.scale
    P = model.params
    slots = (P_EPS, P_FLANGE_OFFSET + F_EPS)
    eps_scene = [float(P[i]) for i in slots]
    eps = max(model.length_scale_m, eps_scene[0])
    try:
        while True:
            for i, e_s in zip(slots, eps_scene):
                P[i] = max(eps, e_s)
            y = settle(model, t, y, ring_balance=lay.ring_dynamic)[0]
            if eps <= eps_scene[0]:
                break
            eps /= EPS_FACTOR
    finally:
        for i, e_s in zip(slots, eps_scene):
            P[i] = e_s
    return y


#: ε reduction per continuation stage of :func:`with_flanges`
EPS_FACTOR = 8.0

