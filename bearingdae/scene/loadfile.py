"""Load histories from other tools: ``[operating] load_file`` (pipeline stage 1, scene).

A load file holds the loads on the inner ring over time (theory.md §14):

- NetCDF (``.nc``, e.g. written by ``xarray.Dataset.to_netcdf``): a coordinate ``time`` in
  seconds and any of the data variables ``radial_load_N``, ``tangential_load_N``, ``moment_Nm``,
  ``tangential_moment_Nm`` and ``axial_load_N`` (a bearing with flanges, theory.md §16) on it;
  every one carries a CF ``units`` attribute, which is read and checked (``s``; ``N`` or
  ``kN``; ``N m`` or ``kN m``) and converted to SI.
- CSV (``.csv``): a header line naming the columns ``time_s`` and any of the five load names
  (the unit is the name's suffix), then one row of numbers per time; ``#`` starts a comment line.

The time must be finite and strictly increasing, have at least 2 samples and start at or before
0 s; loads must be finite. Every problem is one :class:`SceneError` line naming the file, the
variable and what is expected. A variable not given is 0; a variable of another name is refused
(a misspelt name would otherwise silently give a zero load).
"""

from __future__ import annotations

import csv
import hashlib
import io
import os
import stat
from pathlib import Path

import numpy as np

from ..util.atomic import shown_path
from .errors import SceneError, _show

#: the variables a load file may hold, in load-table order (physics/loads.TABLE_COLUMNS)
VARIABLES = ("radial_load_N", "tangential_load_N", "moment_Nm", "tangential_moment_Nm",
             "axial_load_N")
#: accepted CF ``units`` spellings -> factor to SI (udunits names and symbols)
FORCE_UNITS = {"N": 1.0, "newton": 1.0, "newtons": 1.0, "kg m s-2": 1.0, "kg m/s2": 1.0,
               "kN": 1e3, "kilonewton": 1e3, "kilonewtons": 1e3}
MOMENT_UNITS = {"N m": 1.0, "N.m": 1.0, "N*m": 1.0, "N·m": 1.0, "Nm": 1.0, "m N": 1.0,
                "newton meter": 1.0, "newton metre": 1.0, "kN m": 1e3, "kN.m": 1e3,
                "kN*m": 1e3, "kN·m": 1e3, "N mm": 1e-3, "N.mm": 1e-3}
TIME_UNITS = {"s": 1.0, "second": 1.0, "seconds": 1.0, "sec": 1.0, "ms": 1e-3,
              "millisecond": 1e-3, "milliseconds": 1e-3, "msec": 1e-3}
#: largest load file read (256 MiB: millions of samples)
MAX_LOAD_FILE_BYTES = 1 << 28
#: largest number of time samples (the kernel bisects the history each residual call)
MAX_SAMPLES = 10_000_000


def _fail(shown: str, what: str) -> SceneError:
    return SceneError(f"load file '{shown}': {what}")


def _open_regular(path: str | Path, shown: str) -> int:
    """The descriptor of ``path`` opened for reading once it is known to be a regular
    file of at most :data:`MAX_LOAD_FILE_BYTES`; SceneError otherwise. Opened without
    blocking and checked on the open descriptor: a FIFO would block an ordinary open until a
    writer comes, and a device (a link to /dev/zero) never ends, so nothing is read before the
    check, and the file checked is the file read."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except (OSError, ValueError) as exc:  # ValueError: a NUL in the path
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise _fail(shown, f"cannot be read: {reason}") from None
    st = os.fstat(fd)
    if not stat.S_ISREG(st.st_mode):
        os.close(fd)
        raise _fail(shown, "is not a regular file; expected a .nc or .csv file")
    if st.st_size > MAX_LOAD_FILE_BYTES:
        os.close(fd)
        raise _fail(shown, f"is larger than {MAX_LOAD_FILE_BYTES} bytes, the most a load file "
                    "may have")
    return fd


def file_sha256(path: str | Path) -> str:
    """SHA-256 (hex) of a file's bytes: the identity of an input file in a scene's
    (:meth:`bearingdae.scene.Scene.identity`), read in 1 MiB pieces once the file is checked
    to be a regular file of bounded size (SceneError otherwise)."""
    fd = _open_regular(path, shown_path(path))
    h, left = hashlib.sha256(), MAX_LOAD_FILE_BYTES + 1  # a file growing while read stops
    with os.fdopen(fd, "rb") as fh:
        while left > 0 and (piece := fh.read(min(1 << 20, left))):
            h.update(piece)
            left -= len(piece)
    return h.hexdigest()


def read_load_file(path: str | Path) -> tuple[np.ndarray, np.ndarray, tuple[str, ...]]:
    """(times [s] (n,), loads (n, 5) [N, N, N m, N m, N] in :data:`VARIABLES` order, the names
    the file gives) of a load file, checked (module docstring); SceneError with one line
    otherwise. A variable the file does not give is 0."""
    shown = shown_path(path)
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in (".nc", ".csv"):
        raise _fail(shown, f"unknown file type '{p.suffix or '(none)'}'; expected a NetCDF "
                    "file ending in .nc or a CSV file ending in .csv")
    os.close(_open_regular(p, shown))
    times, columns = (_read_netcdf if suffix == ".nc" else _read_csv)(p, shown)
    return _checked(shown, times, columns)


def _read_netcdf(p: Path, shown: str) -> tuple[np.ndarray, dict]:
    import xarray as xr

    try:
        with xr.open_dataset(p, decode_times=False, decode_timedelta=False,
                             decode_coords=False) as ds:
            ds = ds.load()
    except Exception as exc:  # noqa: BLE001 -- any reader failure is one line
        raise _fail(shown, f"is not a readable NetCDF file ({type(exc).__name__}: "
                    f"{_show(str(exc))}); expected a NetCDF file with a 'time' coordinate "
                    "in s") from None
    if "time" not in ds.variables:
        raise _fail(shown, "variable 'time': missing; expected a coordinate 'time' in s")
    tvar = ds.variables["time"]
    if tvar.dims != ("time",):
        raise _fail(shown, f"variable 'time': dimensions {tvar.dims}; expected ('time',)")
    t_factor = _unit(shown, "time", tvar.attrs.get("units"), TIME_UNITS, "s")
    columns = {}
    for name, var in ds.data_vars.items():
        if name not in VARIABLES:
            raise _fail(shown, f"variable {_show(str(name))}: unknown; expected only "
                        f"{', '.join(VARIABLES)} on 'time'")
        if var.dims != ("time",):
            raise _fail(shown, f"variable '{name}': dimensions {var.dims}; expected ('time',)")
        units = FORCE_UNITS if name.endswith("_N") else MOMENT_UNITS
        factor = _unit(shown, name, var.attrs.get("units"), units,
                       "N" if name.endswith("_N") else "N m")
        columns[name] = _numbers(shown, name, var.values) * factor
    return _numbers(shown, "time", tvar.values) * t_factor, columns


def _unit(shown: str, name: str, units, table: dict, si: str) -> float:
    """The factor to SI of a CF ``units`` attribute, or one error line."""
    if units is None:
        raise _fail(shown, f"variable '{name}': no 'units' attribute; expected units = '{si}'")
    text = " ".join(str(units).split())
    if text not in table:
        hint = (" (a reference time 'since ...' is not a duration)"
                if "since" in text else "")
        raise _fail(shown, f"variable '{name}': units {_show(text)}{hint}; expected one of "
                    + ", ".join(f"'{u}'" for u in table))
    return table[text]


def _numbers(shown: str, name: str, values) -> np.ndarray:
    a = np.asarray(values)
    if a.dtype.kind not in "iuf":
        raise _fail(shown, f"variable '{name}': values of type {a.dtype}; expected numbers")
    return a.astype(float).ravel()


def _read_csv(p: Path, shown: str) -> tuple[np.ndarray, dict]:
    try:  # "utf-8-sig": a byte-order mark (Excel's "CSV UTF-8") is dropped
        text = p.read_bytes().decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise _fail(shown, f"is not UTF-8 text (byte {exc.start}); expected a CSV file") from None
    except OSError as exc:
        raise _fail(shown, f"cannot be read: {exc.strerror or exc}") from None
    rows = [(line, r) for line, r in _csv_rows(text, shown)
            if r and not r[0].lstrip().startswith("#")]
    if not rows:
        raise _fail(shown, "is empty; expected a header line 'time_s," + ",".join(VARIABLES)
                    + "' (any of the loads) and rows of numbers")
    header = [h.strip() for h in rows[0][1]]
    if "time_s" not in header:
        raise _fail(shown, f"variable 'time_s': missing from the header {_show(','.join(header))};"
                    " expected a column 'time_s' (time in s)")
    for name in header:
        if name != "time_s" and name not in VARIABLES:
            raise _fail(shown, f"variable {_show(name)}: unknown column; expected time_s and "
                        f"any of {', '.join(VARIABLES)} (units in the name)")
    if len(set(header)) != len(header):
        raise _fail(shown, f"header {_show(','.join(header))}: a column is named twice")
    data = np.empty((len(rows) - 1, len(header)))
    for k, (line, row) in enumerate(rows[1:]):
        if len(row) != len(header):
            raise _fail(shown, f"line {line}: {len(row)} fields; expected {len(header)} "
                        f"({','.join(header)})")
        for c, field in enumerate(row):
            try:
                data[k, c] = float(field)
            except ValueError:
                raise _fail(shown, f"variable '{header[c]}', line {line}: "
                            f"{_show(field.strip())} is not a number") from None
    cols = {name: data[:, c] for c, name in enumerate(header) if name != "time_s"}
    return data[:, header.index("time_s")], cols


def _csv_rows(text: str, shown: str):
    """(line number where the row starts, fields) of every row: lines may end in LF, CRLF or
    CR alone (Excel's "CSV (Macintosh)"; ``newline=""`` hands the reader the line ends as
    they are); a row the reader refuses (a stray double quote, whose field then runs on to
    the end of the file) is one error line naming the line where that row starts."""
    reader = csv.reader(io.StringIO(text, newline=""))
    start = 1
    while True:
        try:
            row = next(reader)
        except StopIteration:
            return
        except csv.Error as exc:
            quote = (" (a double quote opens a quoted field there; remove it or close it "
                     "with another)" if "field larger" in str(exc) or "EOF" in str(exc)
                     else "")
            raise _fail(shown, f"line {start}: not readable as CSV ({exc}){quote}") from None
        yield start, row
        start = reader.line_num + 1


def _checked(shown: str, times: np.ndarray, columns: dict):
    name = "time" if not shown.lower().endswith(".csv") else "time_s"
    if not columns:
        raise _fail(shown, f"no load variable; expected any of {', '.join(VARIABLES)}")
    n = times.size
    if n < 2:
        raise _fail(shown, f"variable '{name}': {n} sample{'s' if n != 1 else ''}; expected at "
                    "least 2 (a history is linear between samples)")
    if n > MAX_SAMPLES:
        raise _fail(shown, f"variable '{name}': {n} samples; expected at most {MAX_SAMPLES}")
    if not np.all(np.isfinite(times)):
        i = int(np.flatnonzero(~np.isfinite(times))[0])
        raise _fail(shown, f"variable '{name}': {times[i]} at index {i}; expected finite times")
    steps = np.diff(times)
    if np.any(steps <= 0.0):
        i = int(np.flatnonzero(steps <= 0.0)[0])
        raise _fail(shown, f"variable '{name}': {times[i + 1]:.9g} s at index {i + 1} follows "
                    f"{times[i]:.9g} s; expected strictly increasing times")
    if times[0] > 0.0:
        raise _fail(shown, f"variable '{name}': starts at {times[0]:.9g} s; expected to start "
                    "at or before 0 s (the start of the run)")
    out = np.zeros((n, len(VARIABLES)))
    for c, var in enumerate(VARIABLES):
        if var not in columns:
            continue
        v = columns[var]
        if v.size != n:
            raise _fail(shown, f"variable '{var}': {v.size} values; expected {n} (one per time)")
        bad = ~np.isfinite(v)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise _fail(shown, f"variable '{var}': {v[i]} at t = {times[i]:.9g} s (index {i}); "
                        "expected finite loads")
        limit = 1e8 if var.endswith("_N") else 1e6
        big = np.abs(v) > limit
        if big.any():
            i = int(np.flatnonzero(big)[0])
            raise _fail(shown, f"variable '{var}': {v[i]:.6g} at t = {times[i]:.9g} s; expected"
                        f" values in [-{limit:g}, {limit:g}] (in SI after the units)")
        out[:, c] = v
    return times.astype(float), out, tuple(v for v in VARIABLES if v in columns)


def merge_histories(histories) -> np.ndarray:
    """One load table (rows [t, F_r, F_t, M, M_t, F_a]) from five histories, each a constant or
    a pair (times [s], values): rows on the union of the given times, each history interpolated
    linearly and held at its ends (exact: a piecewise-linear history sampled at its own
    breakpoints and more). All constants give one row."""
    pairs = [np.asarray(h[0], float) for h in histories if isinstance(h, tuple)]
    if not pairs:
        return np.array([[0.0] + [float(h) for h in histories]])
    grid = np.unique(np.concatenate(pairs))  # sorted, each time once (a load file: millions)
    cols = [np.interp(grid, np.asarray(h[0], float), np.asarray(h[1], float))
            if isinstance(h, tuple) else np.full(grid.size, float(h)) for h in histories]
    return np.column_stack([grid] + cols)
