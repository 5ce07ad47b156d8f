"""A skid start: initial cage and roller speeds from a quasi-static torque balance.

Stage: scene -> geometry -> DAE model -> **initial state** -> solver. The default start
(:func:`bearingdae.solvers.algebraic.initial_state`) puts cage and rollers at the epicyclic
(pure-rolling) speeds. At light load the steady cage speed lies far below it (Harris bearing,
250 N: about half), and the cage takes tens of revolutions to spin down (docs/validation.md,
Fig 11). This module estimates the steady skid speeds instead, from the same residual
(theory.md §6-11, system/residual.py) with every time derivative set to zero:

* all rollers orbit with the cage at one speed Ω, centred in their pockets, skew 0;
* the algebraic unknowns (radial positions, ring) are the static equilibrium at Ω
  (centrifugal force m R_m Ω², theory.md §5; solvers/algebraic.py);
* each roller's spin ω_j balances its own spin equation, ``r Σ(F_i − F_o) − M_lr = 0``
  (traction of both races at their slips against end churning; theory.md §6, 7, 9). The row is
  monotone in ω_j (more spin: less inner, more outer traction and churning), so bisection
  between 0 and 1.5x the fastest pure-rolling spin finds it;
* Ω makes the torque on cage plus rollers about the bearing axis vanish: the sum of every
  roller's orbit equation (times R_m in the force form) and the cage equation. The pocket
  forces are internal to that sum and cancel; what is left is the traction the loaded
  rollers transmit at their slip against orbital drag and cage churning (theory.md §9). Brent's
  method on [0, Ω_epicyclic].

If the torque is not positive below the epicyclic speed for any Ω > 0 (nothing drives the
cage, e.g. no roller touches the inner race: harris36 at 0 N), the balance is Ω = 0: cage and
rollers at rest. If the torque at the epicyclic speed is still positive, the start is the
epicyclic one.

This is a start, not a result: it neglects the spin inertia that carries a roller's speed
from the loaded into the unloaded zone, the pocket friction and skew. ``until_steady``
(bearingdae/run/steady.py) then runs the dynamics to the actual steady state.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from ..system.layout import GLOBAL, LOCAL
from ..system.model import Model
from .algebraic import project_algebraic

SPIN_BISECTIONS = 60  # halvings of the spin bracket: 2^-60 of 1.5x the pure-rolling spin
#: relative tolerance of Ω in Brent's method; far below the 1e-3 steady_tolerance
OMEGA_RTOL = 1e-9


def _state(model: Model, y_template: np.ndarray, omega_rad_s: float,
           spin_rad_s: np.ndarray) -> np.ndarray:
    """Scaled state with every orbit and the cage at Ω, spins ω_j, skew 0 (other unknowns of
    ``y_template`` kept; algebraic ones re-solved by the caller)."""
    lay = model.layout
    full_l, full_g = lay.unpack(y_template * model.scale)
    full_l[:, LOCAL.index("orbit_speed")] = omega_rad_s
    full_l[:, LOCAL.index("spin_speed")] = spin_rad_s
    full_l[:, LOCAL.index("skew_angle")] = 0.0
    full_l[:, LOCAL.index("skew_rate")] = 0.0
    full_g[GLOBAL.index("cage_speed")] = omega_rad_s
    return lay.pack(full_l, full_g) / model.scale


def _rows(model: Model, y: np.ndarray) -> np.ndarray:
    """Unscaled residual rows at (y, y' = 0), i.e. minus the forces and moments."""
    return model.residual(0.0, y, np.zeros_like(y)) * model.row_scale


def _spin_balance(model: Model, y: np.ndarray, ring_rad_s: float, omega: float) -> np.ndarray:
    """Scaled state with each roller's spin solving its own spin equation (bisection)."""
    lay, g = model.layout, model.geometry
    Z = g.rollers
    i_spin = np.array([lay.index("spin_speed", j) for j in range(Z)])
    top = 1.5 * max((ring_rad_s - omega) * g.inner_race_radius_m,
                    omega * g.outer_race_radius_m) / g.roller_radius_m + 1.0
    lo, hi = np.zeros(Z), np.full(Z, top)
    y = y.copy()
    for _ in range(SPIN_BISECTIONS):
        mid = 0.5 * (lo + hi)
        y[i_spin] = mid / model.scale[i_spin]
        # row = I_x ω' - (drive): at y' = 0 a negative row means the net moment still spins up
        up = _rows(model, y)[i_spin] < 0.0
        lo, hi = np.where(up, mid, lo), np.where(up, hi, mid)
    y[i_spin] = 0.5 * (lo + hi) / model.scale[i_spin]
    return y


def _balanced(model: Model, y0: np.ndarray, omega: float) -> np.ndarray:
    """State at orbit/cage speed Ω with algebraic unknowns and spins in balance."""
    g = model.geometry
    w = model.ring_speed(0.0)
    y = _state(model, y0, omega, np.full(g.rollers, 0.0))
    y, _ = project_algebraic(model, 0.0, y)
    return _spin_balance(model, y, w, omega)


def axial_torque_Nm(model: Model, y: np.ndarray) -> float:
    """Net driving torque on cage plus rollers about the bearing axis [N m] at (y, y' = 0):
    the sum of the orbit equations (x R_m in the force form) and the cage equation, in which
    the pocket forces cancel."""
    lay, g = model.layout, model.geometry
    rows = _rows(model, y)
    lever = 1.0 if model.scene.physics.orbit == "paper" else g.pitch_radius_m
    torque = -lever * sum(rows[lay.index("orbit_speed", j)] for j in range(g.rollers))
    if "cage_speed" in lay.global_names:
        torque -= rows[lay.index("cage_speed")]
    return float(torque)


def torque_balance_state(model: Model, y0: np.ndarray) -> tuple[np.ndarray, np.ndarray, dict]:
    """Scaled (y0, yp0) at the torque-balance skid speeds, and a dict describing them.

    ``y0`` is the epicyclic start of :func:`~bearingdae.solvers.algebraic.initial_state`; its
    azimuths, cage angle and ring state are the template. y'0 as there: from the equations of
    motion for the differential rows, zero for the algebraic ones (IDA's consistent
    initialisation corrects both).
    """
    g = model.geometry
    w = model.ring_speed(0.0)
    epi = g.epicyclic_orbit_speed(w)
    if epi <= 0.0:
        omega, how = 0.0, "inner ring at rest: start at rest"
    else:
        def torque(om):
            return axial_torque_Nm(model, _balanced(model, y0, om))

        t_epi = torque(epi)
        t_low = torque(1e-6 * epi)
        if t_epi >= 0.0:
            omega, how = epi, "torque at the epicyclic speed is driving: epicyclic start"
        elif t_low <= 0.0:
            omega, how = 0.0, ("no driving torque at any cage speed (no roller transmits "
                               "traction from the inner race): start at rest")
        else:
            omega = brentq(torque, 1e-6 * epi, epi, rtol=OMEGA_RTOL)
            how = "torque balance"
    y = _balanced(model, y0, omega)
    res0 = model.residual(0.0, y, np.zeros_like(y))
    yp = np.zeros_like(y)
    diff = model.mass > 0
    yp[diff] = -res0[diff] / model.mass[diff]
    lay = model.layout
    spins = [float(y[lay.index("spin_speed", j)] * model.scale[lay.index("spin_speed", j)])
             for j in range(g.rollers)]
    info = {"initial_speeds": "torque_balance", "initial_cage_speed_rad_s": float(omega),
            "initial_cage_speed_fraction_of_epicyclic": float(omega / epi) if epi > 0 else 0.0,
            "initial_spin_speed_min_rad_s": min(spins), "initial_spin_speed_max_rad_s": max(spins),
            "initial_speeds_note": how}
    return y, yp, info
