"""Power loss of a dynamic run by source, and the inner ring's drive (post-processing).

Pipeline: physics (pure, vectorised over time and rollers), called by
:mod:`bearingdae.analysis.engineering` with a run's recorded speeds and forces; nothing here
enters the DAE residual. The loads are recomputed with the kernel's own laws (physics/cage.py,
physics/lubricant.py), so each formula stays in one place.

The drive torque of the inner ring is the reaction of the inner-race traction,
T_in = R_i Σ F_i (docs/theory.md §6-7), its power P_in = ω_i T_in. Multiplying each equation of motion
(docs/theory.md §10, orbit in Newton's form) by its speed and summing gives, exactly,

    P_in = Σ_s P_s + dE/dt - Ω I_x ω' + ζ G

with E = Σ_j (½ m R_m² Ω_j² + ½ I_x ω_j² + ½ I_t ζ_j²) + ½ I_c ω_c² (the model's kinetic energy),
G the gyroscopic term of the skew equation, and the sources P_s (each ≥ 0 on average):

* ``raceway_inner``, ``raceway_outer``: Σ F V over the slices, traction times slip (race
  minus roller surface speed). The traction law is the whole raceway friction of the model
  (rolling and sliding in one law, docs/theory.md §7); the EHL rolling resistance is a separate
  source with its switch (below).
* ``pocket_friction``: -M_spin (ω - Ω + ω_c), the roller-cage friction torque M_spin
  (docs/theory.md §8) times the sliding speed it works on (the roller's absolute spin Ω - ω, docs/theory.md §6,
  relative to the cage).
* ``pocket_impact``: -Σ_e F_e ṡ_e, the work the pocket contacts take from rollers and cage,
  ṡ_a,b = R_m (Ω - ω_c) ∓ (L/2) ζ: the damping loss plus the rate of change of the spring
  energy (which averages out; instantaneous values may be negative).
* ``orbit_drag``: R_m Ω F_D; ``roller_churning``: (ω - Ω) M_lr; ``cage_churning``: ω_c M_lc
  (docs/theory.md §9).
* with flanges (docs/theory.md §16) ``flange_friction``: Σ F_t V over the end-flange contacts;
  the drive torque then adds (R_m - e) Σ F_t of the inner ring's contacts.
* with rolling resistance (docs/theory.md §19) ``rolling_resistance``: Σ H Σ over the slices,
  the film's rolling force times the rolling sum (twice the entrainment speed): its loads on
  orbit and spin and the inner ring's drive torque R_i Σ H_i do exactly this work
  (system/rolling_resistance.py);
* with mixed lubrication (docs/theory.md §20) ``asperity_friction``: Σ F_a V over the slices,
  the asperities' share of the traction F_a = s μ_b q sg(V) times the slip; the raceway
  sources then keep the film's share, Σ (F - F_a) V.
* with cage whirl (docs/theory.md §17) ``cage_land``: the land's loss; the pocket sources
  take the displaced pockets' lead rates, radial lips and radial sliding
  (system/whirl.whirl_powers); E adds ½ m_c |ė|²; an inner land's moment adds to the drive.

Friction torque of a source, referred to the inner ring: T_s = P_s / ω_i.
"""

from __future__ import annotations

import numpy as np

from .cage import _pocket_loads
from .lubricant import cage_side_churning, orbit_drag_force, roller_end_churning

def rolling_resistance_power(contact_force_N, ring_rad_s, orbit_rad_s, spin_rad_s, skew_rad,
                             x_m, radii_m, paper_slip: bool, width_m: float,
                             reduced_radii_m, law: tuple):
    """(P [W], T [N m], H [N]) of the EHL rolling resistance (docs/theory.md §19): the power
    Σ H Σ and the inner ring's drive torque R_i Σ H_i over (roller, slice, race), and the
    slices' signed forces H (..., Z, k, 2), from slice loads (..., Z, k, 2), the ring speed
    (...,), roller speeds and skew angles (..., Z), with the law of
    physics/rolling_resistance.py: ``radii_m`` (R_i, R_o, r), the slice width, the reduced
    radii (inner, outer) and ``law`` the law's other arguments (η₀, α, E', β, k, u₀, w_c, law
    code, min-film factor, inlet film; physics/rolling_resistance.slice_forces).
    Σ in H is the kernel's (r_λ with the paper's slip); the power's is the spin arm r's, the
    work the loads do (equal with rigid slip)."""
    from .kinematics import effective_radius, rolling_sums
    from .rolling_resistance import slice_forces

    q = np.asarray(contact_force_N, dtype=float)
    w = np.asarray(ring_rad_s, dtype=float)[..., None, None]
    Om = np.asarray(orbit_rad_s, dtype=float)[..., None]
    om = np.asarray(spin_rad_s, dtype=float)[..., None]
    Ri, Ro, r = radii_m
    tan_sk = np.tan(np.asarray(skew_rad, dtype=float))[..., None] if paper_slip else 0.0
    r_l = effective_radius(r, np.asarray(x_m), tan_sk)
    s_i, s_o = rolling_sums(w, Om, om, r_l, Ri, Ro)
    H = np.stack([slice_forces(q[..., c], s, width_m, rp, law)
                  for c, s, rp in ((0, s_i, reduced_radii_m[0]),
                                   (1, s_o, reduced_radii_m[1]))], axis=-1)
    a_i, a_o = rolling_sums(w, Om, om, r, Ri, Ro)
    P = np.sum(H[..., 0] * a_i + H[..., 1] * a_o, axis=(-2, -1))
    return P, Ri * np.sum(H[..., 0], axis=(-2, -1)), H


def flange_drive_torque(friction_inner_N, flange_radius_m: float):
    """The inner ring's drive torque through its flanges [N m]: (R_m - e) Σ F_t over the
    inner-ring contacts (the reaction of their friction on the rollers), given the sum Σ F_t."""
    return flange_radius_m * np.asarray(friction_inner_N)


def drive_torque(traction_inner_N, inner_race_radius_m: float):
    """T_in = R_i Σ F_i [N m] over the last two axes (roller, slice) of (..., Z, k)."""
    return inner_race_radius_m * np.sum(traction_inner_N, axis=(-2, -1))


def raceway_power(traction_N, slip_m_s):
    """Σ F V [W] over (roller, slice) of (..., Z, k) arrays."""
    return np.sum(traction_N * slip_m_s, axis=(-2, -1))


def pocket_powers(cage_force_N, orbit_rad_s, spin_rad_s, skew_rate_rad_s, cage_speed_rad_s,
                  length_m, roller_radius_m, pitch_radius_m, friction, spin_scale_rad_s,
                  force_scale_N):
    """(friction, impact) [W], summed over the rollers; arrays (..., Z) and (..., Z, 2) for
    the end forces (a, b); ``cage_speed_rad_s`` (...,)."""
    Fa, Fb = cage_force_N[..., 0], cage_force_N[..., 1]
    wc = np.asarray(cage_speed_rad_s)[..., None]
    _, _, m_spin, _ = _pocket_loads(Fa, Fb, spin_rad_s, length_m, roller_radius_m,
                                    pitch_radius_m, friction, spin_scale_rad_s, force_scale_N)
    friction_W = -np.sum(m_spin * (spin_rad_s - orbit_rad_s + wc), axis=-1)
    lead = pitch_radius_m * (orbit_rad_s - wc)
    half = 0.5 * length_m * skew_rate_rad_s
    impact_W = -np.sum(Fa * (lead - half) + Fb * (lead + half), axis=-1)
    return friction_W, impact_W


def lubricant_powers(orbit_rad_s, spin_rad_s, cage_speed_rad_s, pitch_radius_m,
                     roller_radius_m, length_m, cage_inner_radius_m, cage_outer_radius_m,
                     density_kg_m3, viscosity_Pa_s):
    """(orbit drag, roller churning, cage churning) [W]; rollers summed (arrays (..., Z))."""
    F_D = orbit_drag_force(orbit_rad_s, pitch_radius_m, 2.0 * roller_radius_m, length_m,
                           density_kg_m3, viscosity_Pa_s)
    M_lr = roller_end_churning(spin_rad_s, roller_radius_m, density_kg_m3, viscosity_Pa_s)
    wc = np.asarray(cage_speed_rad_s, dtype=float)
    M_lc = cage_side_churning(wc, cage_inner_radius_m, cage_outer_radius_m, density_kg_m3,
                              viscosity_Pa_s)
    return (np.sum(pitch_radius_m * orbit_rad_s * F_D, axis=-1),
            np.sum((spin_rad_s - orbit_rad_s) * M_lr, axis=-1), wc * M_lc)
