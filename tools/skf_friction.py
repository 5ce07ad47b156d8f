"""The SKF catalogue model of a cylindrical roller bearing's frictional moment (a reference).

An independent reference for bearingdae's friction torque, typed here from the published model
and constants; nothing in this file calls bearingdae. Used by the slow catalogue test
(tests/validation/test_catalogue_friction.py) and by tools/catalogue_friction.py, which writes
the table and figure of docs/user-guide.md ("Friction, power loss and temperature against the
catalogue").

Source: SKF General Catalogue 6000/I EN (2008), chapter "Friction", "The SKF model for
calculating the frictional moment" (the same model in SKF's online "Rolling bearings"
catalogue, 17000 EN, 2018). Units are the catalogue's: n [r/min], ν [mm²/s], d_m [mm],
F [N], M [N·mm]:

    M     = M_rr + M_sl + M_seal + M_drag                                   (total)
    M_rr  = φ_ish φ_rs G_rr (ν n)^0.6                                       (rolling)
    G_rr  = R1 d_m^2.41 F_r^0.31                     (Table 2a, cylindrical roller bearings)
    M_sl  = G_sl μ_sl,  G_sl = S1 d_m^0.9 F_a + S2 d_m F_r                  (sliding)
    μ_sl  = φ_bl μ_bl + (1 - φ_bl) μ_EHL,  φ_bl = exp(-2.6e-8 (n ν)^1.4 d_m)
    φ_ish = 1 / (1 + 1.84e-9 (n d_m)^1.28 ν^0.64)                   (inlet shear heating)
    φ_rs  = exp(-K_rs ν n (d + D) sqrt(K_Z / (2 (D - d))))  (kinematic replenishment/starvation)

Constants of a single-row cylindrical roller bearing with a cage (Tables 1 and 2b, bearing
series 2, 3, 4, 10): R1 = 1.09e-6, S1 = 0.16, S2 = 0.0015, K_Z = 5.1; μ_bl ≈ 0.15 (the
additive package; "generally ≈ 0.15"), μ_EHL = 0.02 for cylindrical roller bearings. K_rs =
6e-8 for oil-air (and grease) lubrication, 3e-8 for a low oil bath and oil jet: bearingdae's
lubricant is an oil-air mixture (oil volume fraction 1.5 %), so 6e-8. The bearings of the
paper are no catalogue series (yang20: 30 x 60 mm with 25.5 mm rollers; harris36: 146 x 220 mm);
series 22 would give R1 = 1.12e-6 (+3 %), the spread the comparison has to live with.

Not included: M_seal (the bearings are open) and M_drag (the catalogue gives drag for an oil
bath; for oil-air lubrication it has none; bearingdae's orbit drag and churning of the
oil-air mixture are reported as sources of their own).

ν: the catalogue wants the oil's kinematic viscosity at the operating temperature; with
bearingdae's thermal model off the oil's viscosity is the scene's fixed dynamic viscosity η,
so ν = η / ρ (η = lubricant.viscosity_Pa_s, ρ = lubricant.oil_density_kg_m3).
"""

from __future__ import annotations

import math

#: cylindrical roller bearings, series 2, 3, 4, 10 (SKF 6000/I EN, Tables 1, 2a, 2b)
R1 = 1.09e-6
S1 = 0.16
S2 = 0.0015
K_Z = 5.1
MU_BL = 0.15
MU_EHL = 0.02
K_RS_OIL_AIR = 6e-8
K_RS_OIL_JET = 3e-8

#: the bore d and outside diameter D [mm] of the paper's bearings (Yang et al. 2024, Tables
#: 1 and 2), and the oil of bearingdae's default lubricant (η [Pa s], ρ [kg/m³])
BEARINGS_MM = {"yang20": (30.0, 60.0), "harris36": (146.0, 220.0)}
OIL_VISCOSITY_PA_S = 0.01
OIL_DENSITY_KG_M3 = 870.0


def kinematic_viscosity_mm2_s(viscosity_Pa_s: float = OIL_VISCOSITY_PA_S,
                              density_kg_m3: float = OIL_DENSITY_KG_M3) -> float:
    """ν = η / ρ in the catalogue's unit, mm²/s (1 m²/s = 1e6 mm²/s)."""
    return viscosity_Pa_s / density_kg_m3 * 1e6


def inlet_shear_factor(n_rpm: float, dm_mm: float, nu_mm2_s: float) -> float:
    """φ_ish = 1 / (1 + 1.84e-9 (n d_m)^1.28 ν^0.64)."""
    return 1.0 / (1.0 + 1.84e-9 * (n_rpm * dm_mm) ** 1.28 * nu_mm2_s ** 0.64)


def replenishment_factor(n_rpm: float, d_mm: float, D_mm: float, nu_mm2_s: float,
                         K_rs: float = K_RS_OIL_AIR) -> float:
    """φ_rs = exp(-K_rs ν n (d + D) sqrt(K_Z / (2 (D - d))))."""
    return math.exp(-K_rs * nu_mm2_s * n_rpm * (d_mm + D_mm)
                    * math.sqrt(K_Z / (2.0 * (D_mm - d_mm))))


def sliding_coefficient(n_rpm: float, dm_mm: float, nu_mm2_s: float) -> float:
    """μ_sl = φ_bl μ_bl + (1 - φ_bl) μ_EHL with φ_bl = exp(-2.6e-8 (n ν)^1.4 d_m)."""
    phi_bl = math.exp(-2.6e-8 * (n_rpm * nu_mm2_s) ** 1.4 * dm_mm)
    return phi_bl * MU_BL + (1.0 - phi_bl) * MU_EHL


def frictional_moment_Nmm(n_rpm: float, Fr_N: float, d_mm: float, D_mm: float,
                          nu_mm2_s: float, Fa_N: float = 0.0, K_rs: float = K_RS_OIL_AIR
                          ) -> dict[str, float]:
    """{"rolling", "sliding", "total"} [N·mm] of an open, oil-air lubricated cylindrical
    roller bearing (no seal, no drag)."""
    dm = 0.5 * (d_mm + D_mm)
    G_rr = R1 * dm ** 2.41 * Fr_N ** 0.31
    M_rr = (inlet_shear_factor(n_rpm, dm, nu_mm2_s)
            * replenishment_factor(n_rpm, d_mm, D_mm, nu_mm2_s, K_rs)
            * G_rr * (nu_mm2_s * n_rpm) ** 0.6)
    G_sl = S1 * dm ** 0.9 * Fa_N + S2 * dm * Fr_N
    M_sl = G_sl * sliding_coefficient(n_rpm, dm, nu_mm2_s)
    return {"rolling": M_rr, "sliding": M_sl, "total": M_rr + M_sl}


def friction_torque_N_m(bearing: str, n_rpm: float, Fr_N: float,
                        nu_mm2_s: float | None = None) -> float:
    """The catalogue's total frictional moment [N m] of one of :data:`BEARINGS_MM`."""
    d, D = BEARINGS_MM[bearing]
    nu = kinematic_viscosity_mm2_s() if nu_mm2_s is None else nu_mm2_s
    return frictional_moment_Nmm(n_rpm, Fr_N, d, D, nu)["total"] * 1e-3
