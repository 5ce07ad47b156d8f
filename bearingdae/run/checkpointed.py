"""Any solver of the contract with checkpoints: :class:`Checkpointed` (``bearingdae run``,
``simulate(..., checkpoint=...)``).

The checkpoint file itself, its fingerprint and its checks are run/checkpoint.py; this module
is the solver that rides on it: each sample of the inner run goes to the checkpoint, a resumed
run hands the held samples on first and continues from the last, and the counters of all
segments are summed.
"""

from __future__ import annotations

import json
from dataclasses import asdict

from ..solvers.base import Solver
from ..util.atomic import shown_path
from .checkpoint import Checkpoint, CheckpointError, fingerprint


class Checkpointed(Solver):
    """Any :class:`~bearingdae.solvers.base.Solver` with checkpoints: ``Checkpointed(IDA(),
    Checkpoint(path, resume=True))``.

    Every sample of the inner run goes to ``checkpoint.sample`` (``on_sample`` of the inner
    solver), which writes the file as it goes; the file is written once more when the run stops.
    With ``checkpoint.resume`` and a checkpoint of the same run (fingerprint) on disk, its
    samples are handed on first and the inner solver continues from the last one
    (``t_start``). Counters of all segments are summed; ``resumed_from_s`` and ``segments``
    say that the run was resumed.
    """

    def __init__(self, solver: Solver, checkpoint: Checkpoint):
        if not isinstance(solver, Solver):
            raise TypeError(f"solver: expected a bearingdae Solver, got {type(solver).__name__}")
        if not isinstance(checkpoint, Checkpoint):
            raise TypeError(f"checkpoint: expected a Checkpoint, got "
                            f"{type(checkpoint).__name__}")
        self.solver, self.checkpoint = solver, checkpoint
        self._extra: dict = {}

    @property
    def name(self) -> str:  # type: ignore[override]
        return self.solver.name

    @property
    def locates_edges(self) -> bool:  # type: ignore[override]
        return self.solver.locates_edges  # the inner solver's root finding does it

    def describe(self) -> dict:
        d = dict(self.solver.describe())
        d["solver_description"] = d["solver_description"] + " (checkpointed)"
        return d

    def dataset_attrs(self, model, solution) -> dict:
        return self.solver.dataset_attrs(model, solution)

    def extra_stats(self) -> dict:
        return dict(self._extra)

    def error_estimate(self, n_samples: int):
        if self.checkpoint.resumed_from_s is not None:
            return None  # the earlier segment's estimates were not kept
        return self.solver.error_estimate(n_samples)

    def _run(self, model, y0, yp0, t_out, t_start, emit):
        ck = self.checkpoint
        d = self.solver.describe()
        held = ck.begin(fingerprint(model.scene, t_out, d["solver"],
                                    json.dumps(d["options"], sort_keys=True, default=str)),
                        model.size, t_out, model.scene.input_files())
        before = dict(ck.stats)
        if ck.held_steps is not None and self._extremes_from is not None:
            from ..system.extremes import Extremes

            size = Extremes(model.layout.rollers, model.geometry.slices, 0.0).maxima().size
            if ck.held_steps[0].size != size:
                raise CheckpointError(f"checkpoint '{shown_path(ck.path)}' is damaged (step "
                                      f"extremes of size {ck.held_steps[0].size}, expected "
                                      f"{size}); delete it to start afresh")
        self._extra = {}
        start, y_start, yp_start = t_start, y0, yp0
        for t, y, yp in held:
            emit(t, y, yp)
        if held:
            start, y_start, yp_start = held.last
        rest = t_out[t_out > start] if held else t_out

        # the inner solver's step extremes: each sample's interval peaks and the maxima
        ck.extremes = lambda: getattr(self.solver, "_extremes", None)

        def hook(t, y, yp):
            try:
                emit(t, y, yp)
            finally:  # keep the sample in the checkpoint even when Ctrl-C lands in progress
                ck.sample(t, y, yp)

        res = None
        try:
            if rest.size == 0:  # the checkpoint already holds the whole run
                return True, "completed", None
            res = self.solver.integrate(model, y_start, yp_start, rest, t_start=start,
                                        on_sample=hook, extremes_from=self._extremes_from,
                                        keep_samples=self._keep_samples)
            self._extremes = res.extremes
            if res.extremes is not None and held:
                if ck.held_steps is not None:  # the part before: its steps, as kept
                    res.extremes.absorb(*ck.held_steps)
                else:  # a checkpoint without them: the part before from its samples
                    res.extremes.steps_from = max(res.extremes.t_from, start)
            return res.success, res.message, res.failure_time_s
        finally:
            merged = _merge_stats(before, res.stats if res is not None else {})
            ck.stats = merged
            ck.write()
            for key in asdict(self.counters):
                setattr(self.counters, key, int(merged.get(key, 0)))
            self._extra = {k: v for k, v in merged.items()
                           if k not in asdict(self.counters)
                           and k not in ("output_samples", "wall_time_s")}
            if "wall_time_s" in merged:
                self._extra["wall_time_s_all_segments"] = merged["wall_time_s"]
            if ck.resumed_from_s is not None:
                self._extra["resumed_from_s"] = ck.resumed_from_s


def _merge_stats(before: dict, now: dict) -> dict:
    """Counters of the segments of a resumed run, summed."""
    out = {**before, **now}
    for key, value in before.items():
        if key in now and isinstance(value, (int, float)) and isinstance(now[key], (int, float)) \
                and not isinstance(value, bool):
            out[key] = now[key] + value
    if before:
        out["segments"] = int(before.get("segments", 1)) + 1
    return out
