"""Oil-air mixture: orbit drag on the rollers, churning of roller ends and cage faces (theory.md §9).

Sits between the roller/cage speeds and the equations of motion (theory.md §10: F_D in the orbit
equation, M_lr in the spin equation, M_lc in the cage equation).

- Mixture density ρ_e = X ρ_oil + (1 - X) ρ_air.
- Orbit drag F_D = ½ C_D ρ_e D_w L (R_m Ω)² sign(Ω), written ½ C_D ρ_e D_w L R_m² Ω|Ω| (C¹ at
  Ω = 0, no sign regularisation needed), with C_D(Re) of a circular cylinder in cross-flow,
  Re = ρ_e D_w R_m |Ω| / μ_oil.
- Churning of a rotating disk, M = ½ ρ_e ω² r⁵ C_M with C_M = 3.87/√Re (Re = ρ_e ω r²/μ < 3e5),
  else 0.146/Re^0.2 (Schlichting's free disk). C_M is defined on the moment of the disk **wetted
  on both sides**: the laminar branch equals twice von Kármán's one-face torque
  (π/2)·0.6159·ρ r⁴ sqrt(ν ω³). A roller's two end faces are those two sides, so
  M_lr = ½ ρ_e ω² r⁵ C_M with no extra factor 2; likewise the cage's two side faces,
  with r⁵ → r_o⁵ - r_i⁵ and Re from r_o, give M_lc.

**Sign convention**: every function returns a value with the sign of its speed argument
(Ω or ω); it is a resistance, so the caller **subtracts** it (theory.md §10: "- F_D", "- M_lr",
"- M_lc"). The two churning branches are not continuous at Re = 3e5 (as in the source law); a
step in a resistance is harmless at that size, but the Jacobian sees a jump there.

All functions are pure arithmetic, physics laws (physics/compiled.py): plain numpy from
Python, inlined when called from an ``@njit`` kernel.
"""

from __future__ import annotations

import numpy as np
from numba import types
from numba.extending import overload

from .compiled import law

AIR_DENSITY_KG_M3 = 1.2

#: C_D of a circular cylinder in cross-flow (theory.md §9 table). **[reading]** "log-linear in Re":
#: C_D is interpolated linearly in log10(Re) between nodes and held constant outside the table
#: (60 below Re = 0.1, 0.3 above 5e5).
_CD_LOG10_RE = np.log10(np.array([0.1, 1.0, 10.0, 100.0, 1e3, 1e4, 2e5, 3e5, 4e5, 5e5]))
_CD_VALUES = np.array([60.0, 10.0, 3.0, 1.8, 1.0, 1.2, 1.2, 0.9, 0.65, 0.3])

CHURNING_TRANSITION_RE = 3e5  # laminar C_M = 3.87/√Re below, turbulent 0.146/Re^0.2 above


@law
def effective_density(oil_fraction, oil_density_kg_m3, air_density_kg_m3=AIR_DENSITY_KG_M3):
    """Oil-air mixture density ρ_e = X ρ_oil + (1 - X) ρ_air [kg/m³] (theory.md §9)."""
    return oil_fraction * oil_density_kg_m3 + (1.0 - oil_fraction) * air_density_kg_m3


_CD_SLOPES = np.diff(_CD_VALUES) / np.diff(_CD_LOG10_RE)
# The same table as tuples for the loop below: a global array in compiled code is reference
# counted (calls into numba's runtime at each use), which kept the residual's roller loop from
# vectorising; tuples are plain constants.
_CD_NODES = tuple(float(v) for v in _CD_LOG10_RE)
_CD_STEPS = tuple(float(v) for v in _CD_SLOPES)
_CD_FIRST = float(_CD_VALUES[0])


@law
def drag_log_reynolds(reynolds):
    """x = log10 Re of the drag table, Re floored at 1e-3 (the argument of
    :func:`drag_coefficient_at_log`)."""
    return np.log10(np.maximum(reynolds, 1e-3))


@law
def drag_coefficient_at_log(log_reynolds):
    """C_D at x = log10 Re: the table of :func:`drag_coefficient_cylinder` (plain arithmetic:
    a compiled loop over rollers vectorises it; the logarithm, a libm call, is taken apart)."""
    x = log_reynolds
    cd = _CD_FIRST + 0.0 * x
    for k in range(len(_CD_STEPS)):
        lo = _CD_NODES[k]
        cd = cd + _CD_STEPS[k] * (np.minimum(np.maximum(x, lo), _CD_NODES[k + 1]) - lo)
    return cd


@law
def drag_coefficient_cylinder(reynolds):
    """C_D(Re) of a cylinder in cross-flow: linear in log10 Re between table nodes, clamped.

    Written as a sum of clipped ramps, C_D = C_0 + Σ_k slope_k (clip(x, x_k, x_k+1) - x_k) with
    x = log10 Re: the same values as ``np.interp`` (tested), for scalars and arrays alike, and
    quick to compile.
    """
    return drag_coefficient_at_log(drag_log_reynolds(reynolds))


@law
def orbit_drag_reynolds(orbit_speed_rad_s, pitch_radius_m, roller_diameter_m, density_kg_m3,
                        viscosity_Pa_s):
    """Re = ρ_e D_w R_m |Ω| / μ of a roller's orbit through the oil-air mixture."""
    speed = pitch_radius_m * orbit_speed_rad_s
    return density_kg_m3 * roller_diameter_m * np.abs(speed) / viscosity_Pa_s


@law
def orbit_drag_at(drag_coefficient, orbit_speed_rad_s, pitch_radius_m, roller_diameter_m,
                  roller_length_m, density_kg_m3):
    """F_D = ½ C_D ρ_e D_w L R_m² Ω|Ω| [N] for a given C_D (:func:`orbit_drag_force`)."""
    speed = pitch_radius_m * orbit_speed_rad_s
    return (0.5 * drag_coefficient * density_kg_m3 * roller_diameter_m
            * roller_length_m * speed * np.abs(speed))


@law
def orbit_drag_force(orbit_speed_rad_s, pitch_radius_m, roller_diameter_m, roller_length_m,
                     density_kg_m3, viscosity_Pa_s):
    """Orbit drag F_D = ½ C_D ρ_e D_w L R_m² Ω|Ω| [N], signed like Ω (caller subtracts)."""
    reynolds = orbit_drag_reynolds(orbit_speed_rad_s, pitch_radius_m, roller_diameter_m,
                                   density_kg_m3, viscosity_Pa_s)
    return orbit_drag_at(drag_coefficient_cylinder(reynolds), orbit_speed_rad_s, pitch_radius_m,
                         roller_diameter_m, roller_length_m, density_kg_m3)


@law
def _churning(omega_rad_s, radius5_m5, reference_radius_m, density_kg_m3, viscosity_Pa_s):
    """½ ρ ω|ω| R5 C_M(Re), Re = ρ|ω| r_ref²/μ; R5 = r⁵ (disk) or r_o⁵ - r_i⁵ (annulus).

    The laminar branch is evaluated as 1.935 sqrt(ρ μ) ω sqrt|ω| R5 / r_ref (identical, but
    exact and finite as ω → 0: M ∝ ω^1.5); Re in the turbulent branch is floored at the
    transition so the branch not taken stays finite.
    """
    a = np.abs(omega_rad_s)
    reynolds = density_kg_m3 * a * reference_radius_m**2 / viscosity_Pa_s
    laminar = (0.5 * 3.87 * np.sqrt(density_kg_m3 * viscosity_Pa_s) * omega_rad_s * np.sqrt(a)
               * radius5_m5 / reference_radius_m)
    turbulent = (0.5 * density_kg_m3 * omega_rad_s * a * radius5_m5 * 0.146
                 * turbulent_reynolds_factor(reynolds))
    is_laminar = (reynolds < CHURNING_TRANSITION_RE) * 1.0
    return is_laminar * laminar + (1.0 - is_laminar) * turbulent


def turbulent_reynolds_factor(reynolds):
    """max(Re, Re_t)^-0.2, the turbulent branch's Reynolds factor (floored at the transition)."""
    return np.maximum(reynolds, CHURNING_TRANSITION_RE) ** -0.2


# Compiled, for one float: the branch-free law evaluates the turbulent branch also where it is
# not taken (the baseline's rollers and cage churn at Re ~ 10-100, laminar), and there the
# floored factor is the constant below, the same libm pow of the same double: skipping the pow
# call there changes no bit.
_FACTOR_AT_TRANSITION = CHURNING_TRANSITION_RE ** -0.2


@overload(turbulent_reynolds_factor)
def _ol_turbulent_reynolds_factor(reynolds):
    if isinstance(reynolds, types.Float):
        def impl(reynolds):
            if reynolds > CHURNING_TRANSITION_RE:
                return reynolds ** -0.2
            if reynolds <= CHURNING_TRANSITION_RE:
                return _FACTOR_AT_TRANSITION
            return reynolds ** -0.2  # NaN, as np.maximum gives
        return impl


@law
def churning_moment(omega_rad_s, radius_m, density_kg_m3, viscosity_Pa_s):
    """Disk churning M = ½ ρ_e ω² r⁵ C_M [N m] (both faces), signed like ω (caller subtracts)."""
    return _churning(omega_rad_s, radius_m**5, radius_m, density_kg_m3, viscosity_Pa_s)


@law
def churning_moment_annulus(omega_rad_s, inner_radius_m, outer_radius_m, density_kg_m3,
                            viscosity_Pa_s):
    """Annulus churning ½ ρ_e ω² (r_o⁵ - r_i⁵) C_M(Re(r_o)) [N m] (both faces), signed like ω."""
    return _churning(omega_rad_s, outer_radius_m**5 - inner_radius_m**5, outer_radius_m,
                     density_kg_m3, viscosity_Pa_s)


@law
def roller_end_churning(spin_rad_s, roller_radius_m, density_kg_m3, viscosity_Pa_s):
    """M_lr [N m] of a roller's two end faces: C_M counts both sides, so factor 1 (module doc)."""
    return churning_moment(spin_rad_s, roller_radius_m, density_kg_m3, viscosity_Pa_s)


@law
def cage_side_churning(cage_speed_rad_s, inner_radius_m, outer_radius_m, density_kg_m3,
                       viscosity_Pa_s):
    """M_lc [N m] of the cage's two side faces (annulus, both sides counted by C_M)."""
    return churning_moment_annulus(cage_speed_rad_s, inner_radius_m, outer_radius_m,
                                   density_kg_m3, viscosity_Pa_s)
