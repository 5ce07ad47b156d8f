"""Every static failure is one line with exit status 1, whatever the physics that failed, and a
load history's short peak does not spoil the start's equilibrium (system/model.py scales).

The flange settling (solvers/flange_static.py) raises a StaticConvergenceError like the slice
Newton; a history's force scale comes from its load at the start or its median load, so the
equilibrium at t = 0 under a history is the equilibrium under the constant load it starts with.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from bearingdae import load_scene, solve_static
from bearingdae.solvers.flange_static import FlangeSettleError
from bearingdae.solvers.static import StaticConvergenceError
from fuzzing import run_cli


def test_a_flange_settling_failure_is_a_static_failure():
    assert issubclass(FlangeSettleError, StaticConvergenceError)


@pytest.mark.parametrize("case", ["yang20_nj_axial", "yang20_baseline"])
def test_a_huge_radial_load_is_solved_or_one_line_with_exit_1(tmp_path, case):
    out = tmp_path / "s.nc"
    rc, stdout, stderr = run_cli(["static", case, "-o", str(out),
                                  "--set", "operating.radial_load_N=1e6"])
    assert "Traceback" not in stderr + stdout
    if rc == 1:
        lines = [ln for ln in stderr.splitlines() if not ln.startswith("bearingdae: warning")]
        assert len(lines) == 1 and lines[0].startswith("bearingdae: static solver failure: ")
        assert not out.exists()
    else:
        assert rc == 0 and out.exists(), stderr


@pytest.mark.parametrize("peak_N", [1e4, 1e6])
def test_a_history_with_a_peak_starts_from_the_constant_loads_equilibrium(peak_N):
    """{0, 10, 20 ms} -> {800 N, peak, 800 N}: the static state at t = 0 is that of 800 N
    constant (the same problem, solved afresh), with flanges and without."""
    history = f"{{times_s = [0.0, 0.01, 0.02], values_N = [800.0, {peak_N!r}, 800.0]}}"
    from bearingdae.scene import scene_from_dict
    import tomllib

    for case in ("yang20_nj_axial", "yang20_baseline"):
        const = load_scene(case, {"operating.radial_load_N": 800.0})
        data = tomllib.loads(const.to_toml())
        data["operating"]["radial_load_N"] = tomllib.loads(f"x = {history}")["x"]
        peaked = scene_from_dict(data)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            a, b = solve_static(const), solve_static(peaked)
        np.testing.assert_allclose(b.contact_force.values, a.contact_force.values,
                                   rtol=1e-9, atol=1e-9 * float(a.contact_force.max()))
