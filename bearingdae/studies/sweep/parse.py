"""Sweep files: TOML -> validated :class:`Sweep` (base scene, axes, one scene per point).

Pipeline place: studies; reads the sweep file and builds every point's scene with the scene
package (its keys, messages and errors), before anything runs.
"""

from __future__ import annotations

import itertools
import json
import os
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

import numpy as np
import tomli_w
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from ...util.atomic import shown_path
from ...scene import (
    _SECTIONS,
    Scene,
    SceneError,
    _show,
    _unknown_message,
    bundled_case_dirs,
    load_scene,
    resolve_case,
)
from ...scene.errors import _clip, close_matches
from ...scene.files import read_input
from ...scene.overrides import entry_key
from .store import run_key


#: Paper figures a sweep may ask ``bearingdae plot`` to draw.
PAPER_FIGURES = tuple(range(11, 25))

_TOP_KEYS = ("title", "base", "overrides", "axes", "sweep")
MAX_RUNS = 100_000
MAX_AXIS_VALUES = 10_000


class SweepSettings(BaseModel):
    """The optional ``[sweep]`` table."""

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True)

    workers: int | None = Field(default=None, ge=1, le=4096, description="worker processes of "
                                "the default LocalCluster (default: CPU count, at most one per "
                                "pending run; --workers overrides)")
    figures: list[int] = Field(default_factory=list, description="paper figures (11-24) that "
                               "`bearingdae plot` draws from this sweep by default")
    orbit_points: int = Field(default=360, ge=8, le=100_000, description="azimuth points of "
                              "the one-orbit curves stored per run")
    orbit_roller: int = Field(default=1, ge=1, le=500, description="roller whose orbit is "
                              "stored (if its window holds a whole orbit; else the first that "
                              "does)")
    signals: list[str] = Field(default_factory=list, description="time series of each run "
                               "stored for every point along `sample` (the recorded window), "
                               "e.g. [\"ring_acceleration\"]: signals labelled by the axes")

    @field_validator("signals")
    @classmethod
    def _time_series(cls, v: list[str]) -> list[str]:
        from ...scene.sections.output import OUTPUT_VARIABLES
        series = [n for n in OUTPUT_VARIABLES if not n.endswith("_max")]  # (_max: no time)
        bad = [n for n in v if n not in series]
        if bad:
            raise ValueError(f"{bad} are not time series of a run; allowed: "
                             + ", ".join(series))
        if len(set(v)) != len(v):
            raise ValueError(f"{v} names a series twice")
        return v

    @field_validator("figures")
    @classmethod
    def _paper_figures(cls, v: list[int]) -> list[int]:
        bad = [f for f in v if f not in PAPER_FIGURES]
        if bad:
            raise ValueError(f"{bad} are not paper figures; allowed: 11..24")
        return v


@dataclass(frozen=True)
class Axis:
    key: str  #: dotted scene key, e.g. operating.speed_rpm
    dim: str  #: Dataset dimension name, e.g. speed_rpm
    values: tuple


@dataclass(frozen=True)
class RunPoint:
    index: tuple[int, ...]  #: position on the axes
    scene: Scene
    key: str  #: run hash (see :func:`run_key`)


@dataclass(frozen=True)
class Sweep:
    name: str
    title: str
    origin: str
    base: str
    overrides: Mapping[str, Any]
    axes: tuple[Axis, ...]
    settings: SweepSettings
    base_scene: Scene
    points: tuple[RunPoint, ...] = field(repr=False)
    text: str = field(default="", repr=False)  #: the sweep file as TOML
    base_path: Path | None = field(default=None, repr=False)  #: the base scene's file

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(a.values) for a in self.axes)


# ---------------------------------------------------------------------------------------------
# Reading and validating sweep files
# ---------------------------------------------------------------------------------------------
def resolve_sweep(path: str | Path) -> Path:
    """A sweep file path as given, or a bundled one by name (``paper/yang20_speed_sweep``)."""
    p = Path(path)
    if _exists(p) and (p.suffix == ".toml" or not p.is_dir()):  # a FIFO, a device: read_input
        return p  # names what it is
    name = p.name if p.suffix == ".toml" else p.name + ".toml"
    for folder in bundled_case_dirs():
        for cand in (folder / p.parent / name, folder / "paper" / name):
            if _is_file(cand):
                return cand
    names = sorted(f"paper/{q.stem}" for d in bundled_case_dirs() for q in (d / "paper").glob(
        "*.toml"))
    close = close_matches(f"paper/{p.stem}", names, n=1)
    hint = f" Did you mean '{close[0]}'?" if close else ""
    raise SceneError(f"sweep file '{shown_path(path)}' does not exist and is not a bundled sweep "
                     f"(bundled: {', '.join(names)}).{hint}")


def is_sweep_file(path: str | Path) -> bool:
    """True for a TOML file with a top-level ``base`` key (a sweep, not a scene)."""
    try:
        return "base" in tomllib.loads(read_input(path, "sweep file").decode("utf-8"))
    except (ValueError, RecursionError):  # SceneError, UnicodeDecodeError, TOMLDecodeError
        return False


def _read_toml(p: Path, what: str) -> dict:
    raw = read_input(p, what)  # a regular file of at most 1 MiB
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SceneError(f"{what} '{shown_path(p)}' is not UTF-8 text (byte {exc.start})") \
            from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{what} '{shown_path(p)}' is not valid TOML: {exc}") from None
    except (ValueError, RecursionError) as exc:
        raise SceneError(f"{what} '{shown_path(p)}' is not usable TOML: "
                         f"{type(exc).__name__}") from None


def load_sweep(path: str | Path, overrides: Mapping[str, Any] | None = None,
               override_origin: str = "--set") -> Sweep:
    """Read and validate a sweep file (or bundled sweep name); every run's scene is built.
    ``overrides`` (dotted keys, as ``bearingdae sweep --set``) are added to the file's
    ``[overrides]``; errors they cause name ``override_origin``."""
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"load_sweep: 'path' must be a sweep file's path or a bundled sweep's "
                        f"name (str or pathlib.Path), not {type(path).__name__}")
    p = resolve_sweep(path)
    return sweep_from_dict(_read_toml(p, "sweep file"), origin=str(p), name=p.stem,
                           folder=p.parent, extra_overrides=overrides,
                           override_origin=override_origin)


def _flatten(table: Any, where: str, origin: str) -> dict[str, Any]:
    """``{"operating": {"speed_rpm": v}}`` and ``{"operating.speed_rpm": v}`` -> dotted keys."""
    if not isinstance(table, dict):
        raise SceneError(f"sweep '{origin}': [{where}] must be a table of dotted scene keys, "
                         f"got {_show(table)}")
    out: dict[str, Any] = {}
    for k, v in table.items():
        items = ([(f"{k}.{k2}", v2) for k2, v2 in v.items()]
                 if isinstance(v, dict) and k in _SECTIONS else [(k, v)])
        for key, value in items:
            if key in out:
                raise SceneError(f"sweep '{origin}': '{where}.{key}' is given twice")
            out[key] = value
    return out


def _check_key(key: str, where: str, origin: str) -> None:
    sec, _, name = key.partition(".")
    if key == "title" and where == "overrides":
        return
    if entry_key(key) is not None:  # "defects[0].depth_um": the scene checks the index
        return
    if sec not in _SECTIONS or name not in _SECTIONS[sec].model_fields:
        raise SceneError(f"sweep '{origin}': [{where}] " + _unknown_message(key, "scene key"))


def _axis_values(key: str, values: Any, origin: str) -> tuple:
    where = f"axes.'{key}'"
    if not isinstance(values, list) or not values:
        raise SceneError(f"sweep '{origin}': {where} = {_show(values)}: must be a non-empty "
                         "list of values, e.g. [2000, 6000]")
    if len(values) > MAX_AXIS_VALUES:
        raise SceneError(f"sweep '{origin}': {where} has {len(values)} values; allowed range "
                         f"[1, {MAX_AXIS_VALUES}]")
    kinds = set()
    for i, v in enumerate(values):
        if isinstance(v, bool):
            kinds.add("bool")
        elif isinstance(v, (int, float)):
            kinds.add("number")
        elif isinstance(v, str):
            kinds.add("str")
        else:
            raise SceneError(f"sweep '{origin}': {where}[{i}] = {_show(v)}: axis values must "
                             "be numbers, strings or booleans (one per run)")
    if len(kinds) > 1:
        raise SceneError(f"sweep '{origin}': {where} = {_show(values)}: mixes "
                         f"{' and '.join(sorted(kinds))} values; use one kind per axis")
    if kinds == {"number"} and any(isinstance(v, float) for v in values):
        values = [float(v) for v in values]
    if len(set(values)) != len(values):
        dup = next(v for v in values if values.count(v) > 1)
        raise SceneError(f"sweep '{origin}': {where} lists {_show(dup)} more than once; "
                         "each value must be distinct")
    return tuple(values)


def _dim_names(keys: list[str]) -> list[str]:
    leaves = [k.rpartition(".")[2] for k in keys]
    reserved = {"azimuth", "slice", "race", "end", "x", "time", "roller", "direction",
                "slice_position", "bounds", "start_azimuth", "sample"}
    return [leaf if leaves.count(leaf) == 1 and leaf not in reserved
            else re.sub(r"[^A-Za-z0-9_]+", "_", k).strip("_") for k, leaf in zip(keys, leaves)]


def _resolve_base(base: Any, folder: Path | None, origin: str) -> Path:
    if not isinstance(base, str) or not base:
        raise SceneError(f"sweep '{origin}': 'base' = {_show(base)}: must be the name of a "
                         "bundled case (bearingdae cases) or the path of a scene TOML file")
    if folder is not None:
        for cand in (folder / base, folder / f"{base}.toml"):
            if _is_file(cand):
                return cand
    try:
        return resolve_case(base)
    except SceneError as exc:
        raise SceneError(f"sweep '{origin}': 'base' = {_show(base)}: {exc}") from None


def _exists(p: Path) -> bool:
    try:
        return p.exists()
    except (OSError, ValueError):
        return False


def _is_file(p: Path) -> bool:
    """``p.is_file()``, but False for names the OS refuses (too long, NUL bytes)."""
    try:
        return p.is_file()
    except (OSError, ValueError):
        return False


def _settings(raw: Any, origin: str) -> SweepSettings:
    if not isinstance(raw, dict):
        raise SceneError(f"sweep '{origin}': [sweep] must be a table, got {_show(raw)}")
    try:
        return SweepSettings.model_validate(raw)
    except ValidationError as exc:
        lines = [f"invalid sweep ({origin}):"]
        for err in exc.errors():
            loc = "sweep." + ".".join(str(p) for p in err["loc"][:1])
            f = SweepSettings.model_fields.get(str(err["loc"][0])) if err["loc"] else None
            rng = ""
            if f is not None:
                lo = next((getattr(c, "ge") for c in f.metadata if hasattr(c, "ge")), None)
                hi = next((getattr(c, "le") for c in f.metadata if hasattr(c, "le")), None)
                if lo is not None:
                    rng = f" (allowed range [{lo}, {hi}])"
            if err["type"] == "extra_forbidden":
                close = close_matches(str(err["loc"][0]),
                                                  list(SweepSettings.model_fields), n=1)
                hint = f" Did you mean 'sweep.{close[0]}'?" if close else ""
                lines.append(f"  - unknown key '{_clip(loc)}'.{hint} Allowed: "
                             + ", ".join(f"sweep.{k}" for k in SweepSettings.model_fields))
            else:
                msg = err["msg"].removeprefix("Value error, ")
                lines.append(f"  - '{loc}' = {_show(err.get('input'))}: "
                             f"{msg[0].lower() + msg[1:]}{rng}.")
        raise SceneError("\n".join(lines)) from None


def sweep_from_dict(data: Mapping[str, Any], origin: str = "<dict>", name: str = "sweep",
                    folder: Path | None = None,
                    extra_overrides: Mapping[str, Any] | None = None,
                    override_origin: str = "--set") -> Sweep:
    """Validate a parsed sweep file; builds (and so validates) the scene of every run.
    ``extra_overrides`` are added to ``[overrides]`` (see :func:`load_sweep`); the title then
    ends in the values set."""
    unknown = [k for k in data if k not in _TOP_KEYS]
    if unknown:
        k = unknown[0]
        close = close_matches(str(k), _TOP_KEYS, n=1)
        hint = f" Did you mean '{close[0]}'?" if close else ""
        raise SceneError(f"sweep '{origin}': unknown key '{_clip(k)}'.{hint} A sweep file has "
                         f"{', '.join(_TOP_KEYS)}.")
    if "base" not in data:
        raise SceneError(f"sweep '{origin}': 'base' is required: the bundled case name or scene "
                         "path the sweep starts from, e.g. base = \"yang20_baseline\"")
    title = data.get("title", name)
    if not isinstance(title, str):
        raise SceneError(f"sweep '{origin}': 'title' = {_show(title)}: must be a string")
    base_path = _resolve_base(data["base"], folder, origin)
    overrides = _flatten(data.get("overrides", {}), "overrides", origin)
    for key in overrides:
        _check_key(key, "overrides", origin)
    raw_axes = _flatten(data.get("axes", {}), "axes", origin)
    if extra_overrides:
        for key, value in extra_overrides.items():
            try:
                _check_key(key, "overrides", origin)
            except SceneError:
                raise SceneError(f"{override_origin}: " + _unknown_message(key, "scene key")) \
                    from None
            if key in raw_axes:
                raise SceneError(f"{override_origin}: '{key}' is an axis of sweep '{origin}' "
                                 f"(values {_show(raw_axes[key])}); set the other keys only")
        overrides = {**overrides, **extra_overrides}
        shown = ", ".join(f"{k} = {v:g}" if isinstance(v, float) else f"{k} = {v}"
                          for k, v in extra_overrides.items() if k != "title")
        title = extra_overrides.get("title", f"{title} [set: {shown}]" if shown else title)
    for key in raw_axes:
        _check_key(key, "axes", origin)
        if key in overrides:
            raise SceneError(f"sweep '{origin}': '{key}' is both an axis and an override; "
                             "give it in one place")
    settings = _settings(data.get("sweep", {}), origin)
    try:
        base_scene = load_scene(base_path, overrides)
    except SceneError as exc:
        raise SceneError(f"sweep '{origin}': base '{data['base']}' with [overrides]"
                         f"{' and ' + override_origin if extra_overrides else ''}: {exc}") \
            from None
    keys = list(raw_axes)
    axes = []
    for key, dim in zip(keys, _dim_names(keys)):
        values = _axis_values(key, raw_axes[key], origin)
        for i, v in enumerate(values):  # each value alone, so the error names it
            try:
                load_scene(base_path, {**overrides, key: v})
            except SceneError as exc:
                raise SceneError(f"sweep '{origin}': axes.'{key}'[{i}] = {_show(v)}: {exc}") \
                    from None
        axes.append(Axis(key, dim, values))
    n_runs = int(np.prod([len(a.values) for a in axes])) if axes else 1
    if n_runs > MAX_RUNS:
        raise SceneError(f"sweep '{origin}': the axes give {n_runs} runs; allowed range "
                         f"[1, {MAX_RUNS}] per sweep file")
    points = []
    for index in itertools.product(*(range(len(a.values)) for a in axes)):
        over = dict(overrides)
        label = ", ".join(f"{a.dim} = {a.values[i]}" for a, i in zip(axes, index))
        over.setdefault("title", f"{title}: {label}" if label else title)
        over.update({a.key: a.values[i] for a, i in zip(axes, index)})
        try:
            scene = load_scene(base_path, over)
        except SceneError as exc:
            raise SceneError(f"sweep '{origin}': the run {label} is invalid: {exc}") from None
        points.append(RunPoint(tuple(index), scene, run_key(scene)))
    try:
        text = tomli_w.dumps(dict(data))
    except (TypeError, ValueError):  # a dict built in Python with non-TOML values
        text = json.dumps(dict(data), default=str)
    return Sweep(name=name, title=title, origin=origin, base=str(data["base"]),
                 overrides=overrides, axes=tuple(axes), settings=settings,
                 base_scene=base_scene, points=tuple(points), text=text, base_path=base_path)
