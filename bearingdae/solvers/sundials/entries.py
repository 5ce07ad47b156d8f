"""The addresses of the kernels the compiled callbacks call through their addresses
(solvers/native_call.py), for the ``user_data`` slots of callbacks.py.

Stage: solvers (compiled IDA core), start-up only. Each entry compiles its kernel for the
argument types the callback gives it, or loads it from numba's cache: the work tuple's arrays
as the callbacks rebuild them (``callbacks._work``: C-contiguous, writable), the marker as
``model.data`` holds it.
"""

from __future__ import annotations

import numpy as np

from ...system.extremes import update_extremes
from ...system.jacobian_analytic import fill_jacobian_analytic
from ...system.residual import residual
from ..native_call import entry
from .callbacks import JD_ANALYTIC, MODEL_WORK_INT, MODEL_WORK_NDIM, S_FILL, S_RESIDUAL


def kernel_entries(marker, jd) -> dict:
    """{slot: (address, key)} of the kernels the callbacks call through their addresses, for a
    work tuple whose marker is ``marker`` (system/optional.py; a defect table) and the
    Jacobian work tuple ``jd``: the residual, and the analytic Jacobian's fill when ``jd`` is
    its."""
    d = tuple(np.empty((0,) * nd, np.int64 if i in MODEL_WORK_INT else np.float64)
              for i, nd in enumerate(MODEL_WORK_NDIM))
    d += (np.empty((0, 0)) if isinstance(marker, np.ndarray) else marker,)
    v = np.empty(0)
    out = {S_RESIDUAL: entry(residual, 0.0, v, v, v, d)}
    if len(jd) == len(JD_ANALYTIC):
        out[S_FILL] = entry(fill_jacobian_analytic, 0.0, v, v, 0.0, d, jd)
    return out


def extremes_entry() -> tuple[int, int]:
    """(address, key) of update_extremes as the per-step hook calls it (slot S_EXTREMES)."""
    f1, f2, f3 = (np.empty((0,) * k) for k in (1, 2, 3))
    return entry(update_extremes, 0.0, f1, f1, np.empty(0, np.int64), f3, f3, f2, f1)
