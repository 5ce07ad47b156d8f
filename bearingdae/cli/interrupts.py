"""Ctrl-C handling of the ``bearingdae`` program, shared by the program (bearingdae/cli/program.py)
and the command line (bearingdae/cli.py): the one-line message, the switch between ending at once
and raising KeyboardInterrupt, and the redelivery of interrupts lost in callbacks.

Stage: a utility below every other module (it imports none of bearingdae), so that cli.py and
program.py both use it without importing each other (program.py runs cli.py's commands).
See bearingdae/cli/program.py for the three phases of the program and why each needs its handling.
"""

from __future__ import annotations

import os
import signal
import sys

INTERRUPTED = "bearingdae: interrupted; no partial output file was left behind"


def _flush() -> None:
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except BrokenPipeError:  # its reader went away (| head): and so Python's own flush at
            try:                 # exit says nothing ("Exception ignored ..."), point it nowhere
                os.dup2(os.open(os.devnull, os.O_WRONLY), stream.fileno())
            except (OSError, ValueError):
                pass
        except Exception:  # a closed or broken stream: nothing more to save
            pass


def _exit_at_once(signum, frame) -> None:
    _flush()
    os.write(2, (INTERRUPTED + "\n").encode())
    os._exit(130)


def exit_on_ctrl_c() -> None:
    """From now on Ctrl-C ends the process at once (one line, status 130), unless the caller
    had its own handler (library use)."""
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        signal.signal(signal.SIGINT, _exit_at_once)


def raise_on_ctrl_c() -> None:
    """Back to KeyboardInterrupt, if :func:`exit_on_ctrl_c` had switched it."""
    if signal.getsignal(signal.SIGINT) is _exit_at_once:
        signal.signal(signal.SIGINT, signal.default_int_handler)


def _redeliver_lost_ctrl_c(previous):
    """sys.unraisablehook: a swallowed KeyboardInterrupt is sent again (SIGINT to this process
    from a helper thread, 20 ms later, when the callback has returned); anything else goes to
    ``previous``."""
    def hook(unraisable):
        if unraisable.exc_type is not None and issubclass(unraisable.exc_type,
                                                          KeyboardInterrupt):
            import threading

            timer = threading.Timer(0.02, os.kill, (os.getpid(), signal.SIGINT))
            timer.daemon = True
            timer.start()
            return
        previous(unraisable)

    return hook
