"""Running extremes at every accepted solver step: the peaks a sampled record misses.

Stage: system (DAE model) -> solvers (IDA's root-function hook, Newmark's step loop) ->
results (``<variable>_max`` and ``<variable>_max_time``). An impact of a roller on a pocket bar
lasts a few µs, IDA's steps ~0.6 µs, output samples 50-300 µs apart: the largest pocket force
of a run is found between samples. :func:`update_extremes` is called by the integrator after
every accepted step, with the step's time and its accepted (scaled) state; it keeps, per roller
(and slice and race where that applies), the largest magnitude of

* ``cage_force``: the pocket forces F_a, F_b on the two roller ends (theory.md §8);
* ``skew_angle``: |θz|, from the accepted state;
* ``contact_force`` and ``slip_velocity``: the slice loads q and slip velocities V (theory.md
  §4, §6);

and the time at which each was reached. Pocket forces, slice loads and slips are those the
kernel left in its work arrays at its last evaluation of the step: the last corrector iterate
of the accepted step (or the Jacobian's evaluation at the same point, which leaves the same
loads, slips and pocket forces), within the solver's Newton tolerance of the accepted state.
Evaluating them again at the accepted state would cost a residual evaluation per step (+40 %
run time; the pocket forces alone, 40 laws, +10 %); reading the arrays costs ~0.5 µs. (With the finite-difference Jacobian the last evaluation
may be one of its perturbed states, ~1e-8 relative away.) The largest Hertz pressure follows
from the largest slice load (p is increasing in q; results/dataset.py). Only steps ending at or after the start
of the recorded window count (``t_from``), and no interpolated state: so the extremes do not
depend on how densely the run is sampled.

Besides the maxima over the whole window, the buffer keeps the **interval peaks**: per
quantity of :data:`PEAKS`, the largest magnitude over the whole bearing since the last output
sample. The solver base closes the interval at each sample (:meth:`Extremes.close_interval`),
which gives a peak trace at the sample rate that misses nothing between samples (the steps
folded at a sample are those accepted before it; IDA's hook folds the step that crosses a
sample time in the next interval). The statistics of the peaks (analysis/statistics.py) are
made of it.

The buffer is one float64 array (the compiled callbacks get it by address through
``user_data``): a header (with the interval peaks), then a (max, time) block per quantity.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..physics.compiled import helper

from .arrayview import c_view
from .residual import A_SK

# ---- header of the buffer: window start, steps counted, sizes; for IDA's hook (solvers/
# sundials/callbacks.py) whether it is armed, the relative tolerance and the current time ----
H_FROM, H_COUNT, H_Z, H_K, H_ARMED, H_RTOL, H_TNOW = 0, 1, 2, 3, 4, 5, 6
#: the interval peaks (largest magnitude over the bearing since the last sample), one slot per
#: name of PEAKS from H_PEAK on
H_PEAK = 8
H_SIZE = 16

#: quantities kept at every step: name -> shape after (rollers, slices) are known
QUANTITIES = ("cage_force", "skew_angle", "contact_force", "slip_velocity")
#: the interval peaks, in their header order: the slice loads per race (their Hertz pressures
#: differ by the race's radius)
PEAKS = ("cage_force", "skew_angle", "contact_force_inner", "contact_force_outer",
         "slip_velocity")


def _shapes(Z: int, k: int) -> dict[str, tuple]:
    return {"cage_force": (Z, 2), "skew_angle": (Z,), "contact_force": (Z, k, 2),
            "slip_velocity": (Z, k, 2)}


def _offsets(Z: int, k: int) -> tuple[dict, int]:
    """Offset of each (max, time) block in the buffer, and the buffer's size."""
    o = H_SIZE
    out = {}
    for name, shape in _shapes(Z, k).items():
        n = int(np.prod(shape))
        out[name] = (o, o + n)
        o += 2 * n
    return out, o


def requested(scene) -> bool:
    """Does the scene's output selection (``output.variables``) ask for any extreme? All by
    default; a list asks only for those it names (then a run without them pays nothing)."""
    from ..scene import EXTREME_VARIABLES

    wanted = scene.output_variables
    return wanted is None or any(name in EXTREME_VARIABLES for name in wanted)


class Extremes:
    """The running-extremes buffer of one run (``Z`` rollers, ``k`` slices), counting steps
    from ``t_from`` [s] on. ``buffer`` is what :func:`update_extremes` updates."""

    def __init__(self, rollers: int, slices: int, t_from: float):
        self.rollers, self.slices, self.t_from = int(rollers), int(slices), float(t_from)
        #: steps were folded in from this time on (later than t_from in a resumed run, whose
        #: earlier part the results take from its samples)
        self.steps_from = self.t_from
        self._off, size = _offsets(self.rollers, self.slices)
        E = np.zeros(size)
        E[H_FROM] = t_from
        E[H_Z], E[H_K] = rollers, slices
        for a, b in self._off.values():
            E[a:b] = -np.inf
            E[b:b + (b - a)] = np.nan
        E[H_PEAK:H_PEAK + len(PEAKS)] = -np.inf
        self.buffer = E
        #: the closed intervals: sample times and their peaks (8 bytes per quantity and
        #: sample, as the statistics series of a streamed run)
        self._peak_t: list[float] = []
        self._peaks: list[np.ndarray] = []
        self.absorbed = False  #: an earlier part was folded in (:meth:`absorb`)

    def close_interval(self, t: float) -> None:
        """End the interval at the sample at ``t``: keep its peaks (NaN: no step in it) if the
        sample is in the window, and start the next."""
        E, a = self.buffer, H_PEAK
        if t >= self.t_from:
            self._peak_t.append(float(t))
            self._peaks.append(E[a:a + len(PEAKS)].copy())
        E[a:a + len(PEAKS)] = -np.inf

    def interval_peaks(self) -> tuple[np.ndarray, np.ndarray]:
        """(sample times (n,), peaks (n, len(PEAKS))) of the closed intervals in the window,
        NaN where no step counted."""
        P = np.array(self._peaks).reshape(-1, len(PEAKS))
        P[~np.isfinite(P)] = np.nan
        return np.array(self._peak_t), P

    def closed_peaks(self, t: float) -> np.ndarray:
        """The peaks of the interval closed at the sample at ``t`` (NaN: none closed there,
        the sample is before the window): what a checkpoint keeps per sample."""
        if self._peak_t and self._peak_t[-1] == float(t):
            return self._peaks[-1].copy()
        return np.full(len(PEAKS), np.nan)

    def maxima(self) -> np.ndarray:
        """The steps counted and the (max, time) blocks, flat: what a checkpoint keeps of the
        window so far (:meth:`absorb` folds it back)."""
        return np.concatenate([[self.buffer[H_COUNT]], self.buffer[H_SIZE:]])

    def absorb(self, maxima: np.ndarray, peak_t, peaks) -> None:
        """Fold in the earlier part of the same window, kept by a checkpoint (a resumed run):
        its ``maxima`` (:meth:`maxima`; the earlier time wins a tie, as over the whole) and
        the interval peaks of its samples (times ``peak_t``, rows ``peaks``; those before
        the window are dropped). The steps then cover the whole window (``steps_from``)."""
        E = self.buffer
        if maxima.shape != (1 + E.size - H_SIZE,):
            raise ValueError(f"kept extremes of size {maxima.size}, expected "
                             f"{1 + E.size - H_SIZE} (another bearing?)")
        for a, b in self._off.values():
            n = b - a
            m = maxima[1 + a - H_SIZE:1 + b - H_SIZE]
            tm = maxima[1 + b - H_SIZE:1 + b + n - H_SIZE]
            take = m >= E[a:b]
            E[a:b] = np.where(take, m, E[a:b])
            E[b:b + n] = np.where(take, tm, E[b:b + n])
        E[H_COUNT] += maxima[0]
        keep = [i for i, t in enumerate(peak_t) if t >= self.t_from]
        self._peak_t = [float(peak_t[i]) for i in keep] + self._peak_t
        self._peaks = [np.array(peaks[i], dtype=float) for i in keep] + self._peaks
        self.steps_from = self.t_from
        self.absorbed = True

    @property
    def steps(self) -> int:
        """Steps that counted (ended in the window)."""
        return int(self.buffer[H_COUNT])

    def result(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """name -> (largest magnitude, time of it) (copies; NaN where no step counted)."""
        shapes = _shapes(self.rollers, self.slices)
        out = {}
        for name, (a, b) in self._off.items():
            m = self.buffer[a:b].copy()
            t = self.buffer[b:b + (b - a)].copy()
            m[~np.isfinite(m)] = np.nan
            out[name] = (m.reshape(shapes[name]), t.reshape(shapes[name]))
        return out


@helper
def _fold(a, m, tm, t, absolute, E, even, odd):
    """m = max(m, |a|) element by element, tm = t where it grew; and the interval peaks
    E[even] = max(E[even], max |a[0::2]|), E[odd] likewise over a[1::2] (the same slot for a
    quantity kept over all elements). First a read-only count of the elements that raise
    either (it vectorises; the stores of an updating loop, which might alias ``a``, do not,
    nor does a running maximum without fast-math), then the updating loops only if one does:
    after the first revolution almost no step raises a maximum, and an interval's peak is
    raised by its first steps."""
    n = a.shape[0]
    p0, p1 = E[even], E[odd]
    grow = 0
    peak = 0
    if absolute:
        for i in range(n):
            x = abs(a[i])
            grow += x > m[i]
            peak += x > (p1 if i & 1 else p0)
    else:
        for i in range(n):
            x = a[i]
            grow += x > m[i]
            peak += x > (p1 if i & 1 else p0)
    if grow > 0:
        for i in range(n):
            v = abs(a[i]) if absolute else a[i]
            if v > m[i]:
                m[i] = v
                tm[i] = t
    if peak > 0:
        for i in range(n):
            v = abs(a[i]) if absolute else a[i]
            if i & 1:
                if v > E[odd]:
                    E[odd] = v
            elif v > E[even]:
                E[even] = v


@njit(cache=True, error_model="numpy", no_cfunc_wrapper=True)
def update_extremes(t, y, S, lmap, q, v, fp, E):
    """Fold the accepted step (t, scaled state y) into the extremes buffer E (module docstring):
    skew from y (unscaled by S, its place in each roller's block from ``lmap``), slice loads q,
    slips v and pocket forces fp from the kernel's work arrays (system/residual.py), which
    hold its last evaluation."""
    if t < E[H_FROM]:
        return
    Z, k = q.shape[0], q.shape[1]
    nl = lmap.shape[0]
    o = H_SIZE
    # cage_force (Z, 2)
    n = 2 * Z
    _fold(c_view(fp, (n,)), E[o:o + n], E[o + n:o + 2 * n], t, True, E, H_PEAK, H_PEAK)
    o += 2 * n
    # skew_angle (Z,): its place in the compact roller block (absent: the extremes stay NaN)
    sk = -1
    for a in range(nl):
        if lmap[a] == A_SK:
            sk = a
    if sk >= 0:
        for j in range(Z):
            i = j * nl + sk
            a = abs(y[i] * S[i])
            if a > E[o + j]:
                E[o + j] = a
                E[o + Z + j] = t
            if a > E[H_PEAK + 1]:
                E[H_PEAK + 1] = a
    o += 2 * Z
    # contact_force, slip_velocity (Z, k, 2)
    n = Z * k * 2
    # race is the last index: inner at even, outer at odd places
    _fold(c_view(q, (n,)), E[o:o + n], E[o + n:o + 2 * n], t, False, E, H_PEAK + 2,
          H_PEAK + 3)
    o += 2 * n
    _fold(c_view(v, (n,)), E[o:o + n], E[o + n:o + 2 * n], t, True, E, H_PEAK + 4,
          H_PEAK + 4)
    E[H_COUNT] += 1.0
