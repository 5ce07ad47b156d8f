"""Cage whirl in the DAE (system/whirl.py, theory.md §17): what a scene without whirl assembles,
and the analytic iteration matrix against central differences of the residual.

Reference: central differences of the residual (as tests/system/test_jacobian.py), at a mid-run
state whose cage centre is then placed where each term acts: in the land's film, in land contact,
in the pockets' radial lips (roller guidance), moving. Tolerance: 2e-4 of each column's largest
entry (the bound of the other Jacobian tests; the drag slopes are central differences), and for
the cage's own columns (θc, ω_c, x, y, ẋ, ẏ) 1e-5.
"""

from __future__ import annotations

import numpy as np
import pytest

from bearingdae.solvers.algebraic import initial_state
from bearingdae.solvers.common import jacobian_filler
from bearingdae.solvers.ida import check_jacobian, integrate
from bearingdae.system.layout import CAGE_CENTRE, CAGE_CENTRE_RATES
from bearingdae.system.model import build_model
from bearingdae.system.residual import P_WH
from conftest import make_scene

SHORT = {"numerics.cage_revolutions": 0.1, "numerics.warmup_cage_revolutions": 0.0}
OPERATING = {"radial_load_N": 800.0, "moment_Nm": 3.0, "speed_rpm": 2000.0}
CAGE_COLUMNS = ("cage_angle", "cage_speed") + CAGE_CENTRE + CAGE_CENTRE_RATES


def test_a_scene_without_whirl_assembles_none_of_it():
    m = build_model(make_scene(SHORT, operating=OPERATING))
    assert not m.layout.whirl
    assert not set(CAGE_CENTRE + CAGE_CENTRE_RATES) & set(m.layout.global_names)
    assert np.all(m.params[P_WH:] == 0.0)
    w = build_model(make_scene({**SHORT, "physics.cage_whirl": True}, operating=OPERATING))
    assert w.size == m.size + 4 and w.params[P_WH] == 1.0


@pytest.fixture(scope="module")
def mid_runs():
    out = {}
    for guidance in ("roller", "outer-land", "inner-land"):
        over = {**SHORT, "physics.cage_whirl": True, "cage.guidance": guidance}
        if guidance == "inner-land":
            over["physics.orbit"] = "paper"  # the other orbit form's arm too
        m = build_model(make_scene(over, operating=OPERATING))
        y0, yp0 = initial_state(m)
        r = integrate(m, y0, yp0, np.array([0.0, 2e-3]))
        assert r.success, r.message
        out[guidance] = (m, r.y[-1], r.yp[-1])
    return out


def _placed(m, y, radius_m, angle, velocity_m_s):
    full_l, full_g = m.layout.unpack(y * m.scale)
    lay = m.layout
    full_g[-4:] = [radius_m * np.cos(angle), radius_m * np.sin(angle), *velocity_m_s]
    return lay.pack(full_l, full_g) / m.scale


@pytest.mark.parametrize("guidance, where", [
    ("roller", 0.3),  # inside the pockets' radial play
    ("roller", 0.5 + 2e-4),  # in the radial lips of the pockets along ±x (c_p/2 = 0.05 mm)
    ("outer-land", 0.6),  # film
    ("outer-land", 1.0 + 4e-4),  # land contact
    ("inner-land", 0.8),
    ("inner-land", 1.0 + 4e-4),
])
def test_whirl_jacobian_matches_central_differences(mid_runs, guidance, where):
    m, y, yp = mid_runs[guidance]
    clearance = m.scene.cage.pocket_clearance_m if guidance == "roller" else (
        0.5 * m.scene.cage.land_clearance_m)
    y = _placed(m, y, where * clearance, 0.1, (2e-4, -1e-4))
    assert check_jacobian(m, y, yp, jacobian="analytic", rel_step=1e-9) < 2e-4
    # the cage's own columns on their own (their entries are small next to a roller's)
    jd, fill, _ = jacobian_filler(m, "analytic")
    cj = 1e3
    fill(0.0, y, yp, cj, m.data, jd)
    J = jd[0]
    for name in CAGE_COLUMNS:
        j = m.layout.index(name)
        h = 1e-9 * max(abs(y[j]), 1.0)
        e = np.zeros_like(y)
        e[j] = h
        ref = (m.residual(0.0, y + e, yp + cj * e) - m.residual(0.0, y - e, yp - cj * e)) / (2 * h)
        scale = np.abs(ref).max()
        assert np.abs(J[:, j] - ref).max() < 1e-5 * scale, (name, np.abs(J[:, j] - ref).max(),
                                                             scale)
