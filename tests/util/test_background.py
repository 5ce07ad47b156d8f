"""util/background.py: work in a thread, started once, joined before its result is used."""

from __future__ import annotations

import sys
import threading

from bearingdae.util import kernel_cache
from bearingdae.util.background import SWITCH_INTERVAL_S, Background


def test_steps_run_once_in_another_thread_in_order_and_join_waits_for_them():
    gate, seen = threading.Event(), []

    def first():
        gate.wait(10.0)
        seen.append(("first", threading.current_thread() is threading.main_thread(),
                     sys.getswitchinterval(), getattr(kernel_cache._THREAD, "quiet", None)))

    def second():
        seen.append(("second", None, None, None))

    interval = sys.getswitchinterval()
    work = Background(first, second)
    work.start()
    work.start()  # again: nothing more
    assert seen == []  # the first step waits for the gate: the caller went on
    gate.set()
    work.join()
    # in the thread: the short switch interval, the compile notices quiet (the run announced
    # its compiling); this thread's notices untouched
    assert seen == [("first", False, min(interval, SWITCH_INTERVAL_S), True),
                    ("second", None, None, None)]
    assert getattr(kernel_cache._THREAD, "quiet", None) is None
    assert sys.getswitchinterval() == interval  # put back when the thread ended
    work.join()  # again: nothing


def test_never_started_runs_nothing_and_a_failing_step_is_left_to_its_caller():
    seen = []
    work = Background(lambda: seen.append(1))
    work.join()
    work.start()  # after a join: nothing (the caller compiles where it first needs it)
    work.join()
    assert seen == []

    def fails():
        raise RuntimeError("compile failed")

    work = Background(fails, lambda: seen.append(2))
    work.start()
    work.join()  # no exception here; the steps after the failing one are skipped
    assert seen == []
