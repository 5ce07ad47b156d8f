"""Time integrators of the DAE model (stage: system -> **solvers** -> results).

Every integrator fulfils the contract of :mod:`bearingdae.solvers.base`:

* :class:`IDA` (solvers/ida.py): SUNDIALS IDA, the reference;
* :class:`Newmark` (solvers/newmark.py): fixed-step Newmark-β / HHT-α, the cross-check;
* :class:`ScipyPeer` (solvers/scipy_peers.py): scipy BDF / Radau / LSODA on the reduced ODE;
* :class:`~bearingdae.run.checkpoint.Checkpointed`: any of them with checkpoints (resumable).

:func:`from_name` maps the names of the command line (``"ida"``, ``"newmark"``,
``"scipy-BDF"``, ...) to solver objects. The names load their modules on first use (PEP 562),
so ``import bearingdae.solvers.static`` does not load SUNDIALS.
"""

from __future__ import annotations

# The kernels of this folder are cached by the hash of the package's source contents, in a
# folder of that hash (util/kernel_cache.py): set up before any kernel module is decorated.
from ..util.kernel_cache import install as _install_kernel_cache  # noqa: E402

_install_kernel_cache()

#: solver name -> scipy method of the nested peers
SCIPY_PEERS = {"scipy-BDF": "BDF", "scipy-Radau": "Radau", "scipy-LSODA": "LSODA"}
#: every name :func:`from_name` knows
NAMES = ("ida", "newmark", *SCIPY_PEERS, "ida-scikit-sundae")

_EXPORTS = {"Solver": "base", "Solution": "base", "Counters": "base", "IDA": "ida", "IDAScikitSundae": "ida",
            "Newmark": "newmark", "NewmarkOptions": "newmark", "ScipyPeer": "scipy_peers"}

__all__ = ["NAMES", "SCIPY_PEERS", "from_name", *_EXPORTS]


def from_name(name: str, **options):
    """The solver object of a command-line name, with its options as keywords.

    ``"ida"``: ``linsolver``, ``jacobian``, ``suppress_alg``, ``max_restarts``,
    ``record_steps``, ``delta_cj_lsetup``, ``atol_factors``, ``max_order``,
    ``nonlin_conv_coef``, ``max_nonlin_iters`` (:class:`IDA`;
    ``"ida-scikit-sundae"`` the same IDA through scikit-sundae's Python callbacks); ``"newmark"``: ``jacobian``,
    ``options`` (a :class:`NewmarkOptions`; default: the scene's) (:class:`Newmark`);
    ``"scipy-BDF"``, ``"scipy-Radau"``, ``"scipy-LSODA"``: ``jac``, ``time_limit_s``,
    ``dae_jacobian``, ``inner`` (:class:`ScipyPeer`; ``jacobian`` is taken as
    ``dae_jacobian``). An unknown name or option is a ValueError that lists the allowed ones.
    """
    import inspect

    if name == "ida":
        from .ida import IDA as cls
    elif name == "ida-scikit-sundae":  # the cross-check path (docs/performance.md)
        from .ida import IDAScikitSundae as cls
    elif name == "newmark":
        from .newmark import Newmark as cls
    elif name in SCIPY_PEERS:
        from .scipy_peers import ScipyPeer as cls

        options = dict(options)
        if "jacobian" in options:  # the DAE Jacobian, as for IDA and Newmark
            options.setdefault("dae_jacobian", options.pop("jacobian"))
        options["method"] = SCIPY_PEERS[name]
    else:
        raise ValueError(f"solver = {name!r}: allowed are {', '.join(map(repr, NAMES))}")
    allowed = [p for p in inspect.signature(cls.__init__).parameters if p != "self"]
    unknown = sorted(set(options) - set(allowed))
    if unknown:
        shown = [p for p in allowed if not (name in SCIPY_PEERS and p == "method")]
        raise ValueError(f"solver {name!r}: unknown option(s) {', '.join(map(repr, unknown))}; "
                         f"allowed are {', '.join(map(repr, shown))}")
    return cls(**options)


def __getattr__(name: str):
    if name in _EXPORTS:
        import importlib

        value = getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
