"""The one contract every time integrator of bearingdae fulfils (IDA, Newmark-β, scipy peers).

Stage: scene -> parameters -> physics -> system (DAE model) -> **solver** -> results. A solver
takes a :class:`~bearingdae.system.model.Model` (the residual F(t, y, y') = 0 of theory.md §11 in
scaled unknowns) and returns a :class:`Solution`; it never builds a Dataset (that is
``results``' job) and never looks at the scene beyond ``model.scene.dynamics`` / ``numerics``.

The contract (as scipy's ``OdeSolver``: numbered; the base class keeps the bookkeeping):

1. ``integrate(model, y0, yp0, t_out, *, t_start=0.0, progress=None, on_sample=None)``
   integrates from ``t_start`` to every time of ``t_out`` (1-D, strictly increasing,
   ``t_out[0] >= t_start``). When ``t_out[0] == t_start`` the initial (consistent) state is the
   first sample.
2. It **never raises** on solver failure: the :class:`Solution` has ``success = False``,
   a ``message`` naming the cause, ``failure_time_s`` and **every sample reached before**.
   Ctrl-C (``KeyboardInterrupt``) is caught here, in the base: ``success = False``, message
   ``"interrupted by the user at t = … s"``. Bad arguments (``t_out`` not increasing, a
   size mismatch) raise ``ValueError`` before any work.
3. After each sample the base calls ``on_sample(t, y, yp)`` (checkpoints) and then
   ``progress(t)``. Subclasses hand samples to the base through ``emit(t, y, yp)`` only.
4. Counters belong to the base (:class:`Counters`): subclasses increment them; the base adds
   ``output_samples`` and ``wall_time_s``. ``Solution.stats`` is that dict plus the
   subclass's ``extra_stats()``.
5. ``describe()`` returns the solver's attributes for the Dataset: at least ``solver`` (its
   short name, e.g. ``"ida"``, ``"newmark"``, ``"scipy-BDF"``, the value recorded in
   ``solver_options.solver``), ``solver_description`` (one human line) and ``options`` (a
   JSON-able dict of every setting that changes the result).
   ``dataset_attrs(model, solution)`` (optional) returns further Dataset attributes that
   depend on the scene (Newmark's resolved step, a solver's own tolerances); its ``"options"``
   entry is merged into ``solver_options``. ``results.from_solution`` writes both.
6. A solver object holds settings only, no run state between calls: one object may integrate
   many models, one after the other. Run state lives in the subclass's ``_run`` locals.

7. ``integrate(..., extremes_from=t)`` asks for the running extremes of every accepted step
   ending at or after t (system/extremes.py). A solver that can keeps them in
   ``self._extremes`` (an :class:`~bearingdae.system.extremes.Extremes` made in ``_run`` from
   ``self._extremes_from``), which the base returns as ``Solution.extremes``; one that cannot
   leaves it None and the results take the extremes from the samples. The base closes the
   extremes' interval at every sample (``Extremes.close_interval``: the peak trace).
8. ``integrate(..., keep_samples=False)``: the Solution keeps only the last sample (and the
   error estimate, if any, of every sample); ``on_sample`` is then the only record (a
   streamed run, results/streamed_record.py: memory that does not grow with the record).
9. A solver that can stop between samples without changing its steps (IDA) keeps a dynamic
   ring's displacement at sub-sample times in ``model.ring_taps`` (system/taps.py), for the
   record's anti-alias filter; the base sets it to None before each run.

Subclasses implement ``_run(model, y0, yp0, t_out, t_start, emit) -> (success, message,
failure_time_s)`` and ``describe()``.
"""

from __future__ import annotations

import time
from abc import ABC, abstractmethod
from dataclasses import asdict, dataclass, field
from typing import Callable

import numpy as np

from ..system.defect_sides import has_sharp


@dataclass
class Counters:
    """Work counters every solver reports (contract item 4). Zero when a solver has no such
    notion (Newmark takes no error test, so ``error_test_failures`` stays 0)."""

    steps: int = 0  #: accepted time steps
    residual_calls: int = 0  #: F(t, y, y') evaluations by the integrator itself
    jacobian_calls: int = 0  #: iteration-matrix evaluations
    residual_calls_in_jacobian: int = 0  #: further F calls spent inside finite-difference Jacobians
    error_test_failures: int = 0
    nonlinear_convergence_failures: int = 0


#: solver statistics that are settings, not work: a run in segments keeps the last one's
SETTING_STATISTICS = frozenset({"step_s", "beta", "gamma", "hht_alpha", "newton_tol",
                                "inner_tolerance", "time_limit_s"})


def merge_statistics(before: dict, now: dict) -> dict:
    """The solver statistics of a run integrated in segments (a resume, warm-up blocks): work
    adds up (counts, wall times, histograms, restart times); what describes the end (``last_*``,
    ``current_*``) and the settings are the last segment's; ``smallest_*`` the least,
    ``largest_*`` / ``most_*`` the largest; a ``*_per_step`` mean weighted by the steps. Nested
    statistics (a dict of them) merge the same way."""
    out = {**before, **now}
    for key, b in before.items():
        if key not in now:
            continue
        n = now[key]
        if _number(b) and _number(n):
            if key in SETTING_STATISTICS or key.startswith(("last_", "current_")):
                out[key] = n
            elif key.startswith("smallest_"):
                out[key] = min(b, n)
            elif key.startswith(("largest_", "most_")):
                out[key] = max(b, n)
            elif key.endswith("_per_step"):
                sb, sn = before.get("steps", 0), now.get("steps", 0)
                out[key] = (b * sb + n * sn) / (sb + sn) if sb + sn > 0 else n
            else:
                out[key] = b + n
        elif isinstance(b, dict) and isinstance(n, dict):
            out[key] = merge_statistics(b, n)
        elif isinstance(b, list) and isinstance(n, list):
            out[key] = b + n
    return out


def _number(v) -> bool:
    return isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool)


@dataclass
class Solution:
    """What every solver returns (contract item 2). Unknowns are scaled (``model.scale``)."""

    t: np.ndarray  #: output times reached [s]
    y: np.ndarray  #: scaled states at those times (n_t, N)
    yp: np.ndarray  #: scaled derivatives (n_t, N)
    success: bool
    message: str
    failure_time_s: float | None
    stats: dict = field(default_factory=dict)
    #: optional (n_t, N) global-error estimate in scaled units (Newmark's Richardson estimate)
    error_estimate: np.ndarray | None = None
    #: the running extremes of every accepted step from ``extremes_from`` on
    #: (system/extremes.py), when asked for and the solver keeps them; None otherwise
    extremes: object | None = None


#: The name earlier versions used; kept so that ``from bearingdae.solvers.ida import
#: IntegrationResult`` keeps working.
IntegrationResult = Solution


def check_output_times(t_out, t_start: float) -> np.ndarray:
    """``t_out`` as a float array, or ValueError naming what is wrong (contract item 1)."""
    t_out = np.asarray(t_out, dtype=float)
    if t_out.ndim != 1 or t_out.size == 0:
        raise ValueError(f"t_out: expected a non-empty 1-D array of times, got shape "
                         f"{t_out.shape}")
    if not np.all(np.isfinite(t_out)):
        raise ValueError("t_out: every output time must be finite")
    if np.any(np.diff(t_out) <= 0):
        raise ValueError("t_out: output times must be strictly increasing")
    if t_out[0] < t_start:
        raise ValueError(f"t_out[0] = {t_out[0]:.6g} s is before t_start = {t_start:.6g} s")
    return t_out


class _Recorder:
    """Collects samples and calls the user's hooks (contract item 3); with ``keep=False`` only
    the last sample (a streamed run: its ``on_sample`` takes them)."""

    def __init__(self, n: int, progress, on_sample, keep: bool = True, solver=None):
        self.n, self.progress, self.on_sample, self.keep = n, progress, on_sample, keep
        self.solver = solver  # whose running extremes get their interval closed per sample
        self.T: list[float] = []
        self.Y: list[np.ndarray] = []
        self.YP: list[np.ndarray] = []
        self.count = 0

    def emit(self, t: float, y: np.ndarray, yp: np.ndarray) -> None:
        ext = getattr(self.solver, "_extremes", None)
        if ext is not None:  # the peaks since the previous sample (system/extremes.py)
            ext.close_interval(float(t))
        y, yp = np.array(y, dtype=float, copy=True), np.array(yp, dtype=float, copy=True)
        if not self.keep:
            self.T.clear(), self.Y.clear(), self.YP.clear()
        self.T.append(float(t)), self.Y.append(y), self.YP.append(yp)
        self.count += 1
        if self.on_sample is not None:
            self.on_sample(self.T[-1], y, yp)
        if self.progress is not None:
            self.progress(self.T[-1])

    def arrays(self):
        return (np.array(self.T), np.array(self.Y).reshape(-1, self.n),
                np.array(self.YP).reshape(-1, self.n))


class Solver(ABC):
    """Base of every integrator: the bookkeeping of the contract above."""

    #: short name, recorded as ``solver_options.solver`` (contract item 5)
    name: str = "abstract"
    #: whether the solver locates sharp defect edges (numerics.defect_edges = "locate": IDA's
    #: root finding, solvers/ida_edges.py); the others refuse such a scene
    locates_edges: bool = False

    def integrate(self, model, y0: np.ndarray, yp0: np.ndarray, t_out, *,
                  t_start: float = 0.0, progress: Callable[[float], None] | None = None,
                  on_sample: Callable[[float, np.ndarray, np.ndarray], None] | None = None,
                  extremes_from: float | None = None, keep_samples: bool = True) -> Solution:
        """Integrate ``model`` from (t_start, y0, yp0) to every time of ``t_out`` (contract).
        ``extremes_from``: keep the running extremes of every accepted step that ends at or
        after this time (``Solution.extremes``; contract item 7). ``keep_samples=False``: the
        Solution holds the last sample only (``on_sample`` took them all: a streamed run,
        whose memory must not grow with the record); ``stats["output_samples"]`` counts all."""
        t_out = check_output_times(t_out, t_start)
        if extremes_from is not None and not np.isfinite(extremes_from):
            raise ValueError(f"extremes_from = {extremes_from!r}: expected a finite time [s] "
                             "or None")
        self._extremes_from = None if extremes_from is None else float(extremes_from)
        self._extremes = None
        n = model.size
        y0, yp0 = np.asarray(y0, dtype=float), np.asarray(yp0, dtype=float)
        if y0.shape != (n,) or yp0.shape != (n,):
            raise ValueError(f"y0, yp0: expected shape ({n},) for this model, got "
                             f"{y0.shape} and {yp0.shape}")
        if not self.locates_edges and has_sharp(model.defect_table):
            raise ValueError(f"numerics.defect_edges = 'locate': solver {self.name} cannot "
                             "locate sharp defect edges (IDA's root finding does); allowed "
                             "with it: 'smooth'")
        self.counters = Counters()
        self._keep_samples = bool(keep_samples)
        model.ring_taps = None  # a solver that taps the ring sets it (system/taps.py)
        rec = _Recorder(n, progress, on_sample, self._keep_samples, self)
        wall0 = time.perf_counter()
        try:
            success, message, failure_t = self._run(model, y0, yp0, t_out, float(t_start),
                                                    rec.emit)
        except KeyboardInterrupt:
            failure_t = rec.T[-1] if rec.T else float(t_start)
            success, message = False, f"interrupted by the user at t = {failure_t:.6g} s"
        wall = time.perf_counter() - wall0
        stats = asdict(self.counters)
        stats.update(self.extra_stats())
        stats["output_samples"] = rec.count
        stats["wall_time_s"] = wall
        T, Y, YP = rec.arrays()
        ext = getattr(self, "_extremes", None)
        if ext is not None:
            stats["extremes_steps"] = ext.steps
        return Solution(T, Y, YP, bool(success), str(message),
                        None if success else failure_t, stats,
                        self.error_estimate(rec.count), ext)

    @abstractmethod
    def _run(self, model, y0, yp0, t_out, t_start, emit) -> tuple[bool, str, float | None]:
        """Integrate and ``emit(t, y, yp)`` each sample; return (success, message, failure
        time). Increment ``self.counters`` as work is done (it is reset per call)."""

    @abstractmethod
    def describe(self) -> dict:
        """``{"solver": name, "solver_description": ..., "options": {...}}`` (item 5)."""

    def dataset_attrs(self, model, solution: Solution) -> dict:
        """Further Dataset attributes of a run on ``model`` (item 5); ``"options"``, if given,
        is merged into ``solver_options``. Default: none (the scene's tolerances apply)."""
        return {}

    def extra_stats(self) -> dict:
        """Solver-specific statistics of the last run (JSON-able), merged into ``stats``."""
        return {}

    def error_estimate(self, n_samples: int) -> np.ndarray | None:
        """Optional global-error estimate of the last run's samples (Newmark: Richardson)."""
        return None
