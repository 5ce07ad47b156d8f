"""IDA across sharp defect edges: root finding, and a restart at each crossing
(``numerics.defect_edges = "locate"``; the model's side: system/defect_sides.py).

Stage: solvers (for solvers/ida.py). At the start of an integration the sides of every sharp
edge are set from the initial state and frozen, and IDA gets the compiled root function of
solvers/sundials/roots.py (``IDARootInit``). Between crossings IDA integrates a residual that
is smooth in the state. When ``IDASolve`` stops at a root (``IDA_ROOT_RETURN``: IDA located the
sign change of a gap within its root tolerance, and returned the interpolated state there),
:meth:`EdgeRoots.cross` sets each crossed side from the direction of the crossing (rising:
inside), then restarts IDA there: ``IDAReInit`` (a fresh BDF history, order 1) and
``IDACalcIC`` (the algebraic unknowns and the differential y' consistent with the jump of the
residual); should that fail, the projected restart of solvers/ida.py. Then IDA goes on to the
same output time. Each crossing is recorded (:attr:`EdgeRoots.crossings`) for the solver's
statistics and the tests.
"""

from __future__ import annotations

import numpy as np

from ..system.defect_sides import freeze_sides, set_side, thaw_sides
from .ida_base import CALC_INIT_DT_S
from .sundials.prototypes import IDA_ROOT_RETURN


class EdgeCrossingError(RuntimeError):
    """IDA could not be restarted after a sharp edge's crossing."""


class EdgeRoots:
    """The root finding of one IDA integration (module docstring)."""

    def __init__(self, model, ses, t_start: float, y0, extremes, project):
        from .sundials import roots

        #: ``project(model, ses, tracker, t)``: solvers/ida.py's projected restart
        self.model, self.ses, self.extremes, self.project = model, ses, extremes, project
        self.count = freeze_sides(model, t_start, y0)
        ses.init_roots(self.count, roots.compiled().address)
        #: (t [s], roller, entry of the defect table, contact, +1 entering / -1 leaving)
        self.crossings: list[tuple[float, int, int, int, int]] = []
        self.root_calls = 0  # root-function evaluations, over the restarts
        self.projected = 0  # restarts whose IDACalcIC failed and the projection made consistent

    def advance(self, solve, tracker, tk: float) -> tuple[int, float]:
        """``solve(tk)`` (IDASolve to tk), restarted at every edge crossing on the way."""
        flag, t = solve(tk)
        while flag == IDA_ROOT_RETURN:
            self.cross(tracker, t)
            flag, t = solve(tk)
        return flag, t

    def cross(self, tracker, t: float) -> None:
        """The crossings at the root IDA returned at t: the sides set, IDA restarted."""
        from ..system.extremes import H_ARMED

        ses = self.ses
        found = ses.roots_found()
        for k in np.flatnonzero(found):
            j, e, p = set_side(self.model, int(k), found[k] > 0)
            self.crossings.append((float(t), j, e, p, int(found[k])))
        self.root_calls += ses.get_long("IDAGetNumGEvals")
        tracker.bank()
        ses.restart(t, ses.y.copy(), ses.yp.copy())
        armed = self.extremes is not None and self.extremes.buffer[H_ARMED] > 0.5
        if armed:  # the initialisation's iterates are not states (Session.track_extremes)
            self.extremes.buffer[H_ARMED] = 0.0
        flag = ses.calc_ic(t + CALC_INIT_DT_S)
        if flag < 0:
            if not self.project(self.model, ses, tracker, t):
                raise EdgeCrossingError(
                    f"IDA could not be restarted after a sharp defect edge at t = {t:.6g} s "
                    "(numerics.defect_edges = 'locate'); 'smooth' ramps the edge instead")
            tracker.restart_times.pop()  # (counted here, not as a corrector-failure restart)
            self.projected += 1
        if armed:
            self.extremes.buffer[H_ARMED] = 1.0

    def finish(self, extra: dict) -> None:
        """The statistics into the solver's ``extra``; the sides from the positions again."""
        self.root_calls += self.ses.get_long("IDAGetNumGEvals")
        extra.update({"edge_crossings": len(self.crossings), "edge_root_functions": self.count,
                      "edge_root_function_calls": self.root_calls,
                      "edge_restarts_projected": self.projected})
        thaw_sides(self.model)
