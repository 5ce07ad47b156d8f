"""Algebraic (quasi-static) equations of rollers and inner ring, with analytic Jacobian (theory.md §5).

Unknowns: per roller the radial position u_j [m] and tilt β_j [rad]; the inner ring's
displacement and tilt (δ_r, δ_t, γ_r, γ_t). Equations:

- roller radial:  R_j = Σ_λ q_i,jλ - Σ_λ q_o,jλ + F_c,j = 0,   F_c,j = m R_m Ω_j²
- roller tilt:    T_j = Σ_λ x_λ (q_i,jλ - q_o,jλ) = 0
- inner ring:     E = (F_r, F_t, M, M_t) - Σ_jλ q_i,jλ P_jλ = 0,
  with P_jλ = (cos φ_j, sin φ_j, x_λ cos φ_j, x_λ sin φ_j) = ∂ρ_jλ/∂(δ_r, δ_t, γ_r, γ_t).

The formulas themselves (approaches, centrifugal force, roller and ring balances) are those of
physics/kinematics.py, which the DAE residual and its analytic Jacobian compile inline: this
module only applies them to all rollers and slices at once (numpy) for the static solve and the
DAE's initial state (tests/physics/test_shared_laws.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .contact import slice_load
from .kinematics import centrifugal_force, race_approaches, ring_approach, ring_load_share
from .kinematics import roller_balance

__all__ = ["centrifugal_force", "ring_basis", "ContactParams", "ContactState", "contact_state",
           "algebraic_equations", "algebraic_jacobian"]


def ring_basis(x_m: np.ndarray, azimuth_rad: np.ndarray) -> np.ndarray:
    """P_jλ = ∂ρ_jλ/∂(δ_r, δ_t, γ_r, γ_t), shape (Z, k, 4)."""
    c = np.cos(azimuth_rad)[:, None]
    s = np.sin(azimuth_rad)[:, None]
    x = x_m[None, :]
    zk = np.broadcast_shapes(c.shape, x.shape)
    return np.stack(
        [np.broadcast_to(c, zk), np.broadcast_to(s, zk), x * c, x * s], axis=-1
    )


@dataclass(frozen=True)
class ContactParams:
    """What the contact equations need from the geometry (SI)."""

    x_m: np.ndarray  #: slice centres (k,)
    profile_drop_m: np.ndarray  #: (k,)
    clearance_m: float
    stiffness: float  #: K_w of a slice, q = K_w δ^(10/9)
    smoothing_m: float
    #: the separations of local defects and waviness (physics/defects.py), (Z, k) each, that
    #: the inner and outer approaches lose; None: a healthy bearing
    separation_m: tuple | None = None


@dataclass(frozen=True)
class ContactState:
    """Slice approaches, loads and load slopes, each (Z, k) for the inner and outer race."""

    approach_inner_m: np.ndarray
    approach_outer_m: np.ndarray
    load_inner_N: np.ndarray
    load_outer_N: np.ndarray
    slope_inner_N_m: np.ndarray
    slope_outer_N_m: np.ndarray


def contact_state(u_m, tilt_rad, ring, azimuth_rad, p: ContactParams) -> ContactState:
    """Approaches and slice loads of every roller and slice for the given unknowns."""
    az = np.asarray(azimuth_rad, dtype=float)[:, None]
    x = p.x_m[None, :]
    rho = ring_approach(ring[0], ring[1], ring[2], ring[3], x, np.cos(az), np.sin(az))[0]
    d_in, d_out = race_approaches(rho, np.asarray(u_m, dtype=float)[:, None],
                                  np.asarray(tilt_rad, dtype=float)[:, None], x,
                                  0.5 * p.clearance_m, p.profile_drop_m[None, :])
    if p.separation_m is not None:  # (theory.md §4: δ <- δ - h)
        d_in, d_out = d_in - p.separation_m[0], d_out - p.separation_m[1]
    q_in, g_in = slice_load(d_in, p.stiffness, p.smoothing_m)
    q_out, g_out = slice_load(d_out, p.stiffness, p.smoothing_m)
    return ContactState(d_in, d_out, q_in, q_out, g_in, g_out)


def algebraic_equations(cs: ContactState, centrifugal_N, loads, x_m, basis):
    """Residuals (R (Z,), T (Z,), E (4,)) of theory.md §5 for a contact state.

    ``loads`` = (F_r, F_t, M, M_t); ``basis`` from :func:`ring_basis`.
    """
    qi, qo = cs.load_inner_N, cs.load_outer_N
    R, T = roller_balance(qi.sum(axis=1), qo.sum(axis=1), (x_m * qi).sum(axis=1),
                          (x_m * qo).sum(axis=1), centrifugal_N)
    # basis[j, 0, :2] = (cos φ_j, sin φ_j) (ring_basis)
    share = ring_load_share(qi.sum(axis=1), (x_m * qi).sum(axis=1), basis[:, 0, 0],
                            basis[:, 0, 1])
    E = np.asarray(loads, dtype=float) - np.array([np.sum(s) for s in share])
    return R, T, E


def algebraic_jacobian(cs: ContactState, x_m, basis):
    """Analytic Jacobian blocks of (R, T, E) with respect to (u, β, ring).

    Returns ``roller`` (Z, 2, 2) = ∂(R_j, T_j)/∂(u_j, β_j) (block diagonal),
    ``roller_ring`` (Z, 2, 4) = ∂(R_j, T_j)/∂ring, ``ring_roller`` (4, Z, 2) = ∂E/∂(u_j, β_j),
    ``ring_ring`` (4, 4) = ∂E/∂ring.
    """
    gi, go = cs.slope_inner_N_m, cs.slope_outer_N_m
    gs = gi + go
    x = x_m[None, :]
    s0 = gs.sum(axis=1)
    s1 = (x * gs).sum(axis=1)
    s2 = (x * x * gs).sum(axis=1)
    # ∂δ_i/∂u = -1, ∂δ_i/∂β = -x, ∂δ_o/∂u = +1, ∂δ_o/∂β = +x
    roller = np.empty((gi.shape[0], 2, 2))
    roller[:, 0, 0] = -s0
    roller[:, 0, 1] = -s1
    roller[:, 1, 0] = -s1
    roller[:, 1, 1] = -s2
    roller_ring = np.stack(
        [np.einsum("jk,jka->ja", gi, basis), np.einsum("jk,jka->ja", x * gi, basis)], axis=1
    )
    ring_roller = np.transpose(roller_ring, (2, 0, 1)).copy()  # ∂E_a/∂u_j = Σ g_i P_a, etc.
    ring_ring = -np.einsum("jk,jka,jkb->ab", gi, basis, basis)
    return roller, roller_ring, ring_roller, ring_ring
