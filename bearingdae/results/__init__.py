"""Solver output -> labelled :class:`xarray.Dataset` -> NetCDF (last pipeline stage).

Every variable carries CF ``units`` and ``long_name``; global attributes record the package,
the scene as TOML text and the regularisation scales. :func:`save` writes NetCDF4 with
compression **atomically** (:func:`bearingdae.util.atomic.atomic_write`: a temporary file beside the
target, then ``os.replace``), so an interrupted write never leaves a partial file at the target
path.

The package is split by job: ``dataset`` (static and dynamic Datasets), ``solution``
(Solution -> Dataset, solver attributes), ``netcdf`` (save); every name of these is
re-exported here. The record of a run: ``streamed_record`` (streamed to NetCDF block by
block), ``running_reductions`` (what a streamed run keeps over its record), ``streamed_netcdf``
(the file written block by block), ``extremes``, ``thermal_variables`` (a thermal run's
temperatures); the way back: ``readers`` (is a file a bearingdae run, static or sweep file,
undamaged?). The quantities the record computes are read off the states by
:mod:`bearingdae.analysis` (the layer below); the figures are :mod:`bearingdae.plots` (the
layer above).
"""

from __future__ import annotations

from ..util.atomic import atomic_write  # noqa: F401  (re-exported: results.atomic_write)
from .dataset import (  # noqa: F401
    RACES,
    DIRECTIONS,
    _var,
    contact_regularisation,
    base_attrs,
    index_coords,
    operating_attrs,
    TIME_ORIGIN,
    static_dataset,
    ENDS,
    DYNAMIC_VARIABLES,
    dynamic_dataset,
)
from .solution import (  # noqa: F401
    ERROR_ESTIMATES,
    error_estimate_variables,
    ProjectionError,
    from_solution,
    _unknown_scales,
    solver_attrs,
    _json_default,
)
from .netcdf import (  # noqa: F401
    PRECISIONS,
    save,
    _name_labels_in_coordinates,
    _ctrl_c_deferred,
)
