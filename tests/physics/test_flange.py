"""Roller end-flange contact laws (physics/flange.py) and their loads on a roller.

References: Hertz's sphere-on-plane law (Johnson, *Contact Mechanics*, Eq. 4.23) for the load;
the slice slip's kinematics (theory.md §6: a contact point at the raceway radius has the
raceway's slip); an independent 3-D implementation (cross products in the roller frame) for the
flange moments in the roller's angular-momentum rows of the DAE residual.
"""

from __future__ import annotations

import numpy as np
import pytest

from bearingdae.physics.flange import (FLANGE_SLIP_SCALE_M_S, flange_friction,
                                       flange_normal_load, flange_slip,
                                       permissible_axial_load, point_contact_stiffness)
from bearingdae.physics.kinematics import slip_velocities
from bearingdae.solvers.algebraic import initial_state
from bearingdae.solvers.ida import integrate
from bearingdae.system.flange import CONTACTS, flange_state
from bearingdae.system.layout import LOCAL
from bearingdae.system.model import build_model
from bearingdae.system.residual import P_FL
from conftest import make_scene


def test_normal_load_is_hertz_point_contact_and_its_slope():
    E, R = 113e9, 0.17
    K = point_contact_stiffness(E, R)
    d = 0.8e-6
    Q, dQ = flange_normal_load(d, 1.0, K, 1e-15)
    # Johnson Eq. 4.23: P = (4/3) E* R^1/2 δ^3/2
    assert Q == pytest.approx(4 / 3 * E * np.sqrt(R) * d**1.5, rel=1e-12)
    h = 1e-12
    ref = (flange_normal_load(d + h, 1.0, K, 1e-15)[0]
           - flange_normal_load(d - h, 1.0, K, 1e-15)[0]) / (2 * h)
    assert dQ == pytest.approx(ref, rel=1e-6)
    # the inclined rib: the normal approach is δ cos α
    c = np.cos(np.radians(3.0))
    assert flange_normal_load(d, c, K, 1e-15)[0] == pytest.approx(K * (d * c) ** 1.5, rel=1e-12)


def test_slip_at_raceway_height_equals_the_raceway_slip():
    """A contact point at ρ = ±r (the raceway) slides as the slice contact there (theory.md §6)."""
    wi, Om, om, zeta, Rm, r, x = 209.0, 90.0, -700.0, 0.3, 0.0225, 0.002, 0.01
    Vi, Vo = slip_velocities(wi, Om, om, zeta, r, x, Rm - r, Rm + r)
    assert flange_slip(1.0, wi, Om, om, zeta, Rm, -r, x) == pytest.approx(Vi, rel=1e-12)
    assert flange_slip(0.0, wi, Om, om, zeta, Rm, r, x) == pytest.approx(Vo, rel=1e-12)


def test_friction_is_regularised_coulomb():
    F, FQ, FV = flange_friction(10.0, 0.5, 0.05, FLANGE_SLIP_SCALE_M_S)
    assert F == pytest.approx(0.5, rel=1e-5) and FQ == pytest.approx(0.05, rel=1e-5)
    assert flange_friction(10.0, 0.0, 0.05, FLANGE_SLIP_SCALE_M_S)[0] == 0.0
    h = 1e-7
    ref = (flange_friction(10.0, 1e-3 + h, 0.05, 1e-3)[0]
           - flange_friction(10.0, 1e-3 - h, 0.05, 1e-3)[0]) / (2 * h)
    assert flange_friction(10.0, 1e-3, 0.05, 1e-3)[2] == pytest.approx(ref, rel=1e-6)


def test_permissible_axial_load_falls_with_speed_and_radial_load():
    """SKF's formula: F_ap ∝ 1/n, minus 0.15 F_r (oil)."""
    a = permissible_axial_load(80e3, 1000.0, 30.0, 60.0, 800.0)
    b = permissible_axial_load(80e3, 2000.0, 30.0, 60.0, 800.0)
    assert a == pytest.approx(1.5 * 80e3 * 1e4 / (1000 * 90) - 0.15 * 800, rel=1e-12)
    assert b < a and permissible_axial_load(80e3, 1000.0, 30.0, 60.0, 1600.0) < a


@pytest.fixture(scope="module")
def nj_mid_run():
    m = build_model(make_scene({"bearing.type": "NUP", "operating.axial_load_N": 600.0},
                               operating={"radial_load_N": 800.0, "moment_Nm": 3.0,
                                          "speed_rpm": 2000.0}))
    y0, yp0 = initial_state(m)
    r = integrate(m, y0, yp0, np.array([0.0, 2e-3]))
    assert r.success, r.message
    return m, r.y[-1]


def test_roller_angular_momentum_rows_carry_the_flange_moments(nj_mid_run):
    """Balance: the change of each roller's spin, skew and tilt rows (and orbit and axial
    rows) when the flange contacts are added equals Σ r_c × F of those contacts computed in 3-D
    from their contact points and forces (an independent implementation of the moment arms and
    the frames' signs)."""
    m, y = nj_mid_run
    res_on = m.residual(0.0, y, np.zeros_like(y))
    P = m.params
    saved = P[P_FL + 1:P_FL + 5].copy()
    P[P_FL + 1:P_FL + 5] = 0.0  # every flange absent: the same state without the contacts
    try:
        res_off = m.residual(0.0, y, np.zeros_like(y))
    finally:
        P[P_FL + 1:P_FL + 5] = saved
    lay, fl, g = m.layout, m.scene.bearing.flanges, m.geometry
    full_l, full_g = lay.unpack(y * m.scale)
    c = np.zeros((g.rollers, 4, 4))
    flange_state(full_l, full_g, m.ring_speed(0.0), np.ascontiguousarray(P[P_FL:]), c)
    assert c[..., 0].max() > 1.0  # loaded contacts
    eX, er, et = np.eye(3)  # roller frame: axis, radial outward, tangential (ê_X × ê_r)
    assert np.allclose(np.cross(eX, er), et)
    L, e, cos_a = g.roller_length_m, fl.contact_height_m, np.cos(fl.angle_rad)
    for j in range(g.rollers):
        moment = np.zeros(3)
        force = np.zeros(3)
        for k, (end, ring) in enumerate(CONTACTS):
            Q, _, _, Ft = c[j, k]
            x_e = 0.5 * L if end == "a" else -0.5 * L
            rho = e if ring == "outer" else -e
            push = -np.sign(x_e) * Q * cos_a  # the flange pushes the end back towards x = 0
            F = push * eX + Ft * et
            moment += np.cross(x_e * eX + rho * er, F)
            force += F
        d = res_on - res_off  # rows: differential "M y' - f" (-= loads), algebraic "+= loads"
        row = {n: lay.index(n, j) for n in ("orbit_speed", "spin_speed", "skew_rate", "tilt",
                                            "axial_position")}
        RS = m.row_scale
        # spin is counted positive when rolling forward on the inner race: about -ê_X
        assert -d[row["spin_speed"]] * RS[row["spin_speed"]] == pytest.approx(-moment[0],
                                                                              rel=1e-9, abs=1e-15)
        assert -d[row["skew_rate"]] * RS[row["skew_rate"]] == pytest.approx(moment[1], rel=1e-9,
                                                                            abs=1e-15)
        assert d[row["tilt"]] * RS[row["tilt"]] == pytest.approx(moment[2], rel=1e-9, abs=1e-15)
        assert -d[row["orbit_speed"]] * RS[row["orbit_speed"]] == pytest.approx(force[2],
                                                                                rel=1e-9,
                                                                                abs=1e-15)
        k_c = P[P_FL + 11]
        s = full_l[j, LOCAL.index("axial_position")]
        assert res_on[row["axial_position"]] * RS[row["axial_position"]] == pytest.approx(
            force[0] - k_c * s, rel=1e-9, abs=1e-12)
