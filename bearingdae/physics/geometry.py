"""Bearing geometry: raceways, roller mass and inertia, slicing and profiles (theory.md §2-3).

Pure functions plus one frozen container, :class:`Geometry`, built once per scene. Everything
in SI. Slices run along the roller's **total** length L (the paper's w = L/k).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..scene import Scene


def slice_centres(length_m: float, slices: int) -> np.ndarray:
    """Slice centres x_λ = -L/2 + (λ - 1/2) w, w = L/k [m] (theory.md §3)."""
    w = length_m / slices
    return -0.5 * length_m + (np.arange(slices) + 0.5) * w


def profile_drop(
    x_m: np.ndarray,
    profile: str,
    length_m: float,
    effective_length_m: float,
    crown_radius_m: float,
    design_load_N: float = 0.0,
    compliance_m2_N: float = 0.0,
) -> np.ndarray:
    """Profile drop c(x) [m] of the roller generatrix relative to its straight part (theory.md §3).

    - ``flat``: 0.
    - ``end-crown`` [reading]: straight over |x| <= L_s/2, then a circular arc of radius R_y
      tangent to the straight part: c = R_y - sqrt(R_y² - (|x| - L_s/2)²).
    - ``full-crown``: one arc over the whole length: c = R - sqrt(R² - x²).
    - ``logarithmic``: Lundberg's profile for a design load Q_d over the effective length
      l = L_s: c = (Q_d η / (π l)) ln[1 / (1 - (2x/L)²)] with η the elastic compliance of the
      pair; evaluated on slice centres, which always lie strictly inside |x| < L/2.
    """
    x = np.abs(np.asarray(x_m, dtype=float))
    if profile == "flat":
        return np.zeros_like(x)
    if profile == "end-crown":
        over = np.maximum(x - 0.5 * effective_length_m, 0.0)
        return crown_radius_m - np.sqrt(crown_radius_m**2 - over**2)
    if profile == "full-crown":
        return crown_radius_m - np.sqrt(crown_radius_m**2 - x**2)
    if profile == "logarithmic":
        scale = design_load_N * compliance_m2_N / (np.pi * effective_length_m)
        return scale * np.log(1.0 / (1.0 - (2.0 * x / length_m) ** 2))
    raise ValueError(f"profile = {profile!r}: allowed are flat, end-crown, full-crown, logarithmic")


def elastic_compliance(E1_Pa: float, nu1: float, E2_Pa: float, nu2: float) -> float:
    """η = (1 - ν₁²)/E₁ + (1 - ν₂²)/E₂ [m²/N] (theory.md §4); E* = 1/η."""
    return (1.0 - nu1**2) / E1_Pa + (1.0 - nu2**2) / E2_Pa


@dataclass(frozen=True)
class Geometry:
    """Derived geometry of one scene (SI). Arrays are over slices (k,) or rollers (Z,)."""

    rollers: int
    slices: int
    roller_radius_m: float  #: r = D_w/2
    roller_length_m: float  #: L (total; slicing length)
    pitch_radius_m: float  #: R_m = d_m/2
    inner_race_radius_m: float  #: R_i = R_m - r
    outer_race_radius_m: float  #: R_o = R_m + r
    slice_width_m: float  #: w = L/k
    x_m: np.ndarray  #: slice centres (k,)
    profile_drop_m: np.ndarray  #: c(x_λ) (k,)
    clearance_m: float  #: diametral clearance P_d
    compliance_m2_N: float  #: η, both contacts (same materials)
    roller_mass_kg: float  #: m = ρ π r² L
    roller_inertia_axial_kgm2: float  #: I_x = m r²/2
    roller_inertia_transverse_kgm2: float  #: I_t = m (3 r² + L²)/12
    azimuth0_rad: np.ndarray  #: initial azimuths φ_j, roller 1 on the load line (Z,)

    @property
    def reduced_radius_inner_m(self) -> float:
        """R' of the inner contact: 1/R' = 1/r + 1/R_i."""
        return 1.0 / (1.0 / self.roller_radius_m + 1.0 / self.inner_race_radius_m)

    @property
    def reduced_radius_outer_m(self) -> float:
        """R' of the outer contact: 1/R' = 1/r - 1/R_o (concave race)."""
        return 1.0 / (1.0 / self.roller_radius_m - 1.0 / self.outer_race_radius_m)

    def epicyclic_orbit_speed(self, ring_speed_rad_s: float) -> float:
        """Pure-rolling orbit (cage) speed Ω = ω_i R_i / (R_i + R_o) = ω_i/2 (1 - D_w/d_m)."""
        return ring_speed_rad_s * self.inner_race_radius_m / (
            self.inner_race_radius_m + self.outer_race_radius_m
        )

    def pure_rolling_spin(self, ring_speed_rad_s: float) -> float:
        """Roller spin ω for pure rolling on both races: ω = Ω R_o / r (theory.md §6, V_o = 0)."""
        return self.epicyclic_orbit_speed(ring_speed_rad_s) * self.outer_race_radius_m / (
            self.roller_radius_m
        )


def make_geometry(scene: Scene) -> Geometry:
    """Geometry of a validated scene."""
    b, mat = scene.bearing, scene.materials
    r = 0.5 * b.roller_diameter_m
    Rm = 0.5 * b.pitch_diameter_m
    L = b.roller_length_m
    k = scene.numerics.slices
    eta = elastic_compliance(
        mat.youngs_modulus_Pa, mat.poisson_ratio, mat.youngs_modulus_Pa, mat.poisson_ratio
    )
    x = slice_centres(L, k)
    c = profile_drop(
        x, b.profile, L, b.effective_length_m, b.crown_radius_m, b.design_load_N, eta
    )
    m = mat.density_kg_m3 * np.pi * r**2 * L
    Z = b.rollers
    return Geometry(
        rollers=Z,
        slices=k,
        roller_radius_m=r,
        roller_length_m=L,
        pitch_radius_m=Rm,
        inner_race_radius_m=Rm - r,
        outer_race_radius_m=Rm + r,
        slice_width_m=L / k,
        x_m=x,
        profile_drop_m=c,
        clearance_m=b.clearance_m,
        compliance_m2_N=eta,
        roller_mass_kg=m,
        roller_inertia_axial_kgm2=0.5 * m * r**2,
        roller_inertia_transverse_kgm2=m * (3.0 * r**2 + L**2) / 12.0,
        azimuth0_rad=2.0 * np.pi * np.arange(Z) / Z,
    )
