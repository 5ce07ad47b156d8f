"""Running extremes at every accepted solver step: the peaks a sampled record misses.

Stage: system (DAE model) -> solvers (IDA's root-function hook, Newmark's step loop) ->
results (``<variable>_max`` and ``<variable>_max_time``). An impact of a roller on a pocket bar
lasts a few µs, IDA's steps ~0.6 µs, output samples 50-300 µs apart: the largest pocket force
of a run is found between samples. :func:`update_extremes` is called by the integrator after
every accepted step, with the step's time and its accepted (scaled) state; it keeps, per roller
(and slice and race where that applies), the largest magnitude of

* ``cage_force``: the pocket forces F_a, F_b on the two roller ends (theory.md §8), evaluated
  at the accepted state by the residual's own law (residual.pocket_end_forces);
* ``skew_angle``: |θz|, from the accepted state;
* ``contact_force`` and ``slip_velocity``: the slice loads q and slip velocities V (theory.md
  §4, §6) as the kernel left them at its last evaluation of the step: the last corrector
  iterate of the accepted step (or the Jacobian's evaluation at the same point), within the
  solver's Newton tolerance of the accepted state. Evaluating them again at the accepted
  state would cost a residual evaluation per step (+40 % run time); the last iterate costs
  a scan of the arrays (~1 µs).

and the time at which each was reached. The largest Hertz pressure follows from the largest
slice load (p is increasing in q; results/dataset.py). Only steps ending at or after the start
of the recorded window count (``t_from``), and not the evaluations IDA makes at output times
(interpolated states): so the extremes do not depend on how densely the run is sampled.

The buffer is one float64 array (the compiled callbacks get it by address through
``user_data``): a header, scratch for the unscaled state, then (max, time) blocks.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .arrayview import c_view
from .residual import A_OM, A_SK, A_SR, A_TH, G_TC, G_WC, P_CAGE, pocket_end_forces

# ---- header of the buffer ----
H_FROM, H_TOUT, H_TOUT_PREV, H_COUNT, H_Z, H_K = 0, 1, 2, 3, 4, 5
H_SIZE = 8
NL_FULL, NG_FULL = 7, 6  # full local / global unknowns (system/layout.py LOCAL, GLOBAL)

#: quantities kept at every step: name -> shape after (rollers, slices) are known
QUANTITIES = ("cage_force", "skew_angle", "contact_force", "slip_velocity")


def _shapes(Z: int, k: int) -> dict[str, tuple]:
    return {"cage_force": (Z, 2), "skew_angle": (Z,), "contact_force": (Z, k, 2),
            "slip_velocity": (Z, k, 2)}


def _offsets(Z: int, k: int) -> tuple[dict, int]:
    """Offset of each (max, time) block in the buffer, and the buffer's size."""
    o = H_SIZE + Z * NL_FULL + NG_FULL
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
        E[H_FROM], E[H_TOUT], E[H_TOUT_PREV] = t_from, np.nan, np.nan
        E[H_Z], E[H_K] = rollers, slices
        for a, b in self._off.values():
            E[a:b] = -np.inf
            E[b:b + (b - a)] = np.nan
        self.buffer = E

    def output_time(self, t: float) -> None:
        """The integrator is about to advance to the output time ``t``: evaluations there (and
        at the previous one) are interpolated states, not steps, and do not count."""
        E = self.buffer
        E[H_TOUT_PREV] = E[H_TOUT]
        E[H_TOUT] = t

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


@njit(cache=True, error_model="numpy")
def update_extremes(t, y, d, E):
    """Fold the accepted step (t, scaled state y) into the extremes buffer E (module docstring);
    ``d``: the model's work tuple (system/residual.py), holding the kernel's last evaluation."""
    if t < E[H_FROM] or t == E[H_TOUT] or t == E[H_TOUT_PREV]:
        return
    P, S, lmap, gmap = d[0], d[3], d[5], d[6]
    q, v = d[16], d[18]
    Z, k = q.shape[0], q.shape[1]
    nl, ng = lmap.shape[0], gmap.shape[0]
    # the unscaled full state (switched-off unknowns stay at the buffer's zeros)
    yl = H_SIZE
    yg = H_SIZE + Z * NL_FULL
    for j in range(Z):
        for a in range(nl):
            i = j * nl + a
            E[yl + j * NL_FULL + lmap[a]] = y[i] * S[i]
    base = Z * nl
    for b in range(ng):
        E[yg + gmap[b]] = y[base + b] * S[base + b]
    o = yg + NG_FULL
    # cage_force (Z, 2): at the accepted state
    n = 2 * Z
    if P[P_CAGE] > 0.5:
        tc, wc = E[yg + G_TC], E[yg + G_WC]
        for j in range(Z):
            r = yl + j * NL_FULL
            Fa, Fb = pocket_end_forces(E[r + A_TH], E[r + A_OM], E[r + A_SK], E[r + A_SR], tc,
                                       wc, j, Z, P)
            Fa, Fb = abs(Fa), abs(Fb)
            if Fa > E[o + 2 * j]:
                E[o + 2 * j] = Fa
                E[o + n + 2 * j] = t
            if Fb > E[o + 2 * j + 1]:
                E[o + 2 * j + 1] = Fb
                E[o + n + 2 * j + 1] = t
    o += 2 * n
    # skew_angle (Z,): at the accepted state
    for j in range(Z):
        s = abs(E[yl + j * NL_FULL + A_SK])
        if s > E[o + j]:
            E[o + j] = s
            E[o + Z + j] = t
    o += 2 * Z
    # contact_force, slip_velocity (Z, k, 2): the kernel's last evaluation
    n = Z * k * 2
    qf, vf = c_view(q, (n,)), c_view(v, (n,))
    for i in range(n):
        if qf[i] > E[o + i]:
            E[o + i] = qf[i]
            E[o + n + i] = t
    o += 2 * n
    for i in range(n):
        a = abs(vf[i])
        if a > E[o + i]:
            E[o + i] = a
            E[o + n + i] = t
    E[H_COUNT] += 1.0
