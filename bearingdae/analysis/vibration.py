"""The dynamic ring's vibration as recorded (theory.md §15): ``ring_acceleration`` low-passed
below the samples' Nyquist frequency by construction, and the ring's natural frequencies
against the output sampling.

Pipeline place: analysis (from the projected samples of a run with ``physics.ring =
"dynamic"``, and the solver's taps, system/taps.py; a scene with the quasi-static ring never
comes here).

**Why a filter.** The ring rings at its contact resonances (yang20 at 800 N, 3 N·m: 2.2, 5.7,
7.4 and 15 kHz), far above the Nyquist frequency of the default output (200 samples per cage
revolution: ~1.5 kHz at 2000 r/min). The acceleration at the sample instants is a sampled
signal without an anti-alias filter: its spectrum below Nyquist is made of the resonances'
aliases.

**The filter** (:func:`tap_filtered`). IDA keeps the ring displacement at R = 16 taps per sample
interval, τ = T/R apart (system/taps.py). At every tap the acceleration weighted by a triangle of
unit area over [t − τ, t + τ] is exactly the central second difference (x₊ − 2x + x₋)/τ²
(integrate the triangle against x'' by parts); a symmetric FIR low-pass h
(:func:`fir_coefficients`: a sinc cut at 1/(2T) under a Kaiser window, 2 M R + 1 taps, M = 9
sample intervals either side) makes each sample of it. Transfer function against the
continuous acceleration, zero phase (:func:`transfer`):

    H(f) = sinc²(f τ) Σ_j h_j cos(2π f j τ)

|H| ≥ 0.98 up to 0.8 f_Nyquist (:data:`PASSBAND_OF_NYQUIST`, which the spectrum divides out),
−36 dB at 1.2 f_Nyquist, below −80 dB from 1.3 to 28 f_Nyquist, below −63 dB beyond.

**Without taps** (:func:`filtered_acceleration`: Newmark-β, the scipy peers, samples whose
taps do not reach M intervals either side on equal steps) a sample records the triangle mean
over its two output intervals, from the sample displacements alone,

    a_k = 2 / (h₁ + h₂) · [ (x_{k+1} − x_k) / h₂ − (x_k − x_{k-1}) / h₁ ]

(H = sinc²(f T) on equal steps), at an end of a record the interval mean (v_k − v_{k−1}) / h
(sinc(f h)), and a record of one sample the equation of motion at it.

The ring's natural frequencies (:func:`natural_frequencies_Hz`) are the modes of its mass and
tilt inertia on the bearing's static stiffness (four load perturbations of the static problem,
theory.md §5, at the recorded operating point and the initial roller azimuths). When the
lowest lies above 0.8 of the samples' Nyquist frequency, the record cannot resolve it:
:func:`vibration_attrs` says so in one line naming the sampling that would.
"""

from __future__ import annotations

import json
import math
from functools import lru_cache

import numpy as np

#: the fraction of the Nyquist frequency up to which a mode counts as resolved: the recording
#: filter's pass band, which the spectrum divides out (analysis/spectrum.py)
RESOLVED_FRACTION_OF_NYQUIST = PASSBAND_OF_NYQUIST = 0.8


def filtered_acceleration(t: np.ndarray, x: np.ndarray, v: np.ndarray, a_point: np.ndarray,
                          before: tuple | None = None, after: tuple | None = None) -> np.ndarray:
    """The recorded acceleration (n, ...) of the samples at ``t`` (n,) from the ring
    displacements ``x`` and velocities ``v`` (n, ...) there (module docstring): the triangle
    mean at every sample with a neighbour on each side, the interval mean at an end with one,
    ``a_point`` (the equation of motion) for a lone sample. ``before`` / ``after``: the
    (t, x, v) of the samples just outside this block (a streamed record), or None."""
    t = np.asarray(t, dtype=float)
    x, v = np.asarray(x, dtype=float), np.asarray(v, dtype=float)
    n = t.size
    if before is not None:
        t, x, v = (np.concatenate([[before[0]], t]),
                   np.concatenate([np.asarray(before[1])[None], x]),
                   np.concatenate([np.asarray(before[2])[None], v]))
    if after is not None:
        t, x, v = (np.concatenate([t, [after[0]]]),
                   np.concatenate([x, np.asarray(after[1])[None]]),
                   np.concatenate([v, np.asarray(after[2])[None]]))
    lo = 1 if before is not None else 0
    out = np.array(a_point, dtype=float, copy=True)
    m = t.size
    if m < 2:
        return out
    shape = (-1,) + (1,) * (x.ndim - 1)
    h = np.diff(t).reshape(shape)
    a = np.empty_like(x)
    # interior: the triangle (linear B-spline) over [t_{k-1}, t_{k+1}]
    slope = np.diff(x, axis=0) / h
    a[1:-1] = 2.0 * np.diff(slope, axis=0) / (h[:-1] + h[1:])
    # the ends: the mean over their one interval
    a[0] = (v[1] - v[0]) / h[0]
    a[-1] = (v[-1] - v[-2]) / h[-1]
    out[...] = a[lo:lo + n]
    return out


def ring_state(model, t: float, y: np.ndarray) -> tuple:
    """(t, x (2,), v (2,)) of the ring at the scaled state ``y``: what
    :func:`filtered_acceleration` takes of a sample outside a block."""
    lay = model.layout
    ix = [lay.index(n) for n in ("ring_dr", "ring_dt")]
    iv = [lay.index(n) for n in ("ring_vr", "ring_vt")]
    return (float(t), np.asarray(y)[ix] * model.scale[ix], np.asarray(y)[iv] * model.scale[iv])


#: the decimation filter's Kaiser window parameter (stopband ~ -80 dB)
KAISER_BETA = 8.0


@lru_cache(maxsize=None)
def _fir() -> np.ndarray:
    from scipy.signal import firwin

    from ..system.taps import TAIL_INTERVALS, TAPS_PER_INTERVAL

    R = TAPS_PER_INTERVAL
    h = firwin(2 * TAIL_INTERVALS * R + 1, 0.5, window=("kaiser", KAISER_BETA), fs=R)
    h.flags.writeable = False
    return h


def fir_coefficients() -> np.ndarray:
    """The decimation filter h_j, j = -M R ... M R (R = TAPS_PER_INTERVAL, M = TAIL_INTERVALS,
    system/taps.py): a windowed-sinc low-pass at the output's Nyquist frequency (Kaiser window,
    β = :data:`KAISER_BETA`), unit gain at 0 Hz, on the taps' rate."""
    return _fir().copy()


def tap_filtered(t: np.ndarray, taps) -> tuple[np.ndarray, np.ndarray]:
    """(acceleration (n, 2), done (n,)) at the samples ``t`` from the ring taps ``taps``
    ((times, displacements) of system/taps.py): at each sample whose taps reach M R + 1 either
    side on equal steps τ, the triangle over [t - τ, t + τ] at every tap (the central second
    difference) convolved with :func:`fir_coefficients`; ``done`` False elsewhere."""
    from ..system.taps import TAIL_INTERVALS, TAPS_PER_INTERVAL

    tt, xx = taps
    t = np.asarray(t, dtype=float)
    out = np.zeros((t.size, 2))
    done = np.zeros(t.size, bool)
    if tt.size == 0:
        return out, done
    h = _fir()
    half = TAIL_INTERVALS * TAPS_PER_INTERVAL + 1  # taps either side the filter reads
    j = np.searchsorted(tt, t)
    for k in range(t.size):
        i = j[k]
        if i >= tt.size or tt[i] != t[k] or i - half < 0 or i + half >= tt.size:
            continue
        w = tt[i - half:i + half + 1]
        steps = np.diff(w)
        tau = steps.mean()
        if np.max(np.abs(steps - tau)) > 1e-6 * tau:
            continue  # a change of sampling (warm-up to record) in the window
        x = xx[i - half:i + half + 1]
        a = (x[2:] - 2.0 * x[1:-1] + x[:-2]) / (tau * tau)
        out[k] = h @ a
        done[k] = True
    return out, done


def transfer(f_Hz, interval_s: float, fir: np.ndarray | None = None) -> np.ndarray:
    """H(f) of the recorded acceleration against the continuous one (module docstring), T the
    sample interval [s]: with the decimation filter ``fir`` (on taps T/R apart, R =
    (len(fir) - 1) / (2 M)) sinc²(f T/R) Σ h_j cos(2π f j T/R); without, sinc²(f T)."""
    f = np.asarray(f_Hz, dtype=float)
    if fir is None:
        return np.sinc(f * interval_s) ** 2
    from ..system.taps import TAPS_PER_INTERVAL

    tau = interval_s / TAPS_PER_INTERVAL
    half = (len(fir) - 1) // 2
    j = np.arange(-half, half + 1)
    return np.sinc(f * tau) ** 2 * (np.cos(2.0 * np.pi * np.multiply.outer(f, j) * tau)
                                    @ np.asarray(fir, dtype=float))


def sample_interval_s(model) -> float:
    """The record's sample interval [s] (run/integrate.py ``output_times``)."""
    from ..system.model import STATIC_REFERENCE_PERIOD_S

    om = model.final_cage_speed()
    period = 2.0 * np.pi / om if om > 0 else STATIC_REFERENCE_PERIOD_S
    return period / model.scene.dynamics.samples_per_cage_revolution


def acceleration_attrs(interval_s: float, tapped: bool = False) -> dict:
    """The attributes that say how ``ring_acceleration`` was filtered (CF ``cell_methods``):
    ``tapped``, by the decimation filter from the taps, else by the triangle."""
    if tapped:
        from ..system.taps import TAPS_PER_INTERVAL

        tau = interval_s / TAPS_PER_INTERVAL
        return {"cell_methods": (f"time: mean (interval: {tau:.6g} s comment: low-pass "
                                 "weighted mean, the decimation filter of "
                                 "filter_fir_coefficients on the taps)"),
                "filter_transfer_function": ("sinc(f tau)^2 sum_j h_j cos(2 pi f j tau), "
                                             "tau = sample_interval_s / filter_taps_per_interval, "
                                             "h = filter_fir_coefficients (zero phase)"),
                "filter_fir_coefficients": fir_coefficients(),
                "filter_taps_per_interval": int(TAPS_PER_INTERVAL),
                "sample_interval_s": float(interval_s),
                "comment": (f"the ring displacement at {TAPS_PER_INTERVAL} taps per sample "
                            "interval, its central second difference, low-passed at the "
                            "samples' Nyquist frequency (Kaiser-windowed sinc); samples "
                            "without taps around them (the first and last of a record without "
                            "them, Newmark-beta) record the triangle "
                            "mean (x[k+1] - 2 x[k] + x[k-1]) / T^2, or at an end "
                            "(v[k] - v[k-1]) / T (theory.md §15)")}
    return {"cell_methods": (f"time: mean (interval: {interval_s:.6g} s comment: weighted by "
                             "a triangle over [t - T, t + T], T the sample interval)"),
            "filter_transfer_function": "sinc(f T)^2 (zero phase), T = sample_interval_s",
            "sample_interval_s": float(interval_s),
            "comment": ("(x[k+1] - 2 x[k] + x[k-1]) / T^2 of the ring displacement, exact for "
                        "the triangle mean; the first and last sample: (v[k] - v[k-1]) / T, the "
                        "interval mean (theory.md §15)")}


def natural_frequencies_Hz(model) -> np.ndarray:
    """The ring's natural frequencies on the bearing [Hz], ascending (module docstring);
    computed once per model."""
    cached = getattr(model, "_ring_natural_frequencies_Hz", None)
    if cached is not None:
        return cached
    from ..physics.geometry import make_geometry
    from ..solvers import static
    from ..system.residual import PARAM_NAMES

    sc = model.scene
    g = make_geometry(sc)
    P = dict(zip(PARAM_NAMES, model.params))
    loads = np.asarray(model.loads_series(np.array([float(model.ramp_t[-1])]))[0, :4], float)
    w = float(model.ramp_w[-1])
    Z = g.rollers
    support = float(sc.ring.support_stiffness_N_m)
    # steps: 1 % of the load scale (force), of the load scale times half the roller length
    # (moment): small against the load, large against the solve's tolerance
    F_ref = max(abs(loads[0]), abs(loads[1]), 100.0)
    steps = np.array([0.01 * F_ref, 0.01 * F_ref, 0.005 * F_ref * g.roller_length_m,
                      0.005 * F_ref * g.roller_length_m])

    def ring(L):
        prob = static.make_problem(g, L, w, sc.numerics.contact_smoothing_m,
                                   support_N_m=support)
        return static.solve(prob).z[2 * Z:2 * Z + 4]

    tilt = bool(model.layout.tilt)
    dofs = 4 if tilt else 2
    C = np.zeros((dofs, dofs))
    for j in range(dofs):
        d = np.zeros(4)
        d[j] = steps[j]
        C[:, j] = (ring(loads + d)[:dofs] - ring(loads - d)[:dofs]) / (2.0 * steps[j])
    M = np.diag([P["ring_m"], P["ring_m"], P["ring_I"], P["ring_I"]][:dofs])
    lam = np.linalg.eigvals(np.linalg.solve(M, np.linalg.inv(C))).real
    f = np.sort(np.sqrt(np.maximum(lam, 0.0))) / (2.0 * math.pi)
    model._ring_natural_frequencies_Hz = f
    return f


def samples_to_resolve(f_Hz: float, interval_s: float, samples_per_rev: int) -> int:
    """The ``numerics.samples_per_cage_revolution`` whose Nyquist frequency puts ``f_Hz`` at
    :data:`RESOLVED_FRACTION_OF_NYQUIST` of it, rounded up to a multiple of 50."""
    period = interval_s * samples_per_rev
    need = 2.0 * f_Hz * period / RESOLVED_FRACTION_OF_NYQUIST
    return int(50 * math.ceil(need / 50.0))


def vibration_attrs(model) -> dict:
    """Global attributes of a dynamic-ring run: its natural frequencies (JSON, Hz), the
    samples' Nyquist frequency and, when the sampling cannot resolve the first natural
    frequency, ``ring_vibration_note``: one line naming the setting that would."""
    interval = sample_interval_s(model)
    per_rev = int(model.scene.dynamics.samples_per_cage_revolution)
    try:
        f = natural_frequencies_Hz(model)
    except Exception as exc:  # noqa: BLE001 - an estimate only: its failure is said, not fatal
        return {"ring_vibration_note": f"ring natural frequencies not estimated "
                                       f"({type(exc).__name__}: {exc})"}
    nyquist = 0.5 / interval
    attrs = {"ring_natural_frequencies_Hz": json.dumps([round(float(x), 1) for x in f]),
             "nyquist_frequency_Hz": float(nyquist)}
    if f.size and f[0] > RESOLVED_FRACTION_OF_NYQUIST * nyquist:
        attrs["ring_vibration_note"] = (
            f"first natural frequency {f[0] / 1e3:.3g} kHz (highest {f[-1] / 1e3:.3g} kHz) "
            f"above {RESOLVED_FRACTION_OF_NYQUIST:g} of the samples' Nyquist frequency "
            f"{nyquist / 1e3:.3g} kHz: ring_acceleration is low-passed below it and shows no "
            f"ring mode; numerics.samples_per_cage_revolution = "
            f"{samples_to_resolve(f[0], interval, per_rev)} would resolve the first "
            f"({samples_to_resolve(f[-1], interval, per_rev)} the highest)")
    return attrs
