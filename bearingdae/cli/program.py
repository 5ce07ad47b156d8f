"""The ``bearingdae`` program (console script): :func:`bearingdae.cli.main` with Ctrl-C handled
at every moment.

A KeyboardInterrupt is the right way to stop a running simulation (the run keeps its samples in
``_partial.nc`` and its checkpoint) and to stop a write (``results.save`` holds it until the
file is complete). It is the wrong one while Python modules load: raised inside an import it
shows a traceback, and raised inside importlib's own clean-up callbacks it is printed and
*ignored* (the run then goes on). So the program has three phases:

1. start-up (argument parsing, loading the command's modules: numpy, xarray, numba, SUNDIALS,
   dask): nothing has been written yet, so Ctrl-C ends the process at once with one line and
   status 130 (:func:`exit_on_ctrl_c`);
2. the command itself: Ctrl-C raises KeyboardInterrupt as usual (:func:`raise_on_ctrl_c`,
   called by ``cli.execute`` once its modules are loaded), which ends in one line and status
   130 (a run interrupted while integrating keeps its samples in ``_partial.nc`` as well and
   also ends with status 130). A KeyboardInterrupt that lands in a callback
   which cannot pass it on (measured: llvmlite's ctypes callback while numba compiles,
   importlib's module-lock clean-up; Python prints "Exception ignored" and goes on) is
   delivered once more from outside the callback (:func:`_redeliver_lost_ctrl_c`). An
   interrupted command ends the process with ``os._exit`` as soon as the line is printed:
   releasing the interrupted frames, with a native library (SUNDIALS, LLVM) stopped half-way,
   was measured to crash (SIGSEGV, 2 of 60 SIGINTs around the start of the integration);
3. after the command has returned (its atexit handlers): at once again, after flushing what
   was printed. The process then ends with ``os._exit`` (:func:`_end`), without Python's
   tear-down of its modules (seconds, uncounted by the run's wall-time line).

Before the first line of bearingdae runs, Python itself is starting (about 20-40 ms): a SIGINT
then is Python's (killed silently before it installs its handler, or its own traceback from
``site``). Library use (``from bearingdae.cli import main`` in a test, a notebook) keeps the
caller's Ctrl-C handling: these handlers are only installed by :func:`main`, and by this
module's import when the process is the program itself (pip's console script ``bearingdae`` or
``python -m bearingdae.cli``). That import is where phase 1 starts: the wrapper still runs a
line of its own (a regular expression on ``sys.argv[0]``) before it calls :func:`main`, and a
SIGINT there showed a traceback (measured under load, 3 ms after the import).
"""

from __future__ import annotations

import signal
import sys

from .interrupts import (INTERRUPTED, _exit_at_once, _flush,  # noqa: F401  (re-exported)
                         _redeliver_lost_ctrl_c, exit_on_ctrl_c, raise_on_ctrl_c)


def _started_as_the_program() -> bool:
    """Whether this process is the ``bearingdae`` program: pip's wrapper script (``bearingdae``,
    ``bearingdae.exe``, ``bearingdae-script.py``) or ``python -m bearingdae.cli``."""
    import os
    import re

    script = os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else ""
    spec = getattr(sys.modules.get("__main__"), "__spec__", None)
    return (re.sub(r"(-script\.pyw?|\.exe)$", "", script) == "bearingdae"
            or getattr(spec, "name", None) == "bearingdae.cli.__main__")


if _started_as_the_program():
    exit_on_ctrl_c()

#: commands whose process holds numpy arrays only (no dask): the program spares xarray's
#: imports of the duck-array libraries and of dask.distributed for them (util/duck_arrays.py)
NUMPY_ONLY = ("run", "static", "plot", "spectrum")


def _command() -> str | None:
    """The command of the program's arguments (its first that is not an option)."""
    return next((a for a in sys.argv[1:] if not a.startswith("-")), None)


def main() -> int:
    exit_on_ctrl_c()
    previous_hook = sys.unraisablehook
    sys.unraisablehook = _redeliver_lost_ctrl_c(previous_hook)
    try:
        from . import execute

        if _command() in NUMPY_ONLY:
            from ..util.duck_arrays import spare_distributed_import, spare_duck_array_imports

            spare_duck_array_imports()
            spare_distributed_import()
        status = execute(None)
    except KeyboardInterrupt:
        # Exit here, before the interrupted frames are released: with a native library
        # interrupted half-way (SUNDIALS, LLVM) their clean-up was measured to crash (SIGSEGV).
        # Everything written so far is complete (atomic writes).
        _exit_at_once(signal.SIGINT, None)
    finally:
        exit_on_ctrl_c()
        sys.unraisablehook = previous_hook
        _flush()
    _end(status)
    return status  # (not reached)


def _end(status) -> None:
    """End the process as the command has left it: the atexit handlers, the output flushed,
    then ``os._exit``. Python's own shut-down after them, tearing down the ~2000 modules of
    numpy, xarray, numba/LLVM and SUNDIALS, took seconds after a run's last line, time the
    run's wall-time line could not count."""
    import atexit
    import os

    atexit._run_exitfuncs()
    _flush()
    os._exit(status if isinstance(status, int) else 1)
