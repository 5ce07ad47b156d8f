"""Roller end-flange contact (theory.md §16): axial approach, Hertz point load, sliding speed,
sliding friction, and the loads one contact puts on the roller. Pure laws (SI), compiled
into the DAE kernels by :data:`~bearingdae.physics.compiled.law` (system/flange.py) and plain
numpy when called from Python.

One contact: roller end σ (+1: end a at x = +L/2, -1: end b at x = -L/2) against a flange of
ring ι (1 inner, 0 outer) whose face is inclined by α. The contact point sits at x_e = σ L/2
and at the signed radial offset ρ = +e (outer ring side) or -e (inner ring side) from the roller
axis (scene/flanges.py gives e).

- Axial approach: δ = σ (s - ρ β - ι a) - c_f/2, with s the roller's axial position, β its
  tilt, a = δ_a - (R_m - e)(γ_r cos φ + γ_t sin φ) the inner ring's axial displacement at its
  flange's contact point and c_f the roller's axial play between the flanges of one ring.
- Normal load (Hertz point contact, sphere on plane; Johnson, *Contact Mechanics* 1985,
  Eq. 4.23): Q = (4/3) E* sqrt(R_c) δ_n^(3/2), δ_n = δ cos α, regularised at the onset as the
  slice contacts (physics/contact.smooth_positive).
- Sliding speed, flange surface minus roller surface along t̂ (the slice slip's convention,
  theory.md §6): V = (ι ω_i - Ω)(R_m + ρ) + ω ρ + x_e ζ.
- Friction on the roller along t̂: F_t = μ_f Q V / sqrt(V² + v_f²) (regularised Coulomb).
- On the roller: axial force N_x = -σ Q cos α; about its centre the moment r_c x F with
  r_c = x_e ê_X + ρ ê_r: spin torque -ρ F_t (spin positive when rolling forward on the inner
  race), skew moment -x_e F_t (about ê_r), tilt moment -ρ N_x (about t̂).
"""

from __future__ import annotations

import numpy as np

from .compiled import law
from .contact import smooth_positive

HERTZ_POINT_EXPONENT = 1.5
#: sliding speed below which the flange friction is regularised (v_f) [m/s]
FLANGE_SLIP_SCALE_M_S = 1e-3


def point_contact_stiffness(reduced_modulus_Pa: float, contact_radius_m: float) -> float:
    """K of Q = K δ^(3/2) for a sphere of radius R_c on a plane: (4/3) E* sqrt(R_c)
    [N/m^1.5] (Johnson 1985, Eq. 4.23)."""
    return 4.0 / 3.0 * reduced_modulus_Pa * np.sqrt(contact_radius_m)


def point_contact_approach(load_N, stiffness: float):
    """Inverse of the Hertz point law: δ = (Q / K)^(2/3) [m]."""
    return (np.asarray(load_N, float) / stiffness) ** (1.0 / HERTZ_POINT_EXPONENT)


@law
def flange_approach(end_sign, inner, axial_position_m, tilt_rad, offset_m, ring_flange_m,
                    half_play_m):
    """Axial approach δ [m] of roller end σ into the flange of ring ι (1 inner, 0 outer):
    σ (s - ρ β - ι a) - c_f/2, with -ρ β the contact point's axial shift by the roller's tilt β
    and a the inner ring's axial displacement at its flange's contact point
    (:func:`ring_flange_axial`)."""
    return end_sign * (axial_position_m - offset_m * tilt_rad - inner * ring_flange_m) - (
        half_play_m)


@law
def ring_flange_axial(ring_axial_m, ring_gr_rad, ring_gt_rad, radius_m, cos_phi, sin_phi):
    """Axial displacement [m] of the inner ring at its flange contact at azimuth φ and radius
    R_m - e: δ_a - (R_m - e)(γ_r cos φ + γ_t sin φ) (a ring tilt γ_r moves the ring's +x side
    outward at φ = 0, theory.md §4, and so its flange at φ = 0 towards -X)."""
    return ring_axial_m - radius_m * (ring_gr_rad * cos_phi + ring_gt_rad * sin_phi)


@law
def flange_normal_load(axial_approach_m, cos_angle, stiffness, smoothing_m):
    """Normal load Q [N] and dQ/dδ [N/m] of the flange contact at axial approach δ."""
    s, ds = smooth_positive(axial_approach_m * cos_angle, smoothing_m)
    root = np.sqrt(s)
    return stiffness * s * root, HERTZ_POINT_EXPONENT * stiffness * root * ds * cos_angle


@law
def flange_slip(inner, ring_speed_rad_s, orbit_speed_rad_s, spin_rad_s, skew_rate_rad_s,
                pitch_radius_m, offset_m, x_end_m):
    """Sliding speed V [m/s] at the contact: (ι ω_i - Ω)(R_m + ρ) + ω ρ + x_e ζ."""
    return ((inner * ring_speed_rad_s - orbit_speed_rad_s) * (pitch_radius_m + offset_m)
            + spin_rad_s * offset_m + x_end_m * skew_rate_rad_s)


@law
def flange_friction(load_N, slip_m_s, friction, slip_scale_m_s):
    """Friction F_t = μ Q V/sqrt(V² + v²) on the roller along t̂ [N], dF/dQ, dF/dV."""
    root = np.sqrt(slip_m_s * slip_m_s + slip_scale_m_s * slip_scale_m_s)
    g = slip_m_s / root
    return (friction * load_N * g, friction * g,
            friction * load_N * slip_scale_m_s * slip_scale_m_s / (root * root * root))


@law
def flange_roller_loads(normal_N, friction_N, end_sign, offset_m, x_end_m, cos_angle):
    """Loads of one contact on the roller: (axial force N_x [N], tangential force F_t [N],
    spin torque [N m], skew moment [N m], tilt moment [N m])."""
    Nx = -end_sign * normal_N * cos_angle
    return Nx, friction_N, -offset_m * friction_N, -x_end_m * friction_N, -offset_m * Nx


def basic_static_load_rating(rollers: int, roller_diameter_m: float, length_m: float,
                             pitch_diameter_m: float) -> float:
    """C0 [N] of a single-row cylindrical roller bearing (ISO 76:2006, radial roller bearings,
    α = 0): C0 = 44 (1 - D_w / d_m) Z L_we D_w, lengths in mm."""
    Dw, L, dm = roller_diameter_m * 1e3, length_m * 1e3, pitch_diameter_m * 1e3
    return 44.0 * (1.0 - Dw / dm) * rollers * L * Dw


def permissible_axial_load(C0_N: float, speed_rpm: float, bore_mm: float,
                           outer_diameter_mm: float, radial_load_N: float,
                           oil: bool = True) -> float:
    """Permissible (thermally limited) axial load of a single-row cylindrical roller bearing
    with flanges [N], the SKF catalogue formula (SKF, "Single row cylindrical roller bearings:
    dynamic axial load carrying capacity", skf.com product pages / Rolling bearings catalogue):

        F_ap = k1 C0 1e4 / (n (d + D)) - k2 F_r

    n [r/min], d, D [mm], C0 and F_r in the unit of the result; k1 = 1.5, k2 = 0.15 for oil
    (k1 = 1, k2 = 0.1 for grease). Valid for ~60 K above ambient and a viscosity ratio κ >= 2;
    the catalogue also asks F_a <= 0.5 F_r and caps F_ap by the flange strength (0.0045 D^1.5 kN
    for the 2 series, 0.0023 D^1.7 kN for the others, D in mm): :func:`flange_strength_limit`."""
    k1, k2 = (1.5, 0.15) if oil else (1.0, 0.1)
    n = max(float(speed_rpm), 1.0)
    return k1 * C0_N * 1e4 / (n * (bore_mm + outer_diameter_mm)) - k2 * radial_load_N


def flange_strength_limit(outer_diameter_m: float, series_2: bool = False) -> float:
    """Mechanical limit of a constantly acting axial load [N] (SKF, as above): 0.0045 D^1.5 kN
    for bearings of the 2 series, 0.0023 D^1.7 kN for the others (D in mm)."""
    D = outer_diameter_m * 1e3
    return 1e3 * (0.0045 * D ** 1.5 if series_2 else 0.0023 * D ** 1.7)
