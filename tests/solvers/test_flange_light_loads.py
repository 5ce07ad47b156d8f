"""The quasi-static state with flanges under light radial loads (solvers/flange_static.py).

An axial load on an NJ bearing pinches each roller between a flange of each ring; under a light
radial load a roller settles across the clearance, hundreds of reference approaches away from
its start. Before the axial load entered the reference scales (system/scales.py) and the step
cap could grow, these points ended in a settling failure. Reference: the balance of the axial
load (the inner ring's flanges carry all of it).
"""

from __future__ import annotations

import warnings

import pytest

from bearingdae import solve_static
from conftest import make_scene
from fuzzing import run_cli

#: (speed [r/min], radial load [N], axial load [N]); no moment
LIGHT = [(0.0, 0.0, 200.0), (0.0, 50.0, 200.0), (200.0, 10.0, 20.0), (500.0, 0.0, 2000.0)]


@pytest.mark.parametrize("speed_rpm, Fr, Fa", LIGHT)
def test_a_lightly_loaded_nj_settles_and_carries_its_axial_load(speed_rpm, Fr, Fa):
    scene = make_scene({"bearing.type": "NJ", "operating.axial_load_N": Fa},
                       operating={"radial_load_N": Fr, "moment_Nm": 0.0, "speed_rpm": speed_rpm})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        st = solve_static(scene)
    assert float(st.inner_flange_axial_force.sum()) == pytest.approx(Fa, rel=1e-8)


def test_an_unsettled_flange_state_names_the_operating_keys(tmp_path):
    """No radial load, no speed and a light axial load: nothing settles the rollers' tilt; the
    failure is one line that names what held them."""
    out = tmp_path / "s.nc"
    rc, stdout, stderr = run_cli(["static", "yang20_nj_axial", "-o", str(out),
                                  "--set", "operating.radial_load_N=0",
                                  "--set", "operating.moment_Nm=0",
                                  "--set", "operating.speed_rpm=0",
                                  "--set", "operating.axial_load_N=20"])
    assert "Traceback" not in stderr + stdout
    lines = [ln for ln in stderr.splitlines() if not ln.startswith("bearingdae: warning")]
    assert rc == 1 and len(lines) == 1, stderr
    assert lines[0].startswith("bearingdae: static solver failure: ")
    for key in ("operating.axial_load_N = 20 N", "operating.radial_load_N",
                "operating.speed_rpm = 0"):
        assert key in lines[0]
    assert not out.exists()
