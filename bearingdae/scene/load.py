"""Loading a scene: TOML file or dict (+ overrides) -> validated SI Scene (pipeline stage 1).

:func:`load_scene` reads the file, :func:`scene_from_dict` applies overrides, resolves the
preset, validates with the pydantic schema and converts to SI (:mod:`.convert`).
"""

from __future__ import annotations

import tomllib
from pathlib import Path
import os
from typing import Any, Mapping

from pydantic import ValidationError

from .parameters import PRESETS
from .convert import _to_si
from .extensions import with_extensions
from ..util.atomic import shown_path
from .errors import SceneError, _show
from .files import read_input
from .lookup import resolve_case
from .defects import known_ranges
from .messages import _format_validation
from .overrides import _apply_override, _check_unknown, _title_with_overrides
from .titles import file_title
from .schema import SceneInput
from .si import Scene

# --------------------------------------------------------------------------------------------
# Loading
# --------------------------------------------------------------------------------------------
def load_scene(path: str | Path, overrides: Mapping[str, Any] | None = None,
               override_origin: str | None = None) -> Scene:
    """Read a TOML scene file and return a validated :class:`Scene` (SI inside).

    Parameters
    ----------
    path : str or pathlib.Path
        A scene TOML file, or the name of a bundled case (``"yang20_baseline"``,
        ``"paper/harris36_5000rpm"``; ``bearingdae cases`` lists them).
    overrides : mapping of str to value, optional
        Dotted scene keys and their values, ``{"operating.radial_load_N": 400}`` (keys: the
        scene-key reference). The scene's title then ends in the values set
        (``... [set: operating.radial_load_N = 400]``), so that no title contradicts them.
    override_origin : str, optional
        Where the overrides come from (``"--set operating.radial_load_N=-5"``): an error that
        only the overrides cause names it instead of the file.

    Returns
    -------
    Scene
        Frozen, validated, in SI units.

    Raises
    ------
    SceneError
        The file cannot be read, is not TOML, or a key is unknown or out of range; the
        message names the key, the value, the allowed range and, where it can, the fix.

    Examples
    --------
    >>> from bearingdae import load_scene
    >>> scene = load_scene("yang20_baseline", overrides={"operating.speed_rpm": 6000})
    >>> scene.operating.speed_rpm
    6000.0
    """
    _check_arguments(path, overrides, override_origin)
    p = resolve_case(path)
    raw = read_input(p, "scene file")
    shown = shown_path(p)
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SceneError(
            f"scene file '{shown}' is not UTF-8 text (byte {exc.start}); save it as UTF-8 TOML"
        ) from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"scene file '{shown}' is not valid TOML: {exc}") from None
    except ValueError as exc:  # an integer beyond Python's 4300-digit conversion limit
        raise SceneError(f"scene file '{shown}' is not usable TOML: {exc}") from None
    except RecursionError:
        raise SceneError(
            f"scene file '{shown}' nests arrays or inline tables too deeply to read; a scene "
            "needs at most two levels ([section] and a speed ramp table)"
        ) from None
    data.setdefault("title", file_title(p))  # its name and operating point (scene/titles.py)
    op = data.get("operating")
    if isinstance(op, dict) and isinstance(op.get("load_file"), str) and op["load_file"]:
        # a load file is named relative to the scene file; kept absolute (sweeps, to_toml)
        data["operating"] = {**op, "load_file": os.path.abspath(
            os.path.join(os.path.dirname(os.path.abspath(p)), op["load_file"]))}
    return scene_from_dict(data, overrides, origin=str(p), override_origin=override_origin)


def _check_arguments(path, overrides, override_origin) -> None:
    """The argument types of :func:`load_scene` (TypeError naming the argument)."""
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"load_scene: path: expected a file path or bundled case name (str or "
                        f"os.PathLike), got {type(path).__name__} {_show(path)}")
    if overrides is not None and not isinstance(overrides, Mapping):
        raise TypeError(f"load_scene: overrides: expected a mapping of dotted keys to values, "
                        f"e.g. {{'operating.radial_load_N': 400}}, got {type(overrides).__name__}"
                        f" {_show(overrides)}")
    if override_origin is not None and not isinstance(override_origin, str):
        raise TypeError(f"load_scene: override_origin: expected a str or None, got "
                        f"{type(override_origin).__name__}")


def scene_from_dict(
    data: Mapping[str, Any], overrides: Mapping[str, Any] | None = None, origin: str = "<dict>",
    override_origin: str | None = None,
) -> Scene:
    """Validate a scene given as a nested dict (the parsed TOML) plus dotted-key overrides.

    Parameters
    ----------
    data : mapping
        The scene as TOML would give it: ``{"bearing": {"preset": "yang20"}, "operating":
        {"speed_rpm": 2000.0}}``.
    overrides : mapping of str to value, optional
        Dotted keys and values applied on top (as for :func:`load_scene`).
    origin : str
        What to call the scene in error messages (a file name).
    override_origin : str, optional
        Where the overrides come from (see :func:`load_scene`).

    Returns
    -------
    Scene

    Raises
    ------
    SceneError
        An unknown key, a wrong type, or a value outside its range.
    """
    if not isinstance(data, Mapping):
        raise TypeError(f"scene_from_dict: data: expected a mapping (the parsed TOML), got "
                        f"{type(data).__name__} {_show(data)}")
    if overrides is not None and not isinstance(overrides, Mapping):
        raise TypeError(f"scene_from_dict: overrides: expected a mapping of dotted keys to "
                        f"values or None, got {type(overrides).__name__} {_show(overrides)}")
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
        raise SceneError(_format_validation(exc, origin, known_ranges(data))) from None
    return with_extensions(_to_si(model, origin), model)


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
