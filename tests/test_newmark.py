"""Newmark-β / HHT-α (issue 4, MODEL §12): the independent cross-check of IDA.

References: IDA (an independent, variable-order BDF integrator of the same residual) for
agreement; the integrator's own refinement at h/8 (and a tight IDA run) for the observed order.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from bearingdae import SceneError, load_scene, simulate

SHORT = {"numerics.warmup_cage_revolutions": 0.02, "numerics.cage_revolutions": 0.03,
         "numerics.samples_per_cage_revolution": 100}


def baseline(**over):
    return load_scene("yang20_baseline", {**SHORT, **over})


@pytest.fixture(scope="module")
def pair():
    sc = baseline()
    return simulate(sc), simulate(sc, solver="newmark")


def test_same_dataset_as_ida(pair):
    ida, nm = pair
    assert set(ida.data_vars) == set(nm.data_vars)
    assert set(ida.attrs) - {"history"} == set(nm.attrs) - {"history"}
    for name in ida.data_vars:
        assert ida[name].dims == nm[name].dims, name
        assert ida[name].attrs == nm[name].attrs, name
    np.testing.assert_array_equal(ida.time, nm.time)
    st = json.loads(nm.attrs["solver_statistics"])
    for key in ("steps", "newton_iterations", "jacobian_calls", "lu_factorisations",
                "step_halvings", "residual_calls", "wall_time_s"):
        assert key in st, key
    assert st["steps"] > 0 and st["newton_iterations"] >= st["steps"]
    assert nm.attrs["solver_status"] == "completed"
    assert "Newmark" in nm.attrs["solver"]


@pytest.mark.parametrize("key, value", [
    ("numerics.newmark_step_s", 0.0), ("numerics.newmark_step_s", 1.0),
    ("numerics.newmark_beta", 0.0), ("numerics.newmark_beta", 0.6),
    ("numerics.newmark_gamma", 0.4), ("numerics.hht_alpha", -0.5), ("numerics.hht_alpha", 0.1),
    ("numerics.newmark_error_estimate", "yes"),
])
def test_bad_newmark_keys_name_the_key(key, value):
    with pytest.raises(SceneError, match=key.replace(".", r"\.")):
        baseline(**{key: value})


def test_unstable_beta_gamma_pair_is_refused():
    """β < (γ + 1/2)²/4 is only conditionally stable for the linear test equation."""
    with pytest.raises(SceneError, match=r"numerics\.newmark_beta.*\[0\.390625, 0\.5\]"):
        baseline(**{"numerics.newmark_gamma": 0.75, "numerics.newmark_beta": 0.3})
