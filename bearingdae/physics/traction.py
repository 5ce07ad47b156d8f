"""Roller-race traction: the paper's μ(V, p), the slide-to-roll law, F = μ q sg(V) (theory.md §7).

Sits between the slip kinematics (theory.md §6: V per slice) and the equations of motion (theory.md §10).
The slice traction force along t̂ on the roller is

    F = μ(|V|, p) q sg(V),      sg(V) = V / sqrt(V² + v₀²)                         (theory.md §7)

with q the slice load [N], p its Hertz pressure and v₀ a small velocity scale. The paper's law
(V in m/s, p in GPa) **[reading]**

    μ = A V exp(-B C V / p) [1 - exp(-p/B)] + D [1 - exp(-C V)],
    A = 0.27 s/m, B = 0.43 GPa, C = 6.93 s/m, D = 0.022,

where the bracket [1 - exp(-p/B)] may also read [1 - exp(-B/p)] (switch ``bracket``). Both
readings give μ(0, p) = 0, so μ(|V|) sign(V) is already C¹ at V = 0 even with the exact sign; the
regularised sign only reshapes F for |V| ≲ v₀. p → 0 is guarded: p is floored at 1e-12 GPa
(1 mPa), where exp(-B C V / p) = 0, so the first term goes to 0 as it should and nothing divides
by zero.

The alternative law in slide-to-roll ratio s = |V| / u (u the rolling speed),
μ(s) = (A + B s) e^(-C s) + D, is offered with illustrative constants (see
``SLIDE_ROLL_DEFAULTS``).

Numerics: the kernels whose names start with ``_`` take only floats (flags as bools), return
tuples of value and analytic derivatives, and are physics laws (physics/compiled.py):
plain Python/numpy functions when called from Python (broadcasting over arrays), compiled inline
when called from an ``@njit`` kernel. The friendly functions without ``_`` add string options and
defaults on top; they are Python-only.
"""

from __future__ import annotations

import numpy as np

from .compiled import law
from .elementary import EXP_ZERO_BELOW, exp_  # noqa: F401  (EXP_ZERO_BELOW: re-exported)

#: Paper constants (Yang et al. 2024, Eq. for μ; theory.md §7): A [s/m], B [GPa], C [s/m], D [-].
PAPER_CONSTANTS = {"A": 0.27, "B_GPa": 0.43, "C": 6.93, "D": 0.022}
BRACKETS = ("exp(-p/B)", "exp(-B/p)")  # [1 - exp(-p/B)] (default) or [1 - exp(-B/p)]
PRESSURE_FLOOR_GPA = 1e-12  # p below this is treated as this: the first term of μ is 0 there
# Exponentials are physics/elementary.exp_ (plain arithmetic, so the contact loop vectorises;
# within 2 ulp of exp, exactly 0.0 below EXP_ZERO_BELOW = -708, where a load multiplies it).

#: Slide-to-roll law μ(s) = (A + B s) e^(-C s) + D **[reading]**: illustrative constants, not a
#: fit to a particular oil. Chosen so that μ(0) = A + D = 0 (no traction in pure rolling), the
#: initial slope is B - C A = 3.8, the peak is μ ≈ 0.069 at s ≈ 0.055 and μ → D = 0.04 in gross
#: sliding: the shape and magnitudes of measured EHL traction curves of mineral bearing oils
#: (peak 0.05-0.1 at a few percent slide-to-roll, slow thermal fall-off; e.g. Johnson &
#: Tevaarwerk, Proc. R. Soc. Lond. A 356 (1977) 215-236). Replace with measured constants.
SLIDE_ROLL_DEFAULTS = {"A": -0.04, "B": 2.8, "C": 25.0, "D": 0.04}


@law
def regularised_sign(v, scale):
    """Smooth sign sg(v) = v / sqrt(v² + scale²) ∈ (-1, 1); ``scale`` > 0 in the units of v."""
    return v / np.sqrt(v * v + scale * scale)


@law
def regularised_sign_slope(v, scale):
    """d sg / dv = scale² / (v² + scale²)^(3/2); equals 1/scale at v = 0."""
    root = np.sqrt(v * v + scale * scale)
    return scale * scale / (root * root * root)


@law
def _paper_bracket(p_GPa, B, alt_bracket):
    """The paper law's bracket g(p) and dg/dp: 1 - exp(-p/B) (default) or 1 - exp(-B/p)."""
    if alt_bracket:
        e_b = exp_(-B / p_GPa)
        return 1.0 - e_b, -e_b * B / (p_GPa * p_GPa)
    e_b = exp_(-p_GPa / B)
    return 1.0 - e_b, e_b / B


@law
def _mu_paper_value(speed_m_s, e_bc, g, e_c, A, D):
    """μ = A |V| e_bc g + D (1 - e_c) from its factors e_bc = exp(-B C |V| / p), the bracket g
    and e_c = exp(-C |V|): the one place of the paper formula."""
    return A * speed_m_s * e_bc * g + D * (1.0 - e_c)


@law
def _mu_paper(slip_m_s, p_GPa, A, B, C, D, alt_bracket):
    """Paper law: (μ, dμ/d|V| [s/m], dμ/dp [1/GPa]) at |V| = |slip_m_s|, pressure p [GPa].

    ``alt_bracket`` False: [1 - exp(-p/B)]; True: [1 - exp(-B/p)]. p is floored at
    ``PRESSURE_FLOOR_GPA`` (the derivative there is that of the floored value, ≈ 0).
    """
    a = np.abs(slip_m_s)
    p = np.maximum(p_GPa, PRESSURE_FLOOR_GPA)
    e_bc = exp_(-B * C * a / p)
    g, dg = _paper_bracket(p, B, alt_bracket)
    e_c = exp_(-C * a)
    mu = _mu_paper_value(a, e_bc, g, e_c, A, D)
    dmu_da = A * g * e_bc * (1.0 - B * C * a / p) + D * C * e_c
    dmu_dp = A * a * e_bc * (g * B * C * a / (p * p) + dg)
    return mu, dmu_da, dmu_dp


@law
def _mu_slide_roll(slide_roll, A, B, C, D):
    """Slide-to-roll law: (μ, dμ/ds) of μ(s) = (A + B s) e^(-C s) + D, s ≥ 0."""
    e = exp_(-C * slide_roll)
    return (A + B * slide_roll) * e + D, (B - C * (A + B * slide_roll)) * e


@law
def _signed_traction(q_N, slip_m_s, mu, dmu_dspeed, velocity_scale_m_s):
    """F = μ q sg(V) and (dF/dV, dF/dq) at fixed μ-law state; dmu_dspeed = dμ/d|V| [s/m].

    d/dV μ(|V|) sg(V) = μ' sign(V) sg(V) + μ sg' and sign(V) sg(V) = |V| / sqrt(V² + v₀²),
    which is continuous through V = 0.
    """
    root = np.sqrt(slip_m_s * slip_m_s + velocity_scale_m_s * velocity_scale_m_s)
    sg = slip_m_s / root
    dsg = regularised_sign_slope(slip_m_s, velocity_scale_m_s)
    force = mu * q_N * sg
    dF_dV = q_N * (dmu_dspeed * np.abs(slip_m_s) / root + mu * dsg)
    return force, dF_dV, mu * sg


@law
def _traction_force_paper(q_N, slip_m_s, pressure_Pa, velocity_scale_m_s, A, B_GPa, C, D,
                          alt_bracket):
    """Paper law F = μ(|V|, p) q sg(V): (F [N], dF/dV [N s/m], dF/dq [-], dF/dp [N/Pa]).

    dF/dq is the partial at fixed p; if p = p(q) (Hertz: dp/dq = p / 2q) the caller adds
    dF/dp · dp/dq.
    """
    mu, dmu_da, dmu_dp = _mu_paper(slip_m_s, pressure_Pa * 1e-9, A, B_GPa, C, D, alt_bracket)
    force, dF_dV, dF_dq = _signed_traction(q_N, slip_m_s, mu, dmu_da, velocity_scale_m_s)
    dF_dp = q_N * regularised_sign(slip_m_s, velocity_scale_m_s) * dmu_dp * 1e-9
    return force, dF_dV, dF_dq, dF_dp


@law
def _traction_force_slide_roll(q_N, slip_m_s, rolling_speed_m_s, velocity_scale_m_s, A, B, C, D,
                               rolling_speed_floor_m_s):
    """Slide-to-roll law F = μ(s) q sg(V), s = |V| / ū, ū = sqrt(u² + u₀²) (smooth floor u₀).

    Returns (F [N], dF/dV [N s/m], dF/dq [-], dF/du [N s/m]).
    """
    u_bar = np.sqrt(rolling_speed_m_s * rolling_speed_m_s
                    + rolling_speed_floor_m_s * rolling_speed_floor_m_s)
    s = np.abs(slip_m_s) / u_bar
    mu, dmu_ds = _mu_slide_roll(s, A, B, C, D)
    force, dF_dV, dF_dq = _signed_traction(q_N, slip_m_s, mu, dmu_ds / u_bar, velocity_scale_m_s)
    ds_du = -s * rolling_speed_m_s / (u_bar * u_bar)
    dF_du = q_N * regularised_sign(slip_m_s, velocity_scale_m_s) * dmu_ds * ds_du
    return force, dF_dV, dF_dq, dF_du


@law
def _traction_value_paper(q_N, slip_m_s, pressure_Pa, velocity_scale_m_s, A, B_GPa, C, D,
                          alt_bracket):
    """F of ``_traction_force_paper`` alone, for scalars (the residual's hot path).

    Why a second entry point: the residual needs no slopes, and the full kernel is too large
    for the compiler to inline, so their divisions were paid on every call (measured: 17 % of
    the residual). Same operations in the same order, hence the same F to the last bit. No
    branch (the contact loop vectorises): for unloaded slices (p at its floor) exp_ of
    -B C |V| / p is exactly 0.0 and so is the first term of μ.
    """
    a = np.abs(slip_m_s)
    p = np.maximum(pressure_Pa * 1e-9, PRESSURE_FLOOR_GPA)
    e_bc = exp_(-B_GPa * C * a / p)
    g = _paper_bracket(p, B_GPa, alt_bracket)[0]
    mu = _mu_paper_value(a, e_bc, g, exp_(-C * a), A, D)
    return mu * q_N * regularised_sign(slip_m_s, velocity_scale_m_s)


@law
def _traction_value_slide_roll(q_N, slip_m_s, rolling_speed_m_s, velocity_scale_m_s, A, B, C, D,
                               rolling_speed_floor_m_s):
    """F of ``_traction_force_slide_roll`` alone (the residual's hot path; same value)."""
    u_bar = np.sqrt(rolling_speed_m_s * rolling_speed_m_s
                    + rolling_speed_floor_m_s * rolling_speed_floor_m_s)
    mu = _mu_slide_roll(np.abs(slip_m_s) / u_bar, A, B, C, D)[0]
    return mu * q_N * regularised_sign(slip_m_s, velocity_scale_m_s)


def _bracket_flag(bracket: str) -> bool:
    if bracket not in BRACKETS:
        raise ValueError(f"bracket = {bracket!r}: allowed are {', '.join(map(repr, BRACKETS))} "
                         "(the reading of the paper's [1 - exp(...)] factor, theory.md §7)")
    return bracket == BRACKETS[1]


def traction_coefficient_paper(slip_m_s, pressure_Pa, A=0.27, B_GPa=0.43, C=6.93, D=0.022,
                               bracket="exp(-p/B)"):
    """Paper's traction coefficient μ(|V|, p) ≥ 0 (theory.md §7); V [m/s], p [Pa] (GPa inside)."""
    flag = _bracket_flag(bracket)
    return _mu_paper(slip_m_s, np.asarray(pressure_Pa) * 1e-9, A, B_GPa, C, D, flag)[0]


def traction_coefficient_slide_roll(slip_m_s, rolling_speed_m_s, A=-0.04, B=2.8, C=25.0, D=0.04,
                                    rolling_speed_floor_m_s=1e-3):
    """μ(s) = (A + B s) e^(-C s) + D with s = |V| / sqrt(u² + u₀²) (theory.md §7 alternative).

    u is the rolling (entrainment) speed [m/s]; u₀ keeps s finite at standstill.
    """
    u_bar = np.sqrt(np.square(rolling_speed_m_s) + rolling_speed_floor_m_s**2)
    return _mu_slide_roll(np.abs(slip_m_s) / u_bar, A, B, C, D)[0]


def traction_force(q_N, slip_m_s, pressure_Pa, velocity_scale_m_s, A=0.27, B_GPa=0.43, C=6.93,
                   D=0.022, bracket="exp(-p/B)"):
    """Slice traction F = μ(|V|, p) q sg(V) along t̂ on the roller (theory.md §7) and its slopes.

    Returns (F [N], dF/dV [N s/m], dF/dq [-] at fixed p, dF/dp [N/Pa]). ``velocity_scale_m_s``
    is the regularisation v₀ of sign(V) (> 0; small against working slips, e.g. 1e-4 m/s).
    """
    flag = _bracket_flag(bracket)
    return _traction_force_paper(q_N, slip_m_s, pressure_Pa, velocity_scale_m_s, A, B_GPa, C, D,
                                 flag)
