"""Sliced Palmgren line contact and Hertz pressure (theory.md §4).

Palmgren's law for one roller-race contact, δ = A Q^0.9 / l^0.8 with A = 1.36 η^0.9, spread over
k slices of width w = L/k gives the slice load

    q_λ = w δ_λ^(10/9) / (A^(10/9) L^(1/9))                                   (theory.md §4)

The exponent is the exact 10/9 (the paper's 1.11 is a rounding). The positive part of the
approach is **regularised** so that a roller touching neither race keeps a well-posed Jacobian:
δ₊ ≈ s(δ) = (δ + sqrt(δ² + ε²))/2 with ε the contact smoothing length (default 1 nm, recorded
in every output). s is smooth, positive and > 0 everywhere, equals δ for δ >> ε and decays like
ε²/(4|δ|) in the gap.

All functions are pure arithmetic on floats or numpy arrays (broadcasting). The ones the DAE
kernel needs are physics laws (physics/compiled.py): plain numpy from Python, compiled
inline inside ``@njit`` code — one place for each formula. The approaches δ themselves
(ring approach, race approaches) are kinematics: physics/kinematics.py.

δ^(1/9) is exp(ln s / 9) with physics/elementary.py's exp_ and log_ (``root9``'s operations,
plain arithmetic, so that the contact loop vectorises; within a few ulp of ``pow``). The law is
written in stages, ``smooth_positive`` -> ``log_`` -> ``palmgren_load``, and ``slice_load``
composes them: the kernels run the stages in separate loops over all contacts, because the
log -> exp chain in one vector loop body ran at half the speed.
"""

from __future__ import annotations

import numpy as np

from .compiled import law
from .elementary import exp_, log_

PALMGREN_EXPONENT = 10.0 / 9.0  # q ∝ δ^(10/9): inverse of δ ∝ Q^0.9


def palmgren_coefficient(compliance_m2_N: float) -> float:
    """A = 1.36 η^0.9 (SI: δ [m] = A Q^0.9 / l^0.8; 3.84e-5 in mm-N units for steel)."""
    return 1.36 * compliance_m2_N**0.9


def palmgren_approach(load_N, length_m: float, compliance_m2_N: float):
    """Approach δ [m] of a whole line contact of length l under load Q: δ = A Q^0.9 / l^0.8."""
    return palmgren_coefficient(compliance_m2_N) * load_N**0.9 / length_m**0.8


def slice_stiffness(slice_width_m: float, length_m: float, compliance_m2_N: float) -> float:
    """K_w [N/m^(10/9)] such that q_λ = K_w δ^(10/9): K_w = w / (A^(10/9) L^(1/9))."""
    A = palmgren_coefficient(compliance_m2_N)
    return slice_width_m / (A**PALMGREN_EXPONENT * length_m ** (1.0 / 9.0))


@law
def smooth_positive(approach_m, smoothing_m: float):
    """Regularised positive part s(δ) = (δ + sqrt(δ² + ε²))/2 and its slope ds/dδ = s/R.

    Evaluated as max(δ, 0) + ε²/(2 (R + |δ|)), R = sqrt(δ² + ε²): the same value without the
    cancellation that ruins the direct form deep in the gap (δ << -ε).
    """
    root = np.sqrt(approach_m * approach_m + smoothing_m * smoothing_m)
    s = np.maximum(approach_m, 0.0) + 0.5 * smoothing_m * smoothing_m / (root + np.abs(approach_m))
    return s, s / root


@law
def palmgren_load(smoothed_m, log_smoothed, smoothed_slope, stiffness: float):
    """q = K s^(10/9) [N] and dq/dδ = (10/9) K s^(1/9) ds/dδ [N/m] from the smoothed approach
    s, its logarithm ln s and its slope ds/dδ (``smooth_positive``); s^(1/9) = exp_(ln s / 9)."""
    s19 = exp_(log_smoothed * (1.0 / 9.0))
    return stiffness * smoothed_m * s19, PALMGREN_EXPONENT * stiffness * s19 * smoothed_slope


@law
def slice_load(approach_m, stiffness: float, smoothing_m: float):
    """Slice load q [N] and its slope dq/dδ [N/m] for approach δ (regularised Palmgren law)."""
    s, ds = smooth_positive(approach_m, smoothing_m)
    return palmgren_load(s, log_(s), ds, stiffness)


@law
def hertz_pressure(load_N, slice_width_m: float, reduced_radius_m: float, compliance_m2_N: float):
    """Maximum Hertz line-contact pressure p = sqrt(q E* / (π w R')) [Pa], E* = 1/η."""
    return np.sqrt(np.maximum(load_N, 0.0) / (np.pi * slice_width_m * reduced_radius_m
                                              * compliance_m2_N))
