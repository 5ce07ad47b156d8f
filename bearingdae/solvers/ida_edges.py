"""IDA across sharp defect edges: root finding, and a restart at each crossing
(``numerics.defect_edges = "locate"``; the model's side: system/defect_sides.py).

Stage: solvers (for solvers/ida.py). At the start of an integration the sides of every sharp
edge are set from the initial state and frozen, and IDA gets the compiled root function of
solvers/sundials/roots.py (``IDARootInit``). Between crossings IDA integrates a residual that
is smooth in the state. When ``IDASolve`` stops at a root (``IDA_ROOT_RETURN``: IDA located the
sign change of a gap within its root tolerance, and returned the interpolated state there),
:meth:`EdgeRoots.cross` sets each crossed side from the direction of the crossing (rising:
inside), then restarts IDA there with the projected restart of solvers/ida.py: the algebraic
unknowns solved again by the static Newton (solvers/algebraic.py, which reads the model's
frozen sides), y' of the differential unknowns from the equations of motion, ``IDAReInit`` (a
fresh BDF history, order 1). Then IDA goes on to the same output time. Why not IDACalcIC:
where a spall takes a roller's whole contact away (the sharp roller spall), the algebraic
unknowns jump by the depth, and IDACalcIC's Newton from the old state stalled in the contact's
regularisation (measured: IDA failed right after the outer contact's entry at 3.8 ms; the
static Newton's line search and continuation solve it). Each crossing is recorded
(:attr:`EdgeRoots.crossings`) for the solver's statistics and the tests.
"""

from __future__ import annotations

import time

import numpy as np

from ..system.defect_sides import freeze_sides, roller_state, set_side, thaw_sides
from .sundials.prototypes import EDGE_RESTART_FAILED, IDA_ROOT_RETURN


class EdgeRoots:
    """The root finding of one IDA integration (module docstring)."""

    def __init__(self, model, ses, t_start: float, y0, project):
        from .sundials import roots

        #: ``project(model, ses, tracker, t)``: solvers/ida.py's projected restart
        self.model, self.ses, self.project = model, ses, project
        self.count = freeze_sides(model, t_start, y0)
        ses.init_roots(self.count, roots.compiled().address)
        #: (t [s], roller j, entry of the defect table, contact, +1 entering / -1 leaving, and
        #: roller j's orbit and spin angles [rad] there)
        self.crossings: list[tuple] = []
        self.root_calls = 0  # root-function evaluations, over the restarts
        self.restart_cpu_s = 0.0  # process CPU of the restarts (the projection, IDAReInit)

    def advance(self, solve, tracker, tk: float) -> tuple[int, float]:
        """``solve(tk)`` (IDASolve to tk), restarted at every edge crossing on the way."""
        flag, t = solve(tk)
        while flag == IDA_ROOT_RETURN:
            if not self.cross(tracker, t):
                return EDGE_RESTART_FAILED, t  # (reported as IDA's failures are)
            flag, t = solve(tk)
        return flag, t

    def cross(self, tracker, t: float) -> bool:
        """The crossings at the root IDA returned at t: the sides set, IDA restarted from the
        state there with its algebraic unknowns solved again (module docstring); False when
        the restart failed."""
        c0 = time.process_time()
        ses = self.ses
        found = ses.roots_found()
        th, phi = roller_state(self.model, ses.y)
        for k in np.flatnonzero(found):
            j, e, p = set_side(self.model, int(k), found[k] > 0)
            self.crossings.append((float(t), j, e, p, int(found[k]), float(th[j]),
                                   float(phi[j])))
        self.root_calls += ses.get_long("IDAGetNumGEvals")
        ok = self.project(self.model, ses, tracker, t)
        if ok:
            tracker.restart_times.pop()  # (counted here, not as a corrector-failure restart)
        self.restart_cpu_s += time.process_time() - c0
        return ok

    def finish(self, extra: dict) -> None:
        """The statistics into the solver's ``extra``; the sides from the positions again."""
        self.root_calls += self.ses.get_long("IDAGetNumGEvals")
        extra.update({"edge_crossings": len(self.crossings), "edge_root_functions": self.count,
                      "edge_root_function_calls": self.root_calls,
                      "edge_restart_cpu_s": self.restart_cpu_s})
        thaw_sides(self.model)
