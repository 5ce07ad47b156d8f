"""A dynamic run's record streamed to NetCDF while it is computed: memory bounded by a block.

Pipeline: solvers -> **results** (the streamed form of results/solution.py's
``from_solution``). :class:`StreamedRecord` is the solver's ``on_sample`` hook: the samples of
the recorded window are gathered into blocks (:func:`~.streamed_netcdf.block_length`), and
each block is projected onto the algebraic equations and labelled by the same functions as an
in-memory run (``project_samples``, ``samples_dataset``: each sample depends on itself only, so
the variables are the same bit for bit), appended to the file (results/streamed_netcdf.py) and
folded into the running reductions (results/running_reductions.py). Memory then holds one
block, the warm-up's samples (the partial file of a failed run keeps them, as before) and 8
bytes per sample for each statistics series.

:meth:`StreamedRecord.finish` writes what is known at the end only — the extremes over the
record (``<variable>_max``), the solver's attributes and statistics, the error bars, the
rating life, the plausibility findings — and renames the file onto its target (a failed run:
the partial target, with the warm-up's samples first). A block that cannot be written (a full
disk) moves the file to the fallback path, with the blocks written so far.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from ..solvers.sundials import precompile
from ..system.layout import LOCAL
from .streamed_netcdf import StreamWriter, block_length, writable_precision


#: the variables the overview figure draws (plots/plotting.py)
FIGURE_VARIABLES = ("cage_speed", "orbit_speed", "skew_angle", "contact_force", "cage_force",
                    "ring_displacement", "ring_acceleration", "flange_force",
                    "flange_friction_power")
#: up to this many recorded samples the figure's variables stay in memory (~0.4 MB per 100
#: samples on the baseline), so that a short run's figure does not read the file back
FIGURE_IN_MEMORY_SAMPLES = 1024


@dataclass
class StreamedResult:
    """What a streamed run wrote and what its summary needs (the record is in the file)."""

    path: Path | None  #: the file written (target, partial or fallback); None: nothing
    success: bool
    message: str
    attrs: dict
    summary: dict  #: analysis.summary.summary's quantities
    engineering: list  #: analysis.engineering.summary_lines
    digest: xr.Dataset  #: time, cage speed, the extremes and the attributes (small)
    samples: int = 0
    problems: list = field(default_factory=list)  #: one line per write failure
    #: the overview figure's variables of a short record (None: read them from the file)
    figure: xr.Dataset | None = None
    #: partial files of an earlier, incomplete run of the target, removed on completion
    superseded: list = field(default_factory=list)

    def open(self) -> xr.Dataset:
        """The result file as a lazily loaded Dataset (``ds.close()`` when done)."""
        from .streamed_netcdf import open_streamed

        return open_streamed(self.path)


class StreamedRecord:
    """``on_sample`` hook of a streamed run; :meth:`begin` before the run, :meth:`finish`
    after. ``target``/``partial``: where a completed/failed run's file goes; ``fallback``:
    a function giving the path a file goes to when its folder cannot take it (None: raise)."""

    def __init__(self, target, partial, fallback=None, complevel: int = 4):
        self.target, self.partial = Path(target), Path(partial)
        self.fallback, self.complevel = fallback, complevel
        self.problems: list[str] = []

    def begin(self, model, start: float, solver, checkpoint=None, until_steady=False) -> None:
        from ..scene import OUTPUT_VARIABLES
        from ..physics.film import compile_kernel as compile_film
        from ..solvers.algebraic import AlgebraicProjector
        from .extremes import extreme_names
        from .running_reductions import Running, quantities_of

        self.model, self.solver = model, solver
        # until steady: only the record's samples come here, and it starts where they do
        self.start = -np.inf if until_steady else float(start)
        dyn = model.scene.dynamics
        n = round(dyn.cage_revolutions * dyn.samples_per_cage_revolution) + 1  # the record's
        self.block = block_length(n)  # samples (api.output_times)
        self.project = AlgebraicProjector(model)
        # compiled now, under the compile notice, so that no block compiles; on a cold start
        # with a second process, that process compiles it while the integration starts, and
        # the samples wait for it (__call__; solvers/sundials/precompile.py)
        self.projection_aside = precompile.projection_pending()
        self.pending: list = []  # samples that came while the second process compiled it
        if not self.projection_aside:
            self.project.prepare()
        compile_film()
        # xarray imports the duck-array modules it checks for (dask.array, pint, ...: ~1 s,
        # 5 s on a busy machine) at its first Variable, which stalled the first block
        from xarray.namedarray.pycompat import array_type

        for module in ("dask", "pint", "sparse", "cupy"):
            array_type(module)
        import netCDF4  # noqa: F401
        wanted = self.wanted = model.scene.output_variables or tuple(OUTPUT_VARIABLES)
        self.names = extreme_names(model, wanted)
        self.block_checks = ["edge_loading", "film_parameter"] + [
            c for c, v in (("contact_pressure", "contact_pressure_max"),
                           ("skew_vs_pocket", "skew_angle_max")) if v not in self.names]

        self.checkpoint = checkpoint

        def cut():  # samples before it count for the extremes (a resumed run's replay when
            resumed = self._sampled_until()  # its checkpoint kept no step extremes)
            return max(self.start, -np.inf if resumed is None else resumed)

        self._running = lambda: Running(model, quantities_of(self.names), cut,
                                        self.block_checks)
        self.running = self._running()
        self.writer = self._writer(self.target)
        self.iterations, self.error = 0, None
        self.warm_t, self.warm_y, self.t, self.y = [], [], [], []
        # a dynamic ring's acceleration is filtered over each sample's neighbours and the
        # solver's taps (analysis/vibration.py): a block's last samples wait for the next
        # block (:meth:`_held`), and the sample before a block is kept
        self.hold = bool(model.layout.ring_dynamic)
        self.before = None
        # the overview's variables of each block when the record is short; a long record's
        # figure reads the file
        self.figure = [] if n <= FIGURE_IN_MEMORY_SAMPLES else None

    def _sampled_until(self) -> float | None:
        return getattr(self.checkpoint, "sampled_until_s", None)

    def _writer(self, target: Path) -> StreamWriter:
        return StreamWriter(target, self.block, self.complevel,
                            writable_precision(self.model.scene))

    # -- samples ---------------------------------------------------------------------------
    def __call__(self, t: float, y: np.ndarray, yp: np.ndarray) -> None:
        if self.projection_aside:
            # the second process still compiles the projection: the samples wait for it
            # (a dynamic ring's blocks read the solver's taps as they come: they wait at
            # their first block instead), then go through in order, as they would have
            if not self.hold and precompile.projection_compiling():
                self.pending.append((t, y))
                return
            self._projection_ready()
        self._take(t, y)

    def _projection_ready(self) -> None:
        """Load the projection the second process compiled (or compile it here if that
        failed), then take the samples that waited for it."""
        precompile.wait_projection()
        self.project.prepare()
        self.projection_aside = False
        pending, self.pending = self.pending, []
        for t, y in pending:
            self._take(t, y)

    def _take(self, t: float, y: np.ndarray) -> None:
        if self.error is not None:  # a projection failed: the record ends before it
            return
        if t < self.start - 1e-12:
            self.warm_t.append(float(t)), self.warm_y.append(y)
            return
        self.t.append(float(t)), self.y.append(y)
        if len(self.t) >= self.block:
            self.flush()

    def flush(self, final: bool = False) -> None:
        """Project, write and fold in the samples gathered so far; Ctrl-C waits until the
        block is handed to the file's writer and in the running reductions (a block half done
        would be lost from the partial file, or counted in one and not the other). The writer
        compresses and writes it in the background while the run goes on; :meth:`finish`
        waits for it. ``final``: the record's last samples (none is held back for the
        next block)."""
        from .netcdf import _ctrl_c_deferred

        hold = self._held()
        if self.hold and not final and len(self.t) <= hold:
            return
        if self.t:
            with _ctrl_c_deferred():
                t, Y = np.array(self.t), np.array(self.y)
                self.t, self.y = [], []
                after = None
                if self.hold:
                    if self.before is None and self.warm_t:
                        self.before = (self.warm_t[-1], self.warm_y[-1])
                    if not final:  # the last ones wait for the taps past them
                        after = (t[-hold], Y[-hold])
                        self.t, self.y = [float(x) for x in t[-hold:]], list(Y[-hold:])
                        t, Y = t[:-hold], Y[:-hold]
                # the projection evaluates the kernel in its work arrays, from which the
                # solver's per-step extremes read the loads of the step that crossed the last
                # sample time (IDA folds it at its next step, system/extremes.py): they are
                # put back as the solver left them
                saved = [a.copy() for a in self.model.work]
                try:
                    before, self.before = self.before, (t[-1], Y[-1])
                    self._block(t, Y, self.running, "writer", before, after)
                    taps = self.model.ring_taps
                    if taps is not None and t.size > 1:  # what the held samples still need
                        from ..system.taps import TAIL_INTERVALS

                        taps.drop_before(t[-1] - (TAIL_INTERVALS + 2) * (t[-1] - t[-2]))
                finally:
                    for a, b in zip(self.model.work, saved):
                        a[...] = b

    def _held(self) -> int:
        """Samples a dynamic ring's block keeps back for the next: the filter reads the taps
        this many sample intervals past each sample (system/taps.py), and the triangle its
        next sample."""
        if not self.hold:
            return 0
        from ..system.taps import TAIL_INTERVALS

        return TAIL_INTERVALS + 1 if self.model.ring_taps is not None else 1

    def _block(self, t, Y, running, which: str, before=None, after=None) -> None:
        from ..system.defect_sides import positional_sides
        from .solution import project_samples, samples_dataset

        if self.projection_aside:  # a dynamic ring's first block (no sample waits)
            self._projection_ready()
        n = t.size
        with positional_sides(self.model):  # (sharp defect edges: each sample's own side)
            t, Yp, diag, its, error = project_samples(self.model, self.project, t, Y)
            self.iterations += its
            if error is not None:
                self.error = error
            if t.size == 0:
                return
            ds, full = samples_dataset(self.model, t, Yp, diag,
                                       {"record_start_s": self.start}, before,
                                       after if t.size == n else None)
        running.add(ds, t, full[0][..., LOCAL.index("skew_angle")], diag)
        if which == "writer" and self.figure is not None:
            # (dropping the others keeps the coordinates, time too, whatever is kept)
            self.figure.append(ds.drop_vars([n for n in ds.data_vars
                                             if n not in FIGURE_VARIABLES]))
        self._append(which, ds)

    def _append(self, which: str, ds: xr.Dataset) -> None:
        self._guarded(which, lambda writer: writer.append(ds))

    def _settle(self, which: str) -> None:
        """Wait for the block the writer has in flight (results/streamed_netcdf.py), through the
        same fallback as a write: its failure is the failure of a write."""
        self._guarded(which, lambda writer: writer.settle())

    def _guarded(self, which: str, action) -> None:
        """``action(writer)``; if the disk refuses it, move the file with what it holds to the
        fallback folder and write the blocks it lacks there."""
        writer = getattr(self, which)
        try:
            action(writer)
            return
        except (OSError, RuntimeError) as exc:  # RuntimeError: netCDF4's own errors
            if self.fallback is None or writer.target.parent == self._fallback_dir():
                writer.abandon()
                raise
            from ..util.atomic import write_failure

            self.problems.append(write_failure(exc, self.target))
        moved = self._writer(self.fallback(writer.target))
        try:
            writer.close()
            if writer.samples:  # what the folder took so far goes with it
                moved.append_file(writer.tmp)
        except Exception as exc:  # noqa: BLE001 - unreadable after the failure: say so
            self.problems.append(f"the {writer.samples} samples written before could not be "
                                 f"moved ({type(exc).__name__}: {exc})")
        unwritten = writer.unwritten  # the block that failed and any after it, in order
        writer.abandon()
        setattr(self, which, moved)
        for ds in unwritten:
            moved.append(ds)

    def _fallback_dir(self) -> Path:
        return self.fallback(self.target).parent

    # -- the end ---------------------------------------------------------------------------
    def finish(self, solution, extra_attrs: dict, start: float) -> StreamedResult:
        """Write the end-of-run variables and attributes and move the file onto the target
        (completed) or the partial target (failed or interrupted); warns the plausibility
        findings as an in-memory run does."""
        res = solution
        if not np.isfinite(self.start):
            self.start = float(start)
        if self.projection_aside:  # the samples that waited for it go first, in order
            self._projection_ready()
        self.flush(final=True)
        self._settle("writer")  # the last block written (or moved to the fallback)
        failed = not res.success or self.error is not None
        running, writer = self.running, self.writer
        if failed and not self.warm_t and writer.samples == 0 and res.t.size and \
                not running.samples:  # failed in an until-steady warm-up: its samples
            self.warm_t, self.warm_y = list(map(float, res.t)), list(res.y)
        if failed and self.warm_t:  # a partial file keeps the warm-up's samples first
            self.warm, warm_running = self._writer(writer.target), self._running()
            error, self.error = self.error, None
            t, Y = np.array(self.warm_t), np.array(self.warm_y)
            for a in range(0, t.size, self.block):
                self._block(t[a:a + self.block], Y[a:a + self.block], warm_running, "warm")
            self._settle("warm")
            self.error = self.error or error
            if writer.samples:
                writer.close()
                self.warm.append_file(writer.tmp)
            writer.abandon()
            running, writer = warm_running.then(running), self.warm
        self.warm_t = self.warm_y = []
        target = self.partial if failed else self.target
        if writer.target.parent != self.target.parent:
            target = self.fallback(target)
        attrs, extra, digest = self._end(res, running, extra_attrs, failed)
        message = res.message if not res.success else (self.error or res.message)
        if running.samples == 0:
            writer.abandon()
            return StreamedResult(None, not failed, message, attrs, {}, [], digest, 0,
                                  self.problems)
        try:
            path = writer.finish(attrs, extra)
            if path != target:
                import os

                os.replace(path, target)
                path = target
        except (OSError, RuntimeError) as exc:
            from ..util.atomic import write_failure

            writer.abandon()
            self.problems.append(write_failure(exc, target))
            path = None
        figure = None
        if self.figure and not (failed and running is not self.running):  # no warm-up first
            figure = xr.concat(self.figure, "time", coords="minimal", compat="override",
                               join="override").assign_attrs(attrs)
            # the run's values without time: epicyclic speed, record start, the
            # characteristic frequencies the spectrum panel marks (over frequency_name)
            figure = figure.assign({n: v for n, v in digest.data_vars.items()
                                    if "time" not in v.dims})
        from ..analysis.result_variables import flat

        return StreamedResult(path, not failed, message, attrs, running.summary(digest),
                              running.engineering_lines(flat(digest)), digest, running.samples,
                              self.problems, figure)

    def _end(self, res, running, extra_attrs: dict, failed: bool):
        """(global attributes, end-of-run variables, digest) of the record."""
        from .dataset import dynamic_attrs
        from ..analysis.engineering import summed_life_attrs
        from .extremes import WARM_UP, finish_extremes, peak_variables
        from .running_reductions import SAMPLED_PEAKS
        from ..analysis.guards import record_findings, run_checks, worst_findings
        from .solution import error_estimate_variables, solver_attrs
        from ..analysis.statistics import peak_statistics, series_statistics, statistics_attrs

        model = self.model
        info = solver_attrs(model, res, self.solver, self.start, self.iterations,
                            self.project.fallbacks)
        attrs = dynamic_attrs(model, info, summed_life_attrs(
            model, running.life, running.samples, running.ring_sum)
            if running.life is not None else {})
        variables, ext_attrs = {}, {}
        if self.names and running.samples:
            pairs = running.sample_pairs(res.extremes is not None)
            # early samples: a resume's replay without step extremes, or (a failed run's
            # partial file) the warm-up before the window
            why = None if self._sampled_until() is not None else WARM_UP
            variables, ext_attrs = finish_extremes(model, self.names, pairs, res.extremes,
                                                   running.any_early, why)
        attrs.update(ext_attrs)
        attrs.update(extra_attrs)
        times = running.time_values()
        # the peak traces: from the solver's intervals, known in full at the end only
        series = running.series_values()
        peaks = peak_variables(model, times, res.extremes, self.wanted,
                               series.pop(SAMPLED_PEAKS, np.empty((0, 0))))
        coords = {"time": ("time", times)}
        if running.last_block is not None:  # roller numbers, labels (for messages)
            coords.update({n: c.variable for n, c in running.last_block.coords.items()
                           if "time" not in c.dims})
        digest = xr.Dataset({**variables, **peaks}, coords=coords)
        if "mean_cage_speed_rad_s" in series:
            digest["cage_speed"] = ("time", series["mean_cage_speed_rad_s"])
        digest.attrs.update(attrs)
        if (model.layout.whirl and "cage_center_x_m" in series
                and "mean_cage_speed_rad_s" in series and running.samples):
            from ..analysis.whirl import whirl_attrs

            attrs.update(whirl_attrs(model, times, np.stack(
                [series["cage_center_x_m"], series["cage_center_y_m"]], axis=-1),
                series["mean_cage_speed_rad_s"]))
        if running.samples:
            epicyclic = float(attrs.get("epicyclic_cage_speed_rad_s", np.nan))
            estimates = series_statistics(series, epicyclic)
            estimates.update(peak_statistics(digest, epicyclic))
            attrs.update(statistics_attrs(digest, estimates))
        ran, found = set(running.ran), list(running.found)
        r, f = run_checks(digest, model.scene, ("scene_units", "cage_slip", "defect_sampling"))
        ran |= set(r)
        found = worst_findings(found, f)
        at_end = [c for c in ("contact_pressure", "skew_vs_pocket")
                  if c not in self.block_checks]
        if at_end and running.last_block is not None:  # judged on the extremes
            r, f = run_checks(running.last_block.assign(variables), model.scene, at_end)
            ran |= set(r)
            found = worst_findings(found, f)
        record_findings(attrs, ran, found)
        # the results as variables, the metadata as attributes (analysis/result_variables.py)
        from ..analysis.result_variables import split_results

        results, attrs = split_results(attrs)
        digest = digest.assign(results)
        digest.attrs = dict(attrs)
        extra = xr.Dataset({**variables, **peaks, **results})
        if getattr(model, "thermal", None) is not None:  # results/thermal_variables.py
            from .thermal_variables import thermal_variables

            from ..analysis.rating_life import mean_speed_rpm

            speed = (mean_speed_rpm(running.ring_sum, running.samples) if running.samples
                     else None)  # the life's speed: one κ (analysis/rating_life.py)
            extra = extra.assign(thermal_variables(model, model.scene.output_variables, speed))
            for name, var in extra.data_vars.items():  # CF 6.1: the label it is on
                if "thermal_node" in var.dims:
                    var.encoding["coordinates"] = "thermal_node"
        if res.error_estimate is not None and running.samples:
            E = res.error_estimate[-running.samples:] if not failed else res.error_estimate
            extra = extra.assign(error_estimate_variables(model, E))
        if "time" in extra.dims:
            extra = extra.assign_coords(time=("time", times))
        return attrs, _with_label_coordinates(extra, running.last_block), digest


def _with_label_coordinates(extra: xr.Dataset, block) -> xr.Dataset:
    """``extra``'s variables with the ``coordinates`` attribute save() gives them: xarray's
    own choice (the non-index coordinates on a subset of their dimensions) plus the label
    coordinates (results/netcdf.py), without writing those coordinates again."""
    if block is None or not extra.data_vars:
        return extra
    aux = [c for c in block.coords if c not in block.dims]
    labels = {d for src in (block, extra) for d in src.dims if d in src.variables
              and src[d].dtype.kind in "OUS"}  # (extra's own: frequency_name)
    for name, var in extra.data_vars.items():
        refs = {c for c in aux if set(block[c].dims) <= set(var.dims)} | (labels
                                                                        & set(var.dims))
        if refs:
            extra[name].encoding["coordinates"] = " ".join(sorted(map(str, refs)))
    return extra
