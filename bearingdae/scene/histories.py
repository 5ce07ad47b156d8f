"""Load histories as written in a scene file: the tables ``{times_s = [...], values_N = [...]}``
of the five load keys (pipeline stage 1, scene; theory.md §14, the axial load §16), and the
base of every pydantic section model.

The tables are merged onto one time grid by :func:`bearingdae.scene.loadfile.merge_histories`
(scene/load_history.py) and evaluated by physics/loads.py.
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field, field_validator


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False, strict=True)


#: Largest force and moment a load key or load history may hold (the constant keys' bounds).
LOAD_MAX_N = 1e8
MOMENT_MAX_NM = 1e6


def _increasing_times(v: list[float]) -> list[float]:
    if v[0] < 0.0:
        raise ValueError("times must not be negative (the run starts at 0 s)")
    if any(b <= a for a, b in zip(v, v[1:])):
        raise ValueError("times must be strictly increasing")
    return v


class LoadTable(_Section):
    """Piecewise-linear force history [N], held at its first and last value."""

    times_s: list[float] = Field(min_length=2, max_length=100_000)
    values_N: list[float] = Field(min_length=2, max_length=100_000)

    @field_validator("times_s")
    @classmethod
    def _times(cls, v: list[float]) -> list[float]:
        return _increasing_times(v)

    @field_validator("values_N")
    @classmethod
    def _range(cls, v: list[float]) -> list[float]:
        if any(not (-LOAD_MAX_N <= f <= LOAD_MAX_N) for f in v):
            raise ValueError(f"every force must lie in [-{LOAD_MAX_N:g}, {LOAD_MAX_N:g}] N")
        return v


class MomentTable(_Section):
    """Piecewise-linear moment history [N m], held at its first and last value."""

    times_s: list[float] = Field(min_length=2, max_length=100_000)
    values_Nm: list[float] = Field(min_length=2, max_length=100_000)

    @field_validator("times_s")
    @classmethod
    def _times(cls, v: list[float]) -> list[float]:
        return _increasing_times(v)

    @field_validator("values_Nm")
    @classmethod
    def _range(cls, v: list[float]) -> list[float]:
        if any(not (-MOMENT_MAX_NM <= m <= MOMENT_MAX_NM) for m in v):
            raise ValueError(f"every moment must lie in [-{MOMENT_MAX_NM:g}, "
                             f"{MOMENT_MAX_NM:g}] N m")
        return v


#: Load keys that take a number or a history table, and the range of the number, in the order
#: of the load table's columns (physics/loads.TABLE_COLUMNS).
LOAD_KEYS = {"radial_load_N": (0.0, LOAD_MAX_N), "tangential_load_N": (-LOAD_MAX_N, LOAD_MAX_N),
             "moment_Nm": (-MOMENT_MAX_NM, MOMENT_MAX_NM),
             "tangential_moment_Nm": (-MOMENT_MAX_NM, MOMENT_MAX_NM),
             "axial_load_N": (-LOAD_MAX_N, LOAD_MAX_N)}
#: the load keys a load file replaces as a whole (the axial load: only if the file has it)
RADIAL_LOAD_KEYS = tuple(LOAD_KEYS)[:4]
