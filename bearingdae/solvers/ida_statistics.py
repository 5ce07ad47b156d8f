"""IDA's statistics over a run: its own counters, banked across projected restarts, and
samples of the step size and order at the output times (stage: solvers, for solvers/ida.py).

IDAReInit (a projected restart) zeroes IDA's counters, so :class:`StatsTracker` adds each
stretch's counts to a bank before it; at the end it writes the totals into the solver's
counters and ``Solution.stats``. The step size and order are sampled once per output time
(approximate: a histogram of the order in use, the smallest last step); ``record_steps``
records every internal step instead.
"""

from __future__ import annotations

import numpy as np


#: IDA's counters that IDAReInit zeroes and :class:`StatsTracker` adds up over restarts
_BANKED = ("IDAGetNumSteps", "IDAGetNumResEvals", "IDAGetNumJacEvals", "IDAGetNumErrTestFails",
           "IDAGetNumNonlinSolvConvFails", "IDAGetNumNonlinSolvIters", "IDAGetNumLinSolvSetups")


class StatsTracker:
    """IDA's own counters, plus per-output-time samples of the step size and order."""

    def __init__(self, ses):
        self.ses = ses
        self.min_last_step = float("inf")
        self.orders: dict[int, int] = {}
        self.steps_s: list[float] = []  # record_steps only
        self.times_s: list[float] = []
        self.limiters: list[int] = []  # record_steps: each step's limiter (Session.limiter)
        self.most_per_output = 0
        self.restart_times: list[float] = []
        #: when the fallback left the algebraic unknowns out of the error test (None: never)
        self.suppressed_from_s: float | None = None
        self.banked: dict[str, int] = {}
        self._last_step = None

    @property
    def restarts(self) -> int:
        return len(self.restart_times)

    def steps_since_restart(self) -> int:
        """Steps IDA accepted since its last (re)initialisation (its own counter)."""
        return self.ses.get_long("IDAGetNumSteps")

    def bank(self) -> None:
        """Add IDA's counters to the banked totals: IDAReInit zeroes them (and the linear
        solver's at its next set-up)."""
        for name in _BANKED:
            self.banked[name] = self.banked.get(name, 0) + self.ses.get_long(name)

    def sample(self) -> None:
        if self._last_step is None:  # the two getters bound once (a sample costs ~2 µs)
            import ctypes as C

            api, mem = self.ses.api, self.ses.mem
            hv, kv = C.c_double(), C.c_int()
            hp, kp = C.byref(hv), C.byref(kv)
            self._last_step = (lambda: (api.IDAGetLastStep(mem, hp), hv.value)[1],
                               lambda: (api.IDAGetLastOrder(mem, kp), kv.value)[1])
        h = self._last_step[0]()
        if h > 0 and h < self.min_last_step:
            self.min_last_step = h
        k = self._last_step[1]()
        self.orders[k] = self.orders.get(k, 0) + 1

    def finish(self, counters, extra: dict, jacobian: str, model) -> None:
        from .sundials.callbacks import S_JFAIL, S_RFAIL

        def g(name):
            return self.ses.get_long(name) + self.banked.get(name, 0)
        counters.steps = g("IDAGetNumSteps")
        counters.residual_calls = g("IDAGetNumResEvals")
        counters.jacobian_calls = g("IDAGetNumJacEvals")
        if jacobian == "fd":
            counters.residual_calls_in_jacobian = counters.jacobian_calls * (
                model.layout.n_local + model.layout.n_global + 1)
        counters.error_test_failures = g("IDAGetNumErrTestFails")
        counters.nonlinear_convergence_failures = g("IDAGetNumNonlinSolvConvFails")
        extra.update({
            "nonlinear_iterations": g("IDAGetNumNonlinSolvIters"),
            "linear_solver_setups": g("IDAGetNumLinSolvSetups"),
            "last_step_s": self.ses.get_double("IDAGetLastStep"),
            "current_step_s": self.ses.get_double("IDAGetCurrentStep"),
            "last_order": self.ses.get_int("IDAGetLastOrder"),
            "current_order": self.ses.get_int("IDAGetCurrentOrder"),
            "smallest_last_step_at_outputs_s": (self.min_last_step
                                                if self.min_last_step < float("inf") else None),
            "order_at_outputs": {str(k): v for k, v in sorted(self.orders.items())},
            "sundials_version": self.ses.api.build.version,
            "nonfinite_residuals": int(self.ses.user_data[S_RFAIL]),
            "nonfinite_jacobians": int(self.ses.user_data[S_JFAIL]),
            "restarts": self.restarts,
            "restart_times_s": list(self.restart_times),
            # 1 if the fallback left the algebraic unknowns out of the error test (its time is
            # the first of restart_times_s); a sum over the blocks of an until-steady run
            "algebraic_error_test_fallbacks": int(self.suppressed_from_s is not None),
        })
        if self.steps_s:
            h = np.array(self.steps_s)
            i = int(np.argmin(h))
            extra.update({"smallest_step_s": float(h[i]),
                          "smallest_step_at_s": float(self.times_s[i]),
                          "median_step_s": float(np.median(h)),
                          "max_steps_per_output": self.most_per_output,
                          "step_limiters": limiter_counts(self.limiters, model.layout)})


def limiter_counts(limiters, layout) -> dict:
    """{unknown name: number of steps it limited} (most first), a roller's unknowns summed over
    the rollers, from the compact indices ``limiters`` (Session.limiter) of ``layout``."""
    names = list(layout.local_names) * layout.rollers + list(layout.global_names)
    counts: dict[str, int] = {}
    for i in limiters:
        counts[names[i]] = counts.get(names[i], 0) + 1
    return dict(sorted(counts.items(), key=lambda kv: -kv[1]))
