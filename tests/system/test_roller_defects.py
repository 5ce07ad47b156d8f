"""Defects and waviness on a roller (system/defects.py): the rollers' spin angles as unknowns.

References: the contact points typed afresh (the roller's surface point at angle a meets the
outer race where a = -φ and the inner race where a = π - φ, φ its spin angle, 0 at t = 0)
(the sliced Palmgren law with the approach reduced by a roller spall's depth:
tests/system/test_defect_rows.py); central
differences of the residual for the analytic Jacobian; the rolling kinematics (the contact
point runs over the roller's surface at ω r, ω the spin speed relative to the cage) for the
force drop; Newmark-β, the independent integrator, for IDA.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearingdae import solve_static
from bearingdae.physics.geometry import make_geometry
from bearingdae.scene import scene_from_dict

#: a spall on roller 0 (on the load line at t = 0), 6 mm wide: slices 5 and 6 of 10 lie
#: wholly inside it
SPALL = {"on": "roller", "roller": 0, "length_mm": 1.0, "width_mm": 6.0, "edge_mm": 0.1}


def _scene(defects=(), waviness=()):
    """yang20 at 2000 N and 2000 r/min, no moment, with the entries given."""
    return scene_from_dict({"bearing": {"preset": "yang20"}, "defects": list(defects),
                            "waviness": list(waviness), "operating": {
                                "radial_load_N": 2000.0, "moment_Nm": 0.0,
                                "speed_rpm": 2000.0}})


def test_spin_angles_are_unknowns_only_with_a_roller_surface():
    """Z spin angles more with a defect or waviness on a roller; none with a race's or none."""
    from bearingdae.system.model import build_model

    healthy = build_model(_scene()).layout
    race = build_model(_scene([dict(SPALL, on="outer", roller=None, depth_um=5.0)])).layout
    roller = build_model(_scene([dict(SPALL, depth_um=5.0)])).layout
    wavy = build_model(_scene(waviness=[{"on": "roller", "order": 2, "amplitude_um": 0.2}]))
    assert "spin_angle" not in healthy.local_names and race.size == healthy.size
    assert roller.size == healthy.size + healthy.rollers
    assert wavy.layout.size == roller.size
    i = roller.index("spin_angle", 3)
    assert roller.names()[i] == "spin_angle[3]" and not roller.algebraic[i]


@pytest.mark.parametrize("contact, angle_deg", [("outer", 0.0), ("inner", 180.0)])
def test_a_deep_roller_spall_unloads_the_contact_it_faces(contact, angle_deg):
    """At t = 0 (φ = 0) a spall centred at a = 0 faces the outer race, at a = π the inner one:
    the covered slices of that contact carry no load, the other contact's stay loaded."""
    s = _scene([dict(SPALL, angle_deg=angle_deg, depth_um=30.0)])
    g = make_geometry(s)
    cov = np.flatnonzero(np.abs(g.x_m) + 0.5 * g.slice_width_m <= 3e-3)
    assert list(cov) == [4, 5]
    other = "inner" if contact == "outer" else "outer"
    ds = solve_static(s)
    healthy = solve_static(_scene()).contact_force.sel(race=contact).values
    assert healthy[0, cov].min() > 50.0
    assert ds.contact_force.sel(race=contact).values[0, cov].max() < 1e-6
    assert ds.contact_force.sel(race=other).values[0, cov].min() > 50.0


@pytest.mark.slow
def test_analytic_jacobian_with_roller_defects_matches_central_differences():
    """A spall on roller 0 with its outer contact on the spall's ramp, roller waviness on every
    roller: central differences of the residual against the analytic iteration matrix (the
    bound of tests/system/test_defect_rows.py), and the spin angle's column is exercised."""
    from bearingdae.solvers.algebraic import initial_state
    from bearingdae.solvers.ida import check_jacobian
    from bearingdae.system.model import build_model

    r = make_geometry(_scene()).roller_radius_m
    on_ramp = math.degrees(0.45e-3 / r)  # the outer contact (a = 0) 0.45 mm from the centre
    s = _scene([dict(SPALL, angle_deg=on_ramp, depth_um=2.0)],
               [{"on": "roller", "order": 3, "amplitude_um": 0.5, "phase_deg": 20.0}])
    m = build_model(s)
    y0, yp0 = initial_state(m)
    res = m.residual(0.0, y0, np.zeros_like(y0))
    assert np.abs(res[m.layout.algebraic]).max() < 1e-9  # the static solve saw the defects
    assert check_jacobian(m, y0, yp0, jacobian="analytic", rel_step=1e-7) < 2e-4
    # the radial balance of roller 0 along its spin angle: analytic against central differences
    from bearingdae.solvers.common import jacobian_filler

    jd, fill, _ = jacobian_filler(m, "analytic")
    fill(0.0, y0, yp0, 0.0, m.data, jd)
    J = jd[0]
    row = m.layout.index("radial_position", 0)
    col = m.layout.index("spin_angle", 0)
    h = 1e-6
    e = np.zeros_like(y0)
    e[col] = h
    fd = (m.residual(0.0, y0 + e, yp0)[row] - m.residual(0.0, y0 - e, yp0)[row]) / (2 * h)
    assert abs(fd) > 1e-3  # the spall's ramp: the outer load moves with φ
    assert J[row, col] == pytest.approx(fd, rel=1e-4)


@pytest.mark.slow
def test_roller_spall_force_drop_and_newmark_against_ida():
    """The bundled roller spall (with the baseline's clearance) over its first 4 ms: its spall (at a = π/2) reaches the inner
    contact (a = π - φ) at φ = π/2, ~1.3 ms. The covered slices of roller 0's inner contact lose
    their load for the time the contact point takes to run over the spall at ω r (ω its measured
    spin speed), within 10 %; the outer contact (a = -φ) is not reached before φ = 3π/2 (4 ms).
    Newmark-β agrees with IDA on roller 0's contact loads within 1 % of the largest, and on the
    ring's displacement within 0.2 % (measured: drop 1.0006 of the expected time, 0.38 %)."""
    from bearingdae import load_scene, simulate

    # the baseline's clearance (the case's preload shrinks the ring's motion to 0.3 µm, below
    # what a 0.2 % comparison of the two integrators resolves)
    s = load_scene("defects/roller_spall", {"numerics.cage_revolutions": 0.055,
                                            "numerics.warmup_cage_revolutions": 0.0,
                                            "bearing.radial_clearance_mm": 0.010})
    g = make_geometry(s)
    a = simulate(s)
    t = a.time.values
    qi = a.contact_force.isel(roller=0, slice=4).sel(race="inner").values
    qo = a.contact_force.isel(roller=0, slice=4).sel(race="outer").values
    before = qi[(t > 0.2e-3) & (t < 0.8e-3)].mean()
    assert before > 10.0  # (800 N over ~6 loaded rollers and 10 slices)
    low = qi < 0.5 * before
    assert low.any() and not low[0] and not low[-1]
    first, last = np.flatnonzero(low)[[0, -1]]
    assert np.all(low[first:last + 1])  # one drop
    spin = float(a.spin_speed.isel(roller=0)[first:last + 1].mean())
    phi_hit = spin * 0.5 * (t[first] + t[last])  # φ(t) ≈ ∫ω dt from φ(0) = 0
    assert phi_hit == pytest.approx(math.pi / 2, rel=0.05)
    duration = (last - first + 1) * (t[1] - t[0])
    assert duration == pytest.approx(1e-3 / (spin * g.roller_radius_m), rel=0.10)
    assert qo[(t > 0.2e-3)].min() > 0.5 * before  # the outer contact not yet
    b = simulate(s, solver="newmark")
    qa = a.contact_force.isel(roller=0).sum("slice")
    qb = b.contact_force.isel(roller=0).sum("slice")
    assert float(abs(qa - qb).max() / qa.max()) < 0.01  # measured 0.38 %
    ring = float(abs(a.ring_displacement).max())  # measured 3.8 nm of 6.2 µm
    assert float(abs(a.ring_displacement - b.ring_displacement).max()) < 2e-3 * ring
