"""The solver contract (bearingdae/solvers/base.py) holds for every solver.

Every integrator — IDA, Newmark-β, each scipy peer, and IDA wrapped in a checkpoint — on a very
short window (0.02 cage revolutions, 5 samples):

* the Dataset's ``solver_options.solver`` names the solver that ran (it once said ``"ida"`` for
  a scipy-BDF run), and its description is that solver's;
* a failure keeps every sample reached before it (the fault: the radial load set to NaN in the
  model's parameters after the second sample, so every later residual is NaN);
* Ctrl-C, delivered as a KeyboardInterrupt raised by the progress callback, is reported in the
  Solution (``"interrupted by the user"``) with the samples up to it;
* bad output times or state sizes raise ValueError before any work.
"""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from bearingdae import (IDA, Checkpoint, Checkpointed, Newmark, ScipyPeer, Solver, load_scene,
                        simulate)
from bearingdae.api import output_times
from bearingdae.solvers import NAMES, from_name
from bearingdae.solvers.algebraic import initial_state
from bearingdae.system.model import build_model

SHORT = {"numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 0.02,
         "numerics.samples_per_cage_revolution": 200, "operating.moment_Nm": 0.0}
PEERS = ("BDF", "Radau", "LSODA")


def solvers(tmp_path) -> dict[str, Solver]:
    """Label -> a fresh solver object (the checkpointed one writes into tmp_path)."""
    out = {"ida": IDA(), "newmark": Newmark()}
    out.update({f"scipy-{m}": ScipyPeer(m) for m in PEERS})
    out["checkpointed-ida"] = Checkpointed(IDA(), Checkpoint(tmp_path / "ck.npz",
                                                             every_samples=1))
    return out


LABELS = ["ida", "newmark", *(f"scipy-{m}" for m in PEERS), "checkpointed-ida"]


@pytest.fixture(scope="module")
def scene():
    return load_scene("yang20_baseline", SHORT)


@pytest.fixture(scope="module")
def start(scene):
    model = build_model(scene)
    y0, yp0 = initial_state(model)
    t_out, _ = output_times(model)
    return model, y0, yp0, t_out


def quiet(fn, *args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kw)


@pytest.mark.parametrize("label", [pytest.param(x, marks=pytest.mark.slow) if x in ("scipy-BDF", "scipy-Radau") else x
                                   for x in LABELS])
def test_dataset_names_the_solver_that_ran(scene, tmp_path, label):
    solver = solvers(tmp_path)[label]
    ds = quiet(simulate, scene, solver=solver)
    options = json.loads(ds.attrs["solver_options"])
    expected = label.removeprefix("checkpointed-")
    assert solver.name == expected
    assert options["solver"] == expected
    d = solver.describe()
    assert d["solver"] == expected and isinstance(d["options"], dict)
    json.dumps(d["options"])  # JSON-able (contract item 5)
    for key, value in d["options"].items():
        assert options[key] == value, key  # every setting of the solver is recorded
    if expected == "ida":
        assert "SUNDIALS IDA" in ds.attrs["solver"]
    else:
        assert "SUNDIALS" not in ds.attrs["solver"]
        assert ds.attrs["sundials_version"].startswith("not used")
    if expected.startswith("scipy-"):
        assert ds.attrs["solver"].startswith(f"scipy {expected.removeprefix('scipy-')}")
    stats = json.loads(ds.attrs["solver_statistics"])
    assert stats["output_samples"] == ds.sizes["time"] == 5
    assert stats["residual_calls"] > 0
    if expected != "ida":  # scikit-sundae's IDA object has no step count (get_stats) to read
        assert stats["steps"] > 0
    if label.startswith("checkpointed"):
        with np.load(tmp_path / "ck.npz") as z:
            assert z["t"].size == 5


@pytest.mark.parametrize("name", NAMES)
def test_names_map_to_solvers_that_name_themselves(scene, name):
    """Strings stay at the command line: from_name(name).name == name, and simulate with the
    name records it too."""
    assert from_name(name).name == name
    ds = quiet(simulate, scene, solver=name)
    assert json.loads(ds.attrs["solver_options"])["solver"] == name


@pytest.mark.parametrize("label", LABELS)
def test_failure_keeps_the_samples_before_it(start, tmp_path, label):
    model, y0, yp0, t_out = start
    solver = solvers(tmp_path)[label]
    table = model.work_array("load_table")
    load = float(table[0, 1])
    seen = []

    def poison(t, y, yp):  # after the second sample every residual is NaN
        seen.append(t)
        if len(seen) == 2:
            table[0, 1] = np.nan

    try:
        sol = quiet(solver.integrate, model, y0, yp0, t_out, on_sample=poison)
    finally:
        table[0, 1] = load
    assert not sol.success
    assert sol.message
    assert sol.t.size == 2 and sol.y.shape == (2, model.size) == sol.yp.shape
    np.testing.assert_array_equal(sol.t, t_out[:2])
    assert np.all(np.isfinite(sol.y))
    assert sol.failure_time_s is not None and t_out[1] <= sol.failure_time_s <= t_out[2]
    assert sol.stats["output_samples"] == 2


@pytest.mark.parametrize("label", LABELS)
def test_ctrl_c_in_progress_is_reported_with_the_samples(start, tmp_path, label):
    model, y0, yp0, t_out = start
    solver = solvers(tmp_path)[label]
    ticks = []

    def progress(t):
        ticks.append(t)
        if len(ticks) == 3:
            raise KeyboardInterrupt

    sol = quiet(solver.integrate, model, y0, yp0, t_out, progress=progress)
    assert not sol.success
    assert sol.message.startswith("interrupted by the user at t = ")
    np.testing.assert_array_equal(sol.t, t_out[:3])
    assert sol.failure_time_s == t_out[2]


@pytest.mark.parametrize("label", LABELS)
def test_bad_output_times_raise_before_any_work(start, tmp_path, label):
    model, y0, yp0, t_out = start
    solver = solvers(tmp_path)[label]
    calls = []
    for bad, match in ((t_out[::-1], "increasing"), (np.array([0.0, 0.0]), "increasing"),
                       (np.array([]), "non-empty"), (np.array([0.0, np.nan]), "finite"),
                       (np.zeros((2, 2)), "1-D")):
        with pytest.raises(ValueError, match=match):
            solver.integrate(model, y0, yp0, bad, on_sample=lambda *a: calls.append(a))
    with pytest.raises(ValueError, match="before t_start"):
        solver.integrate(model, y0, yp0, t_out, t_start=1e-3)
    with pytest.raises(ValueError, match="shape"):
        solver.integrate(model, y0[:-1], yp0, t_out)
    assert not calls
    if label.startswith("checkpointed"):
        assert not (tmp_path / "ck.npz").exists()  # nothing written either


@pytest.mark.parametrize("label", ["ida", "newmark", "scipy-BDF"])
def test_integration_starts_at_t_start(start, tmp_path, label):
    """Contract item 1: from (t_start, y0, y'0); the first sample is the start when
    t_out[0] == t_start (what resuming from a checkpoint relies on)."""
    model, y0, yp0, t_out = start
    t0 = 1e-3
    sol = quiet(solvers(tmp_path)[label].integrate, model, y0, yp0, t0 + t_out[:3], t_start=t0)
    assert sol.success, sol.message
    np.testing.assert_array_equal(sol.t, t0 + t_out[:3])


def test_from_name_rejects_unknown_names_and_options():
    with pytest.raises(ValueError, match="allowed are 'ida', 'newmark', 'scipy-BDF'"):
        from_name("euler")
    with pytest.raises(ValueError, match="unknown option.*'rtol'.*allowed are"):
        from_name("ida", rtol=1e-3)
    assert from_name("scipy-Radau", jacobian="fd").dae_jacobian == "fd"
    with pytest.raises(ValueError, match="linsolver = 'lu'"):
        IDA(linsolver="lu")
    with pytest.raises(ValueError, match="method = 'RK45'"):
        ScipyPeer("RK45")


def test_old_keywords_warn_and_still_apply(scene):
    with pytest.warns(DeprecationWarning, match="linsolver=, jacobian="):
        ds = simulate(scene, linsolver="dense", jacobian="fd")
    options = json.loads(ds.attrs["solver_options"])
    assert (options["solver"], options["linsolver"], options["jacobian"]) == ("ida", "dense",
                                                                               "fd")
    with pytest.warns(DeprecationWarning, match="solver_options="):
        ds = simulate(scene, solver="scipy-BDF", solver_options={"jac": "fd"})
    assert json.loads(ds.attrs["solver_options"])["jac"] == "fd"
    with pytest.raises(ValueError, match="beside the solver object"):
        quiet(simulate, scene, solver=IDA(), jacobian="fd")


def test_old_function_forms_warn_and_still_work(start, tmp_path):
    """One release of deprecation: the module-level integrate functions and
    Checkpoint.integrate keep working, with a DeprecationWarning."""
    from bearingdae.solvers import newmark, scipy_peers

    model, y0, yp0, t_out = start
    for fn in (newmark.integrate, scipy_peers.integrate,
               Checkpoint(tmp_path / "old.npz").integrate):
        with pytest.warns(DeprecationWarning, match="deprecated"):
            sol = fn(model, y0, yp0, t_out[:2])
        assert sol.success and sol.t.size == 2


def test_from_name_knows_the_scikit_sundae_cross_check():
    """The cross-check path is reachable by name and names itself (contract item 5)."""
    from bearingdae.solvers import NAMES, from_name

    s = from_name("ida-scikit-sundae", jacobian="fd")
    assert "ida-scikit-sundae" in NAMES
    assert s.describe()["solver"] == "ida-scikit-sundae" and s.jacobian == "fd"
