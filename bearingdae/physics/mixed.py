"""Mixed lubrication of the slice contacts: the asperities' share of the load (theory.md §20).

Stage: physics (pure laws), called inside the DAE kernels (system/mixed.py) when
``physics.lubrication = "mixed"`` and by the post-processed power loss (analysis/engineering.py).

Below a film parameter λ = h_min / σ of about 3 the surface roughness (composite RMS σ,
``materials.roughness_um``) pierces the film and the asperities carry part of the slice load q.
The slice traction is then split by that share s(λ) (Johnson, Greenwood & Poon, Wear 19 (1972)
91-108: the load shared between the film and the asperities):

    F = (1 - s) F_EHL(q, V, p) + s μ_b q sg_b(V)

with F_EHL the EHL traction law of physics/traction.py on the film's share (linear in the load
at the slice's Hertz pressure p), μ_b the boundary friction coefficient
(``lubricant.boundary_friction``) and sg_b(V) = V / sqrt(V² + v_b²) the traction law's
regularised sign of the slip V (physics/traction.regularised_sign).

**Slip.** The EHL law's μ(|V|) vanishes at V = 0, so its sign needs next to no regularisation
(v₀ = 1e-12 m/s by default). The boundary friction is Coulomb's: with v₀ it would jump by
2 μ_b q within 1e-12 m/s, and a roller that the asperities hold at zero slip on one race
stalled IDA at steps of ~1e-11 s (the baseline: a million steps in 2.5 ms). Its sign is taken
on v_b = max(v₀, 1e-4 m/s) instead: the creep over which a rolling contact's friction builds
up. Carter's rolling contact reaches full slip at the creep ratio ξ = μ b / R' (b the Hertz
half-width; Johnson, *Contact Mechanics*, 1985, ch. 8), 0.1 x 0.1 mm / 5 mm = 2e-3, i.e. about
1e-2 m/s at the baseline's 5 m/s entrainment: v_b = 1e-4 m/s is well inside, so μ_b is fully
developed at the working slips (sg_b = 0.995 at 1 mm/s).
h_min is the Pan & Hamrock minimum film of physics/film.py at the slice's load per length and
entrainment speed.

**The share s(λ)** follows the Greenwood–Tripp asperity load of a Gaussian height distribution
(Greenwood & Tripp, Proc. Instn Mech. Engrs 185 (1970) 625-633): p_a ∝ F_5/2(λ), with
F_5/2(λ) = (2π)^(-1/2) ∫_λ^∞ (z - λ)^(5/2) e^(-z²/2) dz and its usual fit
F_5/2 ≈ 4.4086e-5 (4 - λ)^6.804 for λ < 4 (the fit common in mixed-lubrication models of
piston rings and gears; not taken from a source at hand here, so checked against the integral
instead: within 11 % where it carries the share, λ ≤ 1.5, tests/physics/test_mixed.py).
Normalised to the whole load at λ = 0 (no film left: the asperities carry everything) and with
the tangent at λ = 3 taken off, so that it is exactly 0 at and above λ = 3 with a continuous
slope (C¹) there:

    g(λ) = (4 - λ)^n - 1 - n (3 - λ),   s(λ) = g(λ) / g(0)   (λ < 3),   s = 0 (λ ≥ 3)

with n = 6.804. The tangent removed, 1 + n (3 - λ) ≤ 1 + 3n, is below 2e-3 of g(0): it moves
s by less than 0.002. Against the same construction on the integral F_5/2 itself, s is within
0.015 (tests/physics/test_mixed.py). Why this and not Greenwood–Tripp's absolute asperity pressure
K E' F_5/2(λ) (or Johnson–Greenwood–Poon's iterated sharing): those need the asperity
density, radius and slope (ηβσ, σ/β), which a bearing's data sheet does not give, and with
the usual values (ηβσ ≈ 0.04, σ/β ≈ 1e-3) K E' F_5/2(0) ≈ 20 MPa, a few per cent of the
raceways' Hertz pressure, so the asperities would never carry the load, even at λ → 0, where
the measured friction of a bearing is that of boundary lubrication. The normalised share keeps
the Gaussian tail's dependence on λ and needs no input beyond σ.
"""

from __future__ import annotations

import numpy as np

from .compiled import law
from .elementary import exp_, log_
from .film import _MIN
from .traction import regularised_sign, regularised_sign_slope

#: λ at and above which the film carries the whole load (s = 0 exactly)
LAMBDA_FULL_FILM = 3.0
#: Greenwood–Tripp F_5/2 fit: F_5/2(λ) ≈ GT_COEFFICIENT (GT_CUTOFF - λ)^GT_EXPONENT
GT_COEFFICIENT = 4.4086e-5
GT_CUTOFF = 4.0
GT_EXPONENT = 6.804
#: g(0) of the share: 4^n - 1 - 3 n
_G0 = GT_CUTOFF ** GT_EXPONENT - 1.0 - GT_EXPONENT * LAMBDA_FULL_FILM
#: 1/g(0): a product in the slice loops (a division by a constant stays a division there)
_INV_G0 = 1.0 / _G0
#: default boundary friction coefficient (scene key ``lubricant.boundary_friction``)
BOUNDARY_FRICTION = 0.1
#: slip scale [m/s] of the boundary friction's regularised sign (module docstring, "Slip")
BOUNDARY_SLIP_SCALE_M_S = 1e-4


def boundary_slip_scale(velocity_scale_m_s: float) -> float:
    """v_b [m/s] of sg_b(V) = V / sqrt(V² + v_b²): the traction law's v₀
    (``traction.velocity_scale_m_s``) or :data:`BOUNDARY_SLIP_SCALE_M_S`, the larger."""
    return max(float(velocity_scale_m_s), BOUNDARY_SLIP_SCALE_M_S)


@law
def asperity_share(film_parameter):
    """(s, ds/dλ): the asperities' share of the slice load at film parameter λ ≥ 0 (module
    docstring); exactly 0 (and slope 0) at λ ≥ 3, 1 at λ = 0."""
    below = film_parameter < LAMBDA_FULL_FILM
    x = GT_CUTOFF - (film_parameter if below else LAMBDA_FULL_FILM)
    xn1 = exp_((GT_EXPONENT - 1.0) * log_(x))  # x^(n-1), x in (1, 4]
    g = x * xn1 - 1.0 - GT_EXPONENT * (x - 1.0)
    slope = -GT_EXPONENT * (xn1 - 1.0) * _INV_G0
    return (g * _INV_G0 if below else 0.0), (slope if below else 0.0)


@law
def film_constants(slice_width_m, reduced_radius_m, viscosity_Pa_s, reduced_modulus_Pa,
                   min_factor, roughness_m):
    """(ln(R' c G^g / σ), -ln(Δl E'R'), ln(η₀ / (E'R'))): one race's constants of the film
    parameter λ = h_min / σ of a slice (h_min of physics/film.py for the load q over the
    slice width Δl) folded into logarithms, for :func:`film_parameter`."""
    ER = reduced_modulus_Pa * reduced_radius_m
    return (np.log(reduced_radius_m * min_factor / roughness_m), -np.log(slice_width_m * ER),
            np.log(viscosity_Pa_s / ER))


@law
def film_parameter(q_N, entrainment_m_s, ln_factor, ln_per_load, ln_per_speed):
    """(λ, dλ/dq [1/N], dλ/du [s/m]) of a slice, λ = h_min / σ (physics/film.py's minimum
    film), with its race's constants of :func:`film_constants`: λ = exp(ln(R' c G^g/σ) +
    a ln W' + b ln U), ln W' = ln q - ln(Δl E'R'), ln U = ln u + ln(η₀/(E'R')) (unloaded:
    W' = 1, no slope; standstill: 0). Three logarithms and an exponential, no division but
    the slopes' (the slice loops' cost); Pan & Hamrock's fit to round-off
    (tests/physics/test_mixed.py)."""
    loaded = q_N > 0.0
    rolling = entrainment_m_s > 0.0
    ln_w = log_(q_N if loaded else 1.0) + ln_per_load
    ln_u = log_(entrainment_m_s if rolling else 1.0) + ln_per_speed
    lam = exp_(ln_factor + _MIN[1] * (ln_w if loaded else 0.0)
               + _MIN[2] * (ln_u if rolling else 0.0))
    lam = lam if rolling else 0.0 * entrainment_m_s  # standstill: 0 (a NaN speed stays NaN)
    lam_q = _MIN[1] * lam / (q_N if loaded else 1.0)
    lam_u = _MIN[2] * lam / (entrainment_m_s if rolling else 1.0)
    return lam, lam_q if loaded else 0.0, lam_u if rolling else 0.0


@law
def _mixed_traction(F_ehl_N, q_N, slip_m_s, share, boundary_friction, velocity_scale_m_s):
    """(F, F_a): the slice traction (1 - s) F_EHL + s μ_b q sg_b(V) and its asperity part
    F_a = s μ_b q sg_b(V) [N] (``velocity_scale_m_s``: v_b of :func:`boundary_slip_scale`). F is F_EHL itself, bit for bit, where s = 0 (a select: s (F_b - F)
    added as 0 would turn -0.0 into 0.0)."""
    f_b = boundary_friction * q_N * regularised_sign(slip_m_s, velocity_scale_m_s)
    mixed = F_ehl_N + share * (f_b - F_ehl_N)
    return (mixed if share > 0.0 else F_ehl_N), share * f_b


@law
def _mixed_slopes(F, FV, Fq, Fu, q_N, slip_m_s, share, dshare_dq, dshare_du,
                  boundary_friction, velocity_scale_m_s):
    """(F, dF/dV, dF/dq, dF/du) of :func:`_mixed_traction` from the EHL law's (F, dF/dV, dF/dq,
    dF/du) and the share's slopes along q and u; the EHL values themselves where s = 0 and
    its slopes vanish (λ ≥ 3)."""
    sg = regularised_sign(slip_m_s, velocity_scale_m_s)
    f_b = boundary_friction * q_N * sg
    diff = f_b - F
    m = F + share * diff
    mV = FV + share * (boundary_friction * q_N
                       * regularised_sign_slope(slip_m_s, velocity_scale_m_s) - FV)
    mq = Fq + share * (boundary_friction * sg - Fq) + dshare_dq * diff
    mu = Fu - share * Fu + dshare_du * diff
    on = share > 0.0
    return (m if on else F), (mV if on else FV), (mq if on else Fq), (mu if on else Fu)


def friction_coefficient(film_parameter, ehl_coefficient, boundary_friction=BOUNDARY_FRICTION):
    """μ = (1 - s(λ)) μ_EHL + s(λ) μ_b of a slice in gross sliding (|V| >> v₀), vectorised: the
    Stribeck-like curve of the mixed model (theory.md §20)."""
    lam = np.asarray(film_parameter, dtype=float)
    s = np.vectorize(lambda v: asperity_share(v)[0])(lam)
    return (1.0 - s) * ehl_coefficient + s * boundary_friction
