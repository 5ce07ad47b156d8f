"""``[life]`` and ``[output]``: what a run computes and records, and the output variables each
``[physics]`` switch makes available."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any, Literal

from pydantic import Field, field_validator

from ..errors import close_matches
from ..histories import _Section
from .physics import PhysicsInput

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
    # post-processed (analysis/engineering.py): film, power loss, energy
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
    # temperatures (physics.thermal = "steady", theory.md §21; results/thermal_variables.py)
    "temperature": "thermal", "heat_input_W": "thermal", "operating_viscosity_Pa_s": "thermal",
    "operating_kinematic_viscosity": "thermal", "rated_viscosity": "thermal",
    "viscosity_ratio_kappa": "thermal", "thermal_blocks": "thermal",
    "oil_temperature_last_change_K": "thermal",
    # the rollers' spin angles, unknowns of a scene with a defect or waviness on a roller
    # (system/layout.py; not a [physics] switch: :data:`ROLLER_SURFACE`)
    "roller_spin_angle_rad": "roller_surface",
}
#: the condition of the spin angles' output: a ``[[defects]]`` or ``[[waviness]]`` entry with
#: ``on = "roller"`` (declared in :data:`PRESENT_WHEN`)
ROLLER_SURFACE = "roller_surface"


@dataclasses.dataclass(frozen=True)
class PresentWhen:
    """The condition under which an output variable exists, on the checked scene input ``m``
    (scene/schema.SceneInput). The refusal of an unmet ``output.variables`` entry
    (scene/switches.refuse_unswitched_outputs) and the documentation's variable table
    (scene/keydoc.output_reference) read it: a variable names its condition in
    :data:`OUTPUT_VARIABLES`, and a condition that is not a ``[physics]`` switch (or
    ``bearing.type``) is one entry of :data:`PRESENT_WHEN`."""

    holds: Callable[[Any], bool]  #: whether the condition holds for ``m``
    needs: str  #: when the variables exist, in words (the docs' table)
    unmet: Callable[[Any], str]  #: why they do not, for ``m`` (the refusal's clause)
    fix: str  #: the setting that would make them exist


def _roller_surface(m) -> bool:
    return any(e.on == "roller" for e in (*m.defects, *m.waviness))


#: the conditions of output variables other than a switch's; a switch's condition is built
#: from its field's metadata (scene/switches.present_when)
_SPIN_ANGLES_WHY = "(the rollers' spin angles are unknowns only then)"
PRESENT_WHEN = {
    ROLLER_SURFACE: PresentWhen(
        _roller_surface,
        f'a [[defects]] or [[waviness]] entry with on = "roller" {_SPIN_ANGLES_WHY}',
        lambda m: f'no [[defects]] or [[waviness]] entry has on = "roller" {_SPIN_ANGLES_WHY}',
        "add such an entry"),
}
#: the extremes among the output variables (kept at every solver step, not at samples)
EXTREME_VARIABLES = tuple(name for name in OUTPUT_VARIABLES
                          if name.endswith("_max") or name.endswith("_peak"))


def switch_on(physics, switch: str, bearing=None) -> bool:
    """Whether the ``[physics]`` switch ``switch`` is on: the value its field's metadata names
    (``on``: ``physics.ring = "dynamic"``, ``physics.thermal = "steady"``, ...), else true;
    ``flange``: a ``[bearing] type`` with flanges."""
    if switch == "flange":
        return bearing is not None and bearing.type is not None
    value = getattr(physics, switch)
    extra = PhysicsInput.model_fields[switch].json_schema_extra
    on = extra.get("on", True) if isinstance(extra, dict) else True
    return bool(value) if on is True else value == on


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
