"""Local defects and waviness in the DAE (system/defects.py, physics/defects.py).

References: the line-contact law typed afresh in the test (Palmgren, δ = 1.36 η^0.9 Q^0.9 /
l^0.8, sliced), with the approach reduced by the depth; zero load where the depth exceeds
the deflection; central differences of the residual for the analytic Jacobian; the rolling
kinematics (a contact point crosses the outer race at Ω R_o) for the force drop in a run.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearingdae import solve_static
from bearingdae.physics.geometry import make_geometry
from bearingdae.scene import scene_from_dict

BASE = {"bearing": {"preset": "yang20"},
        "operating": {"radial_load_N": 2000.0, "moment_Nm": 0.0, "speed_rpm": 2000.0}}
#: a spall under roller 0 (on the load line, θ = 0), 6 mm wide: slices 5 and 6 of 10 (centres
#: ±1.275 mm, 2.55 mm wide) lie wholly inside it
SPALL = {"on": "outer", "angle_deg": 0.0, "length_mm": 2.0, "width_mm": 6.0, "edge_mm": 0.2}


def _scene(defects=(), waviness=(), **operating):
    data = {k: dict(v) for k, v in BASE.items()}
    data["operating"].update(operating)
    return scene_from_dict({**data, "defects": list(defects), "waviness": list(waviness)})


def _covered(g, half_width_m):
    return np.flatnonzero(np.abs(g.x_m) + 0.5 * g.slice_width_m <= half_width_m)


def test_a_deep_spall_unloads_the_covered_slices():
    """Depth 30 µm, far beyond the roller's deflection (a few µm): the covered slices of the
    roller on it carry no load, the others carry more than without the spall."""
    s = _scene([dict(SPALL, depth_um=30.0)])
    g = make_geometry(s)
    cov = _covered(g, 3e-3)
    assert list(cov) == [4, 5]
    q = solve_static(s).contact_force.sel(race="outer").values
    healthy = solve_static(_scene()).contact_force.sel(race="outer").values
    assert healthy[0, cov].min() > 50.0  # loaded without the spall
    assert q[0, cov].max() < 1e-6
    others = [i for i in range(g.slices) if abs(g.x_m[i]) > 3e-3 + 0.5 * g.slice_width_m]
    assert np.all(q[0, others] > healthy[0, others])


@pytest.mark.parametrize("surface", [{"on": "outer"}, {"on": "roller", "roller": 0}],
                         ids=["outer race", "roller"])
def test_a_shallow_spall_reduces_the_approach_by_its_depth(surface):
    """Depth 1 µm, less than the deflection: every slice of roller 0 follows the sliced
    Palmgren law typed here, its outer approach u + xβ - c(x) reduced by the depth times the
    slice's covered share; the spall on the outer race under roller 0, or on roller 0 facing
    the outer race at t = 0 (its spin angle 0: the surface point a = 0)."""
    depth = 1e-6
    s = _scene([dict(SPALL, depth_um=depth * 1e6, **surface)])
    g = make_geometry(s)
    ds = solve_static(s)
    q = ds.contact_force.sel(race="outer").values[0]
    u = float(ds.roller_radial_position.values[0])
    beta = float(ds.roller_tilt.values[0])
    E, nu = s.materials.youngs_modulus_Pa, s.materials.poisson_ratio
    eta = 2.0 * (1.0 - nu * nu) / E  # two steel bodies
    A = 1.36 * eta**0.9  # δ = A Q^0.9 / l^0.8 for a whole line contact
    w, L = g.slice_width_m, g.roller_length_m
    share = np.clip((np.minimum(g.x_m + w / 2, 3e-3) - np.maximum(g.x_m - w / 2, -3e-3)) / w,
                    0.0, 1.0)
    delta = u + g.x_m * beta - g.profile_drop_m - depth * share
    assert np.all(delta > 0) and share[4] == 1.0 and share[0] == 0.0
    eps = s.numerics.contact_smoothing_m  # the law's regularised positive part (1 nm)
    smooth = 0.5 * (delta + np.sqrt(delta * delta + eps * eps))
    expected = w * smooth ** (10.0 / 9.0) / (A ** (10.0 / 9.0) * L ** (1.0 / 9.0))
    np.testing.assert_allclose(q, expected, rtol=1e-7)
    assert q[4] < solve_static(_scene()).contact_force.sel(race="outer").values[0, 4]


def _on_ramps():
    """A defect on each race with a roller on its ramp (the slopes are non-zero there), and
    waviness on both races."""
    g = make_geometry(_scene())
    Ro, Ri = g.outer_race_radius_m, g.inner_race_radius_m
    az = g.azimuth0_rad
    return [dict(SPALL, angle_deg=math.degrees(az[0] - 0.9e-3 / Ro), depth_um=2.0),
            {"on": "inner", "angle_deg": math.degrees(az[1] + 0.85e-3 / Ri), "length_mm": 2.0,
             "width_mm": 8.0, "depth_um": 1.0, "edge_mm": 0.2}]


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["defects", "waviness"])
def test_analytic_jacobian_with_defects_matches_central_differences(kind):
    """Central differences of the residual at the initial state (the static solve with the
    defects, which the kernel's residual must satisfy to round-off) against the analytic
    iteration matrix; the same bound as the healthy FD tests (tests/system/test_jacobian.py)."""
    from bearingdae.solvers.algebraic import initial_state
    from bearingdae.solvers.ida import check_jacobian
    from bearingdae.system.model import build_model

    if kind == "defects":
        s = _scene(_on_ramps())
    else:
        s = _scene(waviness=[{"on": "outer", "order": 21, "amplitude_um": 0.5,
                              "phase_deg": 30.0},
                             {"on": "inner", "order": 3, "amplitude_um": 1.0}])
    m = build_model(s)
    y0, yp0 = initial_state(m)
    res = m.residual(0.0, y0, np.zeros_like(y0))
    assert np.abs(res[m.layout.algebraic]).max() < 1e-9  # the static solve saw the defects
    err = check_jacobian(m, y0, yp0, jacobian="analytic", rel_step=1e-7)
    assert err < 2e-4, err
    # the slopes matter: without them the θX columns would be off
    assert check_jacobian(m, y0, yp0, jacobian="fd", rel_step=1e-7) < 2e-3


@pytest.mark.slow
@pytest.mark.parametrize("race", ["outer", "inner"])
def test_contact_force_drops_while_a_roller_crosses_a_spall(race):
    """Roller 0 starts on the load line; a 2 mm spall deeper than the deflection meets it
    after ~1.5 ms: 10° ahead on the outer race, or -10° on the inner race, which turns with
    the shaft towards it. Its covered slices lose their load for the time the contact point
    takes to cross the spall: length / (Ω R_o) on the outer race, length / ((ω_i - Ω) R_i) on
    the inner, Ω the roller's measured orbit speed, within 10 % (the sharp edges are smoothed
    over 0.0025 mm, physics/defects.EDGE_MIN_M)."""
    from bearingdae.solvers.algebraic import initial_state
    from bearingdae.solvers.ida import integrate
    from bearingdae.system.layout import LOCAL
    from bearingdae.system.model import build_model

    length = 2e-3
    angle = 10.0 if race == "outer" else -10.0
    s = _scene([dict(SPALL, on=race, angle_deg=angle, depth_um=20.0, edge_mm=0.0)])
    m = build_model(s)
    g = m.geometry
    y0, yp0 = initial_state(m)
    t = np.linspace(0.0, 4e-3, 401)
    r = integrate(m, y0, yp0, t)
    assert r.success, r.message
    d = m.diagnostics_series(t, r.y)
    q = d["contact_force"][:, 0, 4, 0 if race == "inner" else 1]  # roller 0, a covered slice
    before = q[(t > 0.3e-3) & (t < 0.8e-3)].mean()
    low = q < 0.5 * before
    assert low.any() and not low[0] and not low[-1]
    first, last = np.flatnonzero(low)[[0, -1]]
    assert np.all(low[first:last + 1])  # one drop, not several
    duration = (last - first + 1) * (t[1] - t[0])
    full_l = np.array([m.layout.unpack(y * m.scale)[0] for y in r.y[first:last + 1]])
    orbit = full_l[:, 0, LOCAL.index("orbit_speed")].mean()
    if race == "outer":
        speed = orbit * g.outer_race_radius_m
    else:
        speed = (m.ring_speed(0.0) - orbit) * g.inner_race_radius_m
    expected = length / speed
    assert duration == pytest.approx(expected, rel=0.10), (duration, expected)
    assert q[low].max() < 1e-3 * before


@pytest.mark.slow
def test_ida_and_newmark_agree_over_a_spall():
    """The independent integrator (Newmark-β, theory.md §12) against IDA on the bundled
    outer-race spall with its dynamic ring, over the first rollers' passages (3.3 ms):
    measured 0.32 % of the largest roller load and 3.3 nm of the ring's 6.2 µm."""
    from bearingdae import load_scene, simulate

    s = load_scene("defects/outer_spall", {"numerics.cage_revolutions": 0.05,
                                           "numerics.warmup_cage_revolutions": 0.0})
    a, b = simulate(s), simulate(s, solver="newmark")
    qa = a.contact_force.sel(race="outer").sum("slice")
    qb = b.contact_force.sel(race="outer").sum("slice")
    assert float(qa.min()) < 1.0  # a roller over the spall: its centrifugal force alone
    assert float(abs(qa - qb).max() / qa.max()) < 0.01
    ring = float(abs(a.ring_displacement).max())
    assert float(abs(a.ring_displacement - b.ring_displacement).max()) < 2e-3 * ring
