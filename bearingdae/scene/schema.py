"""The scene file as written (user units), checked by pydantic (pipeline stage 1, layer 1).

The section models live in :mod:`bearingdae.scene.sections` (one module per group of
sections); here they are assembled into :class:`SceneInput` and the section table
``_SECTIONS``, with what documents the keys: :func:`valid_keys`, :func:`key_table`,
:func:`allowed_range`. Conversion to SI is :mod:`bearingdae.scene.convert`.
"""

from __future__ import annotations

from pydantic import Field, field_validator

from .histories import LOAD_KEYS, LOAD_MAX_N, LoadTable, MomentTable, _Section  # noqa: F401
from .sections.bearing import PROFILES, BearingInput, MaterialsInput  # noqa: F401
from .sections.contact import CageInput, LubricantInput, TractionInput  # noqa: F401
from .sections.defects import (ARRAY_SECTIONS, DEPENDENT_RANGES, DefectInput,  # noqa: F401
                               WavinessInput)
from .sections.numerics import NumericsInput  # noqa: F401
from .sections.operating import (RPM_TO_RAD_S, SPEED_MAX_RPM, OperatingInput,  # noqa: F401
                                 SpeedRamp)
from .sections.output import (EXTREME_VARIABLES, OUTPUT_VARIABLES, LifeInput,  # noqa: F401
                              OutputInput, switch_on)
from .sections.physics import PhysicsInput, RingInput  # noqa: F401
from .sections.heat_paths import ThermalInput  # noqa: F401


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
    thermal: ThermalInput = ThermalInput()
    life: LifeInput = LifeInput()
    output: OutputInput = OutputInput()
    #: the arrays of tables (none by default): local defects and waviness (theory.md §4)
    defects: list[DefectInput] = Field(default_factory=list)
    waviness: list[WavinessInput] = Field(default_factory=list)


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
    "thermal": ThermalInput,
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
    array = ARRAY_SECTIONS.get(sec.partition("[")[0])
    if array is not None:  # "defects[0].depth_um"
        name = name.rpartition(".")[2]
        if name not in array.model_fields:
            return ""
        return (field_range(array.model_fields[name])
                or DEPENDENT_RANGES.get(f"{sec.partition('[')[0]}.{name}", ""))
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
