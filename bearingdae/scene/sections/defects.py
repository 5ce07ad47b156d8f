"""``[[defects]]`` and ``[[waviness]]``: local defects and form errors of the rolling
surfaces, as written (arrays of tables; none by default). The laws: physics/defects.py;
the cross-field checks (a defect on the race, no wider than the roller; a roller index in
range) and the SI values: scene/defects.py.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from ..histories import _Section

#: the surfaces a defect or a waviness entry can sit on
SURFACES = ("outer", "inner", "roller")


class DefectInput(_Section):
    """One local defect (a spall, a dent): a pit of depth ``depth_um``, ``length_mm`` along the
    rolling direction and ``width_mm`` across it (centred on the roller's middle), its depth
    reached over ramps of ``edge_mm`` at both ends (theory.md §4)."""

    on: Literal["outer", "inner", "roller"] = Field(
        description="the surface: outer race, inner race (turns with the shaft) or a roller "
        "(turns with its spin angle; meets both races once per roller revolution)")
    angle_deg: float = Field(default=0.0, ge=-360.0, le=360.0, description=
                             "position of its centre: on a race from the load direction "
                             "(the inner race's at t = 0), on a roller from the point facing "
                             "the outer race at t = 0, in the sense of its spin")
    # No Field bounds: the range [0, Z - 1] depends on bearing.rollers, so one check
    # (scene/defects.py) refuses -1 and Z alike with the bearing's own range.
    roller: int | None = Field(default=None, description=
                               "the roller it sits on, from 0 (on = \"roller\" only)")
    length_mm: float = Field(gt=0.0, le=100.0, description="length along the rolling direction")
    width_mm: float = Field(gt=0.0, le=100.0, description="width across the rolling direction "
                            "(the slices it covers; at most the roller length)")
    depth_um: float = Field(gt=0.0, le=1000.0, description="depth (a roller that cannot reach "
                            "the bottom rides over it: physics/defects.py)")
    edge_mm: float = Field(default=0.0, ge=0.0, le=50.0, description="ramp length at each end "
                           "(0: sharp, smoothed over physics/defects.EDGE_MIN_M); at most half "
                           "the length")


class WavinessInput(_Section):
    """One harmonic of a rolling surface's form error: extra separation amplitude · cos(order
    φ + phase), φ the angle on that surface; several entries add up."""

    on: Literal["outer", "inner", "roller"] = Field(description="the surface (as for a defect; "
                                                    "\"roller\": the same on every roller)")
    order: int = Field(ge=1, le=1000, description="number of waves around the surface")
    amplitude_um: float = Field(ge=0.0, le=100.0, description="amplitude of the form error")
    phase_deg: float = Field(default=0.0, ge=-360.0, le=360.0, description=
                             "phase of the cosine at the surface's angle 0")


#: the array-of-tables sections: name -> model of one entry
ARRAY_SECTIONS = {"defects": DefectInput, "waviness": WavinessInput}

#: keys whose range depends on another key (no Field bounds can state it): the range as the
#: key reference writes it, and as a message writes it where that other key is not known (a
#: loaded bearing's own range replaces it: scene/defects.roller_range)
DEPENDENT_RANGES = {"defects.roller": "[0, Z - 1] for Z = bearing.rollers"}
