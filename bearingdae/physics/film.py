"""Elastohydrodynamic film of the slice contacts (line contact, post-processing).

Pipeline: physics (pure laws), called by :mod:`bearingdae.analysis.engineering` with each
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
from numba import njit

from .elementary import exp_, log_

#: (coefficient, exponent of W', of U, of G) of the fits: h_min, then h_c
_MIN = (1.714, -0.128, 0.694, 0.568)
_CENTRAL = (2.922, -0.166, 0.692, 0.470)


def reduced_modulus(compliance_m2_N: float) -> float:
    """E' = 2 / η [Pa] with η = (1 - ν₁²)/E₁ + (1 - ν₂²)/E₂ (Hamrock's E')."""
    return 2.0 / compliance_m2_N


def line_contact_film(load_per_length_N_m, reduced_radius_m, entrainment_speed_m_s,
                      viscosity_Pa_s: float, pressure_viscosity_Pa_inv: float,
                      reduced_modulus_Pa: float):
    """(h_c, h_min) [m], central and minimum film thickness of a line contact (Pan & Hamrock
    1989, module docstring). Vectorised (arrays broadcast); 0 at standstill, nan where the
    slice carries no load (no contact, no film).

    The powers W'^a U^b are evaluated as exp(a ln W' + b ln U) with the plain-arithmetic exp
    and log of physics/elementary.py in one compiled loop (:func:`_film_loop`): a run's
    record holds Z k 2 slices per sample, and numpy's scalar ``pow`` (four per slice) was the
    larger part of an output sample's cost. Within 1e-14 of the powers taken one by one
    (tests/physics/test_film.py)."""
    w, R, u = (np.asarray(a, dtype=float) for a in (load_per_length_N_m, reduced_radius_m,
                                                    entrainment_speed_m_s))
    shape = np.broadcast_shapes(w.shape, R.shape, u.shape)
    E = float(reduced_modulus_Pa)
    G = float(pressure_viscosity_Pa_inv) * E
    n = int(np.prod(shape))
    h_c, h_min = np.empty(n), np.empty(n)
    _film_loop(_flat(w, shape), _flat(R, shape), _flat(u, shape), float(viscosity_Pa_s), E,
               _MIN[0] * G ** _MIN[3], _CENTRAL[0] * G ** _CENTRAL[3], h_c, h_min)
    return h_c.reshape(shape), h_min.reshape(shape)


def _flat(x: np.ndarray, shape: tuple) -> np.ndarray:
    """x broadcast to ``shape``, contiguous and flat, by ``np.repeat`` along each broadcast
    axis (block copies: ~6x quicker than copying a zero-stride broadcast view)."""
    x = x.reshape((1,) * (len(shape) - x.ndim) + x.shape)
    for axis, n in enumerate(shape):
        if x.shape[axis] == 1 and n != 1:
            x = np.repeat(x, n, axis=axis)
    return np.ascontiguousarray(x).reshape(-1)


@njit(cache=True, error_model="numpy")
def _film_loop(w, R, u, viscosity, E, min_factor, central_factor, h_c, h_min):
    """h = R' · (c G^g) · exp(a ln W' + b ln U) per slice, branch-free so that it vectorises;
    ``min_factor``, ``central_factor``: c G^g of the two fits."""
    for i in range(w.shape[0]):
        ER = E * R[i]
        W = max(w[i], 0.0) / ER
        U = viscosity * abs(u[i]) / ER
        loaded = W > 0.0
        rolling = U > 0.0
        lW = log_(W if loaded else 1.0)
        lU = log_(U if rolling else 1.0)
        hm = R[i] * min_factor * exp_(_MIN[1] * lW + _MIN[2] * lU)
        hc = R[i] * central_factor * exp_(_CENTRAL[1] * lW + _CENTRAL[2] * lU)
        hm = hm if rolling else 0.0 * U  # standstill: 0 (a NaN speed stays NaN)
        hc = hc if rolling else 0.0 * U
        h_min[i] = hm if loaded else np.nan
        h_c[i] = hc if loaded else np.nan


def film_parameter(min_film_m, composite_roughness_m: float):
    """λ = h_min / σ [1] (σ: composite RMS roughness of roller and race)."""
    return np.asarray(min_film_m, dtype=float) / composite_roughness_m
