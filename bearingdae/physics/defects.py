"""Local defects and waviness of the rolling surfaces: the extra separation of a slice contact
(theory.md §4, "Defects and waviness").

Stage: physics. A slice contact whose surface is pitted or wavy under it loses that much of
its approach: δ ← δ - h. The laws here give h [m] and its slope along the surface angle
φ [rad] (the DAE's analytic Jacobian needs dh/dθX = dh/dφ), for the contact point at angle φ
on a surface of radius R and a slice at axial position x:

* a defect (length l along the rolling direction, width W across it, depth D, centred at φ_c
  and x = 0): h = D_eff · S(s) · a(x), with s = R wrap(φ - φ_c) the arc length from its centre;
  - the profile S(s) = 1 over |s| ≤ l/2 - e, 0 beyond l/2, and a smooth C¹ ramp
    (smoothstep 3u² - 2u³, u = (l/2 - |s|)/e) over the edge length e at both ends.
    e = min(max(edge_mm, EDGE_MIN_M), l/2): a sharp edge (edge_mm = 0) is a jump of the
    residual, which an implicit integrator can only cross by cutting its step to nothing; it
    is smoothed over :data:`EDGE_MIN_M` (0.0025 mm: the least ramp at which the outputs no
    longer depend on it, see there), or, with ``numerics.defect_edges = "locate"``, kept sharp
    and its crossings located (:func:`edge_gap`, system/defect_sides.py);
  - a body that cannot reach the bottom rides over it, resting on the pit's two edges: the
    edges lie a half chord c = R_p sin(l / (2 R_p)) either side of the centre on the pitted
    surface (radius R_p), and the bridging surface (radius R_b) reaches below the pitted
    surface's own centre by sag(R_b) ± sag(R_p), sag(R) = R - sqrt(R² - c²), each added for
    a convex surface (a roller, the inner race) and subtracted for the concave outer race, so
    D_eff = min(D, that reach) (:func:`defect_depth`). On the yang20 bearing the races'
    curvature moves the reach by +10 % (inner race) and -8 % (outer race) of the roller's sag;
    a pit at least as long as the roller's diameter is reached to its bottom;
  - a(x), the share of the slice [x - w/2, x + w/2] inside the width [-W/2, W/2]
    (:func:`width_share`): 1 under the defect, 0 outside, the covered fraction at its border.
* waviness: h = A cos(n φ + ψ) for every harmonic (order n, amplitude A, phase ψ), summed.

The contact point's angle: on the outer race the roller's orbit angle θX; on the inner race,
which turns with the shaft, θX - θ_s(t) with θ_s the shaft angle, the integral of the ring
speed law (physics/loads.shaft_angle, exact for its piecewise-linear ramp). Laws are plain
arithmetic (physics/compiled.py): the kernels inline them.
"""

from __future__ import annotations

import math

import numpy as np

from .compiled import law
from .kinematics import wrap_angle

#: the least edge ramp [m]: a sharp edge (edge_mm = 0) is smoothed over 0.0025 mm. The outputs
#: converge to the sharp edge at first order in the ramp (each halving halves their change),
#: while IDA's step count stays within 9 % of the 0.05 mm ramp's (rtol 1e-6; 2 % at 1e-8) down
#: to 0.8 µm: IDA's step control, not the ramp, resolves the crossing in time. Halving 0.0025 mm
#: moves the ring acceleration RMS, the force-drop impulse and the acceleration signal by < 1 %
#: on the outer spall and the sharp roller spall (benchmarks/results/defect-edges.json,
#: "sharper"); halving 0.05 mm moved the signal 9 % and the roller's drop impulse 11 %. The ramp
#: is far below a Hertz half-width (~0.1 mm): it converges the slice model's sharp edge (each
#: slice's contact on its centre line); a patch's blur over its width is physics the slice
#: model leaves out, which an ``edge_mm`` of about the half-width imitates. The sharp edge itself
#: (numerics.defect_edges = "locate", its crossings located by IDA's root finding) is the limit
#: the ramps converge to, twice the least ramp's distance from half of it (first order).
EDGE_MIN_M = 2.5e-6


def defect_depth(depth_m: float, length_m: float, pitted_radius_m: float,
                 pitted_convex: bool, bridging_radius_m: float, bridging_convex: bool) -> float:
    """The depth [m] the bridging surface reaches in a pit of depth D and length l (arc) on the
    pitted surface (module docstring): min(D, ±sag(R_b) ± sag(R_p)) over the half chord
    c = R_p sin(l / (2 R_p)), each sag with + for a convex surface, - for a concave one; D
    itself when a convex bridging surface fits in (c ≥ R_b). A race pit: pitted = the race
    (the inner convex, the outer concave), bridging = the roller (convex); a roller pit the
    other way round."""
    c = pitted_radius_m * math.sin(min(0.5 * length_m / pitted_radius_m, 0.5 * math.pi))
    if bridging_convex and c >= bridging_radius_m:
        return depth_m

    def sag(radius_m):
        return radius_m - math.sqrt(max(radius_m * radius_m - c * c, 0.0))

    reach = ((1.0 if bridging_convex else -1.0) * sag(bridging_radius_m)
             + (1.0 if pitted_convex else -1.0) * sag(pitted_radius_m))
    return min(depth_m, max(reach, 0.0))


def edge_ramp(edge_m: float, length_m: float, least_m: float | None = None) -> float:
    """The ramp length e [m] a defect's profile uses: min(max(edge, least), l/2), the least
    ramp ``least_m`` :data:`EDGE_MIN_M` unless given (None)."""
    least = EDGE_MIN_M if least_m is None else least_m
    return min(max(edge_m, least), 0.5 * length_m)


@law
def width_share(x_m, slice_width_m, half_width_m):
    """The share [-] of the slice [x - w/2, x + w/2] inside [-W/2, W/2]."""
    lo = max(x_m - 0.5 * slice_width_m, -half_width_m)
    hi = min(x_m + 0.5 * slice_width_m, half_width_m)
    return max(hi - lo, 0.0) / slice_width_m


@law
def defect_profile(arc_m, half_length_m, ramp_m):
    """(S, dS/ds): the defect's profile [-] at arc length s [m] from its centre, 1 in the
    middle, C¹ smoothstep ramps of length e inside both ends, 0 beyond l/2."""
    a = abs(arc_m)
    if a >= half_length_m:
        return 0.0, 0.0
    u = (half_length_m - a) / ramp_m
    if u >= 1.0:
        return 1.0, 0.0
    sign = 1.0 if arc_m >= 0.0 else -1.0
    return u * u * (3.0 - 2.0 * u), -6.0 * u * (1.0 - u) / ramp_m * sign


@law
def edge_gap(phi_rad, centre_rad, radius_m, half_length_m):
    """l/2 - |s| [m]: how far inside a defect's nearer edge the surface angle φ lies (s = R
    wrap(φ - φ_c) the arc length from its centre; negative outside). Continuous in φ (also
    where wrap jumps: |s| = πR on both sides); a sharp edge is crossed where it changes sign,
    which IDA's root finding locates (numerics.defect_edges = "locate", system/defect_sides.py)."""
    return half_length_m - abs(radius_m * wrap_angle(phi_rad - centre_rad))


@law
def defect_separation(phi_rad, centre_rad, radius_m, half_length_m, ramp_m, depth_m):
    """(h, dh/dφ): a defect's separation [m] (without its width share) at surface angle φ."""
    s = radius_m * wrap_angle(phi_rad - centre_rad)
    S, dS = defect_profile(s, half_length_m, ramp_m)
    return depth_m * S, depth_m * dS * radius_m


@law
def waviness_separation(phi_rad, order, amplitude_m, phase_rad):
    """(h, dh/dφ): one waviness harmonic's separation A cos(n φ + ψ) [m] and its slope."""
    a = order * phi_rad + phase_rad
    return amplitude_m * np.cos(a), -order * amplitude_m * np.sin(a)
