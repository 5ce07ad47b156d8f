"""Work-precision study: error against wall time for IDA, Newmark-β and the scipy peers.

Conventions (SOLVER-NOTES.md, after SciMLBenchmarks and the IVP Test Set):

- **Reference**: IDA at the tightest rtol of its ladder that completes (atol = rtol ·
  ``ATOL_PER_RTOL``, the ratio of the scene defaults), *confirmed* by its agreement with the
  next-tightest completed IDA run (and with the finest run of any ladder marked
  ``confirms_reference``, e.g. Newmark-β at its smallest step). That agreement is recorded as the
  error floor: errors below it are not resolved by the reference.
- **Errors** over the recorded window, the reference interpolated to each run's output times,
  for cage speed, orbit speed, spin speed, skew angle and slice contact force:
  relative RMS ``rms(x - x_ref) / rms(x_ref)`` and relative max ``max|x - x_ref| / max|x_ref|``
  (both over every time and every roller / slice / race), plus
  ``mescd = -log10 max |x - x_ref| / (atol/rtol + |x_ref|)`` over the five quantities in units of
  their unknown scale (contact force in units of the model's force scale), with the fixed
  ratio atol/rtol = ``ATOL_PER_RTOL``.
- **Time**: the integrator's wall time (consistent initialisation and stepping, what
  ``solver_statistics['wall_time_s']`` records; the shared output post-processing is excluded),
  median over ``repeat`` runs after a JIT warm-up of every solver. A scipy peer is stopped after
  ``time_limit_factor`` × the median wall time of IDA at rtol 1e-6 and recorded as failed;
  tighter rungs of that peer are then recorded as skipped.

Adding a ladder (e.g. Newmark-β's step sizes) is one :class:`Ladder` entry in :func:`ladders`.
Failed runs are rows with ``status`` "failed" or "skipped" and their message, never dropped.

The study lives in four modules along its data flow: ``ladders`` (which solver runs at which
tolerances or steps) -> ``runs`` (every rung, the reference chosen and confirmed) -> ``errors``
(metrics against the reference) -> ``report`` (verdict, table, figure, files).
"""

from __future__ import annotations

from .errors import (  # noqa: F401
    error_scales,
    interp_time,
    mescd,
    quantity_errors,
    relative_errors,
    time_at_error,
)
from .ladders import (  # noqa: F401
    ATOL_MAX,
    ATOL_PER_RTOL,
    IDA_RTOLS,
    IDA_TARGET_RTOL,
    NEWMARK_STEPS_S,
    PEER_RTOLS,
    PEERS,
    QUANTITIES,
    QUICK_IDA_RTOLS,
    QUICK_NEWMARK_STEPS_S,
    QUICK_PEER_RTOLS,
    TIME_LIMIT_FACTOR,
    WARMUP_OVERRIDES,
    Ladder,
    ladders,
    naive_ladders,
    tolerance_overrides,
)
from .report import (  # noqa: F401
    BOUNDS,
    COLUMNS,
    RESOLVED_FACTOR,
    SPEEDUP_CLAIM,
    comparison,
    plot,
    table,
    write,
)
from .runs import (  # noqa: F401
    Run,
    Study,
    _execute,
    derive,
    run_ladder,
    study,
    warm_up,
)
