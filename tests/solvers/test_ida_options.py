"""``IDA(...)``'s tuning options. ``atol_factors``: one unknown's absolute tolerance scaled,
every roller's and no other; written into the run's solver options; bad input refused naming
the key and the range; absent by default, so the default run's attributes are unchanged.
``max_order``, ``nonlin_conv_coef``, ``max_nonlin_iters`` and the step ratios ``eta_max_fx``,
``eta_max``, ``eta_conv_fail``: SUNDIALS' step controls, likewise."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from bearingdae import IDA, load_scene, simulate
from bearingdae.solvers.ida import atol_vector
from bearingdae.system.model import build_model

SHORT = {"numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 0.01}


def test_a_factor_scales_that_unknown_of_every_roller_only():
    lay = build_model(load_scene("yang20_baseline")).layout
    base = atol_vector(lay, 1e-8)
    scaled = atol_vector(lay, 1e-8, {"skew_rate": 10.0, "cage_speed": 0.5})
    changed = np.flatnonzero(scaled != base)
    expected = sorted([lay.index("skew_rate", j) for j in range(lay.rollers)]
                      + [lay.index("cage_speed")])
    assert changed.tolist() == expected
    np.testing.assert_array_equal(scaled[expected[:-1]], 10.0 * base[expected[:-1]])
    assert scaled[expected[-1]] == 0.5 * base[expected[-1]]
    # a name this scene does not assemble (the cage's whirl) changes nothing
    np.testing.assert_array_equal(atol_vector(lay, 1e-8, {"cage_vx": 10.0}), base)


def test_a_run_records_its_factors_and_the_default_none():
    scene = load_scene("yang20_baseline", SHORT)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        plain = simulate(scene)
        loose = simulate(scene, solver=IDA(atol_factors={"skew_angle": 1e3, "skew_rate": 1e3}))
    assert "atol_factors" not in json.loads(plain.attrs["solver_options"])
    assert json.loads(loose.attrs["solver_options"])["atol_factors"] == {"skew_angle": 1e3,
                                                                          "skew_rate": 1e3}
    steps = [json.loads(d.attrs["solver_statistics"])["steps"] for d in (plain, loose)]
    assert steps[1] < steps[0]  # the skew's error weight sets steps (docs/performance.md)


@pytest.mark.parametrize("bad, match", [
    ({"skew": 10.0}, "unknown 'skew'; allowed are azimuth"),
    ({"skew_rate": 0.0}, r"atol_factors\['skew_rate'\] = 0.0: allowed is a number in "
                         r"\[0.001, 1000\]"),
    ({"skew_rate": float("nan")}, "allowed is a number in"),
    ({"skew_rate": "10"}, "allowed is a number in"),
    ([("skew_rate", 10.0)], "expected a dict"),
])
def test_bad_factors_are_refused_in_one_line(bad, match):
    with pytest.raises(ValueError, match=match):
        IDA(atol_factors=bad)


def test_step_controls_reach_ida_and_are_refused_out_of_range():
    """``IDA(max_order=3)`` is IDASetMaxOrd: the order IDA uses stays at or below it (IDA's
    statistics), the steps grow; recorded in the solver options; out of range refused."""
    scene = load_scene("yang20_baseline", SHORT)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        plain = simulate(scene)
        low = simulate(scene, solver=IDA(max_order=3))
    st0, st = (json.loads(d.attrs["solver_statistics"]) for d in (plain, low))
    assert max(map(int, st["order_at_outputs"])) <= 3 < max(map(int, st0["order_at_outputs"]))
    assert st["steps"] > st0["steps"]
    assert json.loads(low.attrs["solver_options"])["max_order"] == 3
    for kw, match in (({"max_order": 6}, r"max_order = 6: allowed is an integer in \[1, 5\]"),
                      ({"nonlin_conv_coef": 2.0}, r"allowed is a number in \[0.001, 1\]"),
                      ({"max_nonlin_iters": 0.5}, "allowed is an integer")):
        with pytest.raises(ValueError, match=match):
            IDA(**kw)


def test_step_ratio_controls_reach_ida_and_are_refused_out_of_range(monkeypatch):
    """``eta_max_fx``: IDA keeps its step unless it can grow by this ratio (SUNDIALS' 2): at
    1.2 it grows at smaller ratios, so the steps differ and are fewer; ``eta_max``, the largest
    growth: at 1.5 (SUNDIALS' 2) a step regrows slower after a cut, so more steps.
    ``eta_conv_fail`` acts only after a Newton failure with a fresh Jacobian, which this window
    does not have: its call is watched reaching SUNDIALS with its value and IDA's success flag.
    Each recorded in the solver options; out of range refused naming the key and the range."""
    from bearingdae.solvers.sundials import prototypes

    api = prototypes.load()
    calls, real = [], api.IDASetEtaConvFail

    def watched(mem, value):
        calls.append((value, real(mem, value)))
        return calls[-1][1]

    monkeypatch.setattr(api, "IDASetEtaConvFail", watched)
    scene = load_scene("yang20_baseline", SHORT)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        runs = [simulate(scene, solver=IDA(**kw)) for kw in
                ({}, {"eta_max_fx": 1.2}, {"eta_max": 1.5},
                 {"eta_conv_fail": 0.9})]
    steps = [json.loads(d.attrs["solver_statistics"])["steps"] for d in runs]
    assert steps[1] < steps[0] < steps[2]
    assert calls == [(0.9, 0)]  # only the run that asked, IDA_SUCCESS
    opts = [json.loads(d.attrs["solver_options"]) for d in runs]
    assert opts[1]["eta_max_fx"] == 1.2 and opts[2]["eta_max"] == 1.5
    assert opts[3]["eta_conv_fail"] == 0.9 and "eta_max" not in opts[0]
    for kw, match in (({"eta_max_fx": 0.5}, r"eta_max_fx = 0.5: allowed is a number in "
                                            r"\[1, 10\]"),
                      ({"eta_max": 1.0}, r"eta_max = 1.0: allowed is a number in \[1.01, 100\]"),
                      ({"eta_conv_fail": 1.0}, r"allowed is a number in \[0.01, 0.99\]")):
        with pytest.raises(ValueError, match=match):
            IDA(**kw)
