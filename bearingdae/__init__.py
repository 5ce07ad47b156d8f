"""bearingdae: dynamics of cylindrical roller bearings as one implicit DAE (SUNDIALS IDA).

Pipeline: scene (TOML) -> parameters -> physics -> DAE -> solver -> xarray Dataset -> NetCDF.

>>> from bearingdae import load_scene, solve_static
>>> ds = solve_static(load_scene("yang20_baseline"))
"""

__version__ = "0.1.0"  #: the one version: pyproject.toml, `--version`, every output file and the docs read it

import os as _os

# SUNDIALS' SuperLU_MT (linsolver='sparse') uses OpenMP: unless OMP_NUM_THREADS=1 is set before
# scikit-sundae is imported it runs 5-50x slower on this 2-core class of machine (measured).
_os.environ.setdefault("OMP_NUM_THREADS", "1")
# numba formats an error message with colorama (it wraps stdout and stderr anew each time) for
# every overload it tries and rejects while typing the kernels, ~30000 at a cold start: ~3 %
# of the compile CPU (docs/performance.md, "Cold start"); only its own error text loses colour.
_os.environ.setdefault("NUMBA_DISABLE_ERROR_MESSAGE_HIGHLIGHTING", "1")


# The public names load their modules on first use (PEP 562), so that `import bearingdae.cli`
# (the `bearingdae` program) starts in milliseconds and a Ctrl-C while numpy, xarray, numba and
# SUNDIALS load reaches cli.main, which ends it with one line instead of a traceback.
_EXPORTS = {"Scene": "scene", "SceneError": "scene", "load_scene": "scene",
            "scene_from_dict": "scene", "SimulationError": "api", "simulate": "api",
            "solve_static": "api", "stiffness": "api", "save": "results",
            # the solvers (contract: solvers/base.py), for simulate(scene, solver=IDA(...))
            "Solver": "solvers.base", "Solution": "solvers.base", "IDA": "solvers.ida",
            "Newmark": "solvers.newmark", "NewmarkOptions": "solvers.newmark",
            "ScipyPeer": "solvers.scipy_peers", "Checkpoint": "run.checkpoint",
            "Checkpointed": "run.checkpoint",
            # the convergence study of a scene's headline outputs (bearingdae converge)
            "converge": "studies.converge",
            # the bearing in a rotor model: stiffness over speed x load, a ROSS element
            "coefficients": "studies.coefficients", "to_ross": "studies.coefficients"}

__all__ = ["Scene", "SceneError", "load_scene", "scene_from_dict", "solve_static", "simulate",
           "SimulationError", "save", "Solver", "Solution", "IDA", "Newmark", "NewmarkOptions",
           "ScipyPeer", "Checkpoint", "Checkpointed", "converge", "stiffness", "coefficients", "to_ross",
           "__version__"]


def __getattr__(name: str):
    if name in _EXPORTS:
        import importlib

        value = getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
