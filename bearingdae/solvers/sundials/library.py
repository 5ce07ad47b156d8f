"""Find the SUNDIALS shared libraries that scikit-sundae's wheel ships, and check them.

Stage: solvers (compiled IDA core, solvers/ida.py). scikit-sundae stays our dependency for its
SUNDIALS build: its wheel bundles ``libsundials_{core,ida,nvecserial,sunmatrix*,sunlinsol*}``
(file names carry a build hash, e.g. ``libsundials_ida-16d992eb.so.7.9.0``). We never hard-code
those names: :func:`find_libraries` lists the ``*.libs`` / ``.dylibs`` directory the wheel
puts next to the package, found without importing it; only where that directory lacks a
library (another packaging) does it import ``sksundae._cy_ida``, which makes the dynamic
loader map them into this process, and read their paths back from ``/proc/self/maps`` (Linux).
Why not always import: the package imports scipy.optimize and its own Python front end (0.4 s alone;
~0.07 s of CPU of a run's start, the rest imported anyway), for nothing the compiled core uses.
Either way ``ctypes.CDLL`` of the same file returns the same handle (the loader keys it by soname),
so we call the very functions scikit-sundae calls.
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


def _package_directory() -> str | None:
    """sksundae's directory, found without importing the package (None: not installed)."""
    import importlib.util

    try:
        spec = importlib.util.find_spec("sksundae")
    except (ImportError, ValueError):
        return None
    if spec is None or not spec.submodule_search_locations:
        return None
    return list(spec.submodule_search_locations)[0]


def _collect(paths: list[str]) -> dict[str, str]:
    found: dict[str, str] = {}
    for path in paths:
        m = _NAME.search(os.path.basename(path))
        if m and m.group(1) not in found:
            found[m.group(1)] = path
    return found


def find_libraries() -> dict[str, str]:
    """Component name -> path of every ``libsundials_*`` library of scikit-sundae's build."""
    package = _package_directory()
    if package is not None:
        found = _collect(_directory_paths(os.path.join(package, "__init__.py")))
        if all(n in found for n in REQUIRED):
            return found
    try:
        import sksundae._cy_ida as cy_ida  # loads the bundled libraries
    except ImportError as exc:
        raise SundialsUnavailable(
            f"scikit-sundae is not importable ({exc}); the compiled IDA core uses the SUNDIALS "
            "libraries its wheel ships: pip install 'scikit-sundae>=1.2'") from exc
    found = _collect(_mapped_paths() + _directory_paths(cy_ida.__file__))
    missing = [n for n in REQUIRED if n not in found]
    if missing:
        raise SundialsUnavailable(
            "SUNDIALS libraries not found: " + ", ".join(f"libsundials_{n}" for n in missing)
            + f" (looked at the libraries mapped after importing sksundae and next to "
              f"{os.path.dirname(cy_ida.__file__)}). The compiled IDA core needs the SUNDIALS "
              "7.x that scikit-sundae's wheel bundles; use solver IDAScikitSundae() meanwhile.")
    return found


_CONFIG_LINE = re.compile(r'^\s*(SUNDIALS_[A-Z_]+)\s*=\s*"([^"]*)"\s*$')


def build_config() -> dict[str, str]:
    """scikit-sundae's record of its SUNDIALS build (``SUNDIALS_FLOAT_TYPE``,
    ``SUNDIALS_INT_TYPE``, ...): the ``py_config.pxi`` its wheel ships (the text its
    ``_cy_common.config`` is compiled from), read without importing the package; else that
    ``config`` itself; empty if neither is there."""
    package = _package_directory()
    if package is not None:
        try:
            with open(os.path.join(package, "py_config.pxi")) as fh:
                config = dict(m.groups() for m in map(_CONFIG_LINE.match, fh) if m)
        except OSError:
            config = {}
        if "SUNDIALS_FLOAT_TYPE" in config and "SUNDIALS_INT_TYPE" in config:
            return config
    try:
        from sksundae._cy_common import config
    except ImportError:
        return {}
    return dict(config)


def versions() -> tuple[str, str]:
    """(SUNDIALS version, scikit-sundae version) of the build in use, for the results'
    attributes; from the installed distribution's metadata and :func:`build_config`, without
    importing the package where they are there."""
    import importlib.metadata

    sundials = build_config().get("SUNDIALS_VERSION")
    try:
        package = importlib.metadata.version("scikit-sundae")
    except importlib.metadata.PackageNotFoundError:
        package = None
    if sundials is None or package is None:
        try:
            import sksundae
        except ImportError:
            return sundials or "unknown", package or "unknown"
        sundials = sundials or str(getattr(sksundae, "SUNDIALS_VERSION", "unknown"))
        package = package or str(getattr(sksundae, "__version__", "unknown"))
    return sundials, package


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
    config = build_config()
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
