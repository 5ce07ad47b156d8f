"""The analytic iteration matrix (system/jacobian_analytic.py) against central differences.

Reference: central differences of the residual itself (``check_jacobian``), taken mid-run where
rollers are skewed, in and out of race and pocket contact, for every physics option that
changes a formula (traction law, slip kinematics, orbit form, switched-off unknowns).
"""

from __future__ import annotations

import numpy as np
import pytest

from bearingdae.solvers.ida import check_jacobian, integrate
from bearingdae.solvers.algebraic import initial_state
from bearingdae.solvers.common import jacobian_filler
from bearingdae.system.model import build_model
from conftest import make_scene

SHORT = {"numerics.cage_revolutions": 0.1, "numerics.warmup_cage_revolutions": 0.0}


def _mid_run_state(overrides):
    m = build_model(make_scene({**SHORT, **overrides}, operating={
        "radial_load_N": 800.0, "moment_Nm": 3.0, "speed_rpm": 2000.0}))
    y0, yp0 = initial_state(m)
    r = integrate(m, y0, yp0, np.array([0.0, 2e-3]))
    assert r.success, r.message
    return m, r.y[-1], r.yp[-1]


@pytest.mark.parametrize("overrides, rel_step", [
    ({}, 1e-7),
    ({"traction.law": "slide-roll"}, 1e-7),
    ({"physics.slip": "paper"}, 1e-7),
    ({"physics.orbit": "paper"}, 1e-7),
    ({"physics.skew": False}, 1e-7),
    ({"physics.cage": False, "physics.drag": False}, 1e-7),
    # every roller pressed into a pocket bar, whose force bends over ε = 0.1 µm: the reference's
    # step (R_m h in azimuth) must be far below ε (measured: 1e-8 -> 1e-3, 1e-10 -> 7e-5)
    ({"cage.pocket_clearance_mm": 0.0}, 1e-10),
    # the ring as a body (theory.md §15), with and without support and tilt
    ({"physics.ring": "dynamic"}, 1e-7),
    ({"physics.ring": "dynamic", "ring.support_stiffness_N_m": 2e8,
      "ring.support_damping_N_s_m": 500.0}, 1e-7),
    ({"physics.ring": "dynamic", "physics.tilt": False, "operating.moment_Nm": 0.0,
      "operating.unbalance_N": 100.0}, 1e-7),
    # roller end-flange contacts (theory.md §16): NJ under axial load, NUP loaded the other
    # way, NU (rollers floating in their axial play), with the dynamic ring, the paper's orbit
    # (a roller in pocket contact at the sampled state: a step below the pocket smoothing)
    ({"bearing.type": "NJ", "operating.axial_load_N": 200.0}, 1e-9),
    ({"bearing.type": "NUP", "operating.axial_load_N": -1000.0}, 1e-9),
    ({"bearing.type": "NU"}, 1e-9),
    ({"bearing.type": "NJ", "operating.axial_load_N": 200.0, "physics.ring": "dynamic"}, 1e-9),
    ({"bearing.type": "NJ", "operating.axial_load_N": 200.0, "physics.orbit": "paper",
      "bearing.roller_end": "flat"}, 1e-9),
    # the axial load as a history (theory.md §14), mid-ramp at the sampled state (t = 2 ms);
    # from 0: the ring's axial centring too (system/flange.py)
    ({"bearing.type": "NJ", "operating.axial_load_N": {"times_s": [0.0, 1e-3, 4e-3],
                                                       "values_N": [200.0, 200.0, 1000.0]}},
     1e-9),
    ({"bearing.type": "NJ", "operating.axial_load_N": {"times_s": [0.0, 1e-3, 4e-3],
                                                       "values_N": [0.0, 0.0, 1000.0]}},
     1e-9),
    # EHL rolling resistance (theory.md §19), with the paper's slip (its skew slopes) and orbit
    # and a strong thermal factor; the drag brings rollers into pocket contact at the sampled
    # state: a step below the pocket smoothing (measured: 1e-7 -> 8e-2, 1e-9 -> 2e-6)
    ({"physics.rolling_resistance": True}, 1e-9),
    ({"physics.rolling_resistance": "goksem_hargreaves", "physics.slip": "paper",
      "physics.orbit": "paper", "lubricant.temperature_viscosity_K_inv": 0.5}, 1e-9),
    # each law (true is Biboulet & Houpert's), and starved by a thin inlet film (B&H's eq. 44
    # through each slice's flooded film)
    ({"physics.rolling_resistance": "zhou_hoeprich"}, 1e-9),
    ({"physics.rolling_resistance": "biboulet_houpert", "lubricant.inlet_film_um": 0.2}, 1e-9),
    ({"physics.rolling_resistance": "goksem_hargreaves", "lubricant.inlet_film_um": 0.2}, 1e-9),
    ({"physics.rolling_resistance": "zhou_hoeprich", "lubricant.inlet_film_um": 0.2}, 1e-9),
    # mixed lubrication (theory.md §20): the asperities' share through the film's λ(q, u),
    # with both traction laws, the paper's slip radius and a thinner oil
    ({"physics.lubrication": "mixed"}, 1e-7),
    ({"physics.lubrication": "mixed", "traction.law": "slide-roll"}, 1e-7),
    ({"physics.lubrication": "mixed", "physics.slip": "paper",
      "lubricant.viscosity_Pa_s": 0.003}, 1e-7),
    # with the rolling resistance (§19): both passes on the same slices
    ({"physics.lubrication": "mixed", "physics.rolling_resistance": True}, 1e-9),
], ids=lambda o: ",".join(f"{k}={v}" for k, v in o.items()) if isinstance(o, dict) else "")
def test_analytic_jacobian_matches_central_differences(overrides, rel_step):
    m, y, yp = _mid_run_state(overrides)
    err = check_jacobian(m, y, yp, jacobian="analytic", rel_step=rel_step)
    # central differences are accurate to ~1e-7 of a column's scale here; the drag slopes are
    # themselves central differences (1e-6 relative step), hence the bound
    assert err < 2e-4, err


def test_analytic_jacobian_is_more_accurate_than_forward_differences():
    """Same reference: the exact derivative must beat the structured forward differences."""
    m, y, yp = _mid_run_state({})
    assert check_jacobian(m, y, yp, jacobian="analytic") < check_jacobian(m, y, yp, jacobian="fd")


def test_both_jacobians_give_the_same_trajectory():
    """The iteration matrix only steers Newton: IDA with either must reach the same state to
    the integration tolerance (reference: the run with the independent FD Jacobian)."""
    m = build_model(make_scene(SHORT))
    y0, yp0 = initial_state(m)
    t = np.linspace(0.0, 4e-3, 5)
    a = integrate(m, y0, yp0, t, jacobian="analytic")
    f = integrate(m, y0, yp0, t, jacobian="fd")
    assert a.success and f.success
    assert a.stats["residual_calls_in_jacobian"] == 0
    cage = m.layout.index("cage_speed")
    np.testing.assert_allclose(a.y[:, cage], f.y[:, cage], rtol=1e-5)


def test_ring_axial_centring_enters_the_jacobian():
    """An axial load history from 0 centres the ring axially (system/flange.py): at t = 0, with
    no flange holding the ring, d(ring's axial row)/dδ_a is that centring alone; the analytic
    entry against a central difference (measured: equal to 1e-15)."""
    m = build_model(make_scene({"bearing.type": "NJ"}, operating={
        "radial_load_N": 800.0, "moment_Nm": 3.0, "speed_rpm": 2000.0,
        "axial_load_N": {"times_s": [0.0, 1e-3], "values_N": [0.0, 1000.0]}}))
    y0, yp0 = initial_state(m)
    i = m.layout.index("ring_axial")
    jd, fill, _ = jacobian_filler(m, "analytic")
    fill(0.0, y0, yp0, 0.0, m.data, jd)
    h = 1e-6
    up, down = y0.copy(), y0.copy()
    up[i] += h
    down[i] -= h
    fd = (m.residual(0.0, up, yp0)[i] - m.residual(0.0, down, yp0)[i]) / (2 * h)
    assert jd[0][i, i] == pytest.approx(fd, rel=1e-8)
    assert jd[0][i, i] < 0.0
