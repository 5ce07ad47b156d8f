"""EHL rolling resistance of the slice contacts (docs/theory.md §19).

Pipeline: physics (pure laws). Called by the residual and Jacobian passes of
system/rolling_resistance.py (compiled inline) and by physics/power.py (numpy, the power
source ``rolling_resistance``), with ``[physics] rolling_resistance = true`` only.

**Law: Goksem & Hargreaves (1978)**, the rolling traction of a fully flooded Newtonian EHL line
contact with inlet shear heating (P. G. Goksem, R. A. Hargreaves, "The effect of viscous shear
heating on both film thickness and rolling traction in an EHL line contact, Part I: Fully
flooded conditions", J. Lubrication Technology 100 (1978) 346-352, curve fit of their thermal
solutions). The rolling force per unit length on each surface, against the entrainment:

    f = (w' / G) K,    ln K = e(L) ln D - 0.162625 - ln(1 + 0.411483 L^0.707071)
    e(L) = 0.658228 + 0.0106383 L^0.3174603,    D = 11.81220746 G U / W'^1.5

with W' = w' / (E' R') the load, U = η₀ u / (E' R') the speed, G = α E' the material
parameter, L = η₀ β u² / k the thermal loading parameter (β the temperature-viscosity
coefficient of the oil, k its thermal conductivity), w' = q / Δl the slice load per unit
length, u the entrainment (mean rolling) speed, R' the reduced radius, E' = 2/η the reduced
modulus (physics/film.py). Isothermal (L = 0) it is f = 4.318 E' R' (G U)^0.658 W'^0.0126 / G,
the form quoted by Harris & Kotzalas (Advanced Concepts of Bearing Technology, 5th ed., 2007,
Ch. 5); the thermal factor lowers it at high speed (L ≳ 0.1).

**Light loads.** The fit's load exponent is tiny (f ∝ W'^0.0126): it holds in the
elastic-piezoviscous regime it was fitted to, but would leave a slice that barely touches (the
roller pressed onto the outer race by its centrifugal force alone, a slice in the gap whose load
is the contact regularisation's residue, docs/theory.md §4) with nearly the rolling force of a
loaded one. At light load the film is the rigid-isoviscous one of Martin (1916), h₀ = 4.895 η₀ u
R' / w', whose Poiseuille shear on each surface is (Reynolds's cavitation condition; integrated
in tests/physics/test_rolling_resistance.py)

    f_IV = 2.0796 sqrt(η₀ u w'),

independent of R' and vanishing with the load. Its slope in the load, f_IV/(2 w'), is
unbounded as w' -> 0, and a roller leaving the load zone takes its slices through w' -> 0: at
500 r/min IDA's corrector failed there. Below the load per length w_c of a slice at the contact
smoothing length ε (the approach below which a load is the regularisation's residue, §4) the
force is taken linear in the load (**our regularisation**, not Martin's):

    f_IV = 2.0796 sqrt(η₀ u) w' / sqrt(w' + w_c),    w_c = q(ε) / Δl

which is Martin's law to within w_c / (2 w') (1e-3 of a loaded slice's force at w' = 500 w_c)
and Lipschitz in the load. The law used is the smooth minimum of the two
asymptotes, f = f_EHL f_IV / sqrt(f_EHL² + f_IV²) (**our blend**, not a published fit: the
smaller asymptote where the two differ by far; near their crossing, where the baseline's loaded
slices are, a little below both, and the true transition is not known to this model).

The slice's signed force along its rolling sum Σ (physics/kinematics.rolling_sums, u = |Σ|/2),
as the kernels use it (:func:`_slice_rolling_force`):

    H = F(q, ū) (Σ/2) / ū,    F = f Δl,    ū = sqrt((Σ/2)² + u₀²)

ū is the entrainment speed with a smooth floor u₀ (:data:`ROLLING_SPEED_FLOOR_M_S`), so that
H and its slopes stay finite through Σ = 0 (standstill, reversal); (Σ/2)/ū is its sign.

Each law returns its value with the analytic slopes the Jacobian needs (w.r.t. the load and the
speed). Plain numpy from Python (broadcasting), inlined when called from compiled kernels
(physics/compiled.py).
"""

from __future__ import annotations

import numpy as np

from .compiled import law
from .elementary import exp_, log_

#: Goksem & Hargreaves's fit (module docstring): D factor, exponent e(L) = E0 + E1 L^EL, and
#: ln K's offset and thermal term ln(1 + A L^B)
GH_D_FACTOR = 11.81220746
GH_E0, GH_E1, GH_EL = 0.658228, 0.0106383, 0.3174603
GH_OFFSET, GH_A, GH_B = 0.162625, 0.411483, 0.707071
#: smooth floor u₀ of the entrainment speed [m/s]: a rolling speed this small only occurs at
#: standstill or reversal (working speeds: m/s)
ROLLING_SPEED_FLOOR_M_S = 1e-3
#: Martin's rigid-isoviscous line contact (module docstring): f_IV = IV_FACTOR sqrt(η₀ u w'),
#: 6 √2 I_F / sqrt(C_w) with C_w = 4.895 (h₀ = C_w η₀ u R' / w') and I_F = 0.5422 the shear
#: integral (tests/physics/test_rolling_resistance.py integrates both)
IV_FACTOR = 2.0796226511
_TINY = 1e-300  # floor of L (and of w') under the logarithms: L^b is then 0 to the last bit


@law
def goksem_hargreaves(load_per_length_N_m, reduced_radius_m, entrainment_speed_m_s,
                      viscosity_Pa_s, pressure_viscosity_Pa_inv, reduced_modulus_Pa,
                      temperature_viscosity_K_inv, thermal_conductivity_W_m_K):
    """(f [N/m], df/dw' [1], df/du [N s/m²]): rolling force per unit length on each surface of a
    line contact (module docstring), at load per length w' > 0 and entrainment speed u > 0.

    Exponentials and logarithms are physics/elementary.py's (plain arithmetic: the kernels'
    contact loops over them vectorise; within a few ulp of numpy's)."""
    w = np.maximum(load_per_length_N_m, _TINY)
    u = entrainment_speed_m_s
    ER = reduced_modulus_Pa * reduced_radius_m
    G = pressure_viscosity_Pa_inv * reduced_modulus_Pa
    ln_D = log_(GH_D_FACTOR * G * viscosity_Pa_s * u / ER) - 1.5 * log_(w / ER)
    L = viscosity_Pa_s * temperature_viscosity_K_inv * u * u / thermal_conductivity_W_m_K
    ln_L = log_(np.maximum(L, _TINY))
    L_e = exp_(GH_EL * ln_L)  # L^0.3174603
    L_b = exp_(GH_B * ln_L)  # L^0.707071
    e = GH_E0 + GH_E1 * L_e
    thermal = 1.0 + GH_A * L_b
    f = w / G * exp_(e * ln_D - GH_OFFSET) / thermal
    # d ln f / d ln w' = 1 - 1.5 e; d ln f / d ln u = e + ln D de/dln u - dln(thermal)/dln u,
    # with d ln L / d ln u = 2
    f_w = f / w * (1.0 - 1.5 * e)
    f_u = f / u * (e + ln_D * 2.0 * GH_EL * GH_E1 * L_e - 2.0 * GH_B * GH_A * L_b / thermal)
    return f, f_w, f_u


@law
def rigid_isoviscous(load_per_length_N_m, entrainment_speed_m_s, viscosity_Pa_s,
                     light_load_N_m):
    """(f [N/m], df/dw', df/du): the rolling force per unit length on each surface of a rigid,
    isoviscous line contact (Martin's film), f = C_IV sqrt(η₀ u) w' / sqrt(w' + w_c): Martin's
    C_IV sqrt(η₀ u w') above the light load w_c, linear in w' below it (module docstring)."""
    w = np.maximum(load_per_length_N_m, _TINY)
    root = np.sqrt(w + light_load_N_m)
    f = IV_FACTOR * np.sqrt(viscosity_Pa_s * entrainment_speed_m_s) * w / root
    # d/dw' [w' / sqrt(w' + w_c)] = (w' + 2 w_c) / (2 (w' + w_c)^1.5)
    return (f, f * (w + 2.0 * light_load_N_m) / (2.0 * w * (w + light_load_N_m)),
            0.5 * f / entrainment_speed_m_s)


@law
def rolling_force_per_length(load_per_length_N_m, reduced_radius_m, entrainment_speed_m_s,
                             viscosity_Pa_s, pressure_viscosity_Pa_inv, reduced_modulus_Pa,
                             temperature_viscosity_K_inv, thermal_conductivity_W_m_K,
                             light_load_N_m):
    """(f [N/m], df/dw', df/du): f = a b / sqrt(a² + b²) of the EHL law a
    (:func:`goksem_hargreaves`) and the rigid-isoviscous one b (:func:`rigid_isoviscous`)."""
    a, a_w, a_u = goksem_hargreaves(load_per_length_N_m, reduced_radius_m, entrainment_speed_m_s,
                                    viscosity_Pa_s, pressure_viscosity_Pa_inv,
                                    reduced_modulus_Pa, temperature_viscosity_K_inv,
                                    thermal_conductivity_W_m_K)
    b, b_w, b_u = rigid_isoviscous(load_per_length_N_m, entrainment_speed_m_s, viscosity_Pa_s,
                                   light_load_N_m)
    root = np.sqrt(a * a + b * b)
    # df/da = (b / root)³, df/db = (a / root)³: bounded ratios, finite for any a, b > 0
    da = b / root
    db = a / root
    da = da * da * da
    db = db * db * db
    return a * b / root, da * a_w + db * b_w, da * a_u + db * b_u


@law
def _slice_rolling_force(q_N, rolling_sum_m_s, slice_width_m, reduced_radius_m, viscosity_Pa_s,
                         pressure_viscosity_Pa_inv, reduced_modulus_Pa,
                         temperature_viscosity_K_inv, thermal_conductivity_W_m_K,
                         speed_floor_m_s, light_load_N_m):
    """(H [N], dH/dq [1], dH/dΣ [N s/m]): the slice's signed rolling force H = F (Σ/2)/ū
    (module docstring) at slice load q and rolling sum Σ (u = |Σ|/2)."""
    half = 0.5 * rolling_sum_m_s
    ubar = np.sqrt(half * half + speed_floor_m_s * speed_floor_m_s)
    f, f_w, f_u = rolling_force_per_length(q_N / slice_width_m, reduced_radius_m, ubar,
                                           viscosity_Pa_s, pressure_viscosity_Pa_inv,
                                           reduced_modulus_Pa, temperature_viscosity_K_inv,
                                           thermal_conductivity_W_m_K, light_load_N_m)
    F = f * slice_width_m
    sign = half / ubar
    # dū/dΣ = (Σ/4)/ū = sign/2; d sign/dΣ = u₀² / (2 ū³)
    dsign = 0.5 * speed_floor_m_s * speed_floor_m_s / (ubar * ubar * ubar)
    return F * sign, f_w * sign, f_u * slice_width_m * 0.5 * sign * sign + F * dsign


def light_load_per_length(slice_stiffness: float, smoothing_m: float,
                          slice_width_m: float) -> float:
    """w_c [N/m]: the load per unit length of a slice at the contact smoothing length ε
    (physics/contact.slice_load at δ = ε), where Martin's law turns linear in the load."""
    from .contact import slice_load

    return float(slice_load(smoothing_m, slice_stiffness, smoothing_m)[0]) / slice_width_m
