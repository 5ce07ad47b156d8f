"""Convergence of the numbers a user reads: each headline output under refinement, against its
statistical error, with the run time of each setting (``bearingdae converge``).

Pipeline: studies (many runs of one scene). The scene runs at its own settings (the *base*)
and then once per refinement, one setting refined at a time:

* ``slices``: ``numerics.slices`` times a factor (default 2): the contact's discretisation
  along the roller (slice loads, life by laminae, film, edge stress);
* ``rtol``: ``numerics.rtol`` and ``numerics.atol`` divided by a factor (default 10): IDA's
  error control (the ratio of the two kept; studies/workprecision/ladders.py keeps it fixed);
* ``samples``: ``numerics.samples_per_cage_revolution`` times a factor (default 2): what the
  sampled outputs see (film minima, time means); IDA's steps do not depend on it.

For every headline output (analysis/headline.py: cage slip, peak pocket force and skew per
roller pass, L10r, minimum film and λ per roller pass, power loss, and the ring vibration RMS
of a dynamic ring) a refinement gives the change Δ = x_refined − x_base. The runs decorrelate
(the motion is chaotic), so Δ holds the bias of the base setting plus the sampling noise of two
windows, σ_Δ = sqrt(SE_base² + SE_refined²) (as in studies/workprecision/statistical.py).

**Verdict.** ``converged`` when |Δ| ≤ :data:`CONVERGED_SE` σ_Δ, or when |Δ| is within the
practical tolerance ``tolerance`` |x_base| (:data:`PRACTICAL_REL_TOL`, 0.1 % by default,
``--tolerance``: a long record makes σ_Δ so small that a change of 1e-5, real but of no
consequence, would be significant), or below the base run's
resolution floor (its atol in the unknown's units, and rtol |x|, the floor of the statistical
work-precision study, for outputs that are zero to integration noise); else ``not converged:
raise numerics.slices`` (or the setting refined). Without a standard error (too short a
record) it is ``undetermined``. With a bias-free refinement |Δ| exceeds 2 σ_Δ by chance in
~5 % of the cells; a refinement that moves an output by more than its error bar is caught.
A standard error that is only a lower bound (the record spans too few correlation times,
analysis/statistics.py) is said in the verdict.

**Run time** is the wall and the CPU time of each run (static start, warm-up, record and
post-processing; CPU: this process and the processes it waited for). A short run first loads
the compiled kernels, or compiles them on a first run, so that the settings compare with each
other; its wall and CPU time are reported beside them (``kernels_wall_s``, ``kernels_cpu_s``),
and the study's total wall time (``study_wall_s``) counts everything.

The base run's plausibility warnings (analysis/guards.py: a thin film, ...) are kept as the
study's ``base_run_warnings`` and said once in its summary; the refined runs repeat them.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import time
import warnings
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ..analysis.headline import HEADLINE_OUTPUTS
from .workprecision.ladders import WARMUP_OVERRIDES
from .workprecision.runs import derive
from .workprecision.statistical import _resolution_floor

#: the refinements: name -> (scene key, verb of the advice, default factor)
REFINEMENTS = {"slices": ("numerics.slices", "raise", 2.0),
               "rtol": ("numerics.rtol", "lower", 10.0),
               "samples": ("numerics.samples_per_cage_revolution", "raise", 2.0)}
#: |Δ| above this many combined standard errors: not converged
CONVERGED_SE = 2.0
#: ... and above this fraction of the base value: a change smaller than 0.1 % is below the
#: digits a headline output is read to (a life's own stated error is ±0.4 %), significant or not
PRACTICAL_REL_TOL = 1e-3
#: outputs whose resolution floor is an unknown's atol: output -> statistic of
#: studies/workprecision/statistical._resolution_floor
FLOOR_STATISTIC = {"cage_slip": "cage_slip_ratio", "max_skew_per_pass": "skew_rms_rad"}


@dataclass(frozen=True)
class Setting:
    name: str        #: "base" or a key of REFINEMENTS
    overrides: dict  #: scene overrides against the base scene
    label: str       #: e.g. "20 slices"


def settings(scene, factors: dict | None = None, refine=tuple(REFINEMENTS)) -> list[Setting]:
    """The base and one refined setting per name in ``refine``; ``factors``: name -> factor
    (> 1, default :data:`REFINEMENTS`'). Raises ValueError naming a bad name or factor."""
    factors = dict(factors or {})
    refine = (refine,) if isinstance(refine, str) else tuple(refine)
    unknown = sorted(set(factors) - set(REFINEMENTS)) or sorted(set(refine) - set(REFINEMENTS))
    if unknown:
        raise ValueError(f"refinement {unknown[0]!r}: allowed are {', '.join(REFINEMENTS)}")
    if not refine:
        raise ValueError("refinements: none given; allowed are " + ", ".join(REFINEMENTS))
    n, d = scene.numerics, scene.dynamics
    out = [Setting("base", {}, f"{n.slices} slices, rtol {d.rtol:g}, "
                               f"{d.samples_per_cage_revolution} samples/rev")]
    for name in REFINEMENTS:
        if name not in refine:
            continue
        f = float(factors.get(name, REFINEMENTS[name][2]))
        if not (math.isfinite(f) and f > 1):
            raise ValueError(f"{name} factor {f:g}: must be > 1 (a refinement)")
        if name == "slices":
            k = int(round(n.slices * f))
            if k <= n.slices:
                raise ValueError(f"slices factor {f:g}: {n.slices} slices x {f:g} rounds to "
                                 f"{k}; give a factor of at least {(n.slices + 1) / n.slices:.3g}")
            out.append(Setting(name, {"numerics.slices": k}, f"{k} slices"))
        elif name == "rtol":
            out.append(Setting(name, {"numerics.rtol": d.rtol / f, "numerics.atol": d.atol / f},
                               f"rtol {d.rtol / f:g}"))
        else:
            s = d.samples_per_cage_revolution
            k = int(round(s * f))
            if k <= s:
                raise ValueError(f"samples factor {f:g}: {s} samples x {f:g} rounds to {k}")
            out.append(Setting(name, {"numerics.samples_per_cage_revolution": k},
                               f"{k} samples/rev"))
    return out


def _cpu_s() -> float:
    """CPU time of this process and of its children it waited for [s] (a cold start compiles
    part of the kernels in a child: solvers/sundials/precompile.py)."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def converge(scene, factors: dict | None = None, refine=tuple(REFINEMENTS),
             progress=None, tolerance: float = PRACTICAL_REL_TOL) -> xr.Dataset:
    """Run ``scene`` at its settings and at each refinement (module docstring) and tabulate
    every headline output: value and standard error per setting, the change Δ under each
    refinement with its combined error, the verdict and the CPU time of each run.

    Parameters
    ----------
    scene : Scene
        The scene (:func:`load_scene`); its numerics are the base setting.
    factors : dict, optional
        Refinement factors by name, e.g. ``{"slices": 2, "rtol": 10, "samples": 2}``.
    refine : sequence of str, default ("slices", "rtol", "samples")
        Which refinements to run.
    progress : callable, optional
        ``progress(text)``, told of each run as it starts and ends.
    tolerance : float, default PRACTICAL_REL_TOL (1e-3)
        Practical relative tolerance: a change within ``tolerance`` times the base value is
        converged, however significant.

    Returns
    -------
    xarray.Dataset
        Dims (setting, output): ``value``, ``stderr``, ``delta``, ``delta_stderr``,
        ``verdict``; per setting ``run_time_s`` (CPU time), ``wall_time_s``, ``steps``,
        ``status``; per output
        ``output_units``. Save it with :func:`save`.

    Examples
    --------
    >>> from bearingdae import converge, load_scene
    >>> scene = load_scene("yang20_baseline", {"numerics.cage_revolutions": 0.3})
    >>> ds = converge(scene, refine=["slices"])                     # doctest: +SKIP
    >>> ds.verdict.sel(setting="slices", output="L10r").item()      # doctest: +SKIP
    """
    from ..api import simulate
    from ..analysis.headline import headline_statistics

    if not (isinstance(tolerance, (int, float)) and 0.0 <= tolerance < 1.0):
        raise ValueError(f"tolerance {tolerance!r}: a relative change, 0 <= tolerance < 1")
    wall0 = time.perf_counter()
    plan = settings(scene, factors, tuple(refine))
    scenes = scenes_of(scene, plan)  # every range checked before running
    names = list(HEADLINE_OUTPUTS)
    value = np.full((len(plan), len(names)), np.nan)
    stderr, correlated = np.full_like(value, np.nan), np.zeros(value.shape, bool)
    cpu, steps = np.full(len(plan), np.nan), np.full(len(plan), np.nan)
    wall = np.full(len(plan), np.nan)
    floor, status, said = np.zeros(len(names)), [], []
    c0, w0 = _cpu_s(), time.perf_counter()
    try:  # load (or compile) the kernels outside the timed runs
        with _plausibility_quiet(True):
            simulate(derive(scene, WARMUP_OVERRIDES), progress=False)
    except Exception as exc:  # noqa: BLE001 - the timed run reports its own failure
        _stop_if_interrupted(exc)
    kernels = (time.perf_counter() - w0, _cpu_s() - c0)
    if progress:
        progress(f"kernels loaded or compiled: {kernels[0]:.1f} s wall, {kernels[1]:.1f} s CPU")
    for i, (s, sc) in enumerate(zip(plan, scenes)):
        if progress:
            progress(f"{s.name} ({s.label}): running")
        c0, w0 = _cpu_s(), time.perf_counter()
        try:
            with _plausibility_quiet(i > 0, said):  # the base run's warnings are the scene's
                ds = simulate(sc, progress=False)
        except Exception as exc:  # noqa: BLE001 - a failed setting is a row, not a crash
            _stop_if_interrupted(exc)
            status.append(f"failed: {type(exc).__name__}: {exc}")
            continue
        cpu[i], wall[i] = _cpu_s() - c0, time.perf_counter() - w0
        for j, name in enumerate(names):
            est = headline_statistics(ds, sc).get(name)
            if est is not None:
                value[i, j], stderr[i, j], correlated[i, j] = est.mean, est.stderr, \
                    est.correlated
        steps[i] = json.loads(ds.attrs["solver_statistics"]).get("steps", np.nan)
        if i == 0:
            floor[:] = base_floor(ds, names, value[0], sc.dynamics.rtol)
        status.append("ok")
        if progress:
            progress(f"{s.name}: {wall[i]:.1f} s wall, {cpu[i]:.1f} s CPU, "
                     f"{int(steps[i])} steps")
    keep = np.isfinite(value).any(axis=0)  # the outputs the scene has (a dynamic ring's)
    if not keep.any():
        keep[:] = True
    ds = table(scene, plan, [n for n, k in zip(names, keep) if k], value[:, keep],
               stderr[:, keep], correlated[:, keep], floor[keep], cpu, steps, status,
               tolerance=tolerance)
    ds["wall_time_s"] = (("setting",), wall, {"units": "s", "long_name": "wall time of the run"})
    ds.attrs.update(kernels_wall_s=round(kernels[0], 3), kernels_cpu_s=round(kernels[1], 3),
                    study_wall_s=round(time.perf_counter() - wall0, 3),
                    base_run_warnings=json.dumps(said))
    return ds


def _stop_if_interrupted(exc: Exception) -> None:
    """A run stopped by Ctrl-C (the solver turns it into a failed Solution, solvers/base.py)
    stops the study: KeyboardInterrupt again."""
    if str(exc).startswith("interrupted by the user"):
        raise KeyboardInterrupt from None


def scenes_of(scene, plan) -> list:
    """The scene of each setting; a refinement outside a key's range raises ValueError in one
    line naming the refinement, the key and the range."""
    from ..scene import SceneError

    out = []
    for s in plan:
        try:
            out.append(derive(scene, s.overrides))
        except SceneError as exc:
            detail = "; ".join(line.strip(" -.") for line in str(exc).splitlines()[1:]) or exc
            raise ValueError(f"{s.name} refinement ({s.label}): {detail}; give a smaller "
                             f"--{s.name}-factor") from None
    return out


@contextlib.contextmanager
def _plausibility_quiet(quiet: bool, said: list | None = None):
    """Plausibility warnings ignored (``quiet``: a refined run's repeat the base run's), or
    their messages appended to ``said`` (the study says them once, in its summary)."""
    from ..analysis.guards import PlausibilityWarning

    with warnings.catch_warnings(record=not quiet) as caught:
        warnings.simplefilter("ignore" if quiet else "always", PlausibilityWarning)
        yield
    for w in caught or ():
        if issubclass(w.category, PlausibilityWarning):
            text = " ".join(str(w.message).split())
            if said is not None and text not in said:
                said.append(text)
        else:  # any other warning: as the caller has them
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)


def base_floor(ds, names, base_value, rtol: float) -> np.ndarray:
    """The smallest change the base run resolves in each output (module docstring)."""
    atol = _resolution_floor(ds, [FLOOR_STATISTIC.get(n, "") for n in names])
    return np.maximum(np.asarray(atol, float), rtol * np.nan_to_num(np.abs(base_value)))


def verdict(delta: float, delta_se: float, floor: float, lower_bound: bool,
            refinement: str, practical: float = 0.0) -> str:
    """The verdict of one output under one refinement (module docstring); ``practical``:
    the practical tolerance in the output's units."""
    if not np.isfinite(delta):
        return "not available"
    if abs(delta) <= max(CONVERGED_SE * np.nan_to_num(delta_se), floor,
                         np.nan_to_num(practical)):
        return "converged"
    if not np.isfinite(delta_se):  # a record too short for an error bar
        return "undetermined: record longer (numerics.cage_revolutions)"
    key, verb, _ = REFINEMENTS[refinement]
    note = " (error bar a lower bound: record longer)" if lower_bound else ""
    return f"not converged: {verb} {key}{note}"


def table(scene, plan, names, value, stderr, correlated, floor, cpu, steps,
          status, tolerance: float = PRACTICAL_REL_TOL) -> xr.Dataset:
    """The study's Dataset from its numbers (the verdicts computed here)."""
    delta = value - value[0]
    practical = tolerance * np.abs(value[0])
    delta_se = np.sqrt(stderr ** 2 + stderr[0] ** 2)
    delta_se[0] = 0.0
    verdicts = np.empty(value.shape, dtype=object)
    verdicts[0] = "base"
    for i, s in enumerate(plan[1:], start=1):
        for j in range(len(names)):
            verdicts[i, j] = verdict(delta[i, j], delta_se[i, j], floor[j],
                                     bool(correlated[i, j] or correlated[0, j]), s.name,
                                     practical[j])
    dims = ("setting", "output")
    units = [HEADLINE_OUTPUTS[n][0] for n in names]
    # CF has no units per element: each output's units are the coordinate output_units
    see = "in the units of each output: coordinate output_units"
    n, d = scene.numerics, scene.dynamics
    return xr.Dataset(
        {"value": (dims, value, {"long_name": "headline output of the run", "comment": see}),
         "stderr": (dims, stderr, {"long_name": "standard error of value (blocking, "
                                                "analysis/statistics.py)", "comment": see}),
         "delta": (dims, delta, {"long_name": "value minus the base setting's value",
                                 "comment": see}),
         "delta_stderr": (dims, delta_se, {"long_name": "combined standard error of delta, "
                                                        "sqrt(SE² + SE_base²)", "comment": see}),
         "resolution_floor": (("output",), floor, {
             "long_name": "smallest change the base run resolves (its atol in the unknown's "
                          "units, rtol times the value)", "comment": see}),
         "stderr_lower_bound": (dims, correlated.astype(np.int8), {
             "long_name": "1 where the record spans too few correlation times: stderr is a "
                          "lower bound", "flag_values": "0 1"}),
         "practical_tolerance": (("output",), practical, {
             "long_name": f"practical tolerance: {tolerance:g} times the base value",
             "comment": see}),
         "verdict": (dims, verdicts, {"long_name": f"converged when |delta| <= "
                                                   f"{CONVERGED_SE:g} delta_stderr or <= "
                                                   "practical_tolerance"}),
         "run_time_s": (("setting",), cpu, {"units": "s", "long_name": "CPU time of the run "
                                            "(process time: start, warm-up, record, "
                                            "post-processing)"}),
         "steps": (("setting",), steps, {"long_name": "IDA steps"}),
         "status": (("setting",), np.array(status + [""] * (len(plan) - len(status)),
                                           dtype=object), {"long_name": "run outcome"})},
        coords={"setting": ("setting", np.array([s.name for s in plan], dtype=object),
                            {"long_name": "base, or the setting refined"}),
                "setting_label": ("setting", np.array([s.label for s in plan], dtype=object),
                                  {"long_name": "the setting's value"}),
                "output": ("output", np.array(names, dtype=object),
                           {"long_name": "headline output"}),
                "output_units": ("output", np.array(units, dtype=object),
                                 {"long_name": "units of value, stderr and delta"}),
                "output_long_name": ("output", np.array([HEADLINE_OUTPUTS[k][1] for k in names],
                                                        dtype=object), {"long_name": "meaning"})},
        attrs={"title": f"{scene.title}: convergence of the headline outputs",
               "scene_toml": scene.to_toml(), "slices": n.slices, "rtol": d.rtol,
               "atol": d.atol, "samples_per_cage_revolution": d.samples_per_cage_revolution,
               "warmup_cage_revolutions": d.warmup_cage_revolutions,
               "cage_revolutions": d.cage_revolutions,
               "practical_tolerance_rel": tolerance,
               "rule": f"converged: |delta| <= max({CONVERGED_SE:g} delta_stderr, "
                       f"resolution_floor, {tolerance:g} |base value|); else not converged, "
                       "raise the setting refined"})
