"""Scene files: TOML -> validated, frozen :class:`Scene` in SI units (pipeline stage 1).

A scene (case file) is data only. Keys carry their units in their names (``bore_mm``,
``radial_load_N``); they are converted to SI exactly once, here. Validation happens in two
layers: pydantic models mirror the file (types, ranges, unknown keys), then the cross-field
checks that need the geometry (rollers that fit, clearance against roller size, ...).
Every problem is reported as one :class:`SceneError` naming the key, the value and the
allowed range; nothing from inside numpy ever reaches the user.

The package is split by job: ``errors`` (SceneError), ``schema`` (pydantic sections, key table),
``si`` (frozen SI dataclasses), ``lookup`` (bundled cases), ``overrides`` (dotted --set keys),
``messages`` (validation messages, unit hints), ``convert`` (input -> SI), ``load``
(load_scene, scene_from_dict), ``files`` (which input files are read: regular, at most 1 MiB),
``arguments`` (API arguments checked by a scene key's range), ``histories`` (load history
tables), ``loadfile`` (load files from other tools). Every name of the first eight is
re-exported here: ``from bearingdae.scene import X``.
"""

from __future__ import annotations

from .errors import (  # noqa: F401
    SceneError,
    _show,
    _dedupe,
)
from .schema import (  # noqa: F401
    PROFILES,
    SPEED_MAX_RPM,
    RPM_TO_RAD_S,
    OUTPUT_VARIABLES,
    EXTREME_VARIABLES,
    _Section,
    BearingInput,
    MaterialsInput,
    SpeedRamp,
    OperatingInput,
    PhysicsInput,
    TractionInput,
    CageInput,
    LubricantInput,
    RingInput,
    LoadTable,
    MomentTable,
    OutputInput,
    NumericsInput,
    SceneInput,
    _SECTIONS,
    valid_keys,
    key_table,
    _VALIDATOR_RANGES,
    allowed_range,
)
from .si import (  # noqa: F401
    Bearing,
    Materials,
    Operating,
    Numerics,
    Physics,
    Traction,
    Cage,
    Lubricant,
    Ring,
    Dynamics,
    Scene,
)
from .lookup import (  # noqa: F401
    resolve_case,
    _exists,
    bundled_case_dirs,
)
from .overrides import (  # noqa: F401
    _title_with_overrides,
    _apply_override,
    _unknown_message,
    _check_unknown,
)
from .messages import (  # noqa: F401
    _format_validation,
    _RANGE_ERRORS,
    UNIT_NAMES,
    UNIT_SLIPS,
    in_field_range,
    _unit_hint,
)
from .convert import (  # noqa: F401
    _REQUIRED_BEARING,
    _to_si,
    _newmark_settings,
    _steady_settings,
)
from .pockets import check_pockets_fit as _check_pockets_fit  # noqa: F401
from .load import (  # noqa: F401
    load_scene,
    scene_from_dict,
    _resolve_preset,
)
