"""The inner ring as a body (theory.md §15): its mass and tilt inertia from the geometry, and
the elastic support to ground.

Stage: physics, used by system/model.py (parameters) and the DAE kernels (support law).

- Ring: a steel annulus from the bore d/2 to the inner raceway R_i = R_m − r, of the rollers'
  length L (the raceway's width; shoulders and flanges are neglected):
  m = ρ π (R_i² − (d/2)²) L,  I_d = m (3 (R_i² + (d/2)²) + L²) / 12 (about a diameter; a thick
  cylindrical shell, e.g. Gere & Goodno, *Mechanics of Materials*, App. E).
- Support: a linear spring-damper to ground in each radial direction, in parallel with the
  bearing: F_s = −k δ − c δ'.
"""

from __future__ import annotations

import math

from .compiled import law


def ring_mass_inertia(bore_m: float, raceway_radius_m: float, width_m: float,
                      density_kg_m3: float) -> tuple[float, float]:
    """(m [kg], I_d [kg m²]) of the inner ring annulus (module docstring)."""
    ro, ri = raceway_radius_m, 0.5 * bore_m
    m = density_kg_m3 * math.pi * (ro * ro - ri * ri) * width_m
    return m, m * (3.0 * (ro * ro + ri * ri) + width_m * width_m) / 12.0


@law
def support_force(stiffness_N_m, damping_N_s_m, displacement_m, velocity_m_s):
    """Support force on the ring [N] along one direction, F = −k δ − c δ'; its slopes are −k
    (displacement) and −c (velocity)."""
    return -stiffness_N_m * displacement_m - damping_N_s_m * velocity_m_s
