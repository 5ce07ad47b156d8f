"""What the second process of a cold start compiles (solvers/sundials/precompile.py starts it
as ``python -c "...aside.child(kind, optional)"``).

Stage: solvers (compiled IDA core), start-up only.
"""

from __future__ import annotations


def child(kind: str, optional: str = "") -> None:
    """What the second process compiles, in this order (each into numba's cache): the
    projection's block-arrow solve (projection_kernel.arrow_solve, needed by the projection
    the parent compiles meanwhile), the block-arrow linear solver's operations and the
    Jacobian callback ``kind`` (``optional``: its variant for the effects compiled apart, a
    string of 0s and 1s: system/optional.pattern_tag). The parent compiles the residual, the
    projection of the samples, the residual callback and the per-step extremes hook, then
    waits for this process and loads the rest from the cache: the two shares take about as
    long (docs/performance.md, "Cold start")."""
    from ..projection_kernel import compile_arrow_solve
    from . import callbacks, linsol

    compile_arrow_solve()
    linsol.compile_operations()
    callbacks.compiled(kind, optional)
