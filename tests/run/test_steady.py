"""Steady state on demand: the criterion, the block-by-block warm-up, the skid start, and
bad values of the new keys."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from bearingdae import load_scene, simulate
from bearingdae.scene import SceneError
from bearingdae.run.steady import NotSteadyWarning, assess

TOL = 1e-3


# ---- the criterion on block means (pure function) -----------------------------------------
def test_fluctuating_means_are_steady():
    """Means scattering ±2e-4 about a level (no common sign of the differences): steady."""
    m = 0.95 + np.array([0.0, 2e-4, -1e-4, 1.5e-4, -2e-4])
    v = assess(m, TOL)
    assert v.steady and v.remaining == 0.0, v


def test_slow_geometric_approach_is_not_steady_although_each_change_is_small():
    """m_k = c + A r^k with r = exp(-1/20) (a 20-block time constant, the Harris light-load
    spin-down): per-block changes of 5e-4 < tol, but the geometric tail still to come,
    A r^k = (change) r / (1 - r) ≈ 1e-2, is 10x the tolerance. The geometric fit of the
    differences is exact for a geometric sequence, so the estimate must equal the analytic
    tail."""
    r = np.exp(-1.0 / 20.0)
    k = np.arange(6)
    A = 5e-4 / (r ** 5 * (1 - r))  # the last change A r^4 (1 - r) r ... scaled to ~5e-4
    m = 0.6 + A * r ** k
    v = assess(m, TOL)
    assert np.all(np.abs(np.diff(m)[-2:]) < TOL)
    assert not v.steady
    assert v.remaining == pytest.approx(-A * r ** 5, rel=1e-9)


def test_fast_geometric_approach_is_steady_once_the_tail_is_below_tolerance():
    r = 0.3
    m = 0.9 + 0.05 * r ** np.arange(6)  # last changes 9.5e-4, 2.8e-4: below tol, resolved
    v = assess(m, TOL)
    tail = 0.05 * r ** 5  # what is left to go: the analytic limit 0.9 minus the last mean
    assert tail < TOL and v.steady and v.remaining == pytest.approx(-tail, rel=1e-9)


#: Block means (cage speed / epicyclic) of harris36 at 1000 N, 5000 r/min, from pure rolling,
#: blocks of one revolution (the two-starts study of docs/validation.md, 2026-11-23). Its
#: steady state from the torque-balance start is 0.9575; the first version of the trend test
#: (ratio of the last two differences) called the last of these steady at 0.9632.
SPIN_DOWN_1000N = [0.98987, 0.98197, 0.97942, 0.97794, 0.97697, 0.97622, 0.97558,
                   0.97502, 0.97450, 0.97402, 0.97349, 0.97302, 0.97252, 0.97200,
                   0.97151, 0.97099, 0.97048, 0.96997, 0.96945, 0.96899, 0.96848,
                   0.96795, 0.96750, 0.96699, 0.96659, 0.96616, 0.96571, 0.96531,
                   0.96490, 0.96452, 0.96417, 0.96379, 0.96342, 0.96316]


def test_measured_slow_spin_down_is_not_called_steady():
    """Regression (the bug above): per-block changes of ~4e-4 dying out at r ≈ 0.93-0.96 per
    block still have ≥ 3e-3 of epicyclic to go; no prefix of the measured sequence may pass
    (each is what the criterion saw after that block)."""
    for k in range(4, len(SPIN_DOWN_1000N) + 1):
        v = assess(SPIN_DOWN_1000N[:k], TOL)
        assert not v.steady, (k, v)
    assert assess(SPIN_DOWN_1000N, TOL).remaining < -3e-3


def test_large_change_or_too_few_blocks_is_not_steady():
    assert not assess([0.9, 0.9, 0.9], TOL).steady  # 3 < 4 blocks for the trend test
    v = assess([0.9, 0.9, 0.9, 0.902], TOL)  # last change 2e-3 >= tol
    assert not v.steady and "change" in v.reason
    v = assess([0.90, 0.9005, 0.9011, 0.9018], TOL)  # growing changes: not dying out
    assert not v.steady and v.remaining == np.inf


# ---- bad values of the new keys -----------------------------------------------------------
@pytest.mark.parametrize("key, value, expect", [
    ("numerics.steady_tolerance", 0.0, "[1e-06, 0.1]"),
    ("numerics.steady_tolerance", 0.5, "[1e-06, 0.1]"),
    ("numerics.steady_block_cage_revolutions", 0.0, "[0.05, 100]"),
    ("numerics.max_warmup_cage_revolutions", -1.0, "[0.05, 100000]"),
    ("numerics.until_steady", "yes", "until_steady"),
    ("numerics.initial_speeds", "rest", "epicyclic"),
])
def test_bad_values_name_key_value_and_range(key, value, expect):
    with pytest.raises(SceneError) as e:
        load_scene("yang20_baseline", {key: value})
    msg = str(e.value)
    assert key in msg and expect in msg, msg


def test_cap_shorter_than_a_block_is_refused():
    with pytest.raises(SceneError) as e:
        load_scene("yang20_baseline", {"numerics.max_warmup_cage_revolutions": 0.5,
                                       "numerics.steady_block_cage_revolutions": 2.0})
    msg = str(e.value)
    assert "max_warmup_cage_revolutions" in msg and "0.5" in msg and "[2, 1e+05]" in msg, msg


# ---- the skid start --------------------------------------------------------------------------
def _harris(load, **more):
    return load_scene("paper/harris36_5000rpm", {"operating.radial_load_N": load,
                                                  "numerics.slices": 3, **more})


def test_torque_balance_start():
    """Reference: the balance's own definition. At the returned cage speed the net axial torque
    on cage + rollers vanishes (to a millionth of the traction one loaded roller carries at
    1 m/s slip would be too strict for a root of a regularised law; 1e-6 N m, while the drag
    torque alone is ~1e-2 N m); at 0 N (no roller touches the inner race at 64 µm clearance)
    nothing drives the cage: (almost) rest; under heavy load the start is within 0.1 % of
    epicyclic; and the cage speed rises with load."""
    from bearingdae.solvers.algebraic import initial_state
    from bearingdae.system.model import build_model
    from bearingdae.solvers.torque_balance import (_balanced, axial_torque_Nm,
                                                  torque_balance_state)

    fractions = []
    for load in (0.0, 250.0, 1000.0, 12000.0):
        m = build_model(_harris(load))
        y0, _ = initial_state(m)
        y, yp, info = torque_balance_state(m, y0)
        om = info["initial_cage_speed_rad_s"]
        fractions.append(info["initial_cage_speed_fraction_of_epicyclic"])
        if 0 < fractions[-1] < 1:
            assert abs(axial_torque_Nm(m, _balanced(m, y0, om))) < 1e-6
            # and the drive is positive below, negative above the root
            assert axial_torque_Nm(m, _balanced(m, y0, 0.9 * om)) > 0
            assert axial_torque_Nm(m, _balanced(m, y0, min(1.1 * om, 0.9999 * om + 1e-3 *
                                                          om))) < 0 or fractions[-1] > 0.999
        assert np.all(np.isfinite(y)) and np.all(np.isfinite(yp))
    assert fractions[0] < 1e-3
    assert fractions[-1] > 0.999
    assert all(b > a for a, b in zip(fractions, fractions[1:])), fractions


# ---- the block-by-block warm-up --------------------------------------------------------------
def _short(load, start, cap, **more):
    return _harris(load, **{"numerics.until_steady": True, "numerics.initial_speeds": start,
                            "numerics.warmup_cage_revolutions": 0.0,
                            "numerics.cage_revolutions": 0.25,
                            "numerics.samples_per_cage_revolution": 24,
                            "numerics.steady_block_cage_revolutions": 0.5,
                            "numerics.max_warmup_cage_revolutions": cap,
                            "output.variables": ["cage_speed", "orbit_speed"], **more})


def test_until_steady_stops_on_a_steady_scene():
    """harris36 under 12 kN: the cage runs within 0.3 % of epicyclic from the start; the
    criterion must hold after the fewest blocks it can (4) or a few more, well before the
    cap, and the window recorded after it must not drift by more than the tolerance."""
    from bearingdae.analysis.summary import cage_speed_drift

    ds = simulate(_short(12000.0, "torque_balance", 20.0))
    assert ds["steady_state_reached"].item() == 1
    used = ds["warmup_cage_revolutions_used"].item()
    assert 1.999 <= used <= 5.0, used  # 4 blocks of 0.5 rev at least, the cap is 20
    means = ds.steady_block_means.values.tolist()
    assert len(means) == round(used / 0.5)
    assert abs(ds["steady_last_change"].item()) < TOL
    assert abs(cage_speed_drift(ds)) < 2 * TOL
    assert ds.time.values[0] == pytest.approx(ds["record_start_s"].item())
    st = json.loads(ds.attrs["solver_statistics"])
    assert st["segments"] == len(means) + 1  # every block plus the window


def test_until_steady_continues_on_a_scene_that_is_not_steady():
    """harris36 at 250 N from pure rolling: the cage spins down over tens of revolutions
    (docs/validation.md); with a cap of 2 revolutions the run must use all of it, be marked
    not steady and warn."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = simulate(_short(250.0, "epicyclic", 2.0))
    assert ds["steady_state_reached"].item() == 0
    assert ds["warmup_cage_revolutions_used"].item() == pytest.approx(2.0)
    means = ds.steady_block_means.values.tolist()
    assert len(means) == 4 and means[-1] < means[0]  # still spinning down
    assert any(issubclass(w.category, NotSteadyWarning) for w in caught)


def test_interrupted_warm_up_resumes_from_its_last_block(tmp_path):
    """Every block already restarts the solver from the last state, so a warm-up interrupted
    (Ctrl-C) after two blocks and resumed from its warm-up file must give the block means and
    the recorded window of the uninterrupted run bit for bit (determinism on one machine)."""
    from bearingdae.solvers.ida import IDA
    from bearingdae.run.steady import integrate_until_steady
    from bearingdae.solvers.algebraic import initial_state
    from bearingdae.system.model import build_model

    sc = _short(500.0, "epicyclic", 1.5)
    model = build_model(sc)
    y0, yp0 = initial_state(model)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NotSteadyWarning)
        ref, ref_start, ref_attrs = integrate_until_steady(IDA(), model, y0, yp0)
    path = tmp_path / "run.nc.warmup.npz"
    stop_after = 2 * 12 + 5  # samples: two blocks of 12, then 5 into the third

    class Stop:
        n = 0

        def __call__(self, t):
            self.n += 1
            if self.n == stop_after:
                raise KeyboardInterrupt

    res, _, _ = integrate_until_steady(IDA(), model, y0, yp0, progress=Stop(),
                                       warmup_path=path)
    assert not res.success and "interrupted" in res.message and path.exists()
    # the same file as the older format wrote it (no ring taps): this scene's rings are rigid,
    # so it keeps no taps and that file resumes as well
    old = tmp_path / "old.nc.warmup.npz"
    with np.load(path) as z:
        meta = json.loads(str(z["meta"]))
        assert meta["format"] == 2 and z["taps"].shape[0] == 0
        np.savez(old, y=z["y"], yp=z["yp"], meta=np.array(json.dumps({**meta, "format": 1})))
    for warm in (path, old):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NotSteadyWarning)
            again, start, attrs = integrate_until_steady(IDA(), model, y0, yp0,
                                                         warmup_path=warm, resume=True)
        assert again.success and not warm.exists()  # removed once the window is recorded
        assert attrs["steady_block_means"] == ref_attrs["steady_block_means"]
        assert start == ref_start
        np.testing.assert_array_equal(again.y, ref.y)


def test_a_warm_up_resumed_under_another_solver_is_refused(tmp_path):
    """The warm-up's file holds one integrator's state: resumed under another solver or other
    solver settings (Newmark, IDA's dense linear solver, an error-weight factor) the warm-up
    would continue one run with another's state, so the resume is refused in one line; the
    same solver and settings resume."""
    from bearingdae.run.checkpoint import CheckpointError
    from bearingdae.run.steady import integrate_until_steady
    from bearingdae.solvers.algebraic import initial_state
    from bearingdae.solvers.ida import IDA
    from bearingdae.solvers.newmark import Newmark
    from bearingdae.system.model import build_model

    model = build_model(_short(500.0, "epicyclic", 1.5))
    y0, yp0 = initial_state(model)
    path = tmp_path / "run.nc.warmup.npz"

    class Stop:  # interrupted after the first block of 12 samples
        n = 0

        def __call__(self, t):
            self.n += 1
            if self.n == 14:
                raise KeyboardInterrupt

    res, _, _ = integrate_until_steady(IDA(), model, y0, yp0, progress=Stop(), warmup_path=path)
    assert not res.success and path.exists()
    for other in (Newmark(), IDA(linsolver="dense"), IDA(atol_factors={"skew_rate": 10.0})):
        with pytest.raises(CheckpointError, match="scene, solver or bearingdae version differ"):
            integrate_until_steady(other, model, y0, yp0, warmup_path=path, resume=True)
        assert path.exists()  # nothing lost by the refusal
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NotSteadyWarning)
        again, _, _ = integrate_until_steady(IDA(), model, y0, yp0, warmup_path=path,
                                             resume=True)
    assert again.success


def test_a_warm_up_checkpoint_of_the_older_format_or_without_its_taps_is_refused(tmp_path):
    """The warm-up checkpoint keeps a dynamic ring's last taps since format 2: a file of
    format 1 (no taps: resumed, the record's first samples were triangle means) is refused
    with a line naming its format where the run continues taps, and read where it keeps none;
    a format-2 file without its taps, or with taps past its state's time, is refused as
    damaged; the file written is read back with its taps, bit for bit."""
    from bearingdae.run import warmup_checkpoint as wc
    from bearingdae.run.checkpoint import CheckpointError
    from bearingdae.system.model import build_model

    model = build_model(_short(500.0, "epicyclic", 1.5))
    key, n = wc.fingerprint(model), model.size
    taps = np.array([[0.009, 1e-6, -2e-7], [0.01, 1.1e-6, -2.1e-7]])
    run = wc.Run(0.01, np.ones(n), np.zeros(n), [1.0], {}, 1, {}, taps)
    path = tmp_path / "r.nc.warmup.npz"
    wc.save(path, key, run)
    back = wc.load(path, key, n)
    np.testing.assert_array_equal(back.taps, taps)
    assert back.t == run.t and back.means == run.means

    def rewrite(meta_change=None, **arrays):
        with np.load(path) as z:
            meta = json.loads(str(z["meta"]))
            kept = {k: z[k] for k in ("y", "yp", "taps")}
        meta.update(meta_change or {})
        kept.update(arrays)
        kept = {k: v for k, v in kept.items() if v is not None}
        bad = tmp_path / "bad.npz"
        np.savez(bad, meta=np.array(json.dumps(meta)), **kept)
        return bad

    with pytest.raises(CheckpointError, match="is of format 1, this bearingdae reads format 2"):
        wc.load(rewrite({"format": 1}, taps=None), key, n)
    # a run that keeps no taps (rigid rings) lacks nothing in a file of format 1
    older = wc.load(rewrite({"format": 1}, taps=None), key, n, taps_needed=False)
    assert older.taps.shape == (0, 3) and older.t == run.t
    np.testing.assert_array_equal(older.y, run.y)
    with pytest.raises(CheckpointError, match="is of format 3, this bearingdae reads format 2"):
        wc.load(rewrite({"format": 3}), key, n, taps_needed=False)
    with pytest.raises(CheckpointError, match="damaged .it keeps no ring taps"):
        wc.load(rewrite(taps=None), key, n)
    with pytest.raises(CheckpointError, match="taps' times do not increase up to the state"):
        wc.load(rewrite(taps=taps + [[0.002, 0, 0]]), key, n)
    with pytest.raises(CheckpointError, match="taps are not rows of 3 numbers"):
        wc.load(rewrite(taps=taps[:, :2]), key, n)


def test_a_creep_below_the_drift_resolution_is_no_drift():
    """A cage at rest (harris36, 0 N) whose block means creep by 1e-10 per block: below the
    drift resolution (tolerance/20) the change is not resolved and must not count as drift."""
    m = 2e-5 + 1e-10 * np.arange(5)
    assert assess(m, TOL).steady and assess(m, TOL).remaining == 0.0
    # ... while a monotone creep of 1e-4 per block that is not dying out is drift
    v = assess(0.9 + 1e-4 * np.arange(5), TOL)
    assert not v.steady and v.remaining == np.inf


# ---- where the run starts, and how long it will probably take --------------------------------
@pytest.mark.parametrize("until_steady, given, expect", [
    (True, None, "torque_balance"), (False, None, "epicyclic"),
    (True, "epicyclic", "epicyclic"), (False, "torque_balance", "torque_balance")])
def test_auto_initial_speeds_start_a_steady_search_at_the_torque_balance(until_steady, given,
                                                                          expect):
    over = {"numerics.until_steady": until_steady}
    if given is not None:
        over["numerics.initial_speeds"] = given
    assert load_scene("yang20_baseline", over).dynamics.initial_speeds == expect


@pytest.mark.parametrize("r", [0.5, 0.8, 0.93])
def test_blocks_to_go_predicts_when_a_geometric_approach_becomes_steady(r):
    """Reference: the criterion itself, applied block by block to a geometric approach
    m_k = 1 - 0.2 r^k (exact for the extrapolation the criterion makes). After the first blocks
    the predicted number of further blocks must match the count at which ``assess`` first says
    steady to within one block."""
    from bearingdae.run.steady import blocks_to_go

    means = [1 - 0.2 * r**k for k in range(400)]
    first_steady = next(k for k in range(2, 400) if assess(means[:k + 1], TOL).steady)
    for k in range(4, 40, 3):
        if k >= first_steady:
            continue
        v = assess(means[:k + 1], TOL)
        predicted = k + blocks_to_go(v, TOL, k + 1)
        assert abs(predicted - first_steady) <= 1, (k, predicted, first_steady)


def test_blocks_to_go_without_enough_blocks_or_without_decay():
    from bearingdae.run.steady import TREND_BLOCKS, blocks_to_go

    assert blocks_to_go(assess([0.9, 0.95], TOL), TOL, 2) == TREND_BLOCKS - 2
    growing = [1 + 0.01 * 1.1**k for k in range(8)]  # r > 1: not dying out, the cap decides
    assert blocks_to_go(assess(growing, TOL), TOL, 8) >= 10**6


def test_progress_total_follows_a_new_estimate():
    import io

    from bearingdae.run.progress import SimulationProgress

    out = io.StringIO()
    bar = SimulationProgress(100.0, stream=out, tty=False)
    bar.update(0.0)
    bar.update(5.0)
    bar.set_total(10.0)  # now half done: the next line is at 60 %
    bar.update(5.5)
    bar.update(6.0)
    lines = out.getvalue().splitlines()
    assert lines[-1].startswith("simulated time 6.0000/10.0000 s (60 %)"), lines
    assert not any("(55 %)" in ln for ln in lines)
