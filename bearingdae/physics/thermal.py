"""Temperatures: a lumped thermal network, the oil's viscosity-temperature law and ISO 281's κ
(theory.md §21).

Pipeline: physics (pure, SI; numpy only: nothing here enters the DAE residual). The run's
thermal coupling (run/thermal.py) solves the network's steady state under a block's mean power
losses and sets the oil viscosity the kernel reads from the oil temperature.

* Nodes :data:`NODES`: inner ring, outer ring, rollers (all together), cage, oil. The node
  temperatures T solve the steady balance G T = q + g_b T_b: G the conductance matrix (the
  links between nodes plus each node's links to fixed temperatures g_b, its diagonal),
  q the heat entering each node [W] (:func:`node_heat`).
* Links (theory.md §21): ring sections by radial conduction through a cylindrical shell,
  G = 2π k B / ln(r_out/r_in); roller-race contacts by conduction through the Hertz contact
  bands over the roller radius, G = k A_band / r; convection to the oil G = h A; the oil flow
  ρ c_p Q to the oil inlet temperature; shaft and housing by given conductances (in series
  with the ring sections) to the ambient temperature.
* Viscosity: ASTM D341 (Walther) log10 log10(ν + 0.7) = A − B log10 T [ν mm²/s, T K], through
  two given points (ν at 40 °C and 100 °C).
* ISO 281:2007 rated viscosity ν₁(n, d_m) and κ = ν/ν₁.
"""

from __future__ import annotations

import math

import numpy as np

#: the network's nodes, in the order of every array here
NODES = ("inner_ring", "outer_ring", "rollers", "cage", "oil")
NODE_NAMES = {"inner_ring": "inner ring", "outer_ring": "outer ring",
              "rollers": "rollers (all)", "cage": "cage", "oil": "oil in the bearing"}

#: Walther's constant of ASTM D341 (ν in mm²/s; the standard's simple form, ν ≥ 2 mm²/s)
WALTHER_OFFSET_MM2_S = 0.7
ZERO_CELSIUS_K = 273.15


def node_heat(mean_loss_W: dict, partition: dict) -> np.ndarray:
    """Heat entering each node [W] from the mean power loss by source and where each source
    is dissipated: ``partition`` {source: shares of (inner ring, outer ring, rollers, cage,
    oil)}, each row summing to 1 (each source declares its own: system/effect.Source). A
    source without a row is an error naming it (every source must say where it goes)."""
    q = np.zeros(len(NODES))
    for source, watts in mean_loss_W.items():
        if source not in partition:
            raise KeyError(f"power-loss source '{source}' has no heat partition (where its "
                           "heat goes: its declaration's Source.heat)")
        q += float(watts) * np.asarray(partition[source])
    return q


def shell_conductance(conductivity_W_mK: float, width_m: float, r_in_m: float,
                      r_out_m: float) -> float:
    """Radial conduction through a cylindrical shell, G = 2π k B / ln(r_out / r_in) [W/K]
    (Incropera & DeWitt, Fundamentals of Heat and Mass Transfer, Eq. 3.27)."""
    return 2.0 * math.pi * conductivity_W_mK * width_m / math.log(r_out_m / r_in_m)


def series(*conductances: float) -> float:
    """Conductances in series, 1 / Σ 1/G_i [W/K] (0 if any is 0)."""
    if any(g <= 0.0 for g in conductances):
        return 0.0
    return 1.0 / sum(1.0 / g for g in conductances)


def band_area(load_N, pressure_Pa, slice_width_m: float):
    """Area of the Hertz line-contact band of each slice, 2 b w with b = 2 q / (π w p)
    (p = 2 w'/(π b), w' = q/w the load per length) [m²]; 0 where a slice carries nothing."""
    q = np.asarray(load_N, dtype=float)
    p = np.asarray(pressure_Pa, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        b = np.where(p > 0.0, 2.0 * q / (np.pi * slice_width_m * p), 0.0)
    return 2.0 * b * slice_width_m


def contact_conductance(conductivity_W_mK: float, band_area_m2: float,
                        roller_radius_m: float) -> float:
    """Roller-race link through the contact bands: G = k A_band / r [W/K], conduction over the
    roller radius through the summed band area A_band of one race (theory.md §21)."""
    return conductivity_W_mK * band_area_m2 / roller_radius_m


def conductance_matrix(links: dict, to_fixed: np.ndarray) -> np.ndarray:
    """G of G T = q + g_b T_b: ``links`` {(node a, node b): G_ab [W/K]} between nodes, and
    ``to_fixed`` (n,) each node's summed conductance to fixed temperatures (the diagonal)."""
    n = len(NODES)
    G = np.diag(np.asarray(to_fixed, dtype=float).copy())
    for (a, b), g in links.items():
        i, j = NODES.index(a), NODES.index(b)
        G[i, i] += g
        G[j, j] += g
        G[i, j] -= g
        G[j, i] -= g
    return G.reshape(n, n)


def steady_temperatures(G: np.ndarray, heat_W, fixed_flow_W) -> np.ndarray:
    """Node temperatures of the steady balance G T = q + g_b T_b [same unit as T_b];
    ``fixed_flow_W`` = g_b T_b (n,). A network with no path to a fixed temperature has no
    steady state: ValueError."""
    G = np.atleast_2d(np.asarray(G, dtype=float))
    rhs = np.asarray(heat_W, dtype=float) + np.asarray(fixed_flow_W, dtype=float)
    if np.linalg.cond(G) > 1e12:
        raise ValueError("the thermal network has no path from every node to a fixed "
                         "temperature (oil flow, shaft, housing): no steady state")
    return np.linalg.solve(G, rhs)


# ---------------------------------------------------------------------------------------------
# Viscosity and temperature (ASTM D341) and ISO 281's viscosity ratio
# ---------------------------------------------------------------------------------------------
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
