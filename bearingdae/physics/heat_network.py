"""Temperatures: the bearing's lumped thermal network and its steady state (theory.md §21).

Pipeline: physics (pure, SI; numpy only: nothing here enters the DAE residual). The run's
thermal coupling (run/thermal_coupling.py) solves the network's steady state under a block's
mean power losses and sets the oil viscosity the kernel reads from the oil temperature
(physics/oil_viscosity.py).

* Nodes :data:`NODES`: inner ring, outer ring, rollers (all together), cage, oil. The node
  temperatures T solve the steady balance G T = q + g_b T_b: G the conductance matrix (the
  links between nodes plus each node's links to fixed temperatures g_b, its diagonal),
  q the heat entering each node [W] (:func:`node_heat`).
* Links (theory.md §21): ring sections by radial conduction through a cylindrical shell,
  G = 2π k B / ln(r_out/r_in); roller-race contacts by conduction through the Hertz contact
  bands over the roller radius, G = k A_band / r; convection to the oil G = h A; the oil flow
  ρ c_p Q to the oil inlet temperature; shaft and housing by given conductances (in series
  with the ring sections) to the ambient temperature.
"""

from __future__ import annotations

import math

import numpy as np

#: the network's nodes, in the order of every array here
NODES = ("inner_ring", "outer_ring", "rollers", "cage", "oil")
NODE_NAMES = {"inner_ring": "inner ring", "outer_ring": "outer ring",
              "rollers": "rollers (all)", "cage": "cage", "oil": "oil in the bearing"}


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
