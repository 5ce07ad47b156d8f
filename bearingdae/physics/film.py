"""Elastohydrodynamic film of the slice contacts (line contact, post-processing).

Pipeline: physics (pure laws), called by :mod:`bearingdae.results.engineering` with each
slice's load, reduced radius and entrainment speed; the film does not enter the DAE.

Isothermal, fully flooded, Newtonian line contact, Pan & Hamrock's curve fits of their
numerical solutions (Pan & Hamrock, J. Tribology 111 (1989) 246-251; Hamrock, Schmid & Jacobson,
*Fundamentals of Machine Elements*, Eqs. for rectangular conjunctions):

    H_min = h_min / R' = 1.714 W'^(-0.128) U^(0.694) G^(0.568)
    H_c   = h_c   / R' = 2.922 W'^(-0.166) U^(0.692) G^(0.470)

with the dimensionless load W' = w' / (E' R'), speed U = η₀ u / (E' R') and material
parameter G = α E'; w' = q / w the slice load per unit length, u the entrainment (mean surface)
speed, R' the reduced radius of the slice contact (docs/theory.md §4), E' = 2 / η the reduced modulus
(η = Σ (1 - ν²)/E, physics/geometry.py), η₀ the oil's viscosity and α its pressure-viscosity
coefficient (scene keys ``lubricant.viscosity_Pa_s``, ``lubricant.pressure_viscosity_GPa_inv``).

**Left out (factors 1):** inlet shear heating (e.g. Gupta et al.'s thermal reduction factor
φ_T, which lowers h by 10-30 % at entrainment speeds above ~10 m/s), starvation (the oil-air
mixture of docs/theory.md §9 may well starve the inlet), non-Newtonian behaviour and roughness
effects on the film itself. So the films are upper estimates, the more so at high speed.

The film parameter λ = h_min / σ with σ = sqrt(σ₁² + σ₂²) the composite RMS roughness
(``materials.roughness_um``): λ < 1 is boundary lubrication, 1-3 mixed, > 3 full film.
"""

from __future__ import annotations

import numpy as np


def reduced_modulus(compliance_m2_N: float) -> float:
    """E' = 2 / η [Pa] with η = (1 - ν₁²)/E₁ + (1 - ν₂²)/E₂ (Hamrock's E')."""
    return 2.0 / compliance_m2_N


def line_contact_film(load_per_length_N_m, reduced_radius_m, entrainment_speed_m_s,
                      viscosity_Pa_s: float, pressure_viscosity_Pa_inv: float,
                      reduced_modulus_Pa: float):
    """(h_c, h_min) [m], central and minimum film thickness of a line contact (Pan & Hamrock
    1989, module docstring). Vectorised; 0 at standstill, nan where the slice carries no load
    (no contact, no film)."""
    w = np.maximum(np.asarray(load_per_length_N_m, dtype=float), 0.0)
    u = np.abs(np.asarray(entrainment_speed_m_s, dtype=float))
    R = np.asarray(reduced_radius_m, dtype=float)
    E = reduced_modulus_Pa
    G = pressure_viscosity_Pa_inv * E
    U = viscosity_Pa_s * u / (E * R)
    W = w / (E * R)
    loaded = W > 0.0
    Ws = np.where(loaded, W, 1.0)
    h_min = np.where(loaded, R * 1.714 * Ws ** -0.128 * U ** 0.694 * G ** 0.568, np.nan)
    h_c = np.where(loaded, R * 2.922 * Ws ** -0.166 * U ** 0.692 * G ** 0.470, np.nan)
    return h_c, h_min


def film_parameter(min_film_m, composite_roughness_m: float):
    """λ = h_min / σ [1] (σ: composite RMS roughness of roller and race)."""
    return np.asarray(min_film_m, dtype=float) / composite_roughness_m
