"""What both IDA adapters share: the minimum step, the consistent initialisation and the
validation of the linear solver and Jacobian options.

Stage: solvers. :class:`bearingdae.solvers.ida.IDA` (compiled core) and
:class:`bearingdae.solvers.ida_scikit_sundae.IDAScikitSundae` (cross-check) derive from
:class:`_IDABase`.
"""

from __future__ import annotations

from .base import Solver
from .common import JACOBIANS, check_choice

MIN_STEP_S = 1e-15
#: IDACalcIC's first output time is t_start + this (scikit-sundae's ``calc_init_dt``)
CALC_INIT_DT_S = 1e-7


class _IDABase(Solver):
    """Settings and validation shared by both IDA adapters."""

    LINSOLVERS = ("sparse", "dense")

    def __init__(self, linsolver: str = "sparse", jacobian: str = "analytic"):
        check_choice(linsolver, self.LINSOLVERS, "linsolver")
        check_choice(jacobian, JACOBIANS, "jacobian")
        self.linsolver, self.jacobian = linsolver, jacobian
        self._extra: dict = {}

    def extra_stats(self) -> dict:
        return dict(self._extra)

    @staticmethod
    def _emit_start(t_out, t_start: float, emit, y, yp):
        """Emit the consistent initial state when t_start is an output time; returns the output
        times still to reach."""
        if t_out[0] == t_start:
            emit(t_start, y, yp)
            return t_out[1:]
        return t_out
