"""The scene file as written (user units), checked by pydantic (pipeline stage 1, layer 1).

One pydantic model per TOML section (types, ranges, unknown keys), the section table
``_SECTIONS``, and what documents the keys: :func:`valid_keys`, :func:`key_table`,
:func:`allowed_range`. Conversion to SI is :mod:`bearingdae.scene.convert`.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field, field_validator

from .errors import close_matches
from .histories import LOAD_KEYS, LOAD_MAX_N, LoadTable, MomentTable, _Section  # noqa: F401
from .parameters import PRESETS, STEEL, preset_names

PROFILES = ("flat", "end-crown", "full-crown", "logarithmic")
SPEED_MAX_RPM = 200_000.0  #: highest inner-ring speed a scene may ask for
RPM_TO_RAD_S = 2.0 * math.pi / 60.0  #: the one r/min -> rad/s conversion (scene boundary)

#: Dynamic output variables and the ``[physics]`` switch each needs (None: always available).
OUTPUT_VARIABLES = {
    "cage_angle": "cage", "cage_speed": "cage", "inner_ring_speed": None,
    "roller_azimuth": None, "orbit_speed": None, "spin_speed": None,
    "skew_angle": "skew", "skew_rate": "skew", "roller_tilt": "tilt",
    "roller_radial_position": None, "contact_force": None, "contact_pressure": None,
    "slip_velocity": None, "traction_force": None, "cage_force": "cage",
    "ring_displacement": None, "ring_tilt": "tilt", "applied_load": None,
    "applied_moment": None, "ring_velocity": "ring", "ring_acceleration": "ring",
    # running extremes at every solver step over the recorded window (each with its
    # ``<name>_time``; system/extremes.py): asked for by name, or all by default
    "cage_force_max": "cage", "contact_force_max": None, "contact_pressure_max": None,
    "slip_velocity_max": None, "skew_angle_max": "skew",
    # the peak traces: per sample, the largest value over the bearing of every solver step
    # since the sample before (results/extremes.py)
    "cage_force_peak": "cage", "contact_pressure_peak": None, "skew_angle_peak": "skew",
    "slip_velocity_peak": None,
    # post-processed (results/engineering.py): film, power loss, energy
    "film_thickness_central": None, "film_thickness_min": None, "lambda_ratio": None,
    "power_loss_W": None, "friction_torque_N_m": None, "drive_torque_N_m": None,
    "drive_power_W": None, "kinetic_energy_J": None,
    # roller end-flange contacts (a bearing type with flanges, theory.md §16)
    "flange_force": "flange", "flange_axial_force": "flange", "inner_flange_axial_force":
    "flange", "flange_slip_velocity": "flange", "flange_friction_power": "flange",
    "roller_axial_position": "flange", "ring_axial_displacement": "flange",
    "applied_axial_load": "flange",
    # cage whirl (physics.cage_whirl, theory.md §17)
    "cage_center": "cage_whirl", "cage_land_force": "cage_whirl",
}
#: the extremes among the output variables (kept at every solver step, not at samples)
EXTREME_VARIABLES = tuple(name for name in OUTPUT_VARIABLES
                          if name.endswith("_max") or name.endswith("_peak"))


def switch_on(physics, switch: str, bearing=None) -> bool:
    """Whether the ``[physics]`` switch an output variable needs is on (``ring``: a dynamic
    ring; ``flange``: a ``[bearing] type`` with flanges; the others are booleans)."""
    if switch == "flange":
        return bearing is not None and bearing.type is not None
    value = getattr(physics, switch)
    return value == "dynamic" if switch == "ring" else bool(value)


# --------------------------------------------------------------------------------------------
# Layer 1: the file as written (user units), checked by pydantic
# --------------------------------------------------------------------------------------------
class BearingInput(_Section):
    """Geometry: a named bearing (``preset``, the paper's Tables 1 and 2) and any values that
    override it; without a preset every geometry key must be given."""

    preset: str | None = Field(default=None, description="named bearing (harris36, yang20) whose "
                               "values fill every key not given")
    rollers: int | None = Field(default=None, ge=3, le=500, description="number of rollers Z")
    # Lower bounds: no rolling bearing is smaller (needle rollers start near 1 mm); they catch
    # lengths written in metres (a 4 mm roller as 0.004), which the cross-field checks miss when
    # the whole [bearing] is in metres.
    outer_diameter_mm: float | None = Field(default=None, ge=1.0, le=10_000,
                                            description="bearing outer diameter D")
    bore_mm: float | None = Field(default=None, ge=0.5, le=10_000, description="bore d")
    pitch_diameter_mm: float | None = Field(default=None, ge=1.0, le=10_000,
                                            description="pitch diameter d_m (default (D + d)/2)")
    roller_diameter_mm: float | None = Field(default=None, ge=0.5, le=1_000,
                                             description="roller diameter D_w")
    roller_length_mm: float | None = Field(default=None, ge=0.5, le=1_000,
                                           description="roller total length L (sliced length)")
    effective_length_mm: float | None = Field(default=None, ge=0.5, le=1_000,
                                              description="straight length L_s (default L; "
                                              "at most L)")
    crown_radius_mm: float | None = Field(default=None, ge=0.5, le=1e6,
                                          description="crown radius R_y (end-crown, full-crown)")
    profile: Literal["flat", "end-crown", "full-crown", "logarithmic"] | None = Field(
        default=None, description="roller profile (default end-crown if crown_radius_mm "
        "is given, else flat)")
    radial_clearance_mm: float | None = Field(
        default=None, ge=-1_000, le=1_000,
        description="diametral radial clearance P_d (negative = preload; -D_w < P_d < D_w)")
    design_load_N: float | None = Field(
        default=None, gt=0, le=1e8,
        description="logarithmic profile design load (default 4.08 F_r / Z)")
    # Lower bound: no rolling bearing is rated below 1 N (and a rating of ~0 makes L10r 0).
    basic_dynamic_load_rating_N: float | None = Field(
        default=None, ge=1.0, le=1e9,
        description="catalogue basic dynamic load rating C for the ISO/TS 16281 rating life "
        "(default: from the geometry by ISO 281)")

    # Flanges (ribs; theory.md §16, scene/flanges.py). Every key defaults to None so that a
    # flangeless scene's TOML text (and sweep hashes) stay as they were.
    type: Literal["NU", "N", "NJ", "NUP"] | None = Field(
        default=None, description="bearing type, i.e. which ring has flanges: NU (outer two), "
        "N (inner two), NJ (outer two, inner one at the -x end: axial load in +X), NUP (both "
        "two: axial load either way); default none: the paper's flangeless model")
    flange_angle_deg: float | None = Field(
        default=None, gt=0.0, le=10.0, description="flange (rib) face inclination α from the "
        "radial plane (default 0.5°)")
    flange_height_mm: float | None = Field(
        default=None, gt=0.0, le=1_000, description="flange height above the raceway "
        "(default 0.2 D_w; below the roller radius)")
    roller_end: Literal["flat", "spherical"] | None = Field(
        default=None, description="roller end face: spherical (radius roller_end_radius_mm, "
        "the default) or flat (edge contact at the flange rim)")
    roller_end_radius_mm: float | None = Field(
        default=None, gt=0.0, le=1e5, description="spherical roller end radius R_e (default: "
        "the contact at mid flange face, R_e sin α = r - (h_f + r_k)/2)")
    roller_corner_radius_mm: float | None = Field(
        default=None, ge=0.0, le=1_000, description="roller corner radius r_k (default "
        "0.05 D_w); for flat ends also the radius of the edge contact")
    flange_clearance_mm: float | None = Field(
        default=None, ge=0.0, le=100.0, description="axial play of a roller between the two "
        "flanges of one ring (default 0.02 mm)")
    flange_friction: float | None = Field(
        default=None, ge=0.0, le=1.0, description="sliding friction coefficient of the roller "
        "end-flange contact (default 0.05, mixed lubrication)")

    @field_validator("preset")
    @classmethod
    def _known_preset(cls, v: str | None) -> str | None:
        if v is not None and v not in PRESETS:
            close = close_matches(v, preset_names(), n=1)
            hint = f". Did you mean '{close[0]}'" if close else ""
            raise ValueError(f"unknown preset; allowed: {', '.join(preset_names())}{hint}")
        return v


class MaterialsInput(_Section):
    """Elastic constants and density of rollers and rings (steel by default)."""

    youngs_modulus_GPa: float = Field(default=STEEL["youngs_modulus_GPa"], gt=1.0, le=2000.0,
                                      description="Young's modulus E of rollers and rings")
    poisson_ratio: float = Field(default=STEEL["poisson_ratio"], ge=0.0, lt=0.5,
                                 description="Poisson's ratio ν of rollers and rings")
    density_kg_m3: float = Field(default=STEEL["density_kg_m3"], gt=100.0, le=30_000.0,
                                 description="density ρ of rollers and rings")
    # Default None (= 0.11 µm, scene/convert.py): a default would enter every scene's TOML
    # and so change every sweep run's hash (bearingdae.studies.sweep.run_key).
    # Lower bound 1 nm: smoother than any machined surface (super-polished ~ 1-5 nm).
    roughness_um: float | None = Field(default=None, ge=1e-3, le=10.0, description="composite "
                                       "RMS roughness σ = sqrt(σ_roller² + σ_race²) of the "
                                       "film parameter λ = h_min/σ (default 0.11: rollers "
                                       "0.05 µm, raceways 0.1 µm Rq)")


class SpeedRamp(_Section):
    """Piecewise-linear inner-ring speed, held constant after the last point."""

    times_s: list[float] = Field(min_length=2)
    values_rpm: list[float] = Field(min_length=2)

    @field_validator("times_s")
    @classmethod
    def _increasing(cls, v: list[float]) -> list[float]:
        if v[0] != 0.0:
            raise ValueError("the ramp must start at 0 s")
        if any(b <= a for a, b in zip(v, v[1:])):
            raise ValueError("times must be strictly increasing")
        return v

    @field_validator("values_rpm")
    @classmethod
    def _range(cls, v: list[float]) -> list[float]:
        if any(not (0.0 <= s <= SPEED_MAX_RPM) for s in v):
            raise ValueError(f"every speed must lie in [0, {SPEED_MAX_RPM:g}] r/min")
        return v


class OperatingInput(_Section):
    """Operating point: inner-ring speed (constant or a start-up ramp) and the loads on the
    inner ring (outer ring fixed): constants, histories (a table or a load file) and a load
    rotating with the shaft (unbalance); theory.md §14."""

    speed_rpm: float | SpeedRamp = Field(
        default=0.0, description="inner-ring speed n, or a ramp "
        "{times_s = [...], values_rpm = [...]}")
    radial_load_N: float | LoadTable = Field(
        default=0.0, description="radial load F_r on the inner ring, towards φ = 0, or a "
        "history {times_s = [...], values_N = [...]} (piecewise linear, held at its ends; "
        "values may be negative)")
    moment_Nm: float | MomentTable = Field(
        default=0.0, description="moment M; > 0 loads the +x roller end at φ = 0; or a "
        "history {times_s = [...], values_Nm = [...]}")
    tangential_load_N: float | LoadTable = Field(
        default=0.0, description="second radial component F_t, towards φ = 90°, or a "
        "history {times_s = [...], values_N = [...]}")
    tangential_moment_Nm: float | MomentTable = Field(
        default=0.0, description="moment M_t; > 0 loads +x at φ = 90°; or a history "
        "{times_s = [...], values_Nm = [...]}")
    axial_load_N: float | LoadTable | None = Field(
        default=None, description="axial load F_a on the inner ring along +X (needs "
        "bearing.type NJ (F_a >= 0 at every time) or NUP), or a history {times_s = [...], "
        "values_N = [...]}")
    unbalance_N: float = Field(default=0.0, ge=0.0, le=LOAD_MAX_N, description="amplitude U "
                               "of a load rotating with the shaft (unbalance), added to F_r, F_t")
    unbalance_phase_deg: float = Field(default=0.0, ge=-360.0, le=360.0, description="direction "
                                       "of the unbalance load at t = 0, from φ = 0 towards "
                                       "φ = 90°")
    load_file: str | None = Field(default=None, min_length=1, max_length=4096, description=
                                  "load history from another tool: a NetCDF (.nc) or CSV (.csv) "
                                  "file with radial_load_N, tangential_load_N, moment_Nm "
                                  "(tangential_moment_Nm, axial_load_N) on a time coordinate "
                                  "in s (docs/user-guide.md); relative to the scene file; "
                                  "replaces the four radial load keys (and axial_load_N if "
                                  "the file has it)")

    @field_validator("speed_rpm")
    @classmethod
    def _speed(cls, v: float | SpeedRamp) -> float | SpeedRamp:
        if isinstance(v, float) and not (0.0 <= v <= SPEED_MAX_RPM):
            raise ValueError("must not be negative (the inner ring turns in +X)")
        return v

    @field_validator(*LOAD_KEYS)
    @classmethod
    def _load(cls, v, info):
        lo, hi = LOAD_KEYS[info.field_name]
        if isinstance(v, float) and not (lo <= v <= hi):
            raise ValueError(f"outside the allowed range [{lo:g}, {hi:g}]")
        return v


class PhysicsInput(_Section):
    """Switches: a switched-off effect removes its unknowns and equations (not just zeros)."""

    skew: bool = Field(default=True, description="roller skew θz, ζ (unknowns and equations)")
    cage: bool = Field(default=True, description="cage rotation and roller-pocket contact")
    drag: bool = Field(default=True, description="lubricant orbit drag and churning moments")
    tilt: bool = Field(default=True, description="roller tilt β and ring tilts γ (needed by "
                       "moment loads)")
    gyroscopic: bool = Field(default=True, description="gyroscopic term of the skew equation")
    slip: Literal["rigid", "paper"] = Field(default="rigid", description="slip kinematics "
                                             "(theory.md §6): rigid-body, or the paper's r_λ")
    orbit: Literal["newton", "paper"] = Field(default="newton", description="orbit equation "
                                               "(theory.md §10): Newton on the roller centre, or "
                                               "the paper's moment form")
    ring: Literal["quasi-static", "dynamic"] = Field(
        default="quasi-static", description="inner ring (theory.md §15): massless, in "
        "quasi-static equilibrium (the paper's), or a body whose displacement (and tilt) "
        "are differential unknowns with velocities (section [ring])")
    # None (not False) by default, so that a scene without whirl keeps its TOML text and hashes
    cage_whirl: bool | None = Field(
        default=None, description="cage whirl (theory.md §17): the cage centre's two in-plane "
        "translations and velocities are unknowns, held by the pockets or a guiding land "
        "(section [cage] guidance); default false: the cage only rotates")


class RingInput(_Section):
    """The inner ring as a body (``physics.ring = "dynamic"``; theory.md §15): its mass, tilt
    inertia and an optional elastic support to ground (shaft / housing) in parallel with the
    bearing."""

    mass_kg: float | None = Field(default=None, gt=0.0, le=1e5, description="mass moved with "
                                  "the inner ring (default: the ring from its geometry, bore to "
                                  "inner raceway over the roller length, at materials."
                                  "density_kg_m3; add the shaft's share here)")
    tilt_inertia_kg_m2: float | None = Field(default=None, gt=0.0, le=1e4, description=
                                             "moment of inertia about a diameter (tilt; "
                                             "default: the ring's, from its geometry)")
    support_stiffness_N_m: float = Field(default=0.0, ge=0.0, le=1e12, description="stiffness "
                                         "of an elastic support of the ring to ground, radial "
                                         "(both directions); 0: none, the load acts on the "
                                         "ring alone")
    support_damping_N_s_m: float = Field(default=0.0, ge=0.0, le=1e8, description="viscous "
                                         "damping of that support, radial (both directions)")


class TractionInput(_Section):
    """Roller-race traction law: the paper's law μ(V, p) (``law = "paper"``, default) or a
    slide-to-roll law μ(s) (``law = "slide-roll"``); theory, section 7."""

    law: Literal["paper", "slide-roll"] = Field(default="paper", description="traction law "
                                                "(theory.md §7)")
    A_s_m: float = Field(default=0.27, ge=0.0, le=100.0, description="paper law A [s/m]")
    B_GPa: float = Field(default=0.43, gt=0.0, le=100.0, description="paper law B [GPa]")
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
    pocket_stiffness_N_m: float = Field(default=1e7, gt=0.0, le=1e12, description=
                                        "pocket contact stiffness K_a = K_b")
    damping_ratio: float = Field(default=0.1, ge=0.0, le=2.0, description="pocket contact "
                                 "damping ratio against one roller mass")
    friction: float = Field(default=0.002, ge=0.0, le=1.0, description="roller-cage friction "
                            "coefficient μ_c")
    density_kg_m3: float = Field(default=8500.0, gt=100.0, le=30_000.0, description="cage "
                                 "density (brass)")
    # Lower bound 1e-5 µm (10 pm): a kink sharper than that is no regularisation, and 0.01-1 µm
    # written in metres falls below it.
    # Default 0.01 µm (was 0.1 µm until 2026-11-21): pocket penetrations are only 60-240 nm at
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
    mass_kg: float | None = Field(default=None, gt=0.0, le=1e3, description="cage mass for its "
                                  "translation (default: from the cage annulus and density)")
    guidance: Literal["roller", "outer-land", "inner-land"] | None = Field(
        default=None, description="what holds the cage centre: the rollers (pockets alone, the "
        "default), a land of the outer ring (the cage's outer surface) or of the inner ring "
        "(the cage's bore)")
    land_clearance_mm: float | None = Field(default=None, gt=0.0, le=10.0, description=
                                            "diametral clearance of the cage on its guiding "
                                            "land (default: half the pocket clearance)")
    land_width_mm: float | None = Field(default=None, gt=0.0, le=100.0, description="width "
                                        "of each of the cage's two guiding rims on the land "
                                        "(default: the rim, (cage width - roller length)/2)")
    land_friction: float | None = Field(default=None, ge=0.0, le=1.0, description="friction "
                                        "coefficient of the cage on its land where the film "
                                        "closes (default 0.1)")


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


class LifeInput(_Section):
    """ISO/TS 16281 rating life (post-processing: does not change the simulation)."""

    edge_stress_factors: bool | None = Field(default=None, description="apply ISO/TS 16281's "
                                             "edge-stress factors to the lamina loads "
                                             "(default true, as the standard does)")
    phase_positions: int | None = Field(default=None, ge=0, le=360, description="static "
                                        "solve: also the life averaged over this many "
                                        "positions of the roller set within one roller pitch "
                                        "(a few static solves each; default 0 = off)")


class OutputInput(_Section):
    """What the NetCDF file keeps."""

    variables: list[str] | None = Field(default=None, description="output variables to keep "
                                        "(default: all the physics provides); the extremes "
                                        "(names ending in _max, kept at every solver step) "
                                        "cost run time only when one of them is listed")
    # Default None (= float64) rather than "float64": a default would enter every scene's TOML
    # and so change every sweep run's hash (bearingdae.studies.sweep.run_key).
    precision: Literal["float64", "float32"] | None = Field(
        default=None, description="floating-point type of the data variables in the NetCDF "
        "file: float64 (default, reference runs) or float32 (about half the size, relative "
        "rounding 6e-8; docs/user-guide.md)")

    @field_validator("variables")
    @classmethod
    def _known(cls, v: list[str] | None) -> list[str] | None:
        for name in v or []:
            if name not in OUTPUT_VARIABLES:
                close = close_matches(name, list(OUTPUT_VARIABLES), n=1)
                hint = f"; did you mean '{close[0]}'" if close else ""
                raise ValueError(f"unknown output variable '{name}'{hint}; allowed: "
                                 + ", ".join(OUTPUT_VARIABLES))
        return v


class NumericsInput(_Section):
    """Slices, tolerances, the recorded window and the settings of the solvers."""

    slices: int = Field(default=10, ge=1, le=1000, description="slices k along the roller length")
    rtol: float = Field(default=1e-6, ge=1e-12, le=1e-1, description="IDA relative tolerance")
    # Upper bound measured: atol = 1e-3 (with rtol 1e-3) failed within 8 ms on the baseline,
    # 1e-4 ran; atol = 1e-6 already costs 15x the cage-speed error of 1e-8 (CHANGELOG.md).
    atol: float = Field(default=1e-8, ge=1e-14, le=1e-4, description="IDA absolute tolerance "
                        "in units of each unknown's scale (see output metadata)")
    warmup_cage_revolutions: float = Field(default=1.0, ge=0.0, le=1e4, description="simulated "
                                           "cage revolutions before recording")
    cage_revolutions: float = Field(default=3.0, gt=0.0, le=1e5, description="recorded cage "
                                    "revolutions")
    samples_per_cage_revolution: int = Field(default=200, ge=2, le=100_000, description=
                                             "output samples per cage revolution")
    max_steps: int = Field(default=500_000, ge=100, le=100_000_000, description="step limit (IDA; "
                           "Newmark refuses a run needing more fixed steps)")
    # Lower bound 1e-4 nm (0.1 pm): smaller lengths vanish against a µm approach in double
    # precision; it also catches 1 nm written in metres (1e-9).
    contact_smoothing_nm: float = Field(
        default=1.0, ge=1e-4, le=1.0,
        description="contact-onset regularisation length ε (theory.md §5: at most 1 nm)")
    # Lower bound: the relative residual of a force balance summed over Z x k slices stalls at
    # 1e-16 .. 4e-15 (measured on yang20, harris36, 30 000 r/min, zero load); 1e-14 is reachable.
    static_tolerance: float = Field(default=1e-12, ge=1e-14, le=1e-3,
                                    description="relative force residual of the static Newton")
    static_max_iterations: int = Field(default=100, ge=1, le=10_000,
                                       description="Newton iteration limit per stage")
    # Newmark-β (solver="newmark", theory.md §12). Default step, measured on the baseline
    # (docs/theory.md "Newmark-β"): ~20 steps per period of the ~24 kHz skew-pocket mode, and
    # the stiffest traction mode (λ ≈ -7e5 1/s, h λ ≈ -1.4) still decays ~6x per step.
    newmark_step_s: float = Field(default=2e-6, ge=1e-10, le=1e-2, description="Newmark-β "
                                  "fixed step h (the largest step; output times are hit exactly)")
    newmark_beta: float | None = Field(default=None, gt=0.0, le=0.5, description="Newmark β "
                                       "(default (1 - hht_alpha)²/4: 1/4 = average acceleration)")
    newmark_gamma: float | None = Field(default=None, ge=0.5, le=1.0, description="Newmark γ "
                                        "(default 1/2 - hht_alpha: 1/2 = no numerical damping)")
    hht_alpha: float = Field(default=0.0, ge=-1.0 / 3.0, le=0.0, description="HHT-α numerical "
                             "damping (0 = plain Newmark; -1/3 = most damping)")
    newmark_error_estimate: bool = Field(default=False, description="Newmark: run a second "
                                         "solution at h/2 beside the first and report the "
                                         "Richardson estimate of the global error (3x cost)")
    # Steady state on demand (bearingdae/run/steady.py). The tolerance is a fraction of
    # the epicyclic cage speed: 1e-3 resolves Fig 11's 0.1 %-level saturation; below 1e-6 the
    # block means of a skidding bearing never settle (pocket impacts make ~1e-5 noise).
    until_steady: bool = Field(default=False, description="run the warm-up in blocks until the "
                               "cage speed is steady (criterion: docs/user-guide.md, "
                               "bearingdae/run/steady.py), then record cage_revolutions")
    steady_tolerance: float = Field(default=1e-3, ge=1e-6, le=0.1, description="until_steady: "
                                    "allowed change of the block-mean cage speed between blocks "
                                    "(and extrapolated remaining drift), as a fraction of the "
                                    "epicyclic cage speed")
    steady_block_cage_revolutions: float = Field(default=1.0, ge=0.05, le=100.0, description=
                                                 "until_steady: length of one block of the "
                                                 "warm-up [cage revolutions]")
    max_warmup_cage_revolutions: float = Field(default=200.0, ge=0.05, le=1e5, description=
                                               "until_steady: cap on the warm-up [cage "
                                               "revolutions]; a run reaching it is marked not "
                                               "steady")
    initial_speeds: Literal["auto", "epicyclic", "torque_balance"] = Field(
        default="auto", description="initial cage and roller speeds: 'epicyclic' (pure "
        "rolling), 'torque_balance' (quasi-static skid estimate, bearingdae/solvers/"
        "torque_balance.py) or 'auto' (torque_balance with until_steady, which then starts "
        "near the steady state it looks for; epicyclic otherwise)")


class SceneInput(_Section):
    title: str | None = None

    @field_validator("title")
    @classmethod
    def _utf8(cls, v: str | None) -> str | None:
        if v is not None:
            try:
                v.encode("utf-8")
            except UnicodeEncodeError as exc:  # lone surrogates cannot be written to NetCDF
                raise ValueError(f"must be UTF-8 text (character {exc.start} is not)") from None
        return v
    bearing: BearingInput = BearingInput()
    materials: MaterialsInput = MaterialsInput()
    operating: OperatingInput = OperatingInput()
    numerics: NumericsInput = NumericsInput()
    physics: PhysicsInput = PhysicsInput()
    traction: TractionInput = TractionInput()
    cage: CageInput = CageInput()
    lubricant: LubricantInput = LubricantInput()
    ring: RingInput = RingInput()
    life: LifeInput = LifeInput()
    output: OutputInput = OutputInput()


_SECTIONS: dict[str, type[_Section]] = {
    "bearing": BearingInput,
    "materials": MaterialsInput,
    "operating": OperatingInput,
    "numerics": NumericsInput,
    "physics": PhysicsInput,
    "traction": TractionInput,
    "cage": CageInput,
    "lubricant": LubricantInput,
    "ring": RingInput,
    "life": LifeInput,
    "output": OutputInput,
}


def valid_keys() -> list[str]:
    """Every dotted key a scene file accepts, e.g. ``operating.radial_load_N``."""
    keys = ["title"]
    for sec, model in _SECTIONS.items():
        keys.append(sec)
        keys.extend(f"{sec}.{k}" for k in model.model_fields)
    return keys


def key_table() -> list[tuple[str, str, str, str]]:
    """(key, default, allowed range, description) of every scene key, for docs and the CLI."""
    rows = []
    for sec, model in _SECTIONS.items():
        for name, f in model.model_fields.items():
            default = "" if f.default is None else repr(f.default)
            rows.append((f"{sec}.{name}", default, allowed_range(f"{sec}.{name}"),
                         f.description or ""))
    return rows


#: Ranges enforced by a validator rather than by Field bounds (a union type cannot carry them).
_VALIDATOR_RANGES = {"operating.speed_rpm": f"[0, {SPEED_MAX_RPM:g}]",
                     **{f"operating.{k}": f"[{lo:g}, {hi:g}]" for k, (lo, hi) in LOAD_KEYS.items()}}


def allowed_range(key: str) -> str:
    """Human-readable allowed range of a dotted key, from the model's constraints."""
    if key in _VALIDATOR_RANGES:
        return _VALIDATOR_RANGES[key]
    sec, _, name = key.partition(".")
    model = _SECTIONS.get(sec)
    if model is None or name not in model.model_fields:
        return ""
    return field_range(model.model_fields[name])


def field_range(field) -> str:
    """Allowed range of one pydantic field from its bounds, e.g. ``(0, 1e+08]``; ``""`` if none."""
    lo, hi = "-inf", "inf"
    lo_b, hi_b = "(", ")"
    for c in field.metadata:
        for attr, is_lo, closed in (("gt", True, False), ("ge", True, True),
                                    ("lt", False, False), ("le", False, True)):
            v = getattr(c, attr, None)
            if v is not None:
                # short form unless it would misstate the bound (e.g. -1/3 for HHT-α)
                text = f"{v:g}" if float(f"{v:g}") == v else repr(float(v))
                if is_lo:
                    lo, lo_b = text, "[" if closed else "("
                else:
                    hi, hi_b = text, "]" if closed else ")"
    if (lo, hi) == ("-inf", "inf"):
        return ""
    return f"{lo_b}{lo}, {hi}{hi_b}"

