"""External loads on the inner ring as functions of time (theory.md §14).

Stage: physics, between the scene's load histories and the inner-ring balance of the DAE
(system/residual.py) and the static solve (solvers/algebraic.py). One formula each, written
once and compiled inline into the kernels (physics/compiled.py), plain numpy from Python:

- Load history (a scene table ``{times_s, values_N}`` or a load file): the loads
  (F_r, F_t, M, M_t, F_a) piecewise linear in t through the rows of ``table`` = [[t, F_r, F_t,
  M, M_t, F_a], ...] (one common time grid), held at the first row before it and the last after
  it; one row is a constant load. The axial load F_a (theory.md §16) is one more column of the
  same table, so every load follows one interpolation law.
- Shaft angle ψ(t) = ∫₀ᵗ ω_i dt of the piecewise-linear speed ramp (held after its end), exact
  (trapezoids per ramp segment).
- Rotating (unbalance) load of amplitude U turning with the shaft (Harris & Kotzalas,
  *Rolling Bearing Analysis*, 5th ed., Vol. 1 §1: a load rotating with the inner ring):
  ΔF_r = U cos(ψ + φ_U), ΔF_t = U sin(ψ + φ_U), added to F_r (towards φ = 0) and F_t
  (towards φ = 90°); φ_U is the unbalance phase at t = 0.
"""

from __future__ import annotations

import math

import numpy as np

from .compiled import law

#: columns of a load table row: time, the four loads of theory.md §5, the axial load (§16)
TABLE_COLUMNS = ("time_s", "radial_load_N", "tangential_load_N", "moment_Nm",
                 "tangential_moment_Nm", "axial_load_N")


@law
def shaft_angle(t, ramp_t, ramp_w):
    """ψ(t) = ∫₀ᵗ ω_i dt [rad] for the piecewise-linear speed ramp (ramp_t, ramp_w) [s, rad/s],
    ω_i = ramp_w[0] before ramp_t[0] and held at ramp_w[-1] after the last point."""
    n = ramp_t.shape[0]
    if n == 1 or t <= ramp_t[0]:
        return ramp_w[0] * t
    psi = ramp_w[0] * ramp_t[0]
    for i in range(1, n):
        t0, t1 = ramp_t[i - 1], ramp_t[i]
        if t <= t1:
            w_t = ramp_w[i - 1] + (t - t0) / (t1 - t0) * (ramp_w[i] - ramp_w[i - 1])
            return psi + 0.5 * (ramp_w[i - 1] + w_t) * (t - t0)
        psi += 0.5 * (ramp_w[i - 1] + ramp_w[i]) * (t1 - t0)
    return psi + ramp_w[n - 1] * (t - ramp_t[n - 1])


@law
def table_loads(t, table):
    """(F_r, F_t, M, M_t, F_a) [N, N, N m, N m, N] at t from ``table`` (rows :data:`TABLE_COLUMNS`):
    piecewise linear, held before the first and after the last row."""
    n = table.shape[0]
    if n == 1 or t <= table[0, 0]:
        return table[0, 1], table[0, 2], table[0, 3], table[0, 4], table[0, 5]
    if t >= table[n - 1, 0]:
        return (table[n - 1, 1], table[n - 1, 2], table[n - 1, 3], table[n - 1, 4],
                table[n - 1, 5])
    lo, hi = 0, n - 1  # bisection (a load file may hold many rows): t in (t_lo, t_hi]
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if t <= table[mid, 0]:
            hi = mid
        else:
            lo = mid
    a = (t - table[lo, 0]) / (table[hi, 0] - table[lo, 0])
    return (table[lo, 1] + a * (table[hi, 1] - table[lo, 1]),
            table[lo, 2] + a * (table[hi, 2] - table[lo, 2]),
            table[lo, 3] + a * (table[hi, 3] - table[lo, 3]),
            table[lo, 4] + a * (table[hi, 4] - table[lo, 4]),
            table[lo, 5] + a * (table[hi, 5] - table[lo, 5]))


@law
def applied_loads(t, table, ramp_t, ramp_w, unbalance_N, unbalance_phase_rad):
    """(F_r, F_t, M, M_t, F_a) acting on the inner ring at t: the load history plus the
    rotating unbalance load (module docstring). Without an unbalance the history's values are
    returned unchanged (bit for bit)."""
    Fr, Ft, M, Mt, Fa = table_loads(t, table)
    if unbalance_N != 0.0:
        psi = shaft_angle(t, ramp_t, ramp_w) + unbalance_phase_rad
        Fr += unbalance_N * math.cos(psi)
        Ft += unbalance_N * math.sin(psi)
    return Fr, Ft, M, Mt, Fa


def applied_load_series(t, table, ramp_t, ramp_w, unbalance_N, unbalance_phase_rad):
    """:func:`applied_loads` at every time of ``t`` (n,), as an (n, 5) array (outputs)."""
    out = np.empty((len(t), 5))
    tb, rt, rw = (np.asarray(a, float) for a in (table, ramp_t, ramp_w))
    for i, tk in enumerate(np.asarray(t, float)):
        out[i] = applied_loads(float(tk), tb, rt, rw, float(unbalance_N),
                               float(unbalance_phase_rad))
    return out
