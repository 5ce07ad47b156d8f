"""The per-step extremes of a run as Dataset variables: ``<variable>_max``, ``<variable>_max_time``.

Pipeline: solvers (``Solution.extremes``, system/extremes.py) -> **results**. Per roller (and
slice and race, end) the largest magnitude over the recorded window and the time it was
reached. From a solver that keeps them (IDA, Newmark-β) they come from every accepted step; a
solver that does not (the scipy peers) and the part of a resumed run before the resume are
covered by the output samples, and the attribute ``extremes_source`` says which. The first
and last samples of the window are always folded in (the window's ends lie inside steps).
"""

from __future__ import annotations

import numpy as np

from ..physics.contact import hertz_pressure
from .dataset import _var

#: name -> (quantity kept per step, dims, units, long name, [physics] switch it needs)
EXTREME_VARIABLES = {
    "cage_force_max": ("cage_force", ("roller", "end"), "N",
                       "largest |pocket force| on the roller end", "cage"),
    "contact_force_max": ("contact_force", ("roller", "slice", "race"), "N",
                          "largest slice contact force", None),
    "contact_pressure_max": ("contact_force", ("roller", "slice", "race"), "Pa",
                             "largest maximum Hertz pressure of the slice", None),
    "slip_velocity_max": ("slip_velocity", ("roller", "slice", "race"), "m s-1",
                          "largest |slip velocity| of the slice", None),
    "skew_angle_max": ("skew_angle", ("roller",), "rad", "largest |skew angle| of the roller",
                       "skew"),
}
STEPS = "every accepted solver step in the recorded window"
SAMPLES = "the output samples of the recorded window"
#: what the samples before the window are in a failed run's partial file
WARM_UP = "the warm-up's output samples before it (kept first in a partial file)"


def _from_samples(t, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(max over time of |values|, time of it); NaN where there is no sample."""
    if values.shape[0] == 0:
        shape = values.shape[1:]
        return np.full(shape, np.nan), np.full(shape, np.nan)
    a = np.abs(values)
    i = np.argmax(a, axis=0)
    return np.take_along_axis(a, i[None], 0)[0], np.asarray(t)[i]


def _merge(step, sample):
    """The larger of two (max, time) pairs, element by element (NaN: none)."""
    (ms, ts), (mp, tp) = step, sample
    take = (mp > ms) | np.isnan(ms)
    return np.where(take, mp, ms), np.where(take, tp, ts)


def _pressure(model, load: np.ndarray) -> np.ndarray:
    """Hertz pressure of slice loads (..., race) (physics/contact.py; increasing in the load,
    so the largest pressure is that of the largest load)."""
    g = model.geometry
    out = np.empty_like(load)
    for r, radius in enumerate((g.reduced_radius_inner_m, g.reduced_radius_outer_m)):
        out[..., r] = hertz_pressure(load[..., r], g.slice_width_m, radius, g.compliance_m2_N)
    return np.where(np.isnan(load), np.nan, out)


def extreme_names(model, wanted) -> list[str]:
    """The extreme variables of :data:`EXTREME_VARIABLES` in ``wanted`` (output variable
    names) that the model has."""
    lay = model.layout
    present = {None: True, "cage": lay.cage, "skew": lay.skew}
    return [n for n in EXTREME_VARIABLES if n in wanted and present[EXTREME_VARIABLES[n][4]]]


def extreme_variables(model, t: np.ndarray, skew: np.ndarray, diag: dict, extremes,
                      wanted) -> tuple[dict, dict]:
    """(variables, attributes) of the extremes in ``wanted`` (output variable names).

    ``t``, ``skew`` (n, Z) and ``diag`` (the kernel's diagnostics per sample): the recorded
    samples; ``extremes``: ``Solution.extremes`` or None. Samples before
    ``extremes.steps_from`` (a resumed run) or all of them (no per-step extremes) are folded
    in as well."""
    names = extreme_names(model, wanted)
    if not names:
        return {}, {}
    samples = {"skew_angle": skew, **diag}
    cut = extremes.steps_from if extremes is not None else np.inf
    early = np.asarray(t) < cut
    # the window's two ends: the part between the last step end inside the window and its
    # end (IDA's last step ends beyond it) is covered by the last sample; the same times at
    # any sample density
    early[[0, -1] if early.size else []] = True
    pairs = {quantity: _from_samples(np.asarray(t)[early], samples[quantity][early])
             for quantity in {EXTREME_VARIABLES[n][0] for n in names}}
    # early samples with the steps counted from the window's start: the warm-up's (a failed
    # run's partial record); from later: a resumed run's whose checkpoint kept no steps
    why = None if extremes is not None and extremes.steps_from > extremes.t_from else WARM_UP
    return finish_extremes(model, names, pairs, extremes, bool(np.any(np.asarray(t) < cut)),
                           why)


def finish_extremes(model, names, pairs: dict, extremes, resumed: bool,
                    why: str | None = None) -> tuple[dict, dict]:
    """(variables, attributes) of the extremes ``names`` from the (max, time) ``pairs`` of the
    samples folded in (quantity -> pair) and the solver's per-step ``extremes`` (or None);
    ``resumed``: samples before the steps' start were folded in; ``why``: which samples
    those were (None: a resumed run's, its checkpoint without step extremes)."""
    steps = extremes.result() if extremes is not None else {}
    cut = extremes.steps_from if extremes is not None else np.inf
    pairs = {q: _merge(steps[q], pair) if q in steps else pair for q, pair in pairs.items()}
    if extremes is None:
        source = SAMPLES
    elif resumed and why:
        source = f"{STEPS} from t = {cut:.9g} s, {why}"
    elif resumed:
        source = (f"{STEPS} from t = {cut:.9g} s (the run was resumed there), "
                  f"{SAMPLES} before")
    else:
        source = STEPS + " and its first and last samples"
    out = {}
    for name in names:
        quantity, dims, units, long_name, _ = EXTREME_VARIABLES[name]
        value, when = pairs[quantity]
        if name == "contact_pressure_max":
            value = _pressure(model, value)
        out[name] = _var(dims, value, units, f"{long_name} over the recorded window",
                         comment=f"over {source}")
        out[name + "_time"] = _var(dims, when, "s", f"time of {name}",
                                   comment="time since the start of the simulation")
    # (how many steps they cover: the solver's statistics, extremes_steps)
    return out, {"extremes_source": source}


def later(a, b):
    """Two (max, time) pairs of successive parts of a record as one: the later part's only
    where it is larger (so a tie keeps the earlier time, as ``argmax`` over the whole)."""
    return _merge(a, b)


# ---------------------------------------------------------------------------------------------
# The peak trace: per sample, the largest value over the bearing since the previous sample
# ---------------------------------------------------------------------------------------------
#: name -> (interval peaks of system/extremes.PEAKS it is made of, units, long name, switch)
PEAK_VARIABLES = {
    "cage_force_peak": (("cage_force",), "N", "largest |pocket force| over the rollers", "cage"),
    "contact_pressure_peak": (("contact_force_inner", "contact_force_outer"), "Pa",
                              "largest maximum Hertz pressure over the slices and races", None),
    "skew_angle_peak": (("skew_angle",), "rad", "largest |skew angle| over the rollers", "skew"),
    "slip_velocity_peak": (("slip_velocity",), "m s-1",
                           "largest |slip velocity| over the slices and races", None),
}
PEAK_COMMENT = ("over every accepted solver step since the previous sample (the peak trace: "
                "nothing between samples is missed); where no step ended in that interval (the "
                "window's first sample, samples closer together than the solver's steps, a "
                "resumed run's samples before its restart, a solver that keeps no per-step "
                "extremes) the sample's own value")


def peak_names(model, wanted) -> list[str]:
    """The peak traces of :data:`PEAK_VARIABLES` in ``wanted`` that the model has."""
    lay = model.layout
    present = {None: True, "cage": lay.cage, "skew": lay.skew}
    return [n for n in PEAK_VARIABLES if n in wanted and present[PEAK_VARIABLES[n][3]]]


def sampled_peaks(skew: np.ndarray, diag: dict) -> np.ndarray:
    """(n, len(PEAKS)): each sample's own largest magnitude over the bearing of the quantities
    of system/extremes.PEAKS (``skew`` (n, Z) and the kernel's diagnostics per sample)."""
    from ..system.extremes import PEAKS

    skew = np.asarray(skew)
    n = skew.shape[0]
    q = diag["contact_force"]
    parts = {"cage_force": diag["cage_force"], "skew_angle": skew,
             "contact_force_inner": q[..., 0], "contact_force_outer": q[..., 1],
             "slip_velocity": diag["slip_velocity"]}
    out = np.full((n, len(PEAKS)), np.nan)
    for c, name in enumerate(PEAKS):
        a = np.abs(np.asarray(parts[name])).reshape(n, -1)
        if a.shape[1]:
            out[:, c] = a.max(axis=1)
    return out


def peak_variables(model, t, extremes, wanted, sampled: np.ndarray) -> dict:
    """The peak traces in ``wanted`` at the sample times ``t``: each sample's value is the
    largest over the bearing of the solver's steps since the sample before (its running
    extremes, ``Solution.extremes``, system/extremes.py), or, where no step ended in that
    interval or the solver keeps none, the sample's own value (``sampled``, from
    :func:`sampled_peaks`)."""
    from ..system.extremes import PEAKS

    names = peak_names(model, wanted)
    if not names:
        return {}
    t = np.asarray(t, dtype=float)
    at = np.full((t.size, len(PEAKS)), np.nan)
    tp, P = extremes.interval_peaks() if extremes is not None else (np.empty(0), None)
    if tp.size and t.size:  # the intervals closed at these very sample times
        i = np.clip(np.searchsorted(tp, t), 0, tp.size - 1)
        hit = tp[i] == t
        at[hit] = P[i[hit]]
    if np.shape(sampled) == at.shape:
        at = np.where(np.isnan(at), sampled, at)
    out = {}
    for name in names:
        parts, units, long_name, _ = PEAK_VARIABLES[name]
        cols = [PEAKS.index(p) for p in parts]
        if name == "contact_pressure_peak":
            p = _pressure(model, at[:, cols])
            value = np.where(np.all(np.isnan(p), axis=1), np.nan,
                             np.nanmax(np.where(np.isnan(p), -np.inf, p), axis=1))
        else:
            value = at[:, cols[0]]
        out[name] = _var("time", value, units, f"{long_name} since the previous sample",
                         comment=PEAK_COMMENT)
    return out
