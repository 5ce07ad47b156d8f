"""Reading a result file back: is it a bearingdae run, static or sweep file, whole and of the
shape the figures and summaries expect? (pipeline: NetCDF -> Dataset, the way back.)

:func:`open_result` opens a NetCDF file, loads it and checks it before anything draws from it:
the global attributes every bearingdae file carries (``Conventions`` CF-…,
``bearingdae_version``), then per kind the dimensions and the dimensions of each variable, the label coordinates and
the sample times (a run), or the axes and per-run variables (a sweep, ``sweep_axes``). Every
failure, from an unreadable or damaged file (a bit-flipped HDF5 chunk raises
``RuntimeError: NetCDF: HDF error`` only when the data is read) to a foreign or hand-edited
one, is a :class:`ResultFileError`: one line naming the file, what is wrong (cut to ~100
characters) and which kind of file was expected.

The three kinds (how they are told apart, in this order):

* ``sweep``: the ``sweep_axes`` attribute (``bearingdae sweep``, ``paper``, ``skidmap``);
* ``run``: a ``time`` dimension (``bearingdae run``, also its ``_partial.nc``);
* ``static``: neither (``bearingdae static``).
"""

from __future__ import annotations

import json
import os
import stat
from pathlib import Path

import numpy as np
import xarray as xr

from ..util.atomic import shown_path
from ..analysis.summary import SUMMARY_VARIABLES
from .dataset import DIRECTIONS, DYNAMIC_VARIABLES, ENDS, RACES

#: kind -> how a message names it
KINDS = {"run": "run file (bearingdae run)", "static": "static file (bearingdae static)",
         "sweep": "sweep file (bearingdae sweep or paper)"}
#: labelled dimensions and the labels they must carry
LABELS = {"race": RACES, "end": ENDS, "direction": DIRECTIONS}
#: dimensions a file may have without a coordinate of their own (``bounds``: the two ends of
#: each slice in the CF cell bounds ``slice_position_bounds``); every other dimension a writer
#: adds is labelled by a coordinate variable of its name (index_coords, the label and list
#: coordinates of analysis/result_variables.py, the power loss's ``loss_source``, the thermal
#: network's ``thermal_node``, ...), which is how :func:`file_dimensions` learns it
UNLABELLED_DIMS = {"time", "bounds"}
#: dimensions of a sweep's one-orbit variables besides its axes
ORBIT_DIMS = {"azimuth", "slice", "race", "end", "bounds"}
#: variables of a static file and their dimensions (the figures do not draw static files; the
#: check tells a static file from a damaged one)
STATIC_VARIABLES = {"contact_force": ("roller", "slice", "race")}
#: variables every sweep file holds, one value per run (with the summaries of analysis.py)
SWEEP_VARIABLES = ("status", "error", *SUMMARY_VARIABLES)


class ResultFileError(ValueError):
    """A file that is not a readable bearingdae result of the expected kind (one line)."""


def _expected(expected) -> str:
    return " or ".join(KINDS[k].split(" (")[0] for k in expected)


def open_result(path: str | Path, expected=("run", "sweep")) -> tuple[str, xr.Dataset]:
    """``(kind, dataset)`` of the bearingdae result file ``path``, loaded into memory and
    checked (module docstring); ``expected``: the kinds the caller can use. Raises
    :class:`ResultFileError`."""
    shown, want = shown_path(path), _expected(expected)
    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError) as exc:
        reason = getattr(exc, "strerror", None) or str(exc)
        raise ResultFileError(f"'{shown}': {reason}; give a {want}") from None
    if not stat.S_ISREG(mode):
        what = "a directory" if stat.S_ISDIR(mode) else "not a regular file"
        raise ResultFileError(f"'{shown}' is {what}; give a {want} (a .nc file)")
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            ds = ds.load()
    except Exception as exc:  # HDF5, netCDF4, xarray decoding: any of them on a damaged file
        raise ResultFileError(f"'{shown}' is not a readable NetCDF file ({_brief(exc)}); give "
                              f"a {want}") from None
    try:
        kind = _kind(ds)
        ds = _current(ds)
        if kind not in expected:
            raise ResultFileError(f"is a bearingdae {KINDS[kind]}, expected a {want}")
        {"run": _check_run, "static": _check_static, "sweep": _check_sweep}[kind](ds)
    except ResultFileError as exc:
        raise ResultFileError(f"'{shown}' {exc}") from None
    except Exception as exc:  # a check meeting a structure it did not foresee
        raise ResultFileError(f"'{shown}' is not a usable bearingdae {want} "
                              f"({_brief(exc)})") from None
    return kind, ds


def _brief(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text[:100]}{' ...' if len(text) > 100 else ''}"


def _kind(ds: xr.Dataset) -> str:
    conventions = ds.attrs.get("Conventions")
    version = ds.attrs.get("bearingdae_version")
    if not (isinstance(conventions, str) and conventions.startswith("CF-")
            and isinstance(version, str)):
        raise ResultFileError("is not a bearingdae result file (no CF 'Conventions' and "
                              "'bearingdae_version' attributes); expected a file written by "
                              "bearingdae run, static, sweep or paper")
    if "sweep_axes" in ds.attrs:
        return "sweep"
    return "run" if "time" in ds.dims else "static"


def _current(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` in the current format: a file written before results were variables (they
    were global attributes) is converted by the same table (analysis/result_variables.py);
    one that cannot be says so in one line."""
    from ..analysis.result_variables import stray_result_attributes, upgrade

    stray = stray_result_attributes(ds)
    if stray:  # current (results are variables), with a result as an attribute besides
        raise ResultFileError(f"is damaged: global attribute '{stray[0][:60]}' is a result, "
                              "which this format keeps as a variable (a damaged or "
                              "hand-edited file); write it again with bearingdae")
    try:
        return upgrade(ds)
    except (TypeError, ValueError, RecursionError) as exc:
        raise ResultFileError(f"is from an older bearingdae format (results as global "
                              f"attributes) that could not be converted ({_brief(exc)}); "
                              "run it again with this version") from None


def _fail(kind: str, what: str):
    raise ResultFileError(f"is damaged or not a bearingdae {KINDS[kind]}: {what[:160]}")


def file_dimensions(ds: xr.Dataset) -> set:
    """The dimensions ``ds`` declares as its own: those without a coordinate by design
    (:data:`UNLABELLED_DIMS`) and every dimension labelled by a one-dimensional coordinate of
    its name (numbers or labels). The writers label every dimension a variable table gives
    them, so a new result dimension is read back without a list here to keep up to date."""
    own = set(UNLABELLED_DIMS)
    for name, var in ds.coords.items():
        if var.dims == (name,) and var.dtype.kind in "fiuOSU":
            own.add(str(name))
    return own


def _check_dims(ds: xr.Dataset, kind: str, allowed: set | None = None) -> None:
    allowed = file_dimensions(ds) | (allowed or set())
    extra = sorted(str(d) for d in set(ds.dims) - allowed)
    if extra:
        _fail(kind, f"unexpected dimension(s) {', '.join(extra)[:100]}; allowed are "
                    f"{', '.join(sorted(allowed))}")
    for name, var in ds.variables.items():
        if var.dtype.kind not in "fiuOSUb":
            _fail(kind, f"variable '{name}' has values of type {var.dtype}")


def _check_labels(ds: xr.Dataset, kind: str) -> None:
    for dim, labels in LABELS.items():
        if dim in ds.dims:
            values = tuple(str(v) for v in np.asarray(ds[dim].values).ravel()) \
                if dim in ds.coords else ()
            if values != tuple(labels):
                _fail(kind, f"'{dim}' is labelled {list(values)[:4]}, expected {list(labels)}")
    for dim in ("roller", "slice"):
        if dim in ds.dims:
            n = ds.sizes[dim]
            values = np.asarray(ds[dim].values) if dim in ds.coords else np.array([])
            if values.dtype.kind not in "iu" or not np.array_equal(values, np.arange(1, n + 1)):
                _fail(kind, f"'{dim}' is not numbered 1 to {n}")


def _check_var(ds, kind, name, dims) -> None:
    if name not in ds.data_vars:
        _fail(kind, f"variable '{name}' is missing")
    if ds[name].dims != tuple(dims):
        _fail(kind, f"variable '{name}' has dimensions {ds[name].dims}, expected {tuple(dims)}")


def _check_run(ds: xr.Dataset) -> None:
    _check_dims(ds, "run")
    t = np.asarray(ds["time"].values) if "time" in ds.coords else np.array([])
    if t.dtype.kind != "f" or t.ndim != 1 or t.size == 0:
        _fail("run", f"'time' is not a coordinate of seconds (type {t.dtype})")
    if not np.all(np.isfinite(t)) or (t.size > 1 and not np.all(np.diff(t) > 0)):
        _fail("run", "the sample times are not finite and increasing")
    found = [n for n in DYNAMIC_VARIABLES if n in ds.data_vars]
    if not found:
        _fail("run", f"none of the run variables ({', '.join(list(DYNAMIC_VARIABLES)[:4])}, "
                     "...) is present")
    for name in found:
        _check_var(ds, "run", name, ("time",) + DYNAMIC_VARIABLES[name][0])
    _check_labels(ds, "run")
    if "epicyclic_cage_speed_rad_s" in ds:
        epi = ds["epicyclic_cage_speed_rad_s"]
        if epi.ndim != 0 or epi.dtype.kind not in "fiu":
            _fail("run", f"variable 'epicyclic_cage_speed_rad_s' ({epi.dtype}, dimensions "
                         f"{epi.dims}) is not a number")


def _check_static(ds: xr.Dataset) -> None:
    _check_dims(ds, "static")
    for name, dims in STATIC_VARIABLES.items():
        _check_var(ds, "static", name, dims)
    _check_labels(ds, "static")


def sweep_axes(ds: xr.Dataset) -> list[dict]:
    """The ``sweep_axes`` attribute: a list of ``{"key", "dim", "values"}``."""
    try:
        axes = json.loads(ds.attrs["sweep_axes"])
    except (TypeError, ValueError, RecursionError):
        _fail("sweep", "attribute 'sweep_axes' is not JSON")
    if not isinstance(axes, list) or not all(
            isinstance(a, dict) and isinstance(a.get("dim"), str)
            and isinstance(a.get("key"), str) and isinstance(a.get("values"), list)
            for a in axes):
        _fail("sweep", "attribute 'sweep_axes' is not a list of {key, dim, values}")
    return axes


def _check_sweep(ds: xr.Dataset) -> None:
    axes = sweep_axes(ds)
    dims = tuple(a["dim"] for a in axes)
    if len(set(dims)) != len(dims):
        _fail("sweep", f"axes {list(dims)} repeat a dimension")
    for a in axes:
        if a["dim"] not in ds.dims or a["dim"] not in ds.coords:
            _fail("sweep", f"axis '{a['dim'][:60]}' is not a dimension with coordinates")
        if ds.sizes[a["dim"]] != len(a["values"]):
            _fail("sweep", f"axis '{a['dim']}' has {ds.sizes[a['dim']]} values, the "
                           f"attribute {len(a['values'])}")
    _check_dims(ds, "sweep", set(dims) | ORBIT_DIMS)
    figures = ds.attrs.get("figures", "[]")
    try:
        figures = json.loads(figures)
    except (TypeError, ValueError, RecursionError):
        figures = None
    if not isinstance(figures, list) or not all(
            isinstance(f, (int, str)) and not isinstance(f, bool) for f in figures):
        _fail("sweep", "attribute 'figures' is not a JSON list of figure numbers")
    for name in SWEEP_VARIABLES:
        _check_var(ds, "sweep", name, dims)
    for name, var in ds.data_vars.items():  # every variable is per run: the axes come first
        if var.dims[: len(dims)] != dims:
            _fail("sweep", f"variable '{name}' has dimensions {var.dims}, expected the axes "
                           f"{dims} first")
    for name in ("status", "error"):
        if ds[name].dtype.kind not in "OSU":
            _fail("sweep", f"variable '{name}' is not text")
    for name, (spec, _units, _long) in DYNAMIC_VARIABLES.items():
        if name in ds.data_vars:  # one orbit per run
            _check_var(ds, "sweep", name,
                       dims + ("azimuth",) + tuple(d for d in spec if d != "roller"))
    if "azimuth" in ds.dims and ("azimuth" not in ds.coords
                                 or ds["azimuth"].dtype.kind != "f"):
        _fail("sweep", "'azimuth' is not a coordinate of angles")
    _check_labels(ds, "sweep")
