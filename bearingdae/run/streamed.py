"""One dynamic run streamed to its NetCDF file as it goes (``bearingdae run``,
``simulate(scene, output=path)``).

What surrounds the run is :func:`bearingdae.api.simulate`'s (solver, model, start state,
progress, until steady, checkpoint); the record goes to a :class:`~bearingdae.results.record.
StreamedRecord` instead of the Solution (``keep_samples=False``), so the memory of a run does
not grow with the recorded length. The guarantees of an in-memory run and its ``save`` hold:
the target appears only complete (a temporary beside it, renamed at the end); a failed or
interrupted run leaves ``<stem>_partial.nc`` with every sample computed (the warm-up's first);
the checkpoint (run/checkpoint.py) holds every sample until the file is written, so a run
killed even by SIGKILL loses nothing computed and leaves no file at the target.
"""

from __future__ import annotations

from pathlib import Path


def partial_target(target: str | Path) -> Path:
    """``TARGET_partial.nc``: where the samples of a failed or interrupted run go."""
    from ..util.atomic import fit_name

    target = Path(target)
    return fit_name(target.with_name(target.stem + "_partial.nc"), "_partial.nc")


def simulate_to_file(scene, target, solver="ida", progress=None, checkpoint=None, *,
                     fallback=None, complevel: int = 4, _options=None):
    """Run ``scene`` and stream its record to ``target`` (NetCDF). Returns a
    :class:`~bearingdae.results.record.StreamedResult` (the path written, summary, attributes)
    whether the run completed or not; raises :class:`bearingdae.api.SimulationError` (with the
    partial file's Dataset) when the run failed and was not asked to return (``simulate``).

    ``fallback(path)``: where a file goes when the target's folder cannot take it (a full
    disk); None: the write error is raised.
    """
    import os

    from ..api import SimulationError, _integrate
    from ..results.record import StreamedRecord
    from ..util.atomic import check_writable

    if not isinstance(target, (str, os.PathLike)):
        raise TypeError(f"simulate: output: expected a file path (str or os.PathLike), got "
                        f"{type(target).__name__}")
    target = check_writable(target)
    sink = StreamedRecord(target, partial_target(target), fallback, complevel)
    options = _options if _options is not None else _no_deprecated()
    model, res, start, extra_attrs, solver = _integrate(
        scene, solver, progress, checkpoint, options, on_sample=_Begun(sink, checkpoint),
        keep_samples=False)
    result = sink.finish(res, extra_attrs, start)
    if _options is not None and not result.success:  # simulate(..., output=): raise as it does
        ds = result.open() if result.path is not None else None
        raise SimulationError(result.message, ds)
    return result


class _Begun:
    """The sink as ``on_sample``, told the model, record start and solver by ``_integrate``."""

    def __init__(self, sink, checkpoint):
        self.sink, self.checkpoint = sink, checkpoint

    def begin(self, model, start, solver):
        self.sink.begin(model, start, solver, self.checkpoint,
                        model.scene.dynamics.until_steady)

    def __call__(self, t, y, yp):
        self.sink(t, y, yp)


def _no_deprecated():
    from ..api import _UNSET

    return (_UNSET, _UNSET, None)
