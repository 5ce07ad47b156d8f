"""One law, one place: the residual, the analytic Jacobian and the static solve call the same
functions (physics/kinematics.py, contact.py, traction.py, cage.py).

Each test takes one state of the baseline bearing (rollers skewed, slipping, in and out of race
and pocket contact) and compares what the three users compute with one direct call of the
shared function at that state; a change to the function (or to a constant that the scene sets)
therefore moves all three. Reference: the direct call itself, to round-off (1e-12 relative:
the kernels run the same source compiled, with sums in another order). The static solve's
equations contain no traction and no pocket: for those laws the residual and the Jacobian are
compared.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import make_scene

from bearingdae.physics import cage, contact, traction
from bearingdae.physics import kinematics as kin
from bearingdae.physics.equilibrium import contact_state
from bearingdae.solvers import static
from bearingdae.solvers.algebraic import initial_state
from bearingdae.solvers.ida import jacobian_filler
from bearingdae.system.layout import GLOBAL, LOCAL
from bearingdae.system.model import build_model
from bearingdae.system.residual import PARAM_NAMES

L_ = {n: i for i, n in enumerate(LOCAL)}
G_ = {n: i for i, n in enumerate(GLOBAL)}
OPERATING = {"radial_load_N": 800.0, "moment_Nm": 3.0, "speed_rpm": 2000.0}


def _model(overrides=None):
    return build_model(make_scene(overrides or {}, operating=OPERATING))


def _state(m, rng, wrap=True):
    """A perturbed state: skewed, slipping rollers; roller 2 pressed 0.3 µm into its front
    pocket bar; with ``wrap``, roller 0 exactly half a revolution from its pocket centre (the
    wrap point, where differences of the residual jump)."""
    y0, _ = initial_state(m)
    fl, fg = m.layout.unpack(y0 * m.scale)
    Z = fl.shape[0]
    P = dict(zip(PARAM_NAMES, m.params))
    fl[:, L_["skew_angle"]] = rng.uniform(-1e-3, 1e-3, Z)
    fl[:, L_["skew_rate"]] = rng.uniform(-0.5, 0.5, Z)
    fl[:, L_["spin_speed"]] *= 1 + rng.uniform(-2e-3, 2e-3, Z)
    fl[:, L_["orbit_speed"]] *= 1 + rng.uniform(-2e-3, 2e-3, Z)
    fl[:, L_["radial_position"]] += rng.uniform(-2e-7, 2e-7, Z)
    fl[:, L_["tilt"]] += rng.uniform(-1e-5, 1e-5, Z)
    fg[G_["cage_angle"]] = 0.0
    fg[2:6] *= 1 + rng.uniform(-0.05, 0.05, 4)
    if wrap:
        fl[0, L_["azimuth"]] = np.pi  # θX - θc - 0 = π: (-π, π] gives +π
    fl[2, L_["azimuth"]] = 2 * 2 * np.pi / Z + (0.5 * P["cp"] + 3e-7) / P["Rm"]
    fl[2, L_["skew_angle"]] = 0.0
    y = m.layout.pack(fl, fg) / m.scale
    yp = np.zeros_like(y)
    return 0.0, y, yp, fl, fg, P


def _jacobian(m, t, y, yp):
    jd, fill, _ = jacobian_filler(m, "analytic")
    fill(t, y, yp, 0.0, m.data, jd)
    return jd[0]


def _jacobian_error(m, t, y, yp, names, rollers, rel_step=1e-7):
    """Max |J - central differences of the residual| over the columns of the named unknowns of
    the given rollers, relative to the largest reference entry of those columns."""
    J = _jacobian(m, t, y, yp)
    cols = [m.layout.index(n, j) for n in names for j in rollers]
    err, big = 0.0, 0.0
    for c in cols:
        e = np.zeros_like(y)
        e[c] = rel_step * max(abs(y[c]), 1.0)
        ref = (m.residual(t, y + e, yp) - m.residual(t, y - e, yp)) / (2 * e[c])
        err, big = max(err, np.abs(J[:, c] - ref).max()), max(big, np.abs(ref).max())
    return err / big


def _direct_contact(m, fl, fg, P):
    """Approaches, loads and load slopes (Z, k) of both races by one direct call."""
    az = fl[:, L_["azimuth"]][:, None]
    x = m.geometry.x_m[None, :]
    rho = kin.ring_approach(fg[2], fg[3], fg[4], fg[5], x, np.cos(az), np.sin(az))[0]
    d_in, d_out = kin.race_approaches(rho, fl[:, L_["radial_position"]][:, None],
                                      fl[:, L_["tilt"]][:, None], x, 0.5 * P["clearance"],
                                      m.geometry.profile_drop_m[None, :])
    q_in, k_in = contact.slice_load(d_in, P["K_w"], P["eps_c"])
    q_out, k_out = contact.slice_load(d_out, P["K_w"], P["eps_c"])
    return d_in, d_out, q_in, q_out, k_in, k_out


def test_approach_and_load_laws_are_shared(rng):
    m = _model()
    t, y, yp, fl, fg, P = _state(m, rng)
    d_in, d_out, q_in, q_out, k_in, k_out = _direct_contact(m, fl, fg, P)
    # residual (its per-slice diagnostics)
    q = m.diagnostics(t, y)["contact_force"]
    np.testing.assert_allclose(q[..., 0], q_in, rtol=1e-12, atol=0)
    np.testing.assert_allclose(q[..., 1], q_out, rtol=1e-12, atol=0)
    # static solve
    cs = contact_state(fl[:, L_["radial_position"]], fl[:, L_["tilt"]], fg[2:6],
                       fl[:, L_["azimuth"]], static.contact_params(m.geometry, P["eps_c"]))
    np.testing.assert_allclose(cs.approach_inner_m, d_in, rtol=1e-12, atol=1e-22)
    np.testing.assert_allclose(cs.approach_outer_m, d_out, rtol=1e-12, atol=1e-22)
    np.testing.assert_allclose(cs.load_inner_N, q_in, rtol=1e-12, atol=0)
    # analytic Jacobian: d(radial balance_j)/du_j = -Σ (dq_i/dδ + dq_o/dδ)
    J = _jacobian(m, t, y, yp)
    for j in (0, 5, 11):
        row = col = m.layout.index("radial_position", j)
        expect = -(k_in[j].sum() + k_out[j].sum()) * m.scale[col] / m.row_scale[row]
        assert J[row, col] == pytest.approx(expect, rel=1e-12)


def test_algebraic_equations_are_shared(rng):
    m = _model()
    t, y, yp, fl, fg, P = _state(m, rng)
    res_l, res_g = m.layout.unpack(m.residual(t, y, yp) * m.row_scale)
    prob = static.make_problem(m.geometry, m.scene.operating.loads, 0.0, P["eps_c"],
                               azimuth_rad=fl[:, L_["azimuth"]],
                               orbit_speed_rad_s=fl[:, L_["orbit_speed"]])
    z = np.concatenate([fl[:, L_["radial_position"]], fl[:, L_["tilt"]], fg[2:6]])
    F, _, cs = static.evaluate(prob, z, jacobian=False)
    Z = fl.shape[0]
    scale = cs.load_inner_N.sum(axis=1).max()
    np.testing.assert_allclose(res_l[:, L_["radial_position"]], F[:Z], rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(res_l[:, L_["tilt"]], F[Z:2 * Z], rtol=0,
                               atol=1e-12 * scale * P["L"])
    np.testing.assert_allclose(res_g[2:6], F[2 * Z:], rtol=0, atol=1e-12 * scale * Z)
    # the centrifugal term in the Jacobian: d(radial balance_j)/dΩ_j = dF_c/dΩ
    J = _jacobian(m, t, y, yp)
    j = 7
    row, col = m.layout.index("radial_position", j), m.layout.index("orbit_speed", j)
    Om = fl[j, L_["orbit_speed"]]
    h = 1e-6 * Om
    dFc = (kin.centrifugal_force(P["mass"], P["Rm"], Om + h)
           - kin.centrifugal_force(P["mass"], P["Rm"], Om - h)) / (2 * h)
    assert J[row, col] == pytest.approx(dFc * m.scale[col] / m.row_scale[row], rel=1e-8)


def test_pocket_lead_and_wrap_are_shared(rng):
    m = _model()
    t, y, yp, fl, fg, P = _state(m, rng)
    Z = fl.shape[0]
    law = (P["cp"], P["Kp"], P["cdamp"], P["eps_p"], P["f_p"])
    fp = m.diagnostics(t, y)["cage_force"]
    J = _jacobian(m, t, y, yp)
    for j in (0, 2, 9):
        th, sk, Om = fl[j, L_["azimuth"]], fl[j, L_["skew_angle"]], fl[j, L_["orbit_speed"]]
        s_a, s_b = kin.end_positions(kin.pocket_lead(th, fg[G_["cage_angle"]], j, Z, P["Rm"]),
                                     sk, P["L"])
        v_a, v_b = kin.end_positions(kin.pocket_lead_rate(Om, fg[G_["cage_speed"]], P["Rm"]),
                                     fl[j, L_["skew_rate"]], P["L"])
        Fa, Fa_s, _ = cage.pocket_force(s_a, v_a, *law)
        Fb, Fb_s, _ = cage.pocket_force(s_b, v_b, *law)
        assert fp[j, 0] == pytest.approx(Fa, rel=1e-12, abs=1e-300)
        assert fp[j, 1] == pytest.approx(Fb, rel=1e-12, abs=1e-300)
        # Jacobian: d(skew moment (L/2)(F_b - F_a))/dθc, through ds/dθc = -R_m
        row, col = m.layout.index("skew_rate", j), m.layout.index("cage_angle")
        expect = 0.5 * P["L"] * P["Rm"] * (Fb_s - Fa_s) * m.scale[col] / m.row_scale[row]
        assert J[row, col] == pytest.approx(expect, rel=1e-10, abs=1e-12 * abs(J[row]).max())
    # roller 2 sits in its front bar; roller 0 at the wrap point: (-π, π] puts it at +π R_m,
    # far beyond the front bar (pushed back, F < 0); the other convention would give F > 0
    assert fp[2, 0] < -0.1 and fp[0, 0] < 0 and fp[0, 1] < 0
    assert kin.wrap_angle(np.pi) == np.pi and kin.wrap_angle(-np.pi) == np.pi


def test_slide_roll_constants_come_from_the_scene_into_residual_and_jacobian(rng):
    over = {"traction.law": "slide-roll", "traction.slide_roll_B": 1.5,
            "traction.slide_roll_C": 10.0, "traction.rolling_speed_floor_m_s": 0.01}
    m, m0 = _model(over), _model({"traction.law": "slide-roll"})
    t, y, yp, fl, fg, P = _state(m, rng, wrap=False)
    tr = m.scene.traction
    diag = m.diagnostics(t, y)
    q, f = diag["contact_force"], diag["traction_force"]
    r = P["r"]
    for j in (1, 4):
        Om, om, sr = (fl[j, L_[n]] for n in ("orbit_speed", "spin_speed", "skew_rate"))
        w = m.ring_speed(t)
        x = m.geometry.x_m
        Vi, Vo = kin.slip_velocities(w, Om, om, sr, kin.effective_radius(r, x, 0.0), x,
                                     P["Ri"], P["Ro"])
        si, so = kin.rolling_sums(w, Om, om, kin.effective_radius(r, x, 0.0), P["Ri"], P["Ro"])
        np.testing.assert_allclose(diag["slip_velocity"][j, :, 0], Vi, rtol=1e-12)
        for race, V, s in ((0, Vi, si), (1, Vo, so)):
            expect = traction._traction_value_slide_roll(
                q[j, :, race], V, 0.5 * np.abs(s), tr.velocity_scale_m_s, tr.slide_roll_A,
                tr.slide_roll_B, tr.slide_roll_C, tr.slide_roll_D, tr.rolling_speed_floor_m_s)
            np.testing.assert_allclose(f[j, :, race], expect, rtol=1e-12, atol=1e-300)
    # the changed constants move residual and Jacobian, and the Jacobian stays the residual's
    assert np.abs(m.residual(t, y, yp) - m0.residual(t, y, yp)).max() > 1e-3
    J, J0 = _jacobian(m, t, y, yp), _jacobian(m0, t, y, yp)
    assert np.abs(J - J0).max() > 1e-4 * np.abs(J0).max()  # traction slopes, not contact
    # the slopes along the speeds the law sees (slip and rolling speed)
    assert _jacobian_error(m, t, y, yp, ("orbit_speed", "spin_speed", "skew_rate"),
                           (1, 4, 12)) < 1e-5


def test_spin_friction_force_scale_comes_from_the_scene(rng):
    m = _model({"cage.spin_friction_force_scale_N": 0.05, "cage.friction": 0.1})
    m0 = _model({"cage.friction": 0.1})
    t, y, yp, fl, fg, P = _state(m, rng, wrap=False)
    assert P["spin_f"] == 0.05 and dict(zip(PARAM_NAMES, m0.params))["spin_f"] == 1e-6
    fp = m.diagnostics(t, y)["cage_force"]
    j = 2  # in pocket contact
    row = m.layout.index("spin_speed", j)
    om = fl[j, L_["spin_speed"]]
    spin = [cage.pocket_loads(fp[j, 0], fp[j, 1], om, P["L"], P["r"], P["Rm"], P["mu_c"],
                              P["spin_scale"], f)[2] for f in (0.05, 1e-6)]
    # spin row = I_x ω' - (r ΣF + M_spin - M_lr): only M_spin depends on f
    d_res = (m.residual(t, y, yp) - m0.residual(t, y, yp))[row] * m.row_scale[row]
    assert d_res == pytest.approx(-(spin[0] - spin[1]), rel=1e-9)
    assert abs(spin[0] - spin[1]) > 1e-3 * abs(spin[1])
    # the slopes along the pocket end forces' and spin's unknowns of the roller in contact
    assert _jacobian_error(m, t, y, yp, ("spin_speed", "orbit_speed", "skew_rate"), (j,)) < 1e-5


def test_scene_defaults_of_the_open_constants_are_the_physics_defaults():
    tr, cg = make_scene().traction, make_scene().cage
    d = traction.SLIDE_ROLL_DEFAULTS
    assert (tr.slide_roll_A, tr.slide_roll_B, tr.slide_roll_C, tr.slide_roll_D) == (
        d["A"], d["B"], d["C"], d["D"])
    assert cg.spin_friction_force_scale_N == cage.SPIN_FRICTION_FORCE_SCALE_N
