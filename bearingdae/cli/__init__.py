"""Command line: ``bearingdae run|static|sweep|skidmap|paper|plot|spectrum|workprecision|converge|coefficients|calibrate|cases|keys`` (thin
layer over the Python API).

Errors in the user's input are printed as one paragraph and exit with status 2; no traceback
reaches the user for bad input.

The package is split by job: ``parser`` (the argument parser), ``common`` (--set overrides,
the scene of CASE), one module per command group (``run``: run/static, ``sweeps``:
sweep/skidmap/paper, ``plot``, ``info``: cases/keys, ``workprecision``, ``converge``); this module keeps
:func:`main` and :func:`execute`, which look the handlers up here (tests patch them here).
``python -m bearingdae.cli`` runs ``__main__.py``.
"""

from __future__ import annotations

import contextlib
import sys
import warnings

from .calibrate import _calibrate
from .coefficients import _coefficients
from .converge import _converge
from .common import _check_workers, _notice, _overrides, _scene, _set_origin  # noqa: F401
from .info import _cases, _keys
from .parser import DEFAULT_CASE, _case_arguments, _cluster_arguments, _parser  # noqa: F401
from .plot import _plot
from .run import _run, _static
from .spectrum import _spectrum_table
from .sweeps import _paper, _print_sweep, _skidmap, _sweep  # noqa: F401
from .workprecision import _workprecision


@contextlib.contextmanager
def _plausibility_printed(stated: tuple = ()):
    """Print each of bearingdae's own warnings (util/warning_lines.py: plausibility findings, a
    warm-up that did not settle) as one 'bearingdae: warning:' line on stderr, as it comes,
    except the categories ``stated``, which the command's summary states in a line of its own;
    other warnings go their usual way. A line already printed is not printed again: a command
    of many runs of one scene (workprecision's 108, a convergence study) found the same
    start-state finding in every run. (Not catch_warnings(record=True): recording every
    warning of a sweep kept dask objects alive until a garbage collection at exit
    deadlocked.)"""
    from ..util.warning_lines import BearingdaeWarning, one_line

    printed = set()

    def show(message, category, filename, lineno, file=None, line=None):
        if stated and issubclass(category, stated):
            return
        if issubclass(category, BearingdaeWarning):
            text = one_line(message)
            if text not in printed:
                printed.add(text)
                print(text, file=sys.stderr)
        else:
            shown(message, category, filename, lineno, file, line)

    with warnings.catch_warnings():
        warnings.simplefilter("always", BearingdaeWarning)
        shown, warnings.showwarning = warnings.showwarning, show
        yield


#: modules each command needs, loaded before the command starts (see bearingdae/cli/program.py)
_MODULES = {"run": ("api", "analysis.summary", "run.checkpoint", "plots.plotting"),
            "static": ("api",), "sweep": ("studies.sweep",), "paper": ("studies.paper",),
            "plot": ("plots.plotting",), "spectrum": ("analysis.spectrum_peaks",),
            "workprecision": ("studies.workprecision",),
            "cases": ("studies.sweep",), "keys": (), "converge": ("studies.converge",),
            "coefficients": ("api", "studies.coefficients"),
            "calibrate": ("api", "studies.calibrate"),
            "skidmap": ("studies.skidmap", "studies.sweep", "plots.plotting")}


def main(argv: list[str] | None = None) -> int:
    """The command line, in-process; returns the exit status. A KeyboardInterrupt (the heavy
    modules load here, not at ``import bearingdae.cli``) ends with one line and status 130; a
    dynamic run interrupted while integrating keeps its samples (``_partial.nc``) and ends with
    status 130 as well.
    The ``bearingdae`` program (bearingdae/cli/program.py) adds what only a process can do: Ctrl-C
    during start-up and shut-down, and interrupts lost in callbacks."""
    from .interrupts import INTERRUPTED

    try:
        return execute(argv)
    except KeyboardInterrupt:
        print(INTERRUPTED, file=sys.stderr)
        return 130


def execute(argv: list[str] | None) -> int:
    """:func:`main` without its Ctrl-C handling: a KeyboardInterrupt propagates (the program,
    bearingdae/cli/program.py, handles it)."""
    args = _parser().parse_args(argv)
    from ..util.kernel_cache import notices

    notices(True)  # a first compile says which kernels it compiles (util/kernel_cache.py)
    if args.version:
        from .. import __version__

        print(f"bearingdae {__version__}")
        return 0
    import importlib

    from .interrupts import raise_on_ctrl_c
    from ..scene import SceneError
    from ..solvers.static import StaticConvergenceError
    from ..solvers.sundials.library import SundialsUnavailable

    for module in ("analysis.guards",) + _MODULES.get(args.command, ()):
        importlib.import_module(f"..{module}", __package__)  # bearingdae.<module>
    raise_on_ctrl_c()  # modules loaded: from here on Ctrl-C is a KeyboardInterrupt
    handlers = {"run": _run, "static": _static, "cases": _cases, "keys": _keys,
                "workprecision": _workprecision, "converge": _converge,
                "coefficients": _coefficients, "calibrate": _calibrate,
                "sweep": _sweep, "paper": _paper, "plot": _plot, "skidmap": _skidmap,
                "spectrum": _spectrum_table}
    if args.command is None:
        _parser().print_help()
        return 0
    try:
        from ..analysis.guards import FilmParameterWarning

        # run and static print λ_min, where it occurs and what λ < 1 means in their summary
        stated = (FilmParameterWarning,) if args.command in ("run", "static") else ()
        with _plausibility_printed(stated):
            return handlers[args.command](args)
    except (SceneError, ValueError) as exc:
        print(f"bearingdae: error: {exc}", file=sys.stderr)
        return 2
    except SundialsUnavailable as exc:  # a broken or foreign scikit-sundae installation
        print(f"bearingdae: SUNDIALS unavailable: {exc}", file=sys.stderr)
        return 1
    except StaticConvergenceError as exc:  # e.g. the initial equilibrium of `run`
        print(f"bearingdae: static solver failure: {exc}; no file written", file=sys.stderr)
        return 1
    except BrokenPipeError:  # the reader of stdout went away (| head): nothing more to say
        return 1  # (the program points stdout nowhere before exiting: interrupts._flush)
    except OSError as exc:  # a write no command expected to fail (each keeps its results)
        print(f"bearingdae: {exc.strerror or exc}"
              + (f": '{exc.filename}'" if exc.filename else ""), file=sys.stderr)
        return 1
