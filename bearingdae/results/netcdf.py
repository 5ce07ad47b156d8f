"""Dataset -> NetCDF4 file: compression, precision, CF label coordinates, atomic write.

Pipeline: the last stage (results). :func:`save` writes atomically
(:func:`bearingdae.util.atomic.atomic_write`: a temporary file beside the target, then
``os.replace``) with Ctrl-C held until the file is complete, so an interrupted write never
leaves a partial file at the target path.
"""

from __future__ import annotations

import gc
import os
from pathlib import Path

import xarray as xr

from ..util.atomic import atomic_write
from ..util.ctrl_c import ctrl_c_deferred as _ctrl_c_deferred  # (its callers' name)


#: NetCDF types a result's data variables may be written as (``[output] precision``)
PRECISIONS = ("float64", "float32")


def save(ds: xr.Dataset, path: str | Path, complevel: int = 4,
         precision: str | None = None) -> Path:
    """Write a result Dataset to NetCDF4 (zlib-compressed, CF-1.10) atomically.

    The file is written beside the target under a temporary name and renamed, so a killed
    run never leaves a partial file at ``path``.

    Parameters
    ----------
    ds : xarray.Dataset
        A result of :func:`simulate`, :func:`solve_static` or a sweep.
    path : str or pathlib.Path
        The NetCDF file to write (its folder is created).
    complevel : int, default 4
        zlib compression level.
    precision : {"float64", "float32"}, optional
        Floating-point type of the *data* variables (default: the Dataset's
        ``output_precision`` attribute, set from the scene's ``[output] precision``, else
        float64). Coordinates (time, azimuth, x) stay float64: a float32 time would round
        sample times of a long run to ~1e-7 of the run's length.

    Returns
    -------
    pathlib.Path
        The path written.

    Examples
    --------
    >>> import xarray as xr
    >>> path = save(ds, "run.nc")                        # doctest: +SKIP
    >>> xr.open_dataset(path).cage_speed.attrs["units"]  # doctest: +SKIP
    'rad s-1'
    """
    if not isinstance(ds, xr.Dataset):
        raise TypeError(f"save: ds: expected an xarray.Dataset (from simulate or solve_static), "
                        f"got {type(ds).__name__}")
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"save: path: expected a file path (str or os.PathLike), got "
                        f"{type(path).__name__}")
    if isinstance(complevel, bool) or not isinstance(complevel, int) or not 0 <= complevel <= 9:
        raise ValueError(f"save: complevel = {complevel!r:.100}: allowed are the integers 0-9")
    if precision is not None and (not isinstance(precision, str) or precision not in PRECISIONS):
        raise ValueError(f"save: precision = {precision!r:.100}: allowed are "
                         f"{', '.join(PRECISIONS)}")
    path = Path(path)
    precision = precision or str(ds.attrs.get("output_precision", "float64"))
    if precision not in PRECISIONS:
        raise ValueError(f"precision = {precision!r}: allowed are {', '.join(PRECISIONS)}")
    path.parent.mkdir(parents=True, exist_ok=True)
    ds, encoding = prepared(ds, complevel, precision)
    with atomic_write(path) as tmp, _ctrl_c_deferred():
        write_netcdf4(ds, tmp, encoding=encoding)
    return path


def write_netcdf4(ds: xr.Dataset, path: str | Path, **kwargs) -> None:
    """``ds.to_netcdf(path, format="NETCDF4", engine="netcdf4", **kwargs)`` that leaves no
    HDF5 file open when it fails.

    A failed write (a full disk) leaves xarray's ``netCDF4.Dataset`` open, in a reference cycle
    with the frames of the exception. Python's cyclic collector would close it at some later
    allocation, on whichever thread runs then: in a streamed run maybe while the writer thread
    is in HDF5, which is not thread-safe (measured, a streamed run onto a full disk: the
    fallback file's write then failed with "NetCDF: HDF error", or the process crashed, in 9 of
    35 runs). The failure is raised without those frames, after the collector closed the file on
    this thread."""
    failure = None
    try:
        ds.to_netcdf(path, format="NETCDF4", engine="netcdf4", **kwargs)
    except Exception as exc:  # noqa: BLE001 - re-raised below, the same object
        failure, chained, seen = exc, [exc], set()
        while chained:  # the exceptions it chains hold frames as well
            link = chained.pop()
            if link is not None and id(link) not in seen:
                seen.add(id(link))
                link.__traceback__ = None
                chained += [link.__context__, link.__cause__]
    if failure is not None:
        gc.collect()
        raise failure


def prepared(ds: xr.Dataset, complevel: int, precision: str,
             chunk_time: int | None = None) -> tuple[xr.Dataset, dict]:
    """(Dataset, encoding) as :func:`save` writes them: zlib on numeric arrays, data variables
    in ``precision``, coordinates without fill values, labels as char arrays named in the
    ``coordinates`` attributes. ``chunk_time``: chunk every variable with a ``time`` dimension
    as (``chunk_time``, its whole other dimensions), for a file whose unlimited ``time`` grows
    block by block (results/streamed_netcdf.py)."""
    # Text data (a run's status, its error) and label coordinates (race, end) have no units
    # (CF: units are for quantities; xarray would print "race []" on a plot axis).
    encoding = {}
    for name, var in ds.variables.items():
        enc = encoding.setdefault(name, {})
        if var.dtype.kind in "fiu" and var.ndim > 0:
            enc.update(zlib=True, complevel=complevel)
        if var.dtype.kind == "f" and precision != "float64" and name not in ds.coords:
            enc["dtype"] = precision
        if name in ds.coords:
            enc["_FillValue"] = None  # CF 2.5.1: coordinate variables have no missing values
        if var.dtype.kind in "OUS":
            # Labels (race = inner/outer) as char arrays: CF coordinate variables are numeric
            # (CF 1.3, 6.1); xarray reads them back as the same string coordinate.
            enc["dtype"] = "S1"
        if chunk_time is not None and "time" in var.dims and var.dtype.kind in "fiu":
            enc["chunksizes"] = tuple(chunk_time if d == "time" else max(1, var.sizes[d])
                                      for d in var.dims)
    ds = _name_labels_in_coordinates(ds)
    ds.attrs = char_attrs(ds.attrs)
    return ds, encoding


def char_attrs(attrs: dict) -> dict:
    """Global attributes with every text as UTF-8 bytes: the netCDF4 library writes a text
    that is not plain ASCII (a title with "N·m") as an NC_STRING and the others as NC_CHAR;
    bytes are NC_CHAR whatever they hold, so every text attribute has one type (CF 2.3 allows
    UTF-8 in it). netCDF4 and xarray read them back as the same ``str``."""
    return {k: v.encode("utf-8") if isinstance(v, str) and not v.isascii() else v
            for k, v in attrs.items()}


def _name_labels_in_coordinates(ds: xr.Dataset) -> xr.Dataset:
    """CF 6.1: a label variable (``race`` = inner/outer, written as a char array) is an
    auxiliary coordinate, tied to the data it labels by their ``coordinates`` attribute. xarray
    lists only non-index coordinates there; add the label dimensions (the NCAS cf-checker warns
    "possible incorrect declaration of a coordinate variable" otherwise). xarray reads the
    attribute back into ``encoding``: the round trip stays identical. Returns a shallow copy."""
    ds = ds.copy(deep=False)
    labels = {d for d in ds.dims if d in ds.variables and ds[d].dtype.kind in "OUS"}
    aux = [c for c in ds.coords if c not in ds.dims]
    for name, var in ds.data_vars.items():
        if not labels & set(var.dims) or "coordinates" in var.attrs:
            continue
        # xarray's own choice (non-index coordinates on a subset of the dims) plus the labels
        refs = {c for c in aux if set(ds[c].dims) <= set(var.dims)} | (labels & set(var.dims))
        ds[name].encoding = {**var.encoding, "coordinates": " ".join(sorted(map(str, refs)))}
    return ds


