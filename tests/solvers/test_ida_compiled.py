"""The compiled IDA core (bearingdae/solvers/ida.py IDA, solvers/sundials/): the same SUNDIALS
IDA as scikit-sundae's Python-callback path, deterministic, failing cleanly, freeing its memory.

Reference for the agreement test: :class:`IDAScikitSundae`, the same IDA 7.9 driven through
scikit-sundae's own callback wrappers — an independent binding of the same integrator with the
same options, so the two must agree within the integration tolerance (in practice they agree to
the last bit, since the arithmetic is the same).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from bearingdae import load_scene
from bearingdae.solvers import ida as ida_mod
from bearingdae.solvers.ida import IDA, IDAScikitSundae, integrate
from bearingdae.solvers.sundials import library, prototypes
from bearingdae.solvers.sundials.session import Session
from bearingdae.solvers.algebraic import initial_state
from bearingdae.system.layout import GLOBAL, LOCAL
from bearingdae.system.model import build_model
from bearingdae.system.residual import P_MASS


@pytest.fixture(scope="module")
def baseline():
    m = build_model(load_scene("yang20_baseline"))
    y0, yp0 = initial_state(m)
    return m, y0, yp0


def quarter_revolution(m):
    return np.linspace(0.0, 0.25 * 2 * np.pi / m.final_cage_speed(), 26)


def test_compiled_agrees_with_scikit_sundae_on_first_quarter_revolution(baseline):
    m, y0, yp0 = baseline
    t_out = quarter_revolution(m)
    # SUNDIALS' own Jacobian-refresh threshold (scikit-sundae cannot set ours): same settings
    a = IDA("sparse", delta_cj_lsetup=0.25).integrate(m, y0, yp0, t_out)
    b = IDAScikitSundae("sparse").integrate(m, y0, yp0, t_out)
    assert a.success and b.success, (a.message, b.message)
    np.testing.assert_array_equal(a.t, b.t)
    # within the integration tolerance, in the scaled units atol refers to
    rtol, atol = m.scene.dynamics.rtol, ida_mod.algebraic_atol(m.scene.dynamics.atol)
    err = np.abs(a.y - b.y) / (atol + rtol * np.abs(b.y))
    assert err.max() <= 1.0
    # the same integrator on the same callbacks does the same work
    assert a.stats["residual_calls"] == b.stats["residual_calls"]
    assert a.stats["jacobian_calls"] == b.stats["jacobian_calls"]


def test_jacobian_refresh_threshold_costs_no_accuracy():
    """ida.DELTA_CJ_LSETUP (0.15) against SUNDIALS' default 0.25: fewer residual calls, and
    the default's errors in cage speed, orbit speeds and skew angles over the first quarter
    revolution, against IDA at rtol 1e-9 (SuperLU_MT, SUNDIALS' setting), within the band that
    the event-driven trajectory supports. Measured (CHANGELOG.md, 2026-11-23, "Jacobian
    refresh threshold"): two rtol-1e-9 runs differing only in the linear solver's round-off are
    9e-6 / 2e-5 / 8.5e-4 apart (relative RMS); eight rtol-1e-6 runs (two linear solvers x four
    thresholds 0.12-0.25) lie within 1.7e-5 / 5.1e-5 / 7.1e-3 of the reference. Bounds: about
    3x that, 5e-5 / 2e-4 / 2e-2."""
    def run(rtol, **kw):
        sc = load_scene("yang20_baseline", {"numerics.rtol": rtol, "numerics.atol": rtol * 1e-2})
        m = build_model(sc)
        y0, yp0 = initial_state(m)
        s = IDA(**kw).integrate(m, y0, yp0, quarter_revolution(m))
        assert s.success
        full = [m.layout.unpack(y * m.scale) for y in s.y]
        return s, {"cage": np.array([f[1][GLOBAL.index("cage_speed")] for f in full]),
                   "orbit": np.array([f[0][:, LOCAL.index("orbit_speed")] for f in full]),
                   "skew": np.array([f[0][:, LOCAL.index("skew_angle")] for f in full])}

    def rel_rms(a, b):
        return np.sqrt(np.mean((a - b) ** 2) / np.mean(b ** 2))

    _, ref = run(1e-9, linsolver="sparse", delta_cj_lsetup=0.25)
    s_sun, _ = run(1e-6, delta_cj_lsetup=0.25)
    s_new, new = run(1e-6)
    assert s_new.stats["residual_calls"] < s_sun.stats["residual_calls"]
    for q, bound in (("cage", 5e-5), ("orbit", 2e-4), ("skew", 2e-2)):
        assert rel_rms(new[q], ref[q]) <= bound, q


@pytest.mark.parametrize("linsolver,jacobian", [("dense", "analytic"),
                                                pytest.param("sparse", "fd", marks=pytest.mark.slow)])
def test_other_linear_solvers_and_jacobians_agree(baseline, linsolver, jacobian):
    m, y0, yp0 = baseline
    t_out = np.linspace(0.0, 0.002, 5)
    a = IDA(linsolver, jacobian, delta_cj_lsetup=0.25).integrate(m, y0, yp0, t_out)
    b = IDAScikitSundae(linsolver, jacobian).integrate(m, y0, yp0, t_out)
    assert a.success and b.success
    rtol, atol = m.scene.dynamics.rtol, ida_mod.algebraic_atol(m.scene.dynamics.atol)
    assert (np.abs(a.y - b.y) / (atol + rtol * np.abs(b.y))).max() <= 1.0
    if jacobian == "fd":
        assert a.stats["residual_calls_in_jacobian"] == b.stats["residual_calls_in_jacobian"]


def test_run_to_run_determinism(baseline):
    m, y0, yp0 = baseline
    t_out = np.linspace(0.0, 0.003, 7)
    a = integrate(m, y0, yp0, t_out)
    b = integrate(m, y0, yp0, t_out)
    np.testing.assert_array_equal(a.y, b.y)
    np.testing.assert_array_equal(a.yp, b.yp)
    for k in ("steps", "residual_calls", "jacobian_calls", "error_test_failures"):
        assert a.stats[k] == b.stats[k]


def test_statistics_come_from_ida_and_budget_on_a_short_window(baseline):
    """Cost budget on 2 ms of the baseline (measured: 458 steps, 777 residual calls, 80
    Jacobians at rtol 1e-6); the limits leave room for kernel changes that move round-off."""
    m, y0, yp0 = baseline
    r = IDA().integrate(m, y0, yp0, np.linspace(0.0, 0.002, 5))
    s = r.stats
    assert r.success
    assert 0 < s["steps"] < 900
    assert s["residual_calls"] < 1600
    assert s["jacobian_calls"] < 200
    # analytic Jacobian: no residual calls inside it; about 1.7 residual calls per step
    assert s["residual_calls_in_jacobian"] == 0
    assert s["residual_calls"] < 2.5 * s["steps"]
    assert s["nonlinear_iterations"] >= s["steps"]
    assert 0 < s["smallest_last_step_at_outputs_s"] <= 0.002
    assert sum(s["order_at_outputs"].values()) == 4
    assert all(1 <= int(k) <= 5 for k in s["order_at_outputs"])
    assert s["sundials_version"].startswith("7.")
    # the set-up before the first step (the kernels loaded or compiled) is part of the wall time
    assert 0.0 < s["setup_wall_s"] <= s["wall_time_s"]


def test_describe_names_the_solver():
    assert IDA().describe()["solver"] == "ida"
    assert IDAScikitSundae().describe()["solver"] == "ida-scikit-sundae"
    assert IDA("dense", "fd").describe()["options"] == {
        "linsolver": "dense", "jacobian": "fd", "delta_cj_lsetup": ida_mod.DELTA_CJ_LSETUP,
        "suppress_alg": False}
    with pytest.raises(ValueError, match="delta_cj_lsetup = 1.5: allowed is a number in"):
        IDA(delta_cj_lsetup=1.5)
    with pytest.raises(ValueError, match="linsolver = 'klu'"):
        IDA("klu")
    with pytest.raises(ValueError, match="jacobian = 'exact'"):
        IDA(jacobian="exact")


@pytest.fixture
def closed_sessions(monkeypatch):
    """Records every Session's pointers left after close (must be none)."""
    left = []
    original = Session.close

    def close(self):
        original(self)
        left.append(dict(self._ptrs))
    monkeypatch.setattr(Session, "close", close)
    return left


def test_too_many_steps_fails_cleanly_with_time_and_cause(closed_sessions):
    m = build_model(load_scene("yang20_baseline", {"numerics.max_steps": 100}))
    y0, yp0 = initial_state(m)
    t_out = np.linspace(0.0, 0.01, 11)  # about 230 steps per output interval at rtol 1e-6
    r = IDA().integrate(m, y0, yp0, t_out)
    assert not r.success
    assert "too much work" in r.message and "t = " in r.message
    assert r.failure_time_s is not None and 0.0 < r.failure_time_s < 0.01
    assert r.t.size >= 1 and np.all(r.t < r.failure_time_s + 1e-15)  # samples before it kept
    assert closed_sessions and closed_sessions[-1] == {}


@pytest.mark.parametrize("linsolver", ["sparse", "dense"])
def test_nan_residual_fails_cleanly_and_frees_memory(closed_sessions, linsolver):
    """Also the SuperLU_MT solver that never got set up (freeing it would crash SUNDIALS 7.9:
    session.py leaves it) — the process must survive."""
    m = build_model(load_scene("yang20_baseline"))
    y0, yp0 = initial_state(m)
    m.params[P_MASS] = np.nan  # every orbit/spin row becomes NaN
    r = IDA(linsolver).integrate(m, y0, yp0, np.linspace(0.0, 0.001, 3))
    assert not r.success
    assert "t = 0 s" in r.message
    assert "residual" in r.message
    assert r.failure_time_s == 0.0
    assert closed_sessions and closed_sessions[-1] == {}


def test_interrupt_from_a_hook_frees_memory(baseline, closed_sessions):
    m, y0, yp0 = baseline

    def progress(t):
        if t > 0.0005:
            raise KeyboardInterrupt
    r = IDA().integrate(m, y0, yp0, np.linspace(0.0, 0.002, 9), progress=progress)
    assert not r.success and "interrupted" in r.message
    assert r.t.size == 4  # the sample whose progress call was interrupted is kept
    assert closed_sessions and closed_sessions[-1] == {}


def test_missing_libraries_give_a_clear_error(monkeypatch):
    monkeypatch.setattr(library, "_mapped_paths", lambda: [])
    monkeypatch.setattr(library, "_directory_paths", lambda f: [])
    with pytest.raises(library.SundialsUnavailable, match=r"libsundials_ida.*IDAScikitSundae"):
        library.find_libraries()


def test_libraries_are_found_without_importing_scikit_sundae():
    """The wheel's library folder and build record are read without importing the package
    (its import pulls in scipy.optimize: ~0.1 s of every run's start); they name what the
    package itself reports once imported."""
    code = ("import sys, json; from bearingdae.solvers.sundials import library as L; "
            "p = L.find_libraries(); c = L.build_config(); v = L.versions(); "
            "print(json.dumps([sorted(p), c, v, 'sksundae' in sys.modules]))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    names, config, (sundials, package), imported = json.loads(out.strip().splitlines()[-1])
    if imported:
        pytest.skip("this scikit-sundae install has no library folder beside the package")
    assert set(library.REQUIRED) <= set(names)
    import sksundae
    from sksundae._cy_common import config as cy_config

    for key in ("SUNDIALS_FLOAT_TYPE", "SUNDIALS_INT_TYPE", "SUNDIALS_VERSION"):
        assert config[key] == cy_config[key]
    assert (sundials, package) == (sksundae.SUNDIALS_VERSION, sksundae.__version__)


def test_build_record_falls_back_to_the_package(monkeypatch, tmp_path):
    """Without the wheel's py_config.pxi (another packaging) the record comes from the
    compiled module, as before."""
    monkeypatch.setattr(library, "_package_directory", lambda: str(tmp_path))
    from sksundae._cy_common import config as cy_config

    assert library.build_config()["SUNDIALS_INT_TYPE"] == cy_config["SUNDIALS_INT_TYPE"]


def test_wrong_sundials_version_is_refused():
    class FakeCore:
        class SUNDIALSGetVersion:  # noqa: N801  (stands for the C function)
            argtypes = restype = None

            def __new__(cls, buf, n):
                buf.value = b"6.7.0"
                return 0
    with pytest.raises(library.SundialsUnavailable, match="SUNDIALS 6.7.0 found.*7.x"):
        library.check_build(FakeCore, {})


def test_layout_check_and_build_facts():
    api = prototypes.load()
    assert api.build.version.startswith("7.")
    assert api.build.index_bytes in (4, 8)
    assert api.nvec_data_offset in (8, 16, 24)


def test_message_for_every_documented_failure_flag():
    for flag in (-1, -2, -3, -4, -5, -6, -7, -8, -9, -12, -13, -14, -20, -22, -99):
        assert "IDA flag" in prototypes.flag_message(flag)
        assert "unknown" not in prototypes.flag_message(flag)


def test_recording_mode_takes_the_same_steps(baseline):
    """record_steps (one IDASolve per internal step, for benchmarks) must not change the
    trajectory: same samples, same counts; its exact smallest step is <= the sampled one."""
    m, y0, yp0 = baseline
    t_out = np.linspace(0.0, 0.002, 5)
    a = IDA().integrate(m, y0, yp0, t_out)
    rec = IDA(record_steps=True)
    b = rec.integrate(m, y0, yp0, t_out)
    np.testing.assert_array_equal(a.y, b.y)
    assert a.stats["steps"] == b.stats["steps"] == rec.last_step_record[0].size
    assert b.stats["smallest_step_s"] <= b.stats["smallest_last_step_at_outputs_s"]
    assert np.all(np.diff(rec.last_step_record[1]) > 0)
    # each step's limiter (the unknown of largest weighted local error), by name
    limiters = b.stats["step_limiters"]
    assert sum(limiters.values()) == b.stats["steps"]
    assert set(limiters) <= set(m.layout.local_names) | set(m.layout.global_names)


def test_step_limiters_are_named_by_the_layout(baseline):
    """A compact index counts under the name Layout.index gives it: per roller for a
    roller's unknown (summed over the rollers), once for a global one."""
    from bearingdae.solvers.ida_statistics import limiter_counts

    lay = baseline[0].layout
    last = lay.rollers - 1
    picks = [lay.index("skew_rate", 0), lay.index("skew_rate", last), lay.index("tilt", 3),
             lay.index(lay.global_names[-1])]
    assert limiter_counts(picks, lay) == {"skew_rate": 2, "tilt": 1, lay.global_names[-1]: 1}


def test_callbacks_load_from_numba_cache_in_a_fresh_process():
    """cache=True must hold for the cfuncs (no ctypes address baked in): a second fresh process
    loads them from the cache instead of compiling (~3 s each time otherwise)."""
    code = ("import bearingdae.solvers.sundials.callbacks as cb; "
            "print(sum(cb.compiled(k).cache_hits for k in ('residual', 'analytic')))")
    env = {**os.environ, "OMP_NUM_THREADS": "1"}
    for _ in range(2):  # the first may compile (cold cache); the second must hit
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                             env=env, check=True).stdout
    assert int(out.split()[-1]) == 2
