"""Calibrate the inlet film: the ``lubricant.inlet_film_um`` at which a scene's mean friction
torque equals a measured or catalogue value (``bearingdae calibrate``).

Pipeline place: a scene (with rolling resistance, which the inlet film starves: docs/theory.md
§19) -> dynamic runs at trial films -> the mean friction torque of each, drag excluded as the
catalogues count it (:func:`catalogue_torque_N_mm`) -> a bracketed root on the log of the film
(Brent's method, scipy.optimize.brentq) -> the film and the calibrated scene.

Why a bracket: B&H's starvation ratio rises monotonically with the film (eq. 44), so the torque
goes from its least at the thinnest film the key allows (:data:`FILM_RANGE_UM`'s first) to
nearly the fully flooded torque, its largest, at the thickest (S ~ 1e3-1e4 there: the ratio
is within ~3 % of 1). A torque outside that span is refused naming it. Each trial is one run of
the scene's own numerics (warm-up and window): the film found is as good as the runs' torque.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..system.rolling_resistance import INLET_FILM_KEY as FILM_KEY  # noqa: F401 (the cli's)

#: the bracket of the search [µm]: the ends of ``lubricant.inlet_film_um``'s range
FILM_RANGE_UM = (1e-3, 1e3)
#: the search ends when a run's torque is within this fraction of the target
TORQUE_RTOL = 2e-3
#: and at most after this many runs (the two ends included)
MAX_RUNS = 24


@dataclass(frozen=True)
class Calibration:
    """The film found [µm], the torque of its run [N mm], the target [N mm], the number of
    runs the fit took and (film µm, torque N mm) of every run, in order."""

    film_um: float
    torque_N_mm: float
    target_N_mm: float
    runs: int
    trials: tuple[tuple[float, float], ...]


def catalogue_torque_N_mm(ds) -> float:
    """The window mean of the friction torque referred to the inner ring [N mm], without the
    lubricant's drag (studies/friction.DRAG_SOURCES), as the catalogues count it (their drag
    term is an oil bath's, given apart): trapezoids over the recorded times."""
    from .friction import DRAG_SOURCES, _source_dim

    dim = _source_dim(ds)
    keep = [s for s in map(str, ds[dim].values) if s not in DRAG_SOURCES]
    torque = ds.friction_torque_N_m.sel({dim: keep}).sum(dim).values
    t = ds.time.values
    return float(np.trapezoid(torque, t) / (t[-1] - t[0])) * 1e3


class _Close(Exception):
    """A run within :data:`TORQUE_RTOL` of the target: the search stops there."""


def calibrate_inlet_film(scene_at: Callable, target_N_mm: float,
                         torque_of: Callable | None = None,
                         progress: Callable | None = None) -> Calibration:
    """The inlet film whose run gives the mean friction torque ``target_N_mm`` (module
    docstring). ``scene_at(film_um)``: the scene with that film (SceneError if invalid);
    ``torque_of(scene)``: the torque [N mm] of a scene's run (default: :func:`simulate` and
    :func:`catalogue_torque_N_mm`); ``progress(line)`` is told each run. ValueError (one line)
    for a scene without rolling resistance, a target that is not a positive number, or one
    outside the span the film reaches."""
    from scipy.optimize import brentq

    if not (isinstance(target_N_mm, (int, float)) and math.isfinite(target_N_mm)
            and target_N_mm > 0):
        raise ValueError(f"--friction-torque-Nmm {target_N_mm!r}: a friction torque in N mm, "
                         "greater than 0")
    base = scene_at(None)
    if not base.physics.rolling_resistance:
        raise ValueError("calibrate: the scene has no rolling resistance, through which the "
                         "inlet film acts; set physics.rolling_resistance = true (or physics."
                         "friction_model = \"full\")")
    torque_of = torque_of or _run_torque
    trials: list[tuple[float, float]] = []

    def torque(film: float) -> float:
        T = torque_of(scene_at(film))
        trials.append((film, T))
        if progress is not None:
            progress(f"run {len(trials)}: inlet film {film:.4g} µm -> {T:.5g} N mm")
        return T

    lo, hi = (math.log(f) for f in FILM_RANGE_UM)
    T_lo, T_hi = (torque(f) for f in FILM_RANGE_UM)
    if not min(T_lo, T_hi) <= target_N_mm <= max(T_lo, T_hi):
        raise ValueError(
            f"calibrate: a friction torque of {target_N_mm:g} N mm is out of reach: with "
            f"lubricant.inlet_film_um from {FILM_RANGE_UM[0]:g} to {FILM_RANGE_UM[1]:g} µm "
            f"(a very thin film to nearly flooded) this scene's torque, drag excluded, spans "
            f"[{min(T_lo, T_hi):.4g}, {max(T_lo, T_hi):.4g}] N mm")
    known = {lo: T_lo, hi: T_hi}

    def residual(x: float) -> float:
        T = known.pop(x) if x in known else torque(
            min(max(math.exp(x), FILM_RANGE_UM[0]), FILM_RANGE_UM[1]))
        if abs(T - target_N_mm) <= TORQUE_RTOL * target_N_mm:
            raise _Close
        if len(trials) >= MAX_RUNS:
            raise _Close
        return T - target_N_mm

    try:
        brentq(residual, lo, hi, xtol=1e-4, rtol=1e-6, maxiter=MAX_RUNS)
    except _Close:
        pass
    film, T = min(trials, key=lambda ft: abs(ft[1] - target_N_mm))
    return Calibration(film, T, float(target_N_mm), len(trials), tuple(trials))


def _run_torque(scene) -> float:
    import warnings

    from ..api import simulate

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return catalogue_torque_N_mm(simulate(scene, progress=False))
