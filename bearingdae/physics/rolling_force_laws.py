"""Published hydrodynamic rolling-force laws of a line contact on one dimensionless interface.

Pipeline: physics (numpy, vectorised). The laws themselves are physics/rolling_resistance.py's,
the ones the residual calls (``physics.rolling_resistance``, docs/theory.md §19); this module
puts them on B&H's dimensionless interface side by side, and tools/rolling_force_laws.py
tabulates them (docs/data/rolling_force_laws.csv).

**The interface** (Biboulet & Houpert 2010, "Hydrodynamic force and moment in pure rolling
lubricated contacts. Part 1: line contacts", Proc. IMechE J 224, 765-775, doi
10.1243/13506501JET790; "B&H" below), their eq. (14):

    U = 2 η₀ u_m / (E' R)   (the factor 2: u_m the mean surface speed),
    W = w_l / (E' R),   G = α E',   M_l = W / sqrt(U),   L = G U^(1/4),

with 2/E' = Σ (1 - ν²)/E (eq. 2; physics/film.py's reduced modulus) and R the reduced radius;
each law returns F̃ = f_l / (E' R), the rolling force per unit length f_l over E' R (eq. 20).

**Biboulet & Houpert** (:func:`biboulet_houpert`). The fully flooded moment in Hertzian
units, T* = t_l / (p_h b²), from the rigid-isoviscous to the EHL regime (eq. 42):

    T* = M_l^(-3/2) 1.4 sqrt(M_l) / (1 + ((1.4/1.45) sqrt(M_l))^10)^(1/10),

which joins the IVR asymptote T*_IVR = 1.4 / M_l (eq. 40) and the EHL one T*_EHL∞ = 1.45
M_l^(-3/2) (eq. 41); fitted to their numerical results over L = 4-16, M_l = 0.2-200 (G and L
have no effect on it there). With b E' / (4 R p_h) = 1 and W = π p_h b / (2 E' R) (eq. 14),
p_h b² = E' R² (8W/π)^(3/2) / 4, so T̃ = t_l / (E' R²) = T (8W/π)^(3/2) / 4 (1.42 sqrt(UW)
and 1.47 U^(3/4) at the asymptotes, as eqs. 40-41 print). The rolling force times R is the
moment (eq. 31, T̃ ≈ F̃): F̃ = T̃. Starvation (eq. 44): with S = H_a / H_m*, the film
available at the inlet over the fully flooded minimum film,

    T / T* = (S² + 162.8 S) / (S² + 193.1 S + 1257),

fitted to IVR and EHL results alike; B&H computed down to S = 2 ("a maximum starvation of
S = 2"), so below 2 the fit is extrapolated.

**Goksem & Hargreaves** (:func:`goksem_hargreaves`): physics/rolling_resistance.py's fit,
isothermal; its U is η₀ u / (E'R), half B&H's (F̃ = 2.74 U^0.658
W^0.0126 G^-0.342 in B&H's U, their eq. 39).

**Zhou & Hoeprich** (:func:`zhou_hoeprich`; R. S. Zhou, M. R. Hoeprich, "Torque of tapered
roller bearings", J. Tribol. 113 (1991) 590-597) as B&H's eq. (39) restates it in their U:
F̃ = 18.62 U^0.648 W^0.246 G^-0.352. The original paper was not available here; B&H's
restatement is checked against their printed ratio to T̃*_EHL∞ (0.939 at U = 1e-11,
W = 1e-4, G = 4000; tests/physics/test_rolling_force_laws.py).

Goksem & Hargreaves's and Zhou & Hoeprich's fits are fully flooded; :func:`rolling_force`
scales every law by B&H's T/T* when S is given (B&H found the ratio law-independent over the
IVR and EHL regimes; for the other two fits this is our reading, not their authors').
"""

from __future__ import annotations

import numpy as np

from . import rolling_resistance as _law
from .rolling_resistance import (BH_BLEND, BH_EHL, BH_IVR, BH_STARVATION,  # noqa: F401
                                 ZH_FACTOR, ZH_G, ZH_U, ZH_W)

#: B&H's G of steel with a mineral oil, with which their (L, M_l) range maps to (U, W)
BH_STEEL_G = 4520.0


def moes_parameters(U, W):
    """(M_l, L / G) of B&H's eq. (14): M_l = W / sqrt(U), L / G = U^(1/4)."""
    U = np.asarray(U, dtype=float)
    return np.asarray(W, dtype=float) / np.sqrt(U), U ** 0.25


def dimensionless_from_moes(M_l, L, G=BH_STEEL_G):
    """(U, W, G) of the Moes parameters (M_l, L) at material parameter G (inverse of eq. 14)."""
    U = (np.asarray(L, dtype=float) / G) ** 4
    return U, np.asarray(M_l, dtype=float) * np.sqrt(U), np.full_like(U, G)


def flooded_moment_hertzian(M_l):
    """T* = t_l / (p_h b²), B&H's fully flooded moment, IVR to EHL (eq. 42), in Hertzian units
    (the form B&H print; the force law is physics/rolling_resistance.biboulet_houpert)."""
    M = np.asarray(M_l, dtype=float)
    root = np.sqrt(M)
    blend = (1.0 + (BH_IVR / BH_EHL * root) ** BH_BLEND) ** (1.0 / BH_BLEND)
    return M ** -1.5 * BH_IVR * root / blend


def hertzian_to_tilde(T, W):
    """T̃ = t_l / (E' R²) of a Hertzian moment T = t_l / (p_h b²) at load W (module docstring:
    p_h b² = E' R² (8W/π)^(3/2) / 4)."""
    return np.asarray(T, dtype=float) * (8.0 * np.asarray(W, dtype=float) / np.pi) ** 1.5 / 4.0


def starvation_ratio(S):
    """T / T* of B&H's eq. (44) at S = H_a / H_m* (NaN: fully flooded, ratio 1)."""
    S = np.asarray(S, dtype=float)
    return np.where(np.isnan(S), 1.0, _law.starvation_ratio(S)[0])


def _unit_contact(U, W):
    """(w', R', u, η₀, E') of a contact whose B&H (U, W) are the given ones: E' = R' = η₀ = 1,
    w' = W, u = U/2 (eq. 14's factor 2)."""
    U, W = np.broadcast_arrays(np.asarray(U, dtype=float), np.asarray(W, dtype=float))
    return W, 1.0, 0.5 * U, 1.0, 1.0


def biboulet_houpert(U, W, G):
    """F̃ fully flooded of B&H (eqs. 14, 31, 42), physics/rolling_resistance.py's law without
    its light-load regularisation; G unused (no effect in their range)."""
    w, R, u, eta, E = _unit_contact(U, W)
    return np.asarray(_law.biboulet_houpert(w, R, u, eta, E, 0.0)[0], dtype=float)


def goksem_hargreaves(U, W, G):
    """F̃ fully flooded, isothermal, of physics/rolling_resistance.py's Goksem & Hargreaves
    law, in B&H's U: that law at E' = R = 1, w' = W, α = G, η₀ u = U / 2, no thermal term."""
    U, W, G = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (U, W, G)))
    w, R, u, eta, E = _unit_contact(U, W)
    return np.asarray(_law.goksem_hargreaves(w, R, u, eta, G, E, 0.0, 1.0)[0], dtype=float)


def zhou_hoeprich(U, W, G):
    """F̃ fully flooded of Zhou & Hoeprich as B&H's eq. (39) restates it (module docstring),
    physics/rolling_resistance.py's law."""
    U, W, G = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (U, W, G)))
    w, R, u, eta, E = _unit_contact(U, W)
    return np.asarray(_law.zhou_hoeprich(w, R, u, eta, G, E)[0], dtype=float)


#: law name -> its fully flooded F̃(U, W, G)
LAWS = {"biboulet_houpert": biboulet_houpert, "goksem_hargreaves": goksem_hargreaves,
        "zhou_hoeprich": zhou_hoeprich}


def rolling_force(law: str, U, W, G, S=np.nan):
    """F̃ = f_l / (E' R) of ``law`` (:data:`LAWS`) at (U, W, G) of B&H's eq. (14), times B&H's
    starvation ratio T/T* at S = H_a / H_m* (NaN, the default: fully flooded)."""
    if law not in LAWS:
        raise ValueError(f"rolling force law {law!r}: one of {', '.join(LAWS)}")
    return LAWS[law](U, W, G) * starvation_ratio(S)
