"""Elastohydrodynamic film of the slice contacts (line contact, post-processing).

Pipeline: physics (pure laws), called by :mod:`bearingdae.analysis.engineering` with each
slice's load, reduced radius and entrainment speed. The film enters the DAE only with mixed
lubrication (``physics.lubrication = "mixed"``, physics/mixed.py, theory.md §20), whose kernel
calls the same fit, :func:`_film_fit`, with its slopes.

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

from .compiled import law
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


def compile_kernel() -> None:
    """Compile (or load from numba's cache) :func:`_film_loop` for the types every call gives
    it (contiguous float64 arrays, floats): a streamed run does it before its integration."""
    one = np.ones(1)
    line_contact_film(one, one, one, 1.0, 1.0, 1.0)


def _flat(x: np.ndarray, shape: tuple) -> np.ndarray:
    """x broadcast to ``shape``, contiguous and flat, by ``np.repeat`` along each broadcast
    axis (block copies: ~6x quicker than copying a zero-stride broadcast view)."""
    x = x.reshape((1,) * (len(shape) - x.ndim) + x.shape)
    for axis, n in enumerate(shape):
        if x.shape[axis] == 1 and n != 1:
            x = np.repeat(x, n, axis=axis)
    return np.ascontiguousarray(x).reshape(-1)


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def _film_loop(w, R, u, viscosity, E, min_factor, central_factor, h_c, h_min):
    """h = R' · (c G^g) · exp(a ln W' + b ln U) per slice (:func:`_film_fit`, the law the
    mixed-lubrication kernel calls), branch-free so that it vectorises; ``min_factor``,
    ``central_factor``: c G^g of the two fits."""
    for i in range(w.shape[0]):
        loaded = max(w[i], 0.0) / (E * R[i]) > 0.0
        hm = _film_fit(w[i], R[i], u[i], viscosity, E, min_factor, _MIN[1], _MIN[2])[0]
        hc = _film_fit(w[i], R[i], u[i], viscosity, E, central_factor, _CENTRAL[1],
                       _CENTRAL[2])[0]
        h_min[i] = hm if loaded else np.nan
        h_c[i] = hc if loaded else np.nan


@law
def _film_fit(load_per_length_N_m, reduced_radius_m, entrainment_speed_m_s, viscosity_Pa_s,
              reduced_modulus_Pa, factor, exponent_W, exponent_U):
    """One Pan & Hamrock fit h = R' (c G^g) W'^a U^b (module docstring) for one slice, with its
    slopes: (h [m], dh/dw' [m²/N], dh/du [s]); ``factor`` = c G^g, ``exponent_W`` = a,
    ``exponent_U`` = b (``_MIN`` or ``_CENTRAL``). Scalars; branch-free selects. Unloaded
    (w' <= 0): the powers of W' = 1 (callers mark the slice; no slope); standstill: h = 0."""
    ER = reduced_modulus_Pa * reduced_radius_m
    W = max(load_per_length_N_m, 0.0) / ER
    U = viscosity_Pa_s * abs(entrainment_speed_m_s) / ER
    loaded = W > 0.0
    rolling = U > 0.0
    lW = log_(W if loaded else 1.0)
    lU = log_(U if rolling else 1.0)
    h = reduced_radius_m * factor * exp_(exponent_W * lW + exponent_U * lU)
    h = h if rolling else 0.0 * U  # standstill: 0 (a NaN speed stays NaN)
    dh_dw = exponent_W * h / (load_per_length_N_m if loaded else 1.0)
    dh_du = exponent_U * h / (entrainment_speed_m_s if rolling else 1.0)
    return h, dh_dw if loaded else 0.0, dh_du if rolling else 0.0


def min_film_factor(reduced_modulus_Pa: float, pressure_viscosity_Pa_inv: float) -> float:
    """c G^g of the minimum-film fit (``factor`` of :func:`_film_fit` with ``_MIN``)."""
    G = float(pressure_viscosity_Pa_inv) * float(reduced_modulus_Pa)
    return _MIN[0] * G ** _MIN[3]


def film_parameter(min_film_m, composite_roughness_m: float):
    """λ = h_min / σ [1] (σ: composite RMS roughness of roller and race)."""
    return np.asarray(min_film_m, dtype=float) / composite_roughness_m
