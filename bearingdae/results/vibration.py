"""The dynamic ring's vibration as recorded (theory.md §15): ``ring_acceleration`` low-passed by
construction, and the ring's natural frequencies against the output sampling.

Pipeline place: results (from the projected samples of a run with ``physics.ring =
"dynamic"``; a scene with the quasi-static ring never comes here).

**Why a filter.** The ring rings at its contact resonances (yang20 at 800 N, 3 N·m: 2.2, 5.7,
7.4 and 15 kHz), far above the Nyquist frequency of the default output (200 samples per cage
revolution: ~1.5 kHz at 2000 r/min). The acceleration at the sample instants is a sampled
signal without an anti-alias filter: its spectrum below Nyquist is made of the resonances'
aliases. What a sample records must be what the signal holds below the sample's Nyquist
frequency.

**The filter.** Each sample t_k records the acceleration weighted by a triangle over the two
sample intervals around it (a linear B-spline with knots t_{k-1}, t_k, t_{k+1}, unit area):

    a_k = 2 / (h₁ + h₂) · [ (x_{k+1} − x_k) / h₂ − (x_k − x_{k-1}) / h₁ ],   h₁ = t_k − t_{k-1},
                                                                           h₂ = t_{k+1} − t_k

which is exact: integrating the triangle against x'' by parts leaves only the ring
displacements at the three knots, which are the integrator's own values there (the ring is
held by the projection of the samples). It costs nothing per solver step. On equal steps T it
is the central second difference, whose transfer function against the continuous
acceleration is

    H(f) = sinc²(f T) = [sin(π f T) / (π f T)]²          (zero phase; zeros at multiples of 1/T)

so a line at f above Nyquist is folded back weakened by H(f): −27 dB per sinc at 5/T, against
0 dB for the bare samples. In the band it lowers a line by H(f) (0.81 at 0.25 f_Nyquist, 0.57
at 0.8 f_Nyquist): :func:`transfer` is what the spectrum divides by
(results/spectrum.py). Measured on the baseline with the dynamic ring at the default sampling:
the roller-pass line at ~100× the local median of the spectrum (0.3× for the bare samples, 5×
for a boxcar, the interval mean Δv/T). The first and last sample of a record have one
neighbour only: they record the interval mean over that interval, (v_k − v_{k−1}) / h
(a boxcar, sinc(f h)); a record of one sample, the equation of motion at it.

The ring's natural frequencies (:func:`natural_frequencies_Hz`) are the modes of its mass and
tilt inertia on the bearing's static stiffness (four load perturbations of the static problem,
theory.md §5, at the recorded operating point and the initial roller azimuths). When the
lowest lies above 0.8 of the samples' Nyquist frequency (where H has fallen to 0.57), the
record cannot resolve it: :func:`vibration_attrs` says so in one line naming the sampling
that would.
"""

from __future__ import annotations

import json
import math

import numpy as np

#: the fraction of the Nyquist frequency up to which a mode counts as resolved (H = 0.57)
RESOLVED_FRACTION_OF_NYQUIST = 0.8


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


def transfer(f_Hz, interval_s: float) -> np.ndarray:
    """|H(f)| = sinc²(f T) of the recorded acceleration against the continuous one (module
    docstring), T the sample interval [s]."""
    return np.sinc(np.asarray(f_Hz, dtype=float) * interval_s) ** 2


def sample_interval_s(model) -> float:
    """The record's sample interval [s] (run/integrate.py ``output_times``)."""
    from ..system.model import STATIC_REFERENCE_PERIOD_S

    om = model.final_cage_speed()
    period = 2.0 * np.pi / om if om > 0 else STATIC_REFERENCE_PERIOD_S
    return period / model.scene.dynamics.samples_per_cage_revolution


def acceleration_attrs(interval_s: float) -> dict:
    """The attributes that say how ``ring_acceleration`` was filtered (CF ``cell_methods``)."""
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
            f"above the samples' Nyquist {nyquist / 1e3:.3g} kHz: ring_acceleration holds it "
            f"low-passed; numerics.samples_per_cage_revolution = "
            f"{samples_to_resolve(f[0], interval, per_rev)} would resolve it "
            f"({samples_to_resolve(f[-1], interval, per_rev)} the highest)")
    return attrs
