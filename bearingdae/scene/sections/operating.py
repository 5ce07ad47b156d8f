"""``[operating]``: speed (constant or a ramp), loads and moments (constant or tables), the
unbalance (scene file as written, user units)."""

from __future__ import annotations

import math

from pydantic import Field, field_validator

from ..histories import LOAD_KEYS, LOAD_MAX_N, LoadTable, MomentTable, _Section

SPEED_MAX_RPM = 200_000.0  #: highest inner-ring speed a scene may ask for
RPM_TO_RAD_S = 2.0 * math.pi / 60.0  #: the one r/min -> rad/s conversion (scene boundary)


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
