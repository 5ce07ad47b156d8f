"""What the second process of a cold start compiles (solvers/sundials/precompile.py starts it
as ``python -c "...aside.child(kind, optional, scene)"``).

Stage: solvers (compiled IDA core), start-up only.
"""

from __future__ import annotations


def child(kind: str, optional: str = "", scene_file: str = "", word: int = -1) -> None:
    """What the second process compiles, in this order (each into numba's cache): the
    block-arrow linear solver's operations and the Jacobian callback ``kind`` (``optional``:
    its variant for the effects compiled apart, a string of 0s and 1s: system/
    optional.pattern_tag), then it says so (precompile.READY into the pipe ``word``: the
    parent's integration can start), then the projection's block-arrow solve
    (projection_kernel.arrow_solve) and, given the run's scene (``scene_file``: pickled by the
    parent; "" for none), the projection of its samples, which the parent's samples wait
    for. The parent compiles the residual, the residual callback and the
    per-step extremes hook meanwhile: the two shares before the word take about as long
    (docs/performance.md, "Cold start")."""
    import os

    from ..projection_kernel import compile_arrow_solve
    from . import callbacks, linsol
    from .precompile import PARENT_LINSOL_OPS, READY

    if not scene_file:  # the parent compiles the projection now: it needs the solve first
        compile_arrow_solve()
    linsol.compile_operations([op for op in linsol.COMPILED_OPS
                               if op not in PARENT_LINSOL_OPS])
    callbacks.compiled(kind, optional)
    if word >= 0:
        os.write(word, READY)
        os.close(word)
    if scene_file:
        import pickle

        from ...system.model import build_model
        from ..algebraic import AlgebraicProjector

        with open(scene_file, "rb") as f:
            scene = pickle.load(f)
        try:  # not left behind if the parent was killed (it removes the file too)
            os.unlink(scene_file)
        except OSError:
            pass
        compile_arrow_solve()
        AlgebraicProjector(build_model(scene)).prepare()
