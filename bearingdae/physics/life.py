"""Rating life of a roller bearing from its slice loads: ISO/TS 16281 and ISO 281 (post-processing).

Pipeline: physics (pure laws), called by :mod:`bearingdae.analysis.engineering` on the slice
loads of a static solve or of a dynamic run; nothing here enters the DAE residual. Inputs are
SI; ISO's own formulas are written in mm and N, so lengths are converted inside each function.

Implemented (radial cylindrical roller bearing, one row, contact angle α = 0):

* ISO 281:2007, Eq. (7) with Table 7: basic dynamic load rating from the geometry,
  C_r = b_m f_c (i L_we cos α)^(7/9) Z^(3/4) D_we^(29/27) [N, mm], b_m = 1.1 (ISO 281 Table 1,
  cylindrical roller bearings), and f_c the formula Table 7 tabulates:
  f_c = 207.9 λν γ^(2/9) (1 - γ)^(29/27) (1 + γ)^(-1/4)
  [1 + (1.04 ((1 - γ)/(1 + γ))^(143/108))^(9/2)]^(-2/9), λν = 0.83, γ = D_we cos α / D_pw
  (it gives Table 7's 84.2 at γ = 0.10 and 88.7 at γ = 0.20; tested).
* ISO/TS 16281:2008, clause 6 (roller bearings), laminae model with n_s laminae (the slices
  of the loads given; analysis/rating_life.py solves again with as many as converge the life):
  rolling element loads for the basic rating of inner and outer ring
  Q_ci = C / (λν 0.378 Z i^(7/9) cos α) [1 + (1.038 ((1 - γ)/(1 + γ))^(143/108))^(9/2)]^(2/9),
  Q_ce = C / (λν 0.364 Z i^(7/9) cos α) [1 + (1.038 ((1 - γ)/(1 + γ))^(143/108))^(-9/2)]^(2/9),
  and of a lamina q_c = Q_c (w / L_we)^(7/9) (= Q_c n_s^(-7/9) for w = L_we / n_s);
  the edge-stress factor of lamina k (Eq. 60), f_k = 1 - 0.01 / ln(1.985 |(2k - n_s - 1) /
  (2 n_s - 2)|), multiplies the lamina loads;
  the equivalent lamina loads (the ring rotating relative to the load: exponent 4; the ring
  the load stands still on: exponent 4.5), q_ek = ((1/N) Σ (f_k q_k)^p)^(1/p) over the N
  loads lamina k of the ring sees; and the basic reference rating life
  L10r = [Σ_k ((q_eik / q_cik)^(9/2) + (q_eek / q_cek)^(9/2))]^(-8/9) [10⁶ revolutions],
  with the dynamic equivalent reference load P_ref = C L10r^(-3/10).
* ISO 281:2007, Eq. (11) with Table 11 (radial roller bearings): the life modification factor
  a_ISO = 0.1 [1 - (1.5859 - c2 / κ^c3) (e_C C_u / P)^0.4]^(-9.185), c2 = 1.3993, c3 = 0.054381
  for 0.1 ≤ κ < 0.4; c2 = 1.2348, c3 = 0.19087 for 0.4 ≤ κ < 1; c2 = 1.2348, c3 = 0.071739 for
  1 ≤ κ ≤ 4; κ clamped to [0.1, 4], a_ISO ≤ 50 (:func:`a_iso`). A bracket ≤ 0 (the stress
  below the fatigue limit: the expression grows without bound) takes the cap, 50, as ISO 281's
  limit a_ISO ≤ 50 does. The fatigue load limit of a roller bearing C_u = C0 / 8.2, times
  (100 / D_pw)^0.3 above D_pw = 100 mm (:func:`fatigue_load_limit`).
* The modified reference rating life from the laminae (ISO 16281:2025): each lamina's life
  scaled by its own a_ISO, the laminae combined as for L10r,
  L_nmr = [Σ_k a_ik^(-9/8) (q_eik / q_cik)^(9/2) + a_ek^(-9/8) (q_eek / q_cek)^(9/2)]^(-8/9)
  (:func:`modified_reference_rating_life`), which is a_ISO L10r when every lamina has the same
  a_ISO. The load ratio of a lamina, its counterpart of e_C C_u / P, is e_C C_u / P_k with
  P_k the equivalent reference load of a bearing whose N laminae (both rings) were all loaded
  as lamina k: L10r = N^(-8/9) (q_e/q_c)^-4, P_k = C L10r^(-3/10) = C N^(4/15) (q_e/q_c)^(6/5)
  (:func:`lamina_load_ratio`). Laminae all alike give P_k = P_ref, hence L_nmr = a_ISO(κ,
  e_C C_u / P_ref) L10r, ISO 281's modified life; P_k does not depend on the lamina count
  (q_e/q_c ∝ N^(-2/9)).

A dynamic run (analysis/rating_life.py) takes the power means over every recorded sample and
every roller: each (sample, roller) is one load the ring passes, as the Z rollers of a static
solve are (the standard's mean over the rollers, extended over the recorded time).
"""

from __future__ import annotations

import numpy as np

LAMBDA_NU_RADIAL_ROLLER = 0.83  #: λν of radial roller bearings (ISO 281 / ISO/TS 16281)
B_M_CYLINDRICAL = 1.1  #: b_m of cylindrical roller bearings (ISO 281:2007, Table 1)
EXPONENT_ROTATING_RING = 4.0  #: equivalent-load exponent of the ring rotating against the load
EXPONENT_STATIONARY_RING = 4.5  #: ... and of the ring stationary against the load
MM = 1e-3


def _ratio_term(gamma):
    return ((1.0 - gamma) / (1.0 + gamma)) ** (143.0 / 108.0)


def iso281_fc(gamma):
    """f_c of radial roller bearings (ISO 281:2007 Table 7, as its formula): C in N from D_we, L_we
    in mm.

    ``gamma`` = D_we cos α / D_pw.
    """
    g = np.asarray(gamma, dtype=float)
    return (207.9 * LAMBDA_NU_RADIAL_ROLLER * g ** (2.0 / 9.0) * (1.0 - g) ** (29.0 / 27.0)
            * (1.0 + g) ** -0.25
            * (1.0 + (1.04 * _ratio_term(g)) ** 4.5) ** (-2.0 / 9.0))


def basic_dynamic_load_rating(rollers: int, roller_diameter_m: float, length_m: float,
                              pitch_diameter_m: float, rows: int = 1,
                              b_m: float = B_M_CYLINDRICAL) -> float:
    """C_r [N] of a radial roller bearing from its geometry (ISO 281:2007 Eq. 7, α = 0)."""
    dw, lwe = roller_diameter_m / MM, length_m / MM
    gamma = roller_diameter_m / pitch_diameter_m
    return float(b_m * iso281_fc(gamma) * (rows * lwe) ** (7.0 / 9.0) * rollers ** 0.75
                 * dw ** (29.0 / 27.0))


def lamina_ratings(rating_N: float, rollers: int, gamma: float, lamina_width_m: float,
                   length_m: float, rows: int = 1) -> tuple[float, float]:
    """(q_ci, q_ce) [N], basic dynamic load ratings of one lamina of inner and outer ring
    (ISO/TS 16281 clause 6; α = 0): Q_c (w / L_we)^(7/9)."""
    t = 1.038 * _ratio_term(gamma)
    base = rating_N / (LAMBDA_NU_RADIAL_ROLLER * rollers * rows ** (7.0 / 9.0))
    Q_ci = base / 0.378 * (1.0 + t ** 4.5) ** (2.0 / 9.0)
    Q_ce = base / 0.364 * (1.0 + t ** -4.5) ** (2.0 / 9.0)
    share = (lamina_width_m / length_m) ** (7.0 / 9.0)
    return Q_ci * share, Q_ce * share


def edge_stress_factors(slices: int) -> np.ndarray:
    """f_k (k = 1..n_s), ISO/TS 16281 Eq. (60): 1 at the roller centre, ≈ 2.33 at the ends.

    One slice has no edge: f = 1.
    """
    if slices < 2:
        return np.ones(slices)
    k = np.arange(1, slices + 1)
    arg = 1.985 * np.abs((2.0 * k - slices - 1.0) / (2.0 * slices - 2.0))
    with np.errstate(divide="ignore"):
        f = 1.0 - 0.01 / np.log(arg)  # log(0) = -inf at an odd n_s's centre: f = 1
    return f


def equivalent_lamina_load(q_N, exponent: float, axis) -> np.ndarray:
    """Power mean ((1/N) Σ q^p)^(1/p) [N] of the lamina loads over ``axis`` (rollers, and
    samples for a dynamic run); ISO/TS 16281 Eqs. (61)-(64)."""
    q = np.maximum(np.asarray(q_N, dtype=float), 0.0)
    return np.mean(q ** exponent, axis=axis) ** (1.0 / exponent)


def reference_rating_life(qe_inner_N, qe_outer_N, qc_inner_N, qc_outer_N) -> float:
    """L10r [10⁶ revolutions] = [Σ_k (q_ei/q_ci)^(9/2) + (q_ee/q_ce)^(9/2)]^(-8/9)
    (ISO/TS 16281 Eq. 65); inf for an unloaded bearing."""
    s = float(np.sum((np.asarray(qe_inner_N) / qc_inner_N) ** 4.5
                     + (np.asarray(qe_outer_N) / qc_outer_N) ** 4.5))
    return np.inf if s == 0.0 else s ** (-8.0 / 9.0)


def equivalent_reference_load(rating_N: float, life_Mrev: float) -> float:
    """P_ref = C L10r^(-3/10) [N]: the load that gives L10r by the catalogue formula (0 for an
    unloaded bearing, inf for a life of 0)."""
    if not np.isfinite(life_Mrev):
        return 0.0
    return np.inf if life_Mrev <= 0.0 else rating_N * life_Mrev ** -0.3


def life_hours(life_Mrev: float, speed_rpm: float) -> float:
    """L10r in hours at a constant inner-ring speed: 10⁶ L / (60 n); nan at n = 0 and at a
    speed so small that the hours leave the floating-point range (the ring as good as stands
    still: 5e-324 r/min gave inf)."""
    if not speed_rpm > 0:
        return float("nan")
    with np.errstate(over="ignore"):
        hours = np.float64(life_Mrev) * 1e6 / (60.0 * np.float64(speed_rpm))
    return float(hours) if np.isfinite(hours) else float("nan")


#: ISO 281:2007 a_ISO, radial roller bearings (Eq. 11, Table 11): x1, the bands' lower κ and
#: (c2, c3) of each band, the load-ratio exponent, the outer exponent and the cap
AISO_X1 = 1.5859
AISO_BANDS = ((0.1, 1.3993, 0.054381), (0.4, 1.2348, 0.19087), (1.0, 1.2348, 0.071739))
AISO_KAPPA_MIN, AISO_KAPPA_MAX = 0.1, 4.0
AISO_LOAD_EXPONENT = 0.4
AISO_EXPONENT = -9.185
AISO_CAP = 50.0
#: C_u = C0 / 8.2 for a roller bearing, times (100 / D_pw)^0.3 above D_pw = 100 mm (ISO 281)
CU_DIVISOR = 8.2
CU_PITCH_MM = 100.0
#: exponent e of the lives' Weibull slope (ISO/TS 16281): L = [Σ L_k^(-e)]^(-1/e), e = 9/8
LAMINA_WEIBULL = 9.0 / 8.0


def a_iso(kappa, ec_cu_over_p):
    """a_ISO [1] of a radial roller bearing (ISO 281:2007, the module docstring), vectorised
    over κ = ν/ν1 and e_C C_u / P; κ is clamped to [0.1, 4], a_ISO capped at 50 (also where the
    bracket is ≤ 0: below the fatigue limit). A NaN input gives NaN."""
    k = np.clip(np.asarray(kappa, dtype=float), AISO_KAPPA_MIN, AISO_KAPPA_MAX)
    x = np.asarray(ec_cu_over_p, dtype=float)
    c2 = np.where(k < AISO_BANDS[1][0], AISO_BANDS[0][1], AISO_BANDS[1][1])
    c3 = np.where(k < AISO_BANDS[1][0], AISO_BANDS[0][2],
                  np.where(k < AISO_BANDS[2][0], AISO_BANDS[1][2], AISO_BANDS[2][2]))
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        bracket = 1.0 - (AISO_X1 - c2 / k ** c3) * x ** AISO_LOAD_EXPONENT
        a = 0.1 * np.where(bracket > 0.0, bracket, 1.0) ** AISO_EXPONENT
    a = np.where(bracket > 0.0, np.minimum(a, AISO_CAP), AISO_CAP)
    return np.where(np.isnan(bracket), np.nan, a)


def fatigue_load_limit(static_rating_N: float, pitch_diameter_m: float) -> float:
    """C_u [N] of a roller bearing (ISO 281:2007): C0 / 8.2, times (100 / D_pw)^0.3 above
    D_pw = 100 mm."""
    dpw = pitch_diameter_m / MM
    cu = static_rating_N / CU_DIVISOR
    return cu * (CU_PITCH_MM / dpw) ** 0.3 if dpw > CU_PITCH_MM else cu


def lamina_load_ratio(ec_cu_over_c: float, qe_N, qc_N, laminae: int) -> np.ndarray:
    """e_C C_u / P_k [1] of each lamina (inf for an unloaded one), P_k = C N^(4/15)
    (q_e/q_c)^(6/5) the equivalent reference load of a bearing whose ``laminae`` N (both rings)
    were all loaded as this one (module docstring); ``ec_cu_over_c`` = e_C C_u / C."""
    qe = np.asarray(qe_N, dtype=float)
    ratio = np.where(qe > 0.0, qe, 1.0) / np.asarray(qc_N)
    return np.where(qe > 0.0, ec_cu_over_c / (laminae ** (4.0 / 15.0) * ratio ** 1.2), np.inf)


def modified_reference_rating_life(qe_inner_N, qe_outer_N, qc_inner_N, qc_outer_N,
                                   a_inner, a_outer) -> float:
    """L_nmr [10⁶ revolutions]: each lamina's life scaled by its own a_ISO (``a_inner``,
    ``a_outer``), combined as L10r combines the laminae (module docstring); inf unloaded."""
    def damage(qe, qc, a):  # an unloaded lamina adds none, whatever its a_ISO
        qe = np.asarray(qe, dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            scaled = np.asarray(a, dtype=float) ** -LAMINA_WEIBULL * (qe / qc) ** 4.5
        return np.where(qe > 0.0, scaled, 0.0)

    s = float(np.sum(damage(qe_inner_N, qc_inner_N, a_inner)
                     + damage(qe_outer_N, qc_outer_N, a_outer)))
    return np.inf if s == 0.0 else s ** (-8.0 / 9.0)
