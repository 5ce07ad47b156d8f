"""Holding Ctrl-C (SIGINT) over a step that must not be cut in two: a NetCDF write (xarray's
file lock), a sample on its way to the record and the checkpoint."""

from __future__ import annotations

import contextlib
import signal
import threading


@contextlib.contextmanager
def ctrl_c_deferred():
    """Hold Ctrl-C (SIGINT) until the block is done, then raise KeyboardInterrupt (nested: the
    outermost raises).

    A KeyboardInterrupt inside xarray's NetCDF write can leave its file lock held; the write's
    own clean-up then waits for that lock forever (measured: 1 of 20 SIGINTs during `bearingdae
    run` hung the process). Only the main thread receives signals, so elsewhere this is a no-op.
    """
    previous = signal.getsignal(signal.SIGINT)
    if threading.current_thread() is not threading.main_thread() or previous in (
            None, signal.SIG_IGN) or getattr(previous, "deferral", False):
        yield  # no Python handler to defer (or Ctrl-C ignored anyway), or held already
        return  # by an enclosing block, which raises when it is done
    caught = []

    def hold(signum, frame):
        caught.append(signum)

    hold.deferral = True
    signal.signal(signal.SIGINT, hold)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
    if caught:
        raise KeyboardInterrupt
