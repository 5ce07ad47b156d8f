"""Work done in a thread while the caller goes on: a cold start's kernels compiled while the
integration runs (results/streamed_record.py; docs/performance.md, "Cold start").

Stage: util (no physics). Why a thread pays there: IDA runs in C (ctypes releases the GIL) and
calls compiled callbacks that never take it, and numba's LLVM work runs in C too, so the
compile and the integration use two CPUs; a kernel the thread has not finished when it is
needed is waited for (:meth:`Background.join`), never compiled twice (numba compiles under one
lock). While the thread runs, Python's thread switch interval is 0.5 ms instead of the default 5 ms: the
integration returns to Python at every output time and would otherwise wait up to 5 ms for
the GIL each time.
"""

from __future__ import annotations

import sys
import threading

#: the thread switch interval while the thread runs [s]
SWITCH_INTERVAL_S = 5e-4


class Background:
    """Calls ``steps`` in a thread once :meth:`start` is called (again: nothing);
    :meth:`join` waits for them (never started: nothing, the kernels compile where first
    called). A step that fails is left to its first real call, which raises there."""

    def __init__(self, *steps):
        self.steps, self.thread = steps, None

    def start(self) -> None:
        if self.steps:
            steps, self.steps = self.steps, ()
            self.thread = threading.Thread(target=self._run, args=steps, daemon=True,
                                           name="bearingdae-compile")
            self.thread.start()

    @staticmethod
    def _run(*steps) -> None:
        from .kernel_cache import quiet

        quiet(True, thread=True)  # the run announced its compiling (run/progress.py)
        interval = sys.getswitchinterval()
        sys.setswitchinterval(min(interval, SWITCH_INTERVAL_S))
        try:
            for step in steps:
                step()
        except Exception:  # noqa: BLE001 - raised again where the kernel is first called
            pass
        finally:
            sys.setswitchinterval(interval)

    def join(self) -> None:
        self.steps = ()
        if self.thread is not None:
            self.thread.join()
            self.thread = None
