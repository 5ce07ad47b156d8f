"""xarray's look for optional libraries, spared in a process that cannot meet their objects.

Stage: util (the ``bearingdae`` program's start-up, bearingdae/cli/program.py).

The first time xarray wraps an array it imports every duck-array library it knows and finds
installed (dask.array, pint, sparse, cupy) to learn their array types: 0.42 s of CPU for
dask.array and 0.07 s for pint on a 2-CPU Xeon (2026-11-30), a fifth of a short run's first
call. dask is installed with bearingdae (its sweeps), so every ``bearingdae run`` paid it,
although a run, a static solve, a plot or a spectrum table only ever holds numpy arrays and
arrays read lazily from NetCDF files.

:func:`spare_duck_array_imports` tells xarray that the libraries not imported yet are absent
(its cache of them, ``xarray.namedarray.pycompat``), so it never imports them. Only for the
program's own process and those commands: in a notebook or a test session a later dask or pint
array would then go unrecognised, so library use never calls it. A library already imported is
left to xarray (its arrays may exist). An xarray whose cache is not where this expects it is
left alone as well: the imports then cost what they did.

:func:`spare_distributed_import` does the same for dask.distributed: at every NetCDF write
xarray asks whether a distributed client is dask's scheduler
(``xarray.backends.locks.get_dask_scheduler``), and imports dask.distributed to know (0.2 s
of CPU on that Xeon, in every ``bearingdae run`` that writes its file). While dask.distributed
is not imported no client can exist in the process; xarray's question is then answered as
xarray answers it where dask.distributed is absent.
"""

from __future__ import annotations

import sys

#: xarray's name of a duck-array library -> the module whose import xarray's look costs
LIBRARIES = {"dask": "dask.array", "pint": "pint", "sparse": "sparse", "cupy": "cupy"}


def spare_duck_array_imports() -> list[str]:
    """Mark the duck-array libraries of :data:`LIBRARIES` that are not imported yet as absent
    in xarray's cache; returns their names (empty where xarray's cache is not as expected)."""
    try:
        from packaging.version import Version
        from xarray.namedarray import pycompat

        cache = pycompat._cached_duck_array_modules
        kind = pycompat.DuckArrayModule
    except (ImportError, AttributeError):
        return []
    if not isinstance(cache, dict):
        return []
    spared = []
    for name, module in LIBRARIES.items():
        if name in cache or module in sys.modules:
            continue
        absent = kind.__new__(kind)  # as xarray's own entry for a library it cannot import
        absent.module, absent.version, absent.type, absent.available = (
            None, Version("0.0.0"), (), False)
        cache[name] = absent
        spared.append(name)
    return spared


#: the modules xarray's scheduler check imports to look for a distributed client (xarray's
#: ``from dask.distributed import Client``, dask's ``from distributed import get_client``)
_DISTRIBUTED = ("distributed", "dask.distributed")


def spare_distributed_import() -> bool:
    """Make xarray's scheduler check (``get_dask_scheduler``, in xarray.backends.locks and
    the writers that import it) import nothing of dask.distributed while it is not imported:
    during the check its imports fail as for a missing package, which xarray and dask catch.
    Returns whether the check was found and wrapped."""
    try:
        from xarray.backends import locks, writers

        original = locks.get_dask_scheduler
    except (ImportError, AttributeError):
        return False
    if getattr(original, "spared_distributed", False):
        return True

    def get_dask_scheduler(get=None, collection=None):
        if any(name in sys.modules for name in _DISTRIBUTED):
            return original(get, collection)  # a client may exist: xarray's own check
        for name in _DISTRIBUTED:  # their imports fail as for a missing package
            sys.modules[name] = None
        try:
            return original(get, collection)
        finally:
            for name in _DISTRIBUTED:
                if name in sys.modules and sys.modules[name] is None:
                    del sys.modules[name]

    get_dask_scheduler.spared_distributed = True
    wrapped = False
    for module in (locks, writers):
        if getattr(module, "get_dask_scheduler", None) is original:
            module.get_dask_scheduler = get_dask_scheduler
            wrapped = True
    return wrapped
