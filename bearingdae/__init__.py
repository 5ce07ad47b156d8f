"""bearingdae: dynamics of cylindrical roller bearings as one implicit DAE (SUNDIALS IDA).

Pipeline: scene (TOML) -> parameters -> physics -> DAE -> solver -> xarray Dataset -> NetCDF.

>>> from bearingdae import load_scene, solve_static
>>> ds = solve_static(load_scene("yang20_baseline"))
"""

__version__ = "0.1.0"

import os as _os

# SUNDIALS' SuperLU_MT (linsolver='sparse') uses OpenMP: unless OMP_NUM_THREADS=1 is set before
# scikit-sundae is imported it runs 5-50x slower on this 2-core class of machine (measured).
_os.environ.setdefault("OMP_NUM_THREADS", "1")

from .scene import Scene, SceneError, load_scene, scene_from_dict  # noqa: E402
from .api import SimulationError, simulate, solve_static  # noqa: E402
from .results import save  # noqa: E402

__all__ = ["Scene", "SceneError", "load_scene", "scene_from_dict", "solve_static", "simulate", "SimulationError", "save",
           "__version__"]
