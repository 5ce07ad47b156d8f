"""Error metrics of the work-precision study (pure functions of arrays and Datasets) and the
unit of each quantity in the mescd."""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from .ladders import ATOL_PER_RTOL, QUANTITIES


# ---------------------------------------------------------------------------------------------
# Error metrics (pure functions of arrays)
# ---------------------------------------------------------------------------------------------
def relative_errors(sol: np.ndarray, ref: np.ndarray) -> tuple[float, float]:
    """(relative RMS, relative max) of ``sol`` against ``ref`` over all elements:
    rms(sol - ref) / rms(ref) and max|sol - ref| / max|ref| (NaN for a zero reference)."""
    sol, ref = np.asarray(sol, float), np.asarray(ref, float)
    d = sol - ref
    ref_ms, ref_max = float(np.mean(ref * ref)), float(np.max(np.abs(ref)))
    if ref_max == 0.0:  # a relative error of an identically zero reference is undefined
        return math.nan, math.nan
    return math.sqrt(float(np.mean(d * d)) / ref_ms), float(np.max(np.abs(d))) / ref_max


def mescd(sol: np.ndarray, ref: np.ndarray, floor: float) -> float:
    """Mixed-error significant correct digits, -log10 max |sol - ref| / (floor + |ref|)
    (IVP Test Set; ``floor`` = atol / rtol). +inf for identical arrays."""
    sol, ref = np.asarray(sol, float), np.asarray(ref, float)
    e = float(np.max(np.abs(sol - ref) / (floor + np.abs(ref))))
    return math.inf if e == 0.0 else -math.log10(e)


def interp_time(t_ref: np.ndarray, values: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Linear interpolation along axis 0 of ``values`` (given at ``t_ref``) to times ``t``."""
    t_ref, t = np.asarray(t_ref, float), np.asarray(t, float)
    if t_ref.shape == t.shape and np.array_equal(t_ref, t):
        return np.asarray(values)
    i = np.clip(np.searchsorted(t_ref, t) - 1, 0, t_ref.size - 2)
    w = ((t - t_ref[i]) / (t_ref[i + 1] - t_ref[i])).reshape((-1,) + (1,) * (values.ndim - 1))
    return values[i] * (1.0 - w) + values[i + 1] * w


def relative_rms_errors(t, values: dict, t_ref, ref: dict, quantities) -> dict:
    """{quantity: relative RMS error} of ``values`` (arrays at times ``t``) against ``ref``
    (at ``t_ref``, interpolated to ``t``) over the times inside the reference's window: the
    study's error measure (:func:`quantity_errors`) for arrays a benchmark kept."""
    t, t_ref = np.asarray(t, float), np.asarray(t_ref, float)
    keep = (t >= t_ref[0] - 1e-12) & (t <= t_ref[-1] + 1e-12)
    return {q: relative_errors(np.asarray(values[q])[keep],
                               interp_time(t_ref, np.asarray(ref[q]), t[keep]))[0]
            for q in quantities if q in values and q in ref}


def quantity_errors(ds: xr.Dataset, ref: xr.Dataset, scales: dict[str, float]) -> dict:
    """Errors of a run against the reference, per quantity, over the run's times that lie
    inside the reference window; plus ``mescd`` over all five quantities (scaled)."""
    t = ds.time.values
    t_ref = ref.time.values
    keep = (t >= t_ref[0] - 1e-12) & (t <= t_ref[-1] + 1e-12)
    out, worst = {}, []
    for q in QUANTITIES:
        if q not in ds or q not in ref or not keep.any():
            out[f"{q}_rel_rms"] = out[f"{q}_rel_max"] = math.nan
            continue
        x = ds[q].values[keep]
        x_ref = interp_time(t_ref, ref[q].values, t[keep])
        out[f"{q}_rel_rms"], out[f"{q}_rel_max"] = relative_errors(x, x_ref)
        s = scales[q]
        worst.append(10.0 ** -mescd(x / s, x_ref / s, ATOL_PER_RTOL))
    out["mescd"] = -math.log10(max(worst)) if worst and max(worst) > 0 else math.nan
    return out


def time_at_error(errors, times, target: float) -> tuple[float, str]:
    """Wall time of a solver at error ``target``, log-log interpolated along its Pareto front
    (runs not beaten in both error and time by another run).

    Returns (time, kind): kind "interpolated"; "not reached" (every run less accurate than
    ``target``: time = the most accurate run's time, a lower bound only if that ladder was
    stopped by the time limit); "below ladder" (even the loosest run is more accurate: time =
    that run's, an upper bound); "no runs".
    """
    pts = sorted((e, t) for e, t in zip(errors, times)
                 if np.isfinite(e) and np.isfinite(t) and e > 0)
    if not pts:
        return math.nan, "no runs"
    front = []
    for e, t in pts:  # ascending error: keep a run only if faster than every more accurate one
        if not front or t < front[-1][1]:
            front.append((e, t))
    if target < front[0][0]:
        return front[0][1], "not reached"
    if target >= front[-1][0]:
        return front[-1][1], "below ladder"
    for (e0, t0), (e1, t1) in zip(front, front[1:]):
        if e0 <= target <= e1:
            a = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + a * (math.log(t1) - math.log(t0))), "interpolated"
    return math.nan, "no runs"  # unreachable


def error_scales(scene) -> dict[str, float]:
    """Unit of each quantity in the mescd: its unknown scale; the model's force scale."""
    from ...system.model import build_model

    m = build_model(scene)
    lay = m.layout
    out = {"contact_force": m.force_scale_N}
    for q in ("cage_speed", "orbit_speed", "spin_speed", "skew_angle"):
        try:
            out[q] = float(m.scale[lay.index(q, 0 if q in lay.local_names else None)])
        except KeyError:  # physics switched off: the quantity is not in the output either
            out[q] = 1.0
    return out


