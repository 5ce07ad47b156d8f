"""The inner ring as a body (``physics.ring = "dynamic"``, theory.md §15).

References: the layout (no ring velocity without the switch); a single-degree-of-freedom
oscillator (the ring's mass on the bearing's radial stiffness from two static solves, plus the
support) for the free vibration after a load step at standstill; the quasi-static run, which the
dynamic ring must settle to under constant load; Newmark-β against IDA.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from bearingdae import simulate, solve_static
from bearingdae.system.model import build_model
from tests.conftest import make_scene


def _run(scene, solver="ida"):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return simulate(scene, solver=solver, progress=False)


def test_only_a_dynamic_ring_has_ring_velocities():
    qs = build_model(make_scene(operating={"radial_load_N": 800.0}))
    dyn = build_model(make_scene(operating={"radial_load_N": 800.0},
                                 physics={"ring": "dynamic"}))
    assert not any(n.startswith("ring_v") or n.startswith("ring_w")
                   for n in qs.layout.global_names)
    assert dyn.size == qs.size + 4
    for name in ("ring_dr", "ring_dt", "ring_gr", "ring_gt"):
        assert qs.layout.algebraic[qs.layout.index(name)]
        assert not dyn.layout.algebraic[dyn.layout.index(name)]
        assert dyn.mass[dyn.layout.index(name)] > 0.0
    # mass of the yang20 ring: a steel annulus bore 30 mm to raceway 41 mm, 25.5 mm long
    m = 7850.0 * math.pi * (0.0205**2 - 0.015**2) * 0.0255
    i = dyn.layout.index("ring_vr")
    assert dyn.mass[i] * dyn.row_scale[i] / dyn.scale[i] == pytest.approx(m, rel=1e-12)
    nt = build_model(make_scene(physics={"ring": "dynamic", "tilt": False}))
    assert "ring_wr" not in nt.layout.global_names and nt.size == qs.size - 20 - 2 + 2


@pytest.mark.parametrize("support_N_m, damping_N_s_m", [(0.0, 0.0), (3e8, 400.0)])
def test_free_vibration_after_a_load_step_is_the_single_dof_oscillator(support_N_m,
                                                                       damping_N_s_m):
    """At standstill a load step of 2 % sets the ring vibrating about the new equilibrium at
    ω_n = sqrt((K + k_s) / m), K the bearing's radial stiffness (secant of two static solves),
    and decaying at the damping ratio ζ = c / (2 sqrt((K + k_s) m)) of the support.
    Tolerances: 1 % on the frequency (K is a secant over the step, the stiffness is not
    linear; measured 0.3 %), 10 % on ζ (log decrement over 6 periods of a sampled signal)."""
    F0, F1 = 800.0, 816.0
    base = {"speed_rpm": 0.0, "radial_load_N": F0}
    kw = {"physics": {"ring": "dynamic", "tilt": False},
          "ring": {"support_stiffness_N_m": support_N_m, "support_damping_N_s_m": damping_N_s_m}}

    def static_displacement(load_N):
        ds = solve_static(make_scene(operating={**base, "radial_load_N": load_N}, **kw))
        return float(ds.ring_displacement[0])

    K_total = (F1 - F0) / (static_displacement(F1) - static_displacement(F0))  # bearing + k_s
    scene = make_scene(
        operating={**base, "radial_load_N": {"times_s": [0.0, 1e-6], "values_N": [F0, F1]}},
        numerics={"warmup_cage_revolutions": 0.0, "cage_revolutions": 0.1,
                  "samples_per_cage_revolution": 20000, "rtol": 1e-9}, **kw)
    model = build_model(scene)
    i = model.layout.index("ring_vr")
    mass = float(model.mass[i] * model.row_scale[i] / model.scale[i])
    ds = _run(scene)
    t, x = ds.time.values, ds.ring_displacement.values[:, 0] - static_displacement(F1)
    omega = math.sqrt(K_total / mass)
    zeta = damping_N_s_m / (2.0 * math.sqrt(K_total * mass))
    up = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    tz = t[up] - x[up] * (t[up + 1] - t[up]) / (x[up + 1] - x[up])
    period = np.diff(tz[:7]).mean()
    assert 2 * math.pi / period == pytest.approx(omega * math.sqrt(1.0 - zeta**2), rel=1e-2)
    if zeta > 0:
        peaks = [x[a:b].max() for a, b in zip(up[:6], up[1:7])]
        delta = np.log(peaks[0] / peaks[-1]) / (len(peaks) - 1)
        assert delta / math.sqrt(4 * math.pi**2 + delta**2) == pytest.approx(zeta, rel=0.1)


@pytest.fixture(scope="module")
def baseline_pair():
    over = {"numerics.warmup_cage_revolutions": 0.25, "numerics.cage_revolutions": 1.0,
            "numerics.samples_per_cage_revolution": 100}
    sc = {"operating": {"speed_rpm": 2000.0, "radial_load_N": 800.0, "moment_Nm": 3.0}}
    qs = _run(make_scene(over, **sc))
    dyn_scene = make_scene(over, physics={"ring": "dynamic"}, **sc)
    return qs, _run(dyn_scene), dyn_scene


def test_dynamic_ring_settles_to_the_quasi_static_ring(baseline_pair):
    """Constant load (800 N, 3 N m, 2000 r/min): the mean ring displacement and tilt over the
    last cage revolution within 1 % of the quasi-static run's (measured: 1e-5); the components
    that are zero on average within 1 % of the radial ones."""
    qs, dyn, _ = baseline_pair
    for name in ("ring_displacement", "ring_tilt"):
        a, b = dyn[name].mean("time").values, qs[name].mean("time").values
        assert abs(a[0] / b[0] - 1.0) < 1e-2, (name, a, b)
        assert abs(a[1] - b[1]) < 1e-2 * abs(b[0]), (name, a, b)
    assert "ring_velocity" in dyn and "ring_velocity" not in qs
    assert dyn.ring_acceleration.attrs["units"] == "m s-2"


def test_newmark_agrees_with_ida_on_a_dynamic_ring(baseline_pair):
    """Solver cross-check measures (theory.md §12): mean cage speed within 1e-3, ring
    displacement RMS within 1e-2."""
    _, ida, scene = baseline_pair
    nm = _run(scene, solver="newmark")
    assert abs(float(nm.cage_speed.mean() / ida.cage_speed.mean()) - 1.0) < 1e-3

    def rms(ds):
        d = ds.ring_displacement.values
        return float(np.sqrt((d**2).sum(-1).mean()))

    assert abs(rms(nm) / rms(ida) - 1.0) < 1e-2
