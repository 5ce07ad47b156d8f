"""Kinematics and balances shared by the residual, the analytic Jacobian and the static solve.

Stage: physics (between the state of rollers, ring and cage and the contact/traction/pocket
laws). Every function here is written once and called by all three users:
system/residual.py and system/jacobian_analytic.py compile it inline (numba), the static solve
(physics/equilibrium.py, solvers/static.py) runs the same source on numpy arrays (all functions
are plain arithmetic and broadcast; tests/physics/test_shared_laws.py checks the three against one
direct call).

- Ring approach at roller j, slice λ (theory.md §4):
  ρ = (δ_r + x γ_r) cos φ + (δ_t + x γ_t) sin φ,   dρ/dφ = -(δ_r + x γ_r) sin φ + (δ_t + x γ_t) cos φ
- Slice approaches (theory.md §4): δ_i = ρ - P_d/2 - (u + x β) - c(x),  δ_o = (u + x β) - c(x)
- Effective radius (theory.md §6): r_λ = r + x tan θz (the paper's reading; r with rigid slip)
- Slip velocities along t̂ (theory.md §6):
  V_i = (ω_i - Ω) R_i - ω r_λ + x ζ,   V_o = -Ω R_o + ω r_λ + x ζ
- Rolling (entrainment) sums, rolling speed u = |sum| / 2 (theory.md §7 slide-to-roll law):
  Σ_i = (ω_i - Ω) R_i + ω r_λ,   Σ_o = Ω R_o + ω r_λ
- Pocket lead (theory.md §8): s_j = R_m wrap(θX - θc - 2π j / Z), wrap to (-π, π] (the one
  convention: the earlier kernels wrapped inline to [-π, π); the two differ only at exactly
  half a pitch from the pocket centre, never in contact), lead rate v_j = R_m (Ω - ω_c), ends
  a (x = +L/2) and b (x = -L/2) at s_j ∓ (L/2) θz moving at v_j ∓ (L/2) ζ.
- Algebraic equations (theory.md §5): roller radial R = Q_i - Q_o + m R_m Ω², tilt T = M_i - M_o
  (Q = Σ_λ q, M = Σ_λ x q), inner-ring share of roller j: Q_i (cos φ, sin φ), M_i (cos φ, sin φ).

Functions are physics laws (physics/compiled.py): LLVM inlines them into the kernel's
own IR, so the contact loops stay free of calls and vectorise.
"""

from __future__ import annotations

import numpy as np

from .compiled import law
from .elementary import mod_


@law
def ring_approach(ring_dr_m, ring_dt_m, ring_gr_rad, ring_gt_rad, x_m, cos_phi, sin_phi):
    """Radial approach ρ [m] of the inner ring at a slice and dρ/dφ [m/rad] (theory.md §4)."""
    a_r = ring_dr_m + x_m * ring_gr_rad
    a_t = ring_dt_m + x_m * ring_gt_rad
    return a_r * cos_phi + a_t * sin_phi, -a_r * sin_phi + a_t * cos_phi


@law
def race_approaches(rho_m, radial_position_m, tilt_rad, x_m, half_clearance_m, profile_drop_m):
    """(δ_i, δ_o) [m], inner and outer slice approaches (theory.md §4); ∂δ_i/∂(u, β) = -(1, x),
    ∂δ_o/∂(u, β) = (1, x), ∂δ_i/∂ρ = 1."""
    lift = radial_position_m + x_m * tilt_rad
    return rho_m - half_clearance_m - lift - profile_drop_m, lift - profile_drop_m


@law
def effective_radius(roller_radius_m, x_m, tan_skew):
    """r_λ = r + x tan θz [m] (theory.md §6; pass tan θz = 0 for rigid-body slip); ∂/∂θz = x sec²."""
    return roller_radius_m + x_m * tan_skew


@law
def slip_velocities(ring_speed_rad_s, orbit_speed_rad_s, spin_rad_s, skew_rate_rad_s,
                    radius_m, x_m, inner_race_radius_m, outer_race_radius_m):
    """(V_i, V_o) [m/s], slip of roller on inner and outer race along t̂ (theory.md §6) at a slice of
    effective radius ``radius_m`` (r_λ)."""
    axial = x_m * skew_rate_rad_s
    return ((ring_speed_rad_s - orbit_speed_rad_s) * inner_race_radius_m - spin_rad_s * radius_m
            + axial,
            -orbit_speed_rad_s * outer_race_radius_m + spin_rad_s * radius_m + axial)


@law
def rolling_sums(ring_speed_rad_s, orbit_speed_rad_s, spin_rad_s, radius_m,
                 inner_race_radius_m, outer_race_radius_m):
    """(Σ_i, Σ_o) [m/s], signed sums of the surface speeds; rolling speed u = |Σ| / 2 (theory.md §7).
    ∂Σ_i/∂(Ω, ω) = (-R_i, r_λ), ∂Σ_o/∂(Ω, ω) = (R_o, r_λ)."""
    spin = spin_rad_s * radius_m
    return (ring_speed_rad_s - orbit_speed_rad_s) * inner_race_radius_m + spin, \
        orbit_speed_rad_s * outer_race_radius_m + spin


@law
def wrap_angle(angle_rad):
    """Wrap to (-π, π]: π - mod(π - a, 2π) (``mod_``: np.mod, compiled without a C call)."""
    return np.pi - mod_(np.pi - angle_rad, 2.0 * np.pi)


@law
def pocket_lead(roller_azimuth_rad, cage_angle_rad, pocket_index, rollers, pitch_radius_m):
    """Lead s_j [m] of roller j ahead of its pocket centre, R_m wrap(θX - θc - 2π j/Z), j from 0.

    ds/dθX = R_m, ds/dθc = -R_m (the wrap jumps only half a pitch away, never in contact).
    """
    offset = 2.0 * np.pi * pocket_index / rollers
    return pitch_radius_m * wrap_angle(roller_azimuth_rad - cage_angle_rad - offset)


@law
def pocket_lead_rate(orbit_speed_rad_s, cage_speed_rad_s, pitch_radius_m):
    """ds_j/dt = R_m (Ω - ω_c) [m/s]."""
    return pitch_radius_m * (orbit_speed_rad_s - cage_speed_rad_s)


@law
def end_positions(s_j_m, skew_rad, length_m):
    """Ends a (x = +L/2) and b (x = -L/2): (s_a, s_b) = (s_j - (L/2)θz, s_j + (L/2)θz) [m];
    with (v_j, ζ) in place of (s_j, θz), their speeds."""
    half = 0.5 * length_m
    return s_j_m - half * skew_rad, s_j_m + half * skew_rad


@law
def centrifugal_force(mass_kg, pitch_radius_m, orbit_speed_rad_s):
    """F_c = m R_m Ω² [N], outward (theory.md §5); dF_c/dΩ = 2 m R_m Ω."""
    return mass_kg * pitch_radius_m * orbit_speed_rad_s * orbit_speed_rad_s


@law
def roller_balance(inner_load_N, outer_load_N, inner_moment_Nm, outer_moment_Nm,
                   centrifugal_N):
    """(R, T): radial Q_i - Q_o + F_c [N] and tilt M_i - M_o [N m] of one roller (theory.md §5)."""
    return inner_load_N - outer_load_N + centrifugal_N, inner_moment_Nm - outer_moment_Nm


@law
def ring_load_share(inner_load_N, inner_moment_Nm, cos_phi, sin_phi):
    """Roller j's load on the inner ring along (δ_r, δ_t, γ_r, γ_t): Σ_λ q_i P_jλ with
    P = (cos φ, sin φ, x cos φ, x sin φ) (theory.md §5); the ring rows are loads - Σ_j share_j."""
    return (inner_load_N * cos_phi, inner_load_N * sin_phi, inner_moment_Nm * cos_phi,
            inner_moment_Nm * sin_phi)
