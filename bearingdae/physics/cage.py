"""Roller-cage pocket contact, the loads it puts on roller and cage, cage mass (theory.md §8, §2).

Sits between the roller/cage state (θX_j, θz_j, θc and their rates) and the equations of motion
(theory.md §10). Pocket j (zero-based here) is centred at θc + 2π j / Z; the roller's lead in it is

    s_j = R_m wrap(θX_j - θc - 2π j / Z),   wrap to (-π, π]                        (theory.md §8)

and its ends a (x = +L/2) and b (x = -L/2) sit at s_a = s_j - (L/2) θz, s_b = s_j + (L/2) θz.
Each end meets the front bar (s_e > c_p/2) or the rear bar (s_e < -c_p/2) through a
compression-only spring-damper.

**Regularisation** (the exact law has a kink at ±c_p/2 and a switch when the clip acts; IDA's
Newton iteration needs a Jacobian that is continuous in the state, else it stalls or takes tiny
steps at each contact onset — theory.md §11). For one bar with penetration δ (δ = s - c_p/2 at the
front, -s - c_p/2 at the rear) and penetration rate δ̇ the push (≥ 0) on the end is

    G = H(δ) · S(K P(δ) + c H(δ) δ̇)
    P(δ) = (δ + sqrt(δ² + ε²)) / 2          smooth penetration (ε: smoothing length [m])
    H(δ) = dP/dδ = (1 + δ / sqrt(δ² + ε²)) / 2   smooth contact indicator, 0 → 1
    S(x) = (x + sqrt(x² + f²)) / 2          smooth "never pulls" clip max(x, 0) (f: force scale [N])

and F_e = -G_front + G_rear. For |δ| >> ε and |x| >> f this is the exact law: F = -K δ - c δ̇ in
contact (damping only while in contact), 0 in the dead band, and F never pulls (G > 0 always;
the outer H removes the clip's f/2 offset out of contact). The errors are of order K ε / 2 and
f / 2 at the bar; the default f = K ε keeps them of one size. dF/ds and dF/dv are exact.
Choosing ε: it must be small against the penetration of a typical impact, because the damping
is H(δ) c δ̇ and H only reaches 1 for δ >> ε. The skew impacts of the baseline penetrate only
60-240 nm (1-4 rad/s). Measured restitution of one symmetric skew impact (tests/solvers/test_newmark.py,
reference: the analytic compression-only Kelvin-Voigt impact, 0.515 for the sharp law):

    ε [µm]           1 rad/s   2 rad/s   4 rad/s
    0.1              0.956     0.819     0.678    (nearly elastic)
    0.03             0.711     0.606     0.552
    0.01 (default)   0.569     0.537     0.524
    0.001            0.518     0.516     0.516

The price of a small ε is steps: the damping switch adds up to c δ̇/(2ε) to the contact stiffness
at onset, and the baseline costs about twice the residual calls at 0.01 µm as at 0.1 µm.
ε << c_p/2 keeps the dead band intact. The force scale f = K ε of the clip matters much less
(f / 10 at ε = 0.1 µm moves the 2 rad/s restitution only to 0.69).

Spin friction uses the smooth |F| ≈ sqrt(F² + f²) - f (0 at F = 0) and sg(ω) = ω/sqrt(ω² + ω₀²).

Sign convention for angular momentum about X: ω_j > 0 is rolling forward on the inner race, i.e.
spin about -X (theory.md §6 slip formulas), so a roller's own angular momentum about X is -I_x ω_j.
With the orbit torque R_m F_cr on the roller and -R_m F_cr on the cage, and spin torque
-r μ_c N sg(ω) in the roller's ω equation and -r μ_c N sg(ω) on the cage (theory.md §10), the pocket
interaction changes the total angular momentum about X by R_m F_cr - (-r μ_c N sg) - R_m F_cr
- r μ_c N sg = 0: it is internal, as theory.md §8 requires.

Kernels named ``_…`` are physics laws (physics/compiled.py: plain numpy from Python, inlined in @njit).
"""

from __future__ import annotations

import numpy as np

# The cage's proportions are bearing data (a design rule, theory.md §2), in parameters.py where the
# scene's pocket check reads them too; re-exported here for the cage's physics.
from ..scene.parameters import CAGE_EXTRA_WIDTH_PER_DW, CAGE_THICKNESS_PER_DW, cage_annulus  # noqa: F401
from .compiled import law

# The pocket kinematics (lead, wrap, end positions) live in physics/kinematics.py, shared with
# the residual, the Jacobian and the static solve; re-exported here for the cage's readers.
from .kinematics import end_positions, pocket_lead, wrap_angle  # noqa: F401

BRASS_DENSITY_KG_M3 = 8500.0  # theory.md §2 cage default
# Spin friction regularisation (not in the paper): |F| ≈ sqrt(F² + f²) - f and
# sg(ω) = ω / sqrt(ω² + ω₀²). f is settable as cage.spin_friction_force_scale_N; ω₀ is fixed.
SPIN_FRICTION_FORCE_SCALE_N = 1e-6
SPIN_SPEED_SCALE_RAD_S = 1e-2


@law
def _bar_push(penetration_m, rate_m_s, stiffness_N_m, damping_Ns_m, smoothing_m, force_scale_N):
    """Push G ≥ 0 of one bar and (dG/dδ, dG/dδ̇): G = H(δ) S(K P(δ) + c H(δ) δ̇) (module doc)."""
    root = np.sqrt(penetration_m * penetration_m + smoothing_m * smoothing_m)
    P = 0.5 * (penetration_m + root)
    H = P / root
    dH = 0.5 * smoothing_m * smoothing_m / (root * root * root)
    x = stiffness_N_m * P + damping_Ns_m * H * rate_m_s
    root_x = np.sqrt(x * x + force_scale_N * force_scale_N)
    S = 0.5 * (x + root_x)
    dS = S / root_x
    dG_dpen = dH * S + H * dS * (stiffness_N_m * H + damping_Ns_m * dH * rate_m_s)
    dG_drate = H * dS * damping_Ns_m * H
    return H * S, dG_dpen, dG_drate


@law
def _pocket_force(s_e_m, v_e_m_s, clearance_m, stiffness_N_m, damping_Ns_m, smoothing_m,
                  force_scale_N):
    """End force F_e [N] along t̂ and (dF/ds [N/m], dF/dv [N s/m]); see module docstring."""
    half = 0.5 * clearance_m
    g_f, gp_f, gr_f = _bar_push(s_e_m - half, v_e_m_s, stiffness_N_m, damping_Ns_m, smoothing_m,
                                force_scale_N)
    g_r, gp_r, gr_r = _bar_push(-s_e_m - half, -v_e_m_s, stiffness_N_m, damping_Ns_m,
                                smoothing_m, force_scale_N)
    return g_r - g_f, -gp_f - gp_r, -gr_f - gr_r


def pocket_force(s_e_m, v_e_m_s, clearance_m, stiffness_N_m, damping_Ns_m, smoothing_m,
                 force_smoothing_N=None):
    """Regularised pocket force on one roller end (theory.md §8): (F [N], dF/ds [N/m], dF/dv [N s/m]).

    Exact limit: F = -K(s - c_p/2) - c v beyond the front bar, +K(-s - c_p/2) - c v beyond the
    rear bar, 0 between, never pulling. ``smoothing_m`` is ε (<< c_p/2 and ≳ c v_impact / K, see
    the module docstring); ``force_smoothing_N`` is f, default K ε.
    """
    f = stiffness_N_m * smoothing_m if force_smoothing_N is None else force_smoothing_N
    return _pocket_force(s_e_m, v_e_m_s, clearance_m, stiffness_N_m, damping_Ns_m, smoothing_m, f)


def pocket_damping(stiffness_N_m, roller_mass_kg, damping_ratio=0.1):
    """c = 2 ζ sqrt(K m) [N s/m]: theory.md §2 default ζ = 0.1 against one roller mass."""
    return 2.0 * damping_ratio * np.sqrt(stiffness_N_m * roller_mass_kg)


@law
def _spin_friction_torque(F_a_N, F_b_N, omega_rad_s, roller_radius_m, friction_coefficient,
                          spin_scale_rad_s, force_scale_N):
    """M = -r μ_c (|F_a| + |F_b|) sg(ω) [N m] and (dM/dF_a, dM/dF_b, dM/dω).

    |F| ≈ sqrt(F² + f²) - f (smooth, 0 at 0), sg(ω) = ω / sqrt(ω² + ω₀²).
    """
    ra = np.sqrt(F_a_N * F_a_N + force_scale_N * force_scale_N)
    rb = np.sqrt(F_b_N * F_b_N + force_scale_N * force_scale_N)
    normal = ra + rb - 2.0 * force_scale_N
    rw = np.sqrt(omega_rad_s * omega_rad_s + spin_scale_rad_s * spin_scale_rad_s)
    sg = omega_rad_s / rw
    dsg = spin_scale_rad_s * spin_scale_rad_s / (rw * rw * rw)
    k = -roller_radius_m * friction_coefficient
    return k * normal * sg, k * sg * F_a_N / ra, k * sg * F_b_N / rb, k * normal * dsg


@law
def _pocket_loads(F_a_N, F_b_N, omega_rad_s, length_m, roller_radius_m, pitch_radius_m,
                  friction_coefficient, spin_scale_rad_s, force_scale_N):
    """(F_cr [N], M_cz [N m], M_spin [N m] on the roller, M_cage [N m] on the cage about X).

    F_cr = F_a + F_b along t̂ (orbit equation), M_cz = (L/2)(F_b - F_a) (skew equation),
    M_spin = -r μ_c (|F_a| + |F_b|) sg(ω) (spin equation), M_cage = -R_m F_cr + M_spin (theory.md §8,
    §10). Derivatives: F_cr and M_cz are linear; M_spin's come from ``_spin_friction_torque``.
    """
    m_spin = _spin_friction_torque(F_a_N, F_b_N, omega_rad_s, roller_radius_m,
                                   friction_coefficient, spin_scale_rad_s, force_scale_N)[0]
    f_cr = F_a_N + F_b_N
    return f_cr, 0.5 * length_m * (F_b_N - F_a_N), m_spin, -pitch_radius_m * f_cr + m_spin


def pocket_loads(F_a_N, F_b_N, omega_rad_s, length_m, roller_radius_m, pitch_radius_m,
                 friction_coefficient=0.002, spin_scale_rad_s=SPIN_SPEED_SCALE_RAD_S,
                 force_scale_N=SPIN_FRICTION_FORCE_SCALE_N):
    """Roller and cage loads from the end forces (theory.md §8); see ``_pocket_loads``."""
    return _pocket_loads(F_a_N, F_b_N, omega_rad_s, length_m, roller_radius_m, pitch_radius_m,
                         friction_coefficient, spin_scale_rad_s, force_scale_N)


def cage_mass_inertia(pitch_radius_m, roller_diameter_m, roller_length_m, rollers,
                      pocket_clearance_m, density_kg_m3=BRASS_DENSITY_KG_M3):
    """Cage (mass [kg], moment of inertia about X [kg m²]) (theory.md §2) **[reading]**.

    Annulus r_i..r_o of width W minus Z flat-walled pockets, each a box of circumferential width
    D_w + c_p, axial length L and the full radial thickness t, centred on R_m:
    m = ρ [π (r_o² - r_i²) W - Z (D_w + c_p) L t],
    I = ½ m_ann (r_o² + r_i²) - Z m_pocket (R_m² + (t² + (D_w + c_p)²) / 12).
    """
    r_i, r_o, width = cage_annulus(pitch_radius_m, roller_diameter_m, roller_length_m)
    t = r_o - r_i
    pocket_width = roller_diameter_m + pocket_clearance_m
    m_ann = density_kg_m3 * np.pi * (r_o**2 - r_i**2) * width
    m_pocket = density_kg_m3 * pocket_width * roller_length_m * t
    mass = m_ann - rollers * m_pocket
    if rollers * pocket_width >= 2.0 * np.pi * r_i or mass <= 0.0:
        raise ValueError(
            f"rollers = {rollers} pockets of width D_w + c_p = {pocket_width * 1e3:.4g} mm do not "
            f"fit the cage's inner circumference 2π r_i = {2e3 * np.pi * r_i:.4g} mm: reduce "
            "rollers or pocket clearance, or give the cage mass and inertia explicitly")
    inertia = (0.5 * m_ann * (r_o**2 + r_i**2)
               - rollers * m_pocket * (pitch_radius_m**2 + (t**2 + pocket_width**2) / 12.0))
    return mass, inertia
