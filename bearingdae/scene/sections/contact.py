"""``[traction]``, ``[cage]`` and ``[lubricant]``: the contact laws' constants, as written."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from ..histories import _Section


#: the metadata of a key that only a whirling cage reads (scene/switches.py)
_WHIRL_KEY = {"switch": "cage_whirl"}

#: the least land clearance and width [mm] (1 µm, 10 µm): the short-bearing film's forces grow
#: as width³/clearance³ (physics/cage_guidance.py), so a vanishing clearance (5e-324 was
#: accepted) made the cage's equations singular
LAND_CLEARANCE_MIN_MM = 1e-3
LAND_WIDTH_MIN_MM = 0.01


class TractionInput(_Section):
    """Roller-race traction law: the paper's law μ(V, p) (``law = "paper"``, default) or a
    slide-to-roll law μ(s) (``law = "slide-roll"``); theory, section 7."""

    law: Literal["paper", "slide-roll"] = Field(default="paper", description="traction law "
                                                "(theory.md §7)")
    A_s_m: float = Field(default=0.27, ge=0.0, le=100.0, description="paper law A [s/m]")
    B_GPa: float = Field(default=0.43, ge=1e-3, le=100.0, description="paper law B [GPa]")
    C_s_m: float = Field(default=6.93, ge=0.0, le=1e4, description="paper law C [s/m]")
    D: float = Field(default=0.022, ge=0.0, le=1.0, description="paper law D [-]")
    bracket: Literal["exp(-p/B)", "exp(-B/p)"] = Field(
        default="exp(-p/B)", description="reading of the paper's second bracket [1 - ...]")
    # The paper law has μ(0) = 0 (μ ∝ |V| near 0), so μ q sign(V) is already C¹ through V = 0;
    # a wide sign regularisation would flatten it to ∝ V|V| and remove the rolling damping.
    # Lower bound: v² must stay a normal float, or V/sqrt(V² + v²) is 0/0 at V = 0.
    velocity_scale_m_s: float = Field(default=1e-12, ge=1e-15, le=1.0, description="sign(V) "
                                      "regularisation V/sqrt(V² + v²) (default: effectively "
                                      "exact, the law is continuous)")
    # Slide-to-roll law μ(s) = (A + B s) e^(-C s) + D, s = |V| / sqrt(u² + u₀²) (law =
    # "slide-roll"; theory.md §7). The paper gives no such law: the defaults are illustrative
    # (physics/traction.py SLIDE_ROLL_DEFAULTS, with their reasoning); set measured ones here.
    slide_roll_A: float = Field(default=-0.04, ge=-1.0, le=1.0, description="slide-to-roll law "
                                "A [-] (μ(0) = A + D)")
    slide_roll_B: float = Field(default=2.8, ge=0.0, le=1e3, description="slide-to-roll law B [-]")
    slide_roll_C: float = Field(default=25.0, ge=0.0, le=1e4, description="slide-to-roll law "
                                "C [-] (decay rate in slide-to-roll ratio)")
    slide_roll_D: float = Field(default=0.04, ge=0.0, le=1.0, description="slide-to-roll law D "
                                "[-] (gross-sliding μ)")
    rolling_speed_floor_m_s: float = Field(default=1e-3, ge=1e-9, le=10.0, description="slide-"
                                           "to-roll law u₀ [m/s]: keeps s finite at standstill")


class CageInput(_Section):
    """Cage and roller-pocket contact (spring-damper at each roller end with a dead band of
    half the pocket clearance; theory, section 8)."""

    pocket_clearance_mm: float | None = Field(default=None, ge=0.0, le=100.0, description=
                                              "circumferential pocket clearance c_p (preset "
                                              "default; 0.1 mm without preset; the pockets must "
                                              "fit the cage: Z (D_w + c_p) < 2π r_i)")
    pocket_stiffness_N_m: float = Field(default=1e7, ge=1.0, le=1e12, description=
                                        "pocket contact stiffness K_a = K_b")
    damping_ratio: float = Field(default=0.1, ge=0.0, le=2.0, description="pocket contact "
                                 "damping ratio against one roller mass")
    friction: float = Field(default=0.002, ge=0.0, le=1.0, description="roller-cage friction "
                            "coefficient μ_c")
    density_kg_m3: float = Field(default=8500.0, gt=100.0, le=30_000.0, description="cage "
                                 "density (brass)")
    # Lower bound 1e-5 µm (10 pm): a kink sharper than that is no regularisation, and 0.01-1 µm
    # written in metres falls below it.
    # Default 0.01 µm: pocket penetrations are only 60-240 nm at
    # 1-4 rad/s skew impacts, so a 0.1 µm onset switched the damping only half on and made the
    # impacts nearly elastic (restitution 0.96 / 0.82 at 1 / 2 rad/s against the sharp theory.md §8
    # law's 0.52); at 0.01 µm it is 0.57 / 0.54 (physics/cage.py, tests/solvers/test_newmark.py).
    smoothing_um: float = Field(default=0.01, ge=1e-5, le=100.0, description="pocket contact "
                                "onset regularisation length (keep it << the pocket penetration "
                                "of an impact, ~0.1 µm, or the damping is only partly on)")
    # Not in the paper: the spin friction -r μ_c (|F_a| + |F_b|) sg(ω) uses the smooth
    # |F| ≈ sqrt(F² + f²) - f (physics/cage.py); f must stay << pocket forces of interest.
    spin_friction_force_scale_N: float = Field(default=1e-6, ge=1e-12, le=1.0, description=
                                               "smoothing force f of |F| in the roller-cage "
                                               "spin friction [N]")
    # Cage whirl (physics.cage_whirl = true; theory.md §17, scene/whirl.py). Every key defaults
    # to None so that a scene without whirl keeps its TOML text (and sweep hashes).
    mass_kg: float | None = Field(default=None, ge=1e-4, le=1e3, description="cage mass for its "
                                  "translation (default: from the cage annulus and density)",
                                  json_schema_extra=_WHIRL_KEY)
    guidance: Literal["roller", "outer-land", "inner-land"] | None = Field(
        default=None, json_schema_extra=_WHIRL_KEY,
        description="what holds the cage centre: the rollers (pockets alone, the "
        "default), a land of the outer ring (the cage's outer surface) or of the inner ring "
        "(the cage's bore)")
    land_clearance_mm: float | None = Field(default=None, ge=LAND_CLEARANCE_MIN_MM, le=10.0,
                                            description=
                                            "diametral clearance of the cage on its guiding "
                                            "land (default: half the pocket clearance)",
                                            json_schema_extra=_WHIRL_KEY)
    land_width_mm: float | None = Field(default=None, ge=LAND_WIDTH_MIN_MM, le=100.0,
                                        description="width "
                                        "of each of the cage's two guiding rims on the land "
                                        "(default: the rim, (cage width - roller length)/2)",
                                        json_schema_extra=_WHIRL_KEY)
    land_friction: float | None = Field(default=None, ge=0.0, le=1.0, description="friction "
                                        "coefficient of the cage on its land where the film "
                                        "closes (default 0.1)",
                                        json_schema_extra=_WHIRL_KEY)


class LubricantInput(_Section):
    """Oil-air mixture for orbit drag and churning (theory, section 9)."""

    oil_fraction: float = Field(default=0.015, ge=0.0, le=1.0, description="oil volume "
                                "fraction X of the oil-air mixture")
    oil_density_kg_m3: float = Field(default=870.0, ge=100.0, le=5000.0,
                                     description="oil density")
    air_density_kg_m3: float = Field(default=1.2, ge=0.0, le=100.0, description="air density")
    # Lower bound: below any gas (air 1.8e-5 Pa s); a Reynolds number of inf follows from 0.
    viscosity_Pa_s: float = Field(default=0.01, ge=1e-6, le=100.0, description="oil dynamic "
                                  "viscosity")
    # Range: water ~0.5, mineral oils 10-35, traction fluids up to ~50 GPa⁻¹.
    pressure_viscosity_GPa_inv: float | None = Field(default=None, ge=0.1, le=100.0,
                                                     description="oil pressure-viscosity "
                                                     "coefficient α of the EHL film (default "
                                                     "22 GPa⁻¹, a mineral oil)")
    # None (= 0.1) by default, so that every existing scene keeps its TOML text
    boundary_friction: float | None = Field(default=None, ge=0.0, le=1.0, json_schema_extra={
                                            "switch": "lubrication"}, description=
                                            "friction coefficient of the asperity contacts "
                                            "of mixed lubrication (physics.lubrication = "
                                            "\"mixed\", theory.md §20; default 0.1)")
    # Rolling resistance's thermal loading parameter (physics.rolling_resistance, theory.md §19)
    temperature_viscosity_K_inv: float | None = Field(
        default=None, ge=0.0, le=1.0, json_schema_extra={"switch": "rolling_resistance",
                                                         "supplied_by": "thermal"},
        description="temperature-viscosity coefficient β = "
        "-d ln η / dT of the oil, for the rolling resistance's inlet heating (Goksem & "
        "Hargreaves's law; the others are isothermal) (default 0.03 K⁻¹, a mineral oil; 0: "
        "isothermal)")
    thermal_conductivity_W_m_K: float | None = Field(
        default=None, ge=0.01, le=10.0, json_schema_extra={"switch": "rolling_resistance"},
        description="thermal conductivity of the oil, for the "
        "rolling resistance's inlet heating (Goksem & Hargreaves's law) (default 0.13 W/(m K), "
        "a mineral oil)")
    # The oil's viscosity-temperature data: with or without physics.thermal (the switch changes
    # the oil's temperatures, never the oil). None keeps every other scene's TOML text.
    viscosity_40C_mm2_s: float | None = Field(default=None, ge=2.0, le=1e5, description=
                                              "kinematic viscosity at 40 °C of the oil (ASTM "
                                              "D341's first point; with viscosity_100C_mm2_s "
                                              "it replaces viscosity_Pa_s); default with "
                                              "physics.thermal = \"steady\": 32, an ISO VG 32 "
                                              "mineral oil")
    viscosity_100C_mm2_s: float | None = Field(default=None, ge=2.0, le=1e4, description=
                                               "kinematic viscosity at 100 °C of that oil; "
                                               "default with physics.thermal = \"steady\": 5.4 "
                                               "(ISO VG 32, viscosity index ~100)")
    operating_temperature_C: float | None = Field(
        default=None, ge=-60.0, le=250.0, description="temperature at which the laws read "
        "the oil's viscosity (viscosity_40C_mm2_s, viscosity_100C_mm2_s) without "
        "physics.thermal; with physics.thermal = \"steady\" the network's temperatures replace "
        "it, and the first block starts there (default: the network's answer to the start "
        "state's losses)")
    # Starvation of the rolling resistance (theory.md §19); None: fully flooded, and every
    # other scene keeps its TOML text.
    inlet_film_um: float | None = Field(
        default=None, ge=1e-3, le=1e3, json_schema_extra={"switch": "rolling_resistance"},
        description="oil film available at a raceway contact's inlet h_a, "
        "for the rolling resistance's starvation ratio (Biboulet & Houpert's eq. 44 at S = "
        "h_a / the slice's fully flooded minimum film; the user guide says how to choose it); "
        "default: fully flooded")
    # The modified life (ISO 281's a_ISO; analysis/rating_life.py); None: not computed, and
    # every other scene keeps its TOML text.
    contamination_factor: float | None = Field(
        default=None, ge=0.0, le=1.0, description="contamination factor e_C of ISO 281's "
        "life modification factor a_ISO, from extreme cleanliness (1) to severe contamination "
        "(0); given, the result has the modified rating life L_nmr (default: not computed)")
