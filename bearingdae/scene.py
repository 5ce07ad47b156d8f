"""Scene files: TOML -> validated, frozen :class:`Scene` in SI units (pipeline stage 1).

A scene (case file) is data only. Keys carry their units in their names (``bore_mm``,
``radial_load_N``); they are converted to SI exactly once, here. Validation happens in two
layers: pydantic models mirror the file (types, ranges, unknown keys), then the cross-field
checks that need the geometry (rollers that fit, clearance against roller size, ...).
Every problem is reported as one :class:`SceneError` naming the key, the value and the
allowed range; nothing from inside numpy ever reaches the user.
"""

from __future__ import annotations

import copy
import difflib
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal, Mapping

import numpy as np
import tomli_w
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from .parameters import PRESETS, STEEL, cage_annulus, preset_names

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
    "ring_displacement": None, "ring_tilt": "tilt",
}


class SceneError(ValueError):
    """A scene file or override is invalid. The message names the key, value and allowed range."""


# --------------------------------------------------------------------------------------------
# Layer 1: the file as written (user units), checked by pydantic
# --------------------------------------------------------------------------------------------
class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False, strict=True)


class BearingInput(_Section):
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

    @field_validator("preset")
    @classmethod
    def _known_preset(cls, v: str | None) -> str | None:
        if v is not None and v not in PRESETS:
            close = difflib.get_close_matches(v, preset_names(), n=1)
            hint = f". Did you mean '{close[0]}'" if close else ""
            raise ValueError(f"unknown preset; allowed: {', '.join(preset_names())}{hint}")
        return v


class MaterialsInput(_Section):
    youngs_modulus_GPa: float = Field(default=STEEL["youngs_modulus_GPa"], gt=1.0, le=2000.0,
                                      description="Young's modulus E of rollers and rings")
    poisson_ratio: float = Field(default=STEEL["poisson_ratio"], ge=0.0, lt=0.5,
                                 description="Poisson's ratio ν of rollers and rings")
    density_kg_m3: float = Field(default=STEEL["density_kg_m3"], gt=100.0, le=30_000.0,
                                 description="density ρ of rollers and rings")


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
    speed_rpm: float | SpeedRamp = Field(
        default=0.0, description="inner-ring speed n, or a ramp "
        "{times_s = [...], values_rpm = [...]}")
    radial_load_N: float = Field(default=0.0, ge=0.0, le=1e8,
                                 description="radial load F_r on the inner ring, towards φ = 0")
    moment_Nm: float = Field(default=0.0, ge=-1e6, le=1e6,
                             description="moment M; > 0 loads the +x roller end at φ = 0")
    tangential_load_N: float = Field(default=0.0, ge=-1e8, le=1e8,
                                     description="second radial component F_t, towards φ = 90°")
    tangential_moment_Nm: float = Field(default=0.0, ge=-1e6, le=1e6,
                                        description="moment M_t; > 0 loads +x at φ = 90°")

    @field_validator("speed_rpm")
    @classmethod
    def _speed(cls, v: float | SpeedRamp) -> float | SpeedRamp:
        if isinstance(v, float) and not (0.0 <= v <= SPEED_MAX_RPM):
            raise ValueError("must not be negative (the inner ring turns in +X)")
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
                                             "(MODEL §6): rigid-body, or the paper's r_λ")
    orbit: Literal["newton", "paper"] = Field(default="newton", description="orbit equation "
                                               "(MODEL §10): Newton on the roller centre, or "
                                               "the paper's moment form")


class TractionInput(_Section):
    law: Literal["paper", "slide-roll"] = Field(default="paper", description="traction law "
                                                "(MODEL §7)")
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
    # "slide-roll"; MODEL §7). The paper gives no such law: the defaults are illustrative
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
    # impacts nearly elastic (restitution 0.96 / 0.82 at 1 / 2 rad/s against the sharp MODEL §8
    # law's 0.52); at 0.01 µm it is 0.57 / 0.54 (physics/cage.py, tests/test_newmark.py).
    smoothing_um: float = Field(default=0.01, ge=1e-5, le=100.0, description="pocket contact "
                                "onset regularisation length (keep it << the pocket penetration "
                                "of an impact, ~0.1 µm, or the damping is only partly on)")
    # Not in the paper: the spin friction -r μ_c (|F_a| + |F_b|) sg(ω) uses the smooth
    # |F| ≈ sqrt(F² + f²) - f (physics/cage.py); f must stay << pocket forces of interest.
    spin_friction_force_scale_N: float = Field(default=1e-6, ge=1e-12, le=1.0, description=
                                               "smoothing force f of |F| in the roller-cage "
                                               "spin friction [N]")


class LubricantInput(_Section):
    oil_fraction: float = Field(default=0.015, ge=0.0, le=1.0, description="oil volume "
                                "fraction X of the oil-air mixture")
    oil_density_kg_m3: float = Field(default=870.0, ge=100.0, le=5000.0,
                                     description="oil density")
    air_density_kg_m3: float = Field(default=1.2, ge=0.0, le=100.0, description="air density")
    # Lower bound: below any gas (air 1.8e-5 Pa s); a Reynolds number of inf follows from 0.
    viscosity_Pa_s: float = Field(default=0.01, ge=1e-6, le=100.0, description="oil dynamic "
                                  "viscosity")


class OutputInput(_Section):
    variables: list[str] | None = Field(default=None, description="output variables to keep "
                                        "(default: all the physics provides)")
    # Default None (= float64) rather than "float64": a default would enter every scene's TOML
    # and so change every sweep run's hash (bearingdae.sweep.run_key).
    precision: Literal["float64", "float32"] | None = Field(
        default=None, description="floating-point type of the data variables in the NetCDF "
        "file: float64 (default, reference runs) or float32 (about half the size, relative "
        "rounding 6e-8; docs/user-guide.md)")

    @field_validator("variables")
    @classmethod
    def _known(cls, v: list[str] | None) -> list[str] | None:
        for name in v or []:
            if name not in OUTPUT_VARIABLES:
                close = difflib.get_close_matches(name, list(OUTPUT_VARIABLES), n=1)
                hint = f"; did you mean '{close[0]}'" if close else ""
                raise ValueError(f"unknown output variable '{name}'{hint}; allowed: "
                                 + ", ".join(OUTPUT_VARIABLES))
        return v


class NumericsInput(_Section):
    slices: int = Field(default=10, ge=1, le=1000, description="slices k along the roller length")
    rtol: float = Field(default=1e-6, ge=1e-12, le=1e-1, description="IDA relative tolerance")
    # Upper bound measured: atol = 1e-3 (with rtol 1e-3) failed within 8 ms on the baseline,
    # 1e-4 ran; atol = 1e-6 already costs 15x the cage-speed error of 1e-8 (docs/performance.md).
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
        description="contact-onset regularisation length ε (MODEL §5: at most 1 nm)")
    # Lower bound: the relative residual of a force balance summed over Z x k slices stalls at
    # 1e-16 .. 4e-15 (measured on yang20, harris36, 30 000 r/min, zero load); 1e-14 is reachable.
    static_tolerance: float = Field(default=1e-12, ge=1e-14, le=1e-3,
                                    description="relative force residual of the static Newton")
    static_max_iterations: int = Field(default=100, ge=1, le=10_000,
                                       description="Newton iteration limit per stage")
    # Newmark-β (solver="newmark", MODEL §12). Default step, measured on the baseline
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
    # Steady state on demand (bearingdae/steady.py, issue 14). The tolerance is a fraction of
    # the epicyclic cage speed: 1e-3 resolves Fig 11's 0.1 %-level saturation; below 1e-6 the
    # block means of a skidding bearing never settle (pocket impacts make ~1e-5 noise).
    until_steady: bool = Field(default=False, description="run the warm-up in blocks until the "
                               "cage speed is steady (criterion: docs/user-guide.md, "
                               "bearingdae/steady.py), then record cage_revolutions")
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
    initial_speeds: Literal["epicyclic", "torque_balance"] = Field(
        default="epicyclic", description="initial cage and roller speeds: 'epicyclic' (pure "
        "rolling) or 'torque_balance' (quasi-static skid estimate, bearingdae/system/"
        "torque_balance.py)")


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
    "output": OutputInput,
}


def valid_keys() -> list[str]:
    """Every dotted key a scene file accepts, e.g. ``operating.radial_load_N``."""
    keys = ["title"]
    for sec, model in _SECTIONS.items():
        keys.append(sec)
        keys.extend(f"{sec}.{k}" for k in model.model_fields)
    return keys


# --------------------------------------------------------------------------------------------
# Layer 2: the frozen, SI scene handed to the physics
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Bearing:
    rollers: int
    outer_diameter_m: float
    bore_m: float
    pitch_diameter_m: float
    roller_diameter_m: float
    roller_length_m: float
    effective_length_m: float
    crown_radius_m: float
    profile: str
    clearance_m: float  #: diametral radial clearance P_d (negative = preload)
    design_load_N: float  #: logarithmic profile design load (unused by other profiles)


@dataclass(frozen=True)
class Materials:
    youngs_modulus_Pa: float
    poisson_ratio: float
    density_kg_m3: float


@dataclass(frozen=True)
class Operating:
    #: inner-ring speed as written in the scene [r/min] (kept for outputs and sweeps)
    speed_rpm: float | tuple[tuple[float, ...], tuple[float, ...]]
    radial_load_N: float
    moment_Nm: float
    tangential_load_N: float
    tangential_moment_Nm: float
    #: the same speed in SI [rad/s] (a constant, or (times [s], speeds [rad/s]) of a ramp): the
    #: one conversion from r/min, done here at the boundary; everything downstream uses it
    speed_rad_s: float | tuple[tuple[float, ...], tuple[float, ...]]

    @property
    def loads(self) -> tuple[float, float, float, float]:
        """External loads on the inner ring (F_r, F_t, M, M_t) [N, N, N m, N m] (MODEL §5)."""
        return (self.radial_load_N, self.tangential_load_N, self.moment_Nm,
                self.tangential_moment_Nm)

    def speed_at(self, time_s: float) -> float:
        """Inner-ring speed [r/min] at ``time_s`` (piecewise-linear ramp, held at the end); for
        outputs: computations use :meth:`speed_rad_s_at`."""
        if isinstance(self.speed_rpm, tuple):
            times, values = self.speed_rpm
            return float(np.interp(time_s, times, values))
        return float(self.speed_rpm)

    def speed_rad_s_at(self, time_s: float) -> float:
        """Inner-ring speed [rad/s] at ``time_s`` (piecewise-linear ramp, held at the end)."""
        if isinstance(self.speed_rad_s, tuple):
            times, values = self.speed_rad_s
            return float(np.interp(time_s, times, values))
        return float(self.speed_rad_s)


@dataclass(frozen=True)
class Numerics:
    slices: int
    contact_smoothing_m: float
    static_tolerance: float
    static_max_iterations: int


@dataclass(frozen=True)
class Physics:
    skew: bool
    cage: bool
    drag: bool
    tilt: bool
    gyroscopic: bool
    slip: str
    orbit: str


@dataclass(frozen=True)
class Traction:
    law: str
    A_s_m: float
    B_Pa: float
    C_s_m: float
    D: float
    alternative_bracket: bool  #: True reads the bracket as [1 - exp(-B/p)]
    velocity_scale_m_s: float
    slide_roll_A: float = -0.04  #: slide-to-roll law μ(s) = (A + B s) e^(-C s) + D
    slide_roll_B: float = 2.8
    slide_roll_C: float = 25.0
    slide_roll_D: float = 0.04
    rolling_speed_floor_m_s: float = 1e-3  #: u₀ of s = |V| / sqrt(u² + u₀²)


@dataclass(frozen=True)
class Cage:
    pocket_clearance_m: float
    pocket_stiffness_N_m: float
    damping_ratio: float
    friction: float
    density_kg_m3: float
    smoothing_m: float
    spin_friction_force_scale_N: float = 1e-6  #: f of the smooth |F| in the spin friction


@dataclass(frozen=True)
class Lubricant:
    oil_fraction: float
    oil_density_kg_m3: float
    air_density_kg_m3: float
    viscosity_Pa_s: float


@dataclass(frozen=True)
class Dynamics:
    """IDA, Newmark-β and output-window settings."""

    rtol: float
    atol: float
    warmup_cage_revolutions: float
    cage_revolutions: float
    samples_per_cage_revolution: int
    max_steps: int
    newmark_step_s: float = 2e-6
    newmark_beta: float = 0.25
    newmark_gamma: float = 0.5
    hht_alpha: float = 0.0
    newmark_error_estimate: bool = False
    until_steady: bool = False
    steady_tolerance: float = 1e-3
    steady_block_cage_revolutions: float = 1.0
    max_warmup_cage_revolutions: float = 200.0
    initial_speeds: str = "epicyclic"


@dataclass(frozen=True)
class Scene:
    """A validated scene in SI units. Build it with :func:`load_scene` or :func:`scene_from_dict`."""

    title: str
    bearing: Bearing
    materials: Materials
    operating: Operating
    numerics: Numerics
    physics: Physics
    traction: Traction
    cage: Cage
    lubricant: Lubricant
    dynamics: Dynamics
    output_variables: tuple[str, ...] | None
    source: Mapping[str, Any] = field(repr=False, compare=False)
    preset_citation: str | None = field(default=None, repr=False)
    output_precision: str = "float64"  #: NetCDF type of the data variables (results.save)

    def to_toml(self) -> str:
        """The scene as TOML text in the file's own units (presets resolved)."""
        return tomli_w.dumps(copy.deepcopy(dict(self.source)))


# --------------------------------------------------------------------------------------------
# Loading
# --------------------------------------------------------------------------------------------
def load_scene(path: str | Path, overrides: Mapping[str, Any] | None = None,
               override_origin: str | None = None) -> Scene:
    """Read a TOML scene file and return a validated :class:`Scene` (SI inside).

    ``path`` may also be the name of a bundled case (``"yang20_baseline"``).
    ``overrides`` maps dotted keys to values: ``{"operating.radial_load_N": 400}``; the scene's
    title then ends in the values set (``... [set: operating.radial_load_N = 400]``), so that
    titles never contradict them. ``override_origin`` names where the overrides come from
    (``"--set operating.radial_load_N=-5"``): an error that only the overrides cause names it
    instead of the file.
    """
    p = resolve_case(path)
    try:
        raw = p.read_bytes()
    except OSError as exc:
        raise SceneError(f"cannot read scene file '{p}': {exc.strerror or exc}") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SceneError(
            f"scene file '{p}' is not UTF-8 text (byte {exc.start}); save it as UTF-8 TOML"
        ) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"scene file '{p}' is not valid TOML: {exc}") from None
    except ValueError as exc:  # an integer beyond Python's 4300-digit conversion limit
        raise SceneError(f"scene file '{p}' is not usable TOML: {exc}") from None
    except RecursionError:
        raise SceneError(
            f"scene file '{p}' nests arrays or inline tables too deeply to read; a scene needs "
            "at most two levels ([section] and a speed ramp table)"
        ) from None
    title = data.get("title") if isinstance(data.get("title"), str) else p.stem
    data.setdefault("title", title)
    return scene_from_dict(data, overrides, origin=str(p), override_origin=override_origin)


def scene_from_dict(
    data: Mapping[str, Any], overrides: Mapping[str, Any] | None = None, origin: str = "<dict>",
    override_origin: str | None = None,
) -> Scene:
    """Validate a scene given as a nested dict (the parsed TOML) plus dotted-key overrides
    (``override_origin``: see :func:`load_scene`)."""
    if overrides and override_origin:
        try:  # the scene as written first: its own errors name the file
            scene_from_dict(data, None, origin)
        except SceneError:
            try:  # invalid alone, but the overrides may complete it
                return scene_from_dict(data, overrides, origin)
            except SceneError as exc:
                raise SceneError(str(exc).replace(f"({origin})", f"({origin} with "
                                                  f"{override_origin})")) from None
        return scene_from_dict(data, overrides, override_origin)
    # Only the top level and the section tables are modified below: copy those (a deepcopy
    # would recurse into arbitrarily nested values).
    data = {k: dict(v) if isinstance(v, dict) else v for k, v in dict(data).items()}
    for key, value in (overrides or {}).items():
        _apply_override(data, key, value, origin if origin.startswith("--set") else None)
    if overrides and "title" not in overrides:
        data["title"] = _title_with_overrides(data.get("title"), overrides)
    _check_unknown(data)
    data = _resolve_preset(data)
    try:
        model = SceneInput.model_validate(data)
    except ValidationError as exc:
        raise SceneError(_format_validation(exc, origin)) from None
    return _to_si(model, origin)


def resolve_case(path: str | Path) -> Path:
    """A path as given, or the bundled case of that name (``yang20_baseline``)."""
    p = Path(path)
    if _exists(p):
        return p
    name = p.name if p.suffix == ".toml" else p.name + ".toml"
    rel = p if p.suffix == ".toml" else Path(f"{p}.toml")  # "extreme/zero_speed" as written
    for folder in bundled_case_dirs():
        for cand in (folder / rel, folder / name, folder / "extreme" / name,
                     folder / "paper" / name):
            if _exists(cand):
                return cand
    # Bundled names as `bearingdae cases` lists them (extreme/... included); a typo is matched
    # against each name's last part.
    names = sorted({q.relative_to(d).with_suffix("").as_posix()
                    for d in bundled_case_dirs() for q in d.rglob("*.toml")})
    leaf = {n.rsplit("/", 1)[-1]: n for n in names}
    close = difflib.get_close_matches(p.stem, list(leaf), n=1)
    hint = f" Did you mean the bundled case '{leaf[close[0]]}'?" if close else ""
    raise SceneError(
        f"scene file '{path}' does not exist and is not a bundled case "
        f"(bundled: {', '.join(names)}).{hint}"
    )


def _exists(p: Path) -> bool:
    """``p.exists()``, but False for names the OS rejects (too long, NUL bytes)."""
    try:
        return p.exists()
    except (OSError, ValueError):
        return False


def bundled_case_dirs() -> list[Path]:
    """Folders holding the bundled cases: the installed package data, then a source checkout."""
    # Installed wheels carry the top-level cases/ folder as bearingdae/cases (pyproject.toml);
    # it is a data folder, not an importable module, so it is found beside this file.
    here = Path(__file__).resolve().parent
    return [d for d in (here / "cases", here.parent / "cases") if d.is_dir()]


def _title_with_overrides(title: Any, overrides: Mapping[str, Any]) -> Any:
    """The title followed by the values set: ``"harris36: 12 kN [set: operating.radial_load_N
    = 8000]"`` (a case title states its case's values; with overrides they no longer hold)."""
    if not isinstance(title, str):
        title = "bearingdae scene" if title is None else title
        if not isinstance(title, str):
            return title  # not a string: the validator names it
    def shown(v: Any) -> str:
        if isinstance(v, float):
            return f"{v:g}"
        return v if isinstance(v, str) else _show(v, 40)
    return f"{title} [set: " + ", ".join(f"{k} = {shown(v)}" for k, v in overrides.items()) + "]"


def _apply_override(data: dict, key: str, value: Any, origin: str | None = None) -> None:
    what = "--set key" if origin else "override"
    if not isinstance(key, str):
        raise SceneError(f"override key {_show(key)} must be a dotted string such as "
                         "'operating.radial_load_N'")
    parts = key.split(".")
    if len(parts) == 1 and parts[0] == "title":
        data["title"] = value
        return
    if len(parts) != 2 or parts[0] not in _SECTIONS:
        raise SceneError(_unknown_message(key, what))
    sec, name = parts
    if name not in _SECTIONS[sec].model_fields:
        raise SceneError(_unknown_message(key, what))
    if isinstance(value, np.generic):
        value = value.item()
    data.setdefault(sec, {})
    if not isinstance(data[sec], dict):
        raise SceneError(f"[{sec}] must be a table, got {_show(data[sec])}")
    data[sec][name] = value


def _unknown_message(key: str, what: str = "key") -> str:
    sec, dot, name = key.partition(".")
    if dot and sec in _SECTIONS:  # a known section: suggest one of its keys, not the section
        names = list(_SECTIONS[sec].model_fields)
        close = difflib.get_close_matches(name, names, n=1, cutoff=0.5)
        hint = (f" Did you mean '{sec}.{close[0]}'?" if close else
                f" [{sec}] has: {', '.join(f'{sec}.{n}' for n in names)}.")
        return f"unknown {what} '{key}'.{hint} Valid keys are listed in docs/user-guide.md."
    close = difflib.get_close_matches(key, valid_keys(), n=1, cutoff=0.5)
    if not close:  # same key name in the wrong section?
        leaf = key.split(".")[-1]
        close = [k for k in valid_keys() if k.split(".")[-1] == leaf][:1]
    hint = f" Did you mean '{close[0]}'?" if close else ""
    return f"unknown {what} '{key}'.{hint} Valid keys are listed in docs/user-guide.md."


def _check_unknown(data: Mapping[str, Any]) -> None:
    problems = []
    for sec, body in data.items():
        if sec == "title":
            continue
        if sec not in _SECTIONS:
            problems.append(_unknown_message(str(sec), "section"))
            continue
        if not isinstance(body, dict):
            problems.append(f"[{sec}] must be a table of keys, got {_show(body)}")
            continue
        for k in body:
            if k not in _SECTIONS[sec].model_fields:
                problems.append(_unknown_message(f"{sec}.{k}"))
    if problems:
        raise SceneError("\n".join(problems))


def _resolve_preset(data: dict) -> dict:
    bearing = data.get("bearing", {})
    name = bearing.get("preset")
    if not isinstance(name, str) or name not in PRESETS:
        return data  # no preset, or an unknown one (reported by the validator)
    preset = PRESETS[name]
    merged = dict(preset["bearing"])
    merged.update(bearing)
    data["bearing"] = merged
    return data


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
_VALIDATOR_RANGES = {"operating.speed_rpm": f"[0, {SPEED_MAX_RPM:g}]"}


def allowed_range(key: str) -> str:
    """Human-readable allowed range of a dotted key, from the model's constraints."""
    if key in _VALIDATOR_RANGES:
        return _VALIDATOR_RANGES[key]
    sec, _, name = key.partition(".")
    model = _SECTIONS.get(sec)
    if model is None or name not in model.model_fields:
        return ""
    lo, hi = "-inf", "inf"
    lo_b, hi_b = "(", ")"
    for c in model.model_fields[name].metadata:
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


def _format_validation(exc: ValidationError, origin: str) -> str:
    lines = [f"invalid scene ({origin}):"]
    errors = exc.errors()
    # A union (speed_rpm: float | SpeedRamp) reports every member; keep the member the input
    # was meant for: a table -> the ramp's errors, anything else -> the number's.
    ramp = [e for e in errors if "SpeedRamp" in e["loc"]]
    if ramp and len(ramp) < len(errors):
        meant_ramp = {tuple(p for p in e["loc"] if p != "SpeedRamp")[:2]
                      for e in ramp if e["type"] != "model_type"}
        errors = [e for e in errors if not (
            ("SpeedRamp" in e["loc"] and e["type"] == "model_type")
            or ("float" in e["loc"] and tuple(e["loc"][:2]) in meant_ramp))]
    for err in errors:
        # Union members (float | SpeedRamp) add their type name to the location: drop it.
        parts = [str(p) for p in err["loc"] if p not in ("float", "int", "SpeedRamp", "str")]
        loc = ".".join(parts)
        value = _show(err.get("input"))
        msg = err["msg"].removeprefix("Value error, ")
        rng = allowed_range(loc)
        rng = f" (allowed range {rng})" if rng else ""
        if err["type"] == "missing":
            lines.append(f"  - '{loc}' is required but missing.")
        elif err["type"] == "finite_number":
            lines.append(f"  - '{loc}' = {value}: must be a finite number, not NaN or inf{rng}.")
        elif err["type"] in ("float_type", "int_type", "string_type", "bool_type", "model_type",
                             "int_from_float", "literal_error", "list_type", "dict_type"):
            lines.append(f"  - '{loc}' = {value}: wrong type or value; {msg[0].lower() + msg[1:]}"
                         f"{rng}.")
        else:
            if err["type"] in _RANGE_ERRORS and rng:
                # pydantic prints bounds as 0.00000000000001; the range says it once, as 1e-14.
                lines.append(f"  - '{loc}' = {value}: outside the allowed range "
                             f"{allowed_range(loc)}."
                             f"{_unit_hint(loc, err.get('input'))}")
                continue
            lines.append(f"  - '{loc}' = {value}: {msg[0].lower() + msg[1:].rstrip('.')}{rng}.")
    return "\n".join(_dedupe(lines))


def _show(value: Any, limit: int = 100) -> str:
    """``repr`` for messages: at most ``limit`` characters, and never raising (Python refuses
    to print integers beyond 4300 digits and values nested deeper than its recursion limit)."""
    try:
        text = repr(value)
    except ValueError:
        if not isinstance(value, int):
            raise
        text = f"<integer of about {int(value.bit_length() * math.log10(2)) + 1} digits>"
    except RecursionError:
        text = f"<{type(value).__name__} nested too deeply to print>"
    return text if len(text) <= limit else text[: limit - 4] + " ..."


def _dedupe(lines: list[str]) -> list[str]:
    seen, out = set(), []
    for line in lines:
        if line not in seen:
            seen.add(line)
            out.append(line)
    return out


_RANGE_ERRORS = ("greater_than", "greater_than_equal", "less_than", "less_than_equal")

#: Unit suffix of a key name -> (unit a value is often written in by mistake, factor from that
#: unit to the key's unit). Used to suggest the fix when a value is out of range.
UNIT_NAMES = {"_mm": "mm", "_um": "µm", "_nm": "nm", "_GPa": "GPa", "_kg_m3": "kg/m³",
              "_Pa_s": "Pa s"}
UNIT_SLIPS = {
    "_mm": (("m", 1e3), ("µm", 1e-3)),
    "_um": (("m", 1e6), ("mm", 1e3), ("nm", 1e-3)),
    "_nm": (("m", 1e9), ("µm", 1e3)),
    "_GPa": (("Pa", 1e-9), ("MPa", 1e-3)),
    "_kg_m3": (("g/cm³", 1e3),),
    "_Pa_s": (("mPa s (cP)", 1e-3),),
}


def in_field_range(key: str, value: float) -> bool:
    """True when ``value`` satisfies the Field bounds of the dotted ``key``."""
    sec, _, name = key.partition(".")
    for c in _SECTIONS[sec].model_fields[name].metadata:
        for attr, ok in (("gt", lambda b: value > b), ("ge", lambda b: value >= b),
                         ("lt", lambda b: value < b), ("le", lambda b: value <= b)):
            bound = getattr(c, attr, None)
            if bound is not None and not ok(bound):
                return False
    return True


def _unit_hint(key: str, value: Any) -> str:
    """' The key is in mm: 0.004 m is 4 mm.' when ``value`` fits the range in a slipped unit."""
    sec, _, name = key.partition(".")
    if sec not in _SECTIONS or name not in _SECTIONS[sec].model_fields:
        return ""
    if not isinstance(value, (int, float)) or isinstance(value, bool):
        return ""
    try:
        v = float(value)
    except OverflowError:  # an integer beyond float range: no unit makes it fit
        return ""
    if not math.isfinite(v):
        return ""
    for suffix, slips in UNIT_SLIPS.items():
        if name.endswith(suffix):
            unit = UNIT_NAMES[suffix]
            for wrong, factor in slips:
                fixed = v * factor
                if in_field_range(key, fixed):
                    return (f" The key is in {unit}: if {_show(value)} is in {wrong}, write "
                            f"{fixed:.6g}.")
    return ""


_REQUIRED_BEARING = (
    "rollers",
    "outer_diameter_mm",
    "bore_mm",
    "roller_diameter_mm",
    "roller_length_mm",
    "radial_clearance_mm",
)


def _to_si(m: SceneInput, origin: str) -> Scene:
    b, o = m.bearing, m.operating
    missing = [k for k in _REQUIRED_BEARING if getattr(b, k) is None]
    if missing:
        raise SceneError(
            f"invalid scene ({origin}): [bearing] needs "
            + ", ".join(f"'bearing.{k}'" for k in missing)
            + f" (or a 'bearing.preset', one of {', '.join(preset_names())})."
        )
    mm = 1e-3
    profile = b.profile or ("end-crown" if b.crown_radius_mm else "flat")
    L = b.roller_length_mm
    Ls = b.effective_length_mm if b.effective_length_mm is not None else L
    Dw = b.roller_diameter_mm
    dm = b.pitch_diameter_mm if b.pitch_diameter_mm is not None else 0.5 * (
        b.outer_diameter_mm + b.bore_mm
    )
    errs: list[str] = []

    def bad(key: str, value: Any, rule: str) -> None:
        errs.append(f"  - 'bearing.{key}' = {value!r}: {rule}.")

    if b.bore_mm >= b.outer_diameter_mm:
        bad("bore_mm", b.bore_mm, f"must be smaller than outer_diameter_mm = {b.outer_diameter_mm}")
    if not (b.bore_mm + Dw < dm < b.outer_diameter_mm - Dw):
        bad(
            "roller_diameter_mm" if b.pitch_diameter_mm is None else "pitch_diameter_mm",
            Dw if b.pitch_diameter_mm is None else dm,
            f"the raceways (pitch diameter {dm:g} mm -/+ roller diameter {Dw:g} mm) must lie "
            f"between the bore {b.bore_mm:g} mm and the outer diameter {b.outer_diameter_mm:g} mm",
        )
    # Rollers fit on the pitch circle when the chord between neighbours exceeds D_w.
    chord = dm * math.sin(math.pi / b.rollers)
    if chord <= Dw:
        zmax = max(3, int(math.pi / math.asin(min(1.0, Dw / dm))) if Dw < dm else 0)
        bad(
            "rollers",
            b.rollers,
            f"{b.rollers} rollers of {Dw:g} mm do not fit on a {dm:g} mm pitch circle; "
            f"allowed range is 3..{zmax}",
        )
    if not (abs(b.radial_clearance_mm) < Dw):
        bad("radial_clearance_mm", b.radial_clearance_mm,
            f"must lie in (-{Dw:g}, {Dw:g}) mm (smaller than the roller diameter)")
    if Ls > L:
        bad("effective_length_mm", Ls, f"must not exceed roller_length_mm = {L:g}")
    crown = b.crown_radius_mm
    if profile in ("end-crown", "full-crown") and crown is None:
        bad("crown_radius_mm", None, f"is required for profile '{profile}' (in mm, > 0)")
    if profile == "end-crown" and crown is not None and (L - Ls) / 2 >= crown:
        bad("crown_radius_mm", crown,
            f"must exceed the crowned end length (L - L_s)/2 = {(L - Ls) / 2:g} mm")
    if profile == "full-crown" and crown is not None and L / 2 >= crown:
        bad("crown_radius_mm", crown, f"must exceed half the roller length, {L / 2:g} mm")
    if errs:
        raise SceneError(f"invalid scene ({origin}):\n" + "\n".join(errs))

    if isinstance(o.speed_rpm, SpeedRamp):
        if len(o.speed_rpm.times_s) != len(o.speed_rpm.values_rpm):
            raise SceneError(
                f"invalid scene ({origin}): 'operating.speed_rpm' ramp has "
                f"{len(o.speed_rpm.times_s)} times_s but {len(o.speed_rpm.values_rpm)} values_rpm;"
                " they must have the same length."
            )
        speed: Any = (tuple(o.speed_rpm.times_s), tuple(o.speed_rpm.values_rpm))
        speed_si: Any = (speed[0], tuple(v * RPM_TO_RAD_S for v in speed[1]))
    else:
        speed = float(o.speed_rpm)
        speed_si = speed * RPM_TO_RAD_S

    design = b.design_load_N
    if design is None:
        # Johns-Gohar/Lundberg profiles are designed for a roller load; Stribeck's maximum roller
        # load 4.08 F_r / Z (zero clearance, line contact) is the usual choice.
        design = max(4.08 * o.radial_load_N / b.rollers, 1.0)

    if m.operating.moment_Nm or m.operating.tangential_moment_Nm:
        if not m.physics.tilt:
            raise SceneError(
                f"invalid scene ({origin}): 'physics.tilt' = false cannot carry "
                f"'operating.moment_Nm' = {m.operating.moment_Nm} / 'operating."
                f"tangential_moment_Nm' = {m.operating.tangential_moment_Nm}: a moment needs the "
                "tilt unknowns; set physics.tilt = true or the moments to 0."
            )
        if m.numerics.slices < 2:
            raise SceneError(
                f"invalid scene ({origin}): 'numerics.slices' = {m.numerics.slices} cannot carry "
                f"'operating.moment_Nm' = {m.operating.moment_Nm}: one slice sits at x = 0 and "
                "has no lever arm; use at least 2 slices (allowed range [2, 1000] with a moment)."
            )
    for name in m.output.variables or []:
        switch = OUTPUT_VARIABLES[name]
        if switch is not None and not getattr(m.physics, switch):
            raise SceneError(
                f"invalid scene ({origin}): 'output.variables' asks for '{name}' but "
                f"'physics.{switch}' = false removes it; drop it or switch {switch} on."
            )
    cp = m.cage.pocket_clearance_mm
    if cp is None:
        cp = PRESETS[b.preset]["cage"]["pocket_clearance_mm"] if b.preset else 0.10
    if m.cage.pocket_clearance_mm is not None:  # a default that does not fit: build_model's
        _check_pockets_fit(b.rollers, dm, Dw, L, cp, origin)  # error (static runs need no cage)
    t, n, c = m.traction, m.numerics, m.cage
    source = m.model_dump(exclude_none=True, mode="json")
    source["bearing"]["profile"] = profile
    return Scene(
        title=m.title or "bearingdae scene",
        bearing=Bearing(
            rollers=b.rollers,
            outer_diameter_m=b.outer_diameter_mm * mm,
            bore_m=b.bore_mm * mm,
            pitch_diameter_m=dm * mm,
            roller_diameter_m=Dw * mm,
            roller_length_m=L * mm,
            effective_length_m=Ls * mm,
            crown_radius_m=(crown if crown is not None else math.inf) * mm,
            profile=profile,
            clearance_m=b.radial_clearance_mm * mm,
            design_load_N=design,
        ),
        materials=Materials(
            youngs_modulus_Pa=m.materials.youngs_modulus_GPa * 1e9,
            poisson_ratio=m.materials.poisson_ratio,
            density_kg_m3=m.materials.density_kg_m3,
        ),
        operating=Operating(
            speed_rpm=speed,
            speed_rad_s=speed_si,
            radial_load_N=o.radial_load_N,
            moment_Nm=o.moment_Nm,
            tangential_load_N=o.tangential_load_N,
            tangential_moment_Nm=o.tangential_moment_Nm,
        ),
        numerics=Numerics(
            slices=m.numerics.slices,
            contact_smoothing_m=m.numerics.contact_smoothing_nm * 1e-9,
            static_tolerance=m.numerics.static_tolerance,
            static_max_iterations=m.numerics.static_max_iterations,
        ),
        physics=Physics(**m.physics.model_dump()),
        traction=Traction(
            law=t.law, A_s_m=t.A_s_m, B_Pa=t.B_GPa * 1e9, C_s_m=t.C_s_m, D=t.D,
            alternative_bracket=t.bracket == "exp(-B/p)",
            velocity_scale_m_s=t.velocity_scale_m_s, slide_roll_A=t.slide_roll_A,
            slide_roll_B=t.slide_roll_B, slide_roll_C=t.slide_roll_C,
            slide_roll_D=t.slide_roll_D, rolling_speed_floor_m_s=t.rolling_speed_floor_m_s,
        ),
        cage=Cage(
            pocket_clearance_m=cp * mm, pocket_stiffness_N_m=c.pocket_stiffness_N_m,
            damping_ratio=c.damping_ratio, friction=c.friction, density_kg_m3=c.density_kg_m3,
            smoothing_m=c.smoothing_um * 1e-6,
            spin_friction_force_scale_N=c.spin_friction_force_scale_N,
        ),
        lubricant=Lubricant(**m.lubricant.model_dump()),
        dynamics=Dynamics(
            rtol=n.rtol, atol=n.atol, warmup_cage_revolutions=n.warmup_cage_revolutions,
            cage_revolutions=n.cage_revolutions,
            samples_per_cage_revolution=n.samples_per_cage_revolution, max_steps=n.max_steps,
            **_newmark_settings(n, origin), **_steady_settings(n, origin),
        ),
        output_variables=tuple(m.output.variables) if m.output.variables is not None else None,
        output_precision=m.output.precision or "float64",
        source=source,
        preset_citation=PRESETS[b.preset]["citation"] if b.preset else None,
    )


def _newmark_settings(n: NumericsInput, origin: str) -> dict:
    """β and γ (defaults from hht_alpha: β = (1 - α)²/4, γ = 1/2 - α, Hilber et al. 1977),
    checked for unconditional stability of the linear scheme: γ ≥ 1/2, β ≥ (γ + 1/2)²/4."""
    a = n.hht_alpha
    beta = n.newmark_beta if n.newmark_beta is not None else 0.25 * (1.0 - a) ** 2
    gamma = n.newmark_gamma if n.newmark_gamma is not None else 0.5 - a
    beta_min = 0.25 * (gamma + 0.5) ** 2
    if beta < beta_min * (1.0 - 1e-12):
        raise SceneError(
            f"invalid scene ({origin}): 'numerics.newmark_beta' = {beta!r} with newmark_gamma = "
            f"{gamma!r} is not unconditionally stable; allowed range [{beta_min:.6g}, 0.5] "
            "(β ≥ (γ + 1/2)²/4)."
        )
    return {"newmark_step_s": n.newmark_step_s, "newmark_beta": float(beta),
            "newmark_gamma": float(gamma), "hht_alpha": float(a),
            "newmark_error_estimate": n.newmark_error_estimate}


def _steady_settings(n: NumericsInput, origin: str) -> dict:
    """The until_steady keys (bearingdae/steady.py); the cap must hold at least one block."""
    if n.max_warmup_cage_revolutions < n.steady_block_cage_revolutions:
        raise SceneError(
            f"invalid scene ({origin}): 'numerics.max_warmup_cage_revolutions' = "
            f"{n.max_warmup_cage_revolutions!r} is shorter than one block "
            f"('numerics.steady_block_cage_revolutions' = {n.steady_block_cage_revolutions!r});"
            f" allowed range [{n.steady_block_cage_revolutions:g}, 1e+05].")
    return {"until_steady": n.until_steady, "steady_tolerance": n.steady_tolerance,
            "steady_block_cage_revolutions": n.steady_block_cage_revolutions,
            "max_warmup_cage_revolutions": n.max_warmup_cage_revolutions,
            "initial_speeds": n.initial_speeds}


def _check_pockets_fit(rollers: int, dm_mm: float, dw_mm: float, length_mm: float, cp_mm: float,
                       origin: str) -> None:
    """Z pockets of width D_w + c_p must fit the cage's inner circumference (parameters.py).

    A pocket clearance in µm written into the mm key (100 for 0.1 mm) is caught here. A bearing
    whose rollers alone fill the cage (a full complement) is left to the dynamic model, which
    needs the cage: its static solve does not.
    """
    r_i, _, _ = cage_annulus(0.5 * dm_mm, dw_mm, length_mm)
    room = 2.0 * math.pi * r_i / rollers - dw_mm  # the largest pocket clearance [mm]
    if room > 0.0 and cp_mm >= room:
        raise SceneError(
            f"invalid scene ({origin}):\n  - 'cage.pocket_clearance_mm' = {cp_mm!r}: {rollers} "
            f"pockets of {dw_mm:g} mm + c_p do not fit the cage's inner circumference "
            f"({2 * math.pi * r_i:.4g} mm); allowed range [0, {room:.4g}) mm." + (
                f" If it was written in µm, write {cp_mm * 1e-3:.6g}."
                if cp_mm * 1e-3 < room else ""))
