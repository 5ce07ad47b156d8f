"""Find the SUNDIALS shared libraries that scikit-sundae's wheel ships, and check them.

Stage: solvers (compiled IDA core, solvers/ida.py). scikit-sundae stays our dependency for its
SUNDIALS build: its wheel bundles ``libsundials_{core,ida,nvecserial,sunmatrix*,sunlinsol*}``
(file names carry a build hash, e.g. ``libsundials_ida-16d992eb.so.7.9.0``). We never hard-code
those names: importing ``sksundae._cy_ida`` makes the dynamic loader map them into this process,
and :func:`find_libraries` reads their paths back from ``/proc/self/maps`` (Linux), falling
back to the ``*.libs`` / ``.dylibs`` directory next to the package. ``ctypes.CDLL`` of a mapped
file returns the handle already loaded, so we call the very functions scikit-sundae calls.

:func:`check_build` refuses, with an error that says what to do, a SUNDIALS that is not 7.x,
whose real type is not double or whose index type is not 32/64-bit, before any IDA memory
exists. The N_Vector layout the compiled callbacks read is checked in ``prototypes.py``.
"""

from __future__ import annotations

import ctypes
import os
import re
from dataclasses import dataclass

#: the component libraries the compiled IDA core needs (``libsundials_<name>``)
REQUIRED = ("core", "ida", "nvecserial", "sunmatrixsparse", "sunmatrixdense",
            "sunlinsolsuperlumt", "sunlinsoldense")
_NAME = re.compile(r"libsundials_([a-z]+)(?:-[0-9a-f]+)?\.(?:so|dylib|dll)")


class SundialsUnavailable(RuntimeError):
    """The SUNDIALS libraries cannot be found or do not match what the bindings need."""


@dataclass(frozen=True)
class Build:
    """Facts about the SUNDIALS build in use."""

    version: str  #: e.g. "7.9.0"
    index_bytes: int  #: sizeof(sunindextype)
    paths: dict  #: component name -> file path


def _mapped_paths() -> list[str]:
    try:
        with open("/proc/self/maps") as fh:
            return [line.split()[-1] for line in fh if "libsundials_" in line]
    except OSError:  # not Linux
        return []


def _directory_paths(package_file: str) -> list[str]:
    site = os.path.dirname(os.path.dirname(package_file))
    out = []
    for d in ("scikit_sundae.libs", os.path.join("sksundae", ".dylibs"), "scikit_sundae.dylibs"):
        full = os.path.join(site, d)
        if os.path.isdir(full):
            out += [os.path.join(full, f) for f in sorted(os.listdir(full))]
    return out


def find_libraries() -> dict[str, str]:
    """Component name -> path of every ``libsundials_*`` library scikit-sundae loaded."""
    try:
        import sksundae._cy_ida as cy_ida  # loads the bundled libraries
    except ImportError as exc:
        raise SundialsUnavailable(
            f"scikit-sundae is not importable ({exc}); the compiled IDA core uses the SUNDIALS "
            "libraries its wheel ships: pip install 'scikit-sundae>=1.2'") from exc
    found: dict[str, str] = {}
    for path in _mapped_paths() + _directory_paths(cy_ida.__file__):
        m = _NAME.search(os.path.basename(path))
        if m and m.group(1) not in found:
            found[m.group(1)] = path
    missing = [n for n in REQUIRED if n not in found]
    if missing:
        raise SundialsUnavailable(
            "SUNDIALS libraries not found: " + ", ".join(f"libsundials_{n}" for n in missing)
            + f" (looked at the libraries mapped after importing sksundae and next to "
              f"{os.path.dirname(cy_ida.__file__)}). The compiled IDA core needs the SUNDIALS "
              "7.x that scikit-sundae's wheel bundles; use solver IDAScikitSundae() meanwhile.")
    return found


def check_build(core: ctypes.CDLL, paths: dict) -> Build:
    """Version 7.x, real = double, index 32 or 64 bit, else :class:`SundialsUnavailable`."""
    buf = ctypes.create_string_buffer(32)
    core.SUNDIALSGetVersion.argtypes = [ctypes.c_char_p, ctypes.c_int]
    core.SUNDIALSGetVersion.restype = ctypes.c_int
    if core.SUNDIALSGetVersion(buf, 32) != 0:
        raise SundialsUnavailable("SUNDIALSGetVersion failed: cannot tell the SUNDIALS version")
    version = buf.value.decode()
    if not version.startswith("7."):
        raise SundialsUnavailable(f"SUNDIALS {version} found, the compiled IDA core is written "
                                  "for the 7.x API (scikit-sundae 1.2 ships 7.9)")
    try:
        from sksundae._cy_common import config
    except ImportError:
        config = {}
    real = config.get("SUNDIALS_FLOAT_TYPE", "double")
    if real != "double":
        raise SundialsUnavailable(f"SUNDIALS built with sunrealtype = {real}; the compiled "
                                  "IDA core needs double")
    index = config.get("SUNDIALS_INT_TYPE", "int")
    index_bytes = {"int": 4, "int32_t": 4, "int64_t": 8, "long int": 8, "long": 8}.get(index)
    if index_bytes is None:
        raise SundialsUnavailable(f"SUNDIALS built with sunindextype = {index!r}; expected a "
                                  "32- or 64-bit integer")
    return Build(version, index_bytes, dict(paths))
