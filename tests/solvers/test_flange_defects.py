"""A bearing with flanges and a local defect starts from a state that has the defect in it.

The quasi-static state with flanges (solvers/flange_static.py) is a Newton on the compiled DAE
residual, whose slice approaches lose the defect's separation (system/defects.py), after the
radial static solve that has it too (solvers/algebraic.py). Reference: a spall deeper than the
deflection (30 µm against a few µm) leaves the slices it covers without load, on the race or
the roller it sits on (the roller on the load line at t = 0; the roller spall faces the outer
race then); the same NJ bearing without it loads them.
"""

from __future__ import annotations

import numpy as np
import pytest

from bearingdae import solve_static
from bearingdae.physics.geometry import make_geometry
from bearingdae.scene import scene_from_dict
from bearingdae.solvers.algebraic import initial_state
from bearingdae.system.model import build_model

BASE = {"bearing": {"preset": "yang20", "type": "NJ"},
        "operating": {"radial_load_N": 2000.0, "axial_load_N": 200.0, "speed_rpm": 2000.0}}
SPALL = {"angle_deg": 0.0, "length_mm": 2.0, "width_mm": 6.0, "depth_um": 30.0,
         "edge_mm": 0.2}


def _scene(defects=()):
    return scene_from_dict({**BASE, "defects": list(defects)})


@pytest.mark.parametrize("surface", [{"on": "outer"}, {"on": "roller", "roller": 0}],
                         ids=["outer race", "roller"])
def test_the_flange_static_state_unloads_the_slices_a_deep_spall_covers(surface):
    s = _scene([dict(SPALL, **surface)])
    g = make_geometry(s)
    cov = np.flatnonzero(np.abs(g.x_m) + 0.5 * g.slice_width_m <= 3e-3)
    assert list(cov) == [4, 5]
    ds = solve_static(s)
    assert "flange_force" in ds  # the state with flanges, not the flangeless one
    q = ds.contact_force.sel(race="outer").values
    healthy = solve_static(_scene()).contact_force.sel(race="outer").values
    assert healthy[0, cov].min() > 50.0
    assert q[0, cov].max() < 1e-6
    # the dynamic run's start: the same state (its slice loads from the residual's kernel)
    model = build_model(s)
    y0, _ = initial_state(model)
    start = model.diagnostics_series(np.zeros(1), y0[None])["contact_force"][0]
    assert start[0, cov, 1].max() < 1e-6 and start[0, :, 1].max() > 50.0
