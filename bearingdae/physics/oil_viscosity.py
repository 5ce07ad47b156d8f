"""The oil's viscosity against temperature (ASTM D341) and the viscosity ISO 281 compares it
with (theory.md §21).

Pipeline: physics (pure, SI except where the standards' units are named; numpy only). The
thermal run's oil viscosity follows its temperature through these laws
(system/thermal_network.py); the rating life reads κ = ν/ν₁ (analysis/rating_life.py).

* Viscosity: ASTM D341 (Walther) log10 log10(ν + 0.7) = A − B log10 T [ν mm²/s, T K], through
  two given points (ν at 40 °C and 100 °C).
* ISO 281:2007 rated viscosity ν₁(n, d_m) and κ = ν/ν₁.
"""

from __future__ import annotations

import math

import numpy as np

#: Walther's constant of ASTM D341 (ν in mm²/s; the standard's simple form, ν ≥ 2 mm²/s)
WALTHER_OFFSET_MM2_S = 0.7
ZERO_CELSIUS_K = 273.15


def walther_constants(t1_C: float, nu1_mm2_s: float, t2_C: float, nu2_mm2_s: float):
    """(A, B) of ASTM D341, log10 log10(ν + 0.7) = A − B log10(T / K), through two points."""
    z1 = math.log10(math.log10(nu1_mm2_s + WALTHER_OFFSET_MM2_S))
    z2 = math.log10(math.log10(nu2_mm2_s + WALTHER_OFFSET_MM2_S))
    x1, x2 = math.log10(t1_C + ZERO_CELSIUS_K), math.log10(t2_C + ZERO_CELSIUS_K)
    B = (z1 - z2) / (x2 - x1)
    return z1 + B * x1, B


def walther_viscosity(temperature_C, A: float, B: float):
    """Kinematic viscosity ν [mm²/s] at ``temperature_C`` by ASTM D341 with constants (A, B)."""
    x = np.log10(np.asarray(temperature_C, dtype=float) + ZERO_CELSIUS_K)
    return 10.0 ** (10.0 ** (A - B * x)) - WALTHER_OFFSET_MM2_S


def walther_temperature_coefficient(temperature_C: float, A: float, B: float) -> float:
    """β = −d ln η / dT [1/K] of the oil of (A, B) at ``temperature_C`` (ρ held constant:
    −d ln ν / dT), from ASTM D341: with w = log10(ν + 0.7), dν/dT = −(ν + 0.7) w ln10 B / T,
    so β = (ν + 0.7) w ln10 B / (ν T). The temperature-viscosity coefficient of the EHL
    thermal reduction laws, at the operating temperature instead of a constant."""
    T = float(temperature_C) + ZERO_CELSIUS_K
    nu = float(walther_viscosity(temperature_C, A, B))
    w = math.log10(nu + WALTHER_OFFSET_MM2_S)
    return (nu + WALTHER_OFFSET_MM2_S) * w * math.log(10.0) * B / (nu * T)


def walther_temperature(nu_mm2_s: float, A: float, B: float) -> float:
    """The temperature [°C] at which the oil of (A, B) has viscosity ``nu_mm2_s``."""
    z = math.log10(math.log10(nu_mm2_s + WALTHER_OFFSET_MM2_S))
    return 10.0 ** ((A - z) / B) - ZERO_CELSIUS_K


def rated_viscosity(speed_rpm: float, pitch_diameter_mm: float) -> float:
    """ISO 281:2007 rated (reference) viscosity ν₁ [mm²/s] of its life modification factor,
    the viscosity needed for adequate lubrication: 45000 n^-0.83 d_m^-0.5 for n < 1000 r/min, else
    4500 n^-0.5 d_m^-0.5 (n [r/min], d_m [mm]). NaN at n = 0 and where it leaves the float
    range (a ring as good as standing still): the standard defines it for a turning ring only,
    and an infinite ν₁ (as stored before) read as a number."""
    n, dm = float(speed_rpm), float(pitch_diameter_mm)
    if not n > 0.0:
        return math.nan
    try:
        nu = 45000.0 * n ** -0.83 * dm ** -0.5 if n < 1000.0 else 4500.0 * n ** -0.5 * dm ** -0.5
    except OverflowError:
        return math.nan
    return nu if math.isfinite(nu) else math.nan
