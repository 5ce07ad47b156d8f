"""``[bearing]`` and ``[materials]``: the geometry (a named preset and any values that
override it) and the elastic constants (scene file as written, user units)."""

from __future__ import annotations

from typing import Literal

from pydantic import Field, field_validator

from ..errors import close_matches
from ..histories import _Section
from ..parameters import PRESETS, STEEL, preset_names

PROFILES = ("flat", "end-crown", "full-crown", "logarithmic")


#: the metadata of a key that only a bearing with flanges reads (scene/switches.py)
_FLANGE_KEY = {"switch": "flange"}


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
        default=None, ge=1.0, le=1e8,
        description="logarithmic profile design load (default 4.08 F_r / Z)")
    # Lower bound: no rolling bearing is rated below 1 N (and a rating of ~0 makes L10r 0).
    basic_dynamic_load_rating_N: float | None = Field(
        default=None, ge=1.0, le=1e9,
        description="catalogue basic dynamic load rating C for the ISO/TS 16281 rating life "
        "(default: from the geometry by ISO 281)")

    # Flanges (ribs; theory.md §16, scene/flanges.py). Every key defaults to None so that a
    # flangeless scene's TOML text (and sweep hashes) stay as they were.
    type: Literal["NU", "N", "NJ", "NUP"] | None = Field(
        default=None, json_schema_extra={"on": ("NU", "N", "NJ", "NUP"),
                                         "effect": "a bearing with flanges"},
        description="bearing type, i.e. which ring has flanges: NU (outer two), "
        "N (inner two), NJ (outer two, inner one at the -x end: axial load in +X), NUP (both "
        "two: axial load either way); default none: the paper's flangeless model")
    flange_angle_deg: float | None = Field(
        default=None, gt=0.0, le=10.0, json_schema_extra=_FLANGE_KEY,
        description="flange (rib) face inclination α from the "
        "radial plane (default 0.5°)")
    flange_height_mm: float | None = Field(
        default=None, ge=0.001, le=1_000, json_schema_extra=_FLANGE_KEY,
        description="flange height above the raceway "
        "(default 0.2 D_w; below the roller radius)")
    roller_end: Literal["flat", "spherical"] | None = Field(
        default=None, json_schema_extra=_FLANGE_KEY,
        description="roller end face: spherical (radius roller_end_radius_mm, "
        "the default) or flat (edge contact at the flange rim)")
    roller_end_radius_mm: float | None = Field(
        default=None, gt=0.0, le=1e5, json_schema_extra=_FLANGE_KEY,
        description="spherical roller end radius R_e (default: "
        "the contact at mid flange face, R_e sin α = r - (h_f + r_k)/2)")
    roller_corner_radius_mm: float | None = Field(
        default=None, ge=0.0, le=1_000, json_schema_extra=_FLANGE_KEY,
        description="roller corner radius r_k (default "
        "0.05 D_w); for flat ends also the radius of the edge contact")
    flange_clearance_mm: float | None = Field(
        default=None, ge=0.0, le=100.0, json_schema_extra=_FLANGE_KEY,
        description="axial play of a roller between the two "
        "flanges of one ring (default 0.02 mm)")
    flange_friction: float | None = Field(
        default=None, ge=0.0, le=1.0, json_schema_extra=_FLANGE_KEY,
        description="sliding friction coefficient of the roller "
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
