"""Newmark-β / HHT-α (issue 4, MODEL §12): the independent cross-check of IDA.

References: IDA (an independent, variable-order BDF integrator of the same residual) for
agreement; the integrator's own refinement at h/8 (and a tight IDA run) for the observed order.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.linalg as sl
import scipy.sparse as sp

from bearingdae import SceneError, load_scene, simulate
from bearingdae.solvers.ida import _jacobian_work
from bearingdae.solvers.newmark import NewmarkOptions, integrate
from bearingdae.system.jacobian import fill_jacobian
from bearingdae.system.model import build_model, initial_state

SHORT = {"numerics.warmup_cage_revolutions": 0.05, "numerics.cage_revolutions": 0.1,
         "numerics.samples_per_cage_revolution": 200}


def baseline(**over):
    return load_scene("yang20_baseline", {**SHORT, **over})


def agreement(ref, ds) -> dict[str, float]:
    """The issue-4 agreement measures of ``ds`` against ``ref`` over the recorded window."""
    skew_amp = float(abs(ds.skew_angle).max("time").mean())  # mean over rollers of the peak
    skew_amp_ref = float(abs(ref.skew_angle).max("time").mean())
    return {
        "cage_speed_mean": abs(float(ds.cage_speed.mean() / ref.cage_speed.mean()) - 1),
        "skew_amplitude": abs(skew_amp / skew_amp_ref - 1),
        "contact_force": float(abs(ds.contact_force - ref.contact_force).max()
                               / ref.contact_force.max()),
    }


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
    assert json.loads(nm.attrs["solver_options"])["newmark_step_s"] == 2e-6


def test_newmark_agrees_with_ida_on_shortened_baseline(pair):
    """Reference: IDA (independent BDF integrator, rtol 1e-6) on the first 10 ms of the
    baseline, short enough for the two trajectories to stay together (the skew motion is
    chaotic over longer windows, docs/theory.md): the issue-4 measures, cage speed 1e-3
    (mean), skew amplitude 5 %, slice contact force 1 %, are met with a wide margin."""
    ida, nm = pair
    got = agreement(ida, nm)
    assert got["cage_speed_mean"] <= 1e-3 / 100, got
    assert got["skew_amplitude"] <= 0.05 / 10, got
    assert got["contact_force"] <= 0.01 / 10, got


@pytest.mark.slow
def test_newmark_agrees_with_ida_over_the_deterministic_horizon():
    """Reference: IDA (rtol 1e-6) over the first quarter cage revolution (16.5 ms) from the
    common initial state, where the trajectories of both integrators still shadow each other
    (measured: pointwise skew differences grow from 1e-3 at 12 ms to O(1) after ~30 ms, for
    any two runs that differ at round-off level, IDA against IDA included). Issue-4 measures
    with the default h = 2 µs; measured 8e-8, 0.1 %, 8e-6."""
    sc = load_scene("yang20_baseline", {"numerics.warmup_cage_revolutions": 0.0,
                                        "numerics.cage_revolutions": 0.25})
    got = agreement(simulate(sc), simulate(sc, solver="newmark"))
    assert got["cage_speed_mean"] <= 1e-3, got
    assert got["skew_amplitude"] <= 0.05, got
    assert got["contact_force"] <= 0.01, got


@pytest.mark.slow
def test_newmark_agrees_with_ida_on_full_baseline():
    """Reference: IDA (rtol 1e-6) on the full baseline (1 warm-up + 3 recorded cage
    revolutions). Cage speed (mean) to 1e-3 and slice contact force to 1 % of its peak,
    pointwise, as issue 4 asks (measured 5e-5 and 0.4 %). The skew motion is chaotic after
    ~30 ms, so its amplitude over the window is a statistic of one realisation: IDA runs whose
    initial spin of one roller differs by 1e-12 (relative) gave mean per-roller peaks of
    2.54-2.89 mrad (8 runs), Newmark at 1, 2, 4 µs 2.81-3.02 mrad (6 runs), a ~6 % difference
    of the means that refinement does not remove (docs/theory.md, "Newmark-β"). Measured for
    this pair: 7.9 %. The 5 % of issue 4 holds over the deterministic horizon (test above);
    here the two must agree to 20 %, the spread of those ensembles."""
    sc = load_scene("yang20_baseline")
    got = agreement(simulate(sc), simulate(sc, solver="newmark"))
    assert got["cage_speed_mean"] <= 1e-3, got
    assert got["contact_force"] <= 0.01, got
    assert got["skew_amplitude"] <= 0.20, got


def test_step_budget_and_cost_counts(pair):
    """Cost budget (counts, not wall time), recorded on the project machine: 10 ms at the
    default h = 2 µs is 5000 steps and took ~2.2 Newton iterations per step and ~150
    factorisations."""
    st = json.loads(pair[1].attrs["solver_statistics"])
    assert st["steps"] == pytest.approx(0.15 * 2 * np.pi / 95.411 / 2e-6, rel=0.01)
    assert st["newton_iterations"] <= 3.0 * st["steps"]
    assert st["lu_factorisations"] <= 0.1 * st["steps"]
    assert st["step_halvings"] == 0


def test_cli_runs_newmark(tmp_path):
    from bearingdae.cli import main

    out = tmp_path / "nm.nc"
    args = ["run", "yang20_baseline", "--solver", "newmark", "--no-plot", "--no-progress",
            "-o", str(out), "--set", "numerics.warmup_cage_revolutions=0.01",
            "--set", "numerics.cage_revolutions=0.01"]
    assert main(args) == 0
    import xarray as xr

    with xr.open_dataset(out) as ds:
        assert "Newmark" in ds.attrs["solver"] and ds.sizes["time"] >= 2


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


# ---------------------------------------------------------------------------------------------
# Accuracy: observed order, error estimate, HHT damping (direct calls on the baseline model)
# ---------------------------------------------------------------------------------------------
QUANTITIES = ("orbit_speed", "spin_speed", "skew_angle", "cage_speed")


@pytest.fixture(scope="module")
def model():
    m = build_model(load_scene("yang20_baseline"))
    return m, *initial_state(m)


def hht(h, alpha=0.0, **kw):
    return NewmarkOptions(step_s=h, alpha=alpha, beta=0.25 * (1 - alpha) ** 2,
                          gamma=0.5 - alpha, **kw)


def relative_errors(m, r, ref) -> dict[str, float]:
    """Max over output times (and rollers) of |y - y_ref|, relative to max |y_ref|, per kind."""
    lay, out = m.layout, {}
    for q in QUANTITIES:
        idx = ([lay.index(q, j) for j in range(lay.rollers)] if q in lay.local_names
               else [lay.index(q)])
        a, b = r.y[:, idx] * m.scale[idx], ref.y[:, idx] * m.scale[idx]
        out[q] = float(np.abs(a - b).max() / np.abs(b).max())
    return out


def observed_orders(model, alpha):
    m, y0, yp0 = model
    t_out = np.linspace(0.0, 2e-3, 11)
    steps = np.array([16e-6, 8e-6, 4e-6])
    ref = integrate(m, y0, yp0, t_out, hht(steps[-1] / 8, alpha))
    errs = {q: [] for q in QUANTITIES}
    for h in steps:
        r = integrate(m, y0, yp0, t_out, hht(h, alpha))
        assert r.success
        for q, e in relative_errors(m, r, ref).items():
            errs[q].append(e)
    return {q: np.polyfit(np.log(steps), np.log(e), 1)[0] for q, e in errs.items()}, errs


@pytest.mark.parametrize("alpha", [0.0, -0.3])
def test_observed_order_is_two(model, alpha):
    """Reference: the same integrator at h/8 of the finest step. Newmark-β (β = 1/4, γ = 1/2)
    and HHT-α (γ = 1/2 - α, β = (1 - α)²/4) are second order; the slope of a least-squares
    fit of log(error) against log(h) over h = 16, 8, 4 µs must be 2 ± 0.3 for every kind of
    unknown. Scene: the baseline's first 2 ms (rollers start at pure rolling, skew grows
    smoothly from 0; no pocket impact yet)."""
    orders, errs = observed_orders(model, alpha)
    for q, p in orders.items():
        assert abs(p - 2.0) <= 0.3, (q, p, errs[q])


def test_step_doubling_estimate_tracks_true_error(model):
    """Reference: the true error against the same integrator at h/16. The Richardson estimate
    4/3 (y_h - y_h/2) of a second-order method must be within a factor 3 of it."""
    m, y0, yp0 = model
    t_out = np.linspace(0.0, 2e-3, 11)
    h = 8e-6
    ref = integrate(m, y0, yp0, t_out, hht(h / 16))
    r = integrate(m, y0, yp0, t_out, hht(h, error_estimate=True))
    assert r.error_estimate is not None and r.error_estimate.shape == r.y.shape
    est = type(r)(r.t, r.y + r.error_estimate, r.yp, True, "", None)  # estimate as an offset
    true = relative_errors(m, r, ref)
    estimated = relative_errors(m, est, r)
    for q in QUANTITIES:
        assert true[q] / 3 <= estimated[q] <= 3 * true[q], (q, true[q], estimated[q])
    # the estimate runs a second solution at h/2: 3x the steps of the plain run
    st = r.stats["error_estimate_solution_statistics"]
    assert st["steps"] == 2 * r.stats["steps"]


def hht_scalar_response(z: float, alpha: float, n: int) -> np.ndarray:
    """y_0..y_n of HHT-α (γ = 1/2 - α) applied to y' = λ y, z = h λ, y_0 = 1, y'_0 = λ:
    M x_{n+1} = (1 + α) f_{n+1} - α f_n, y_{n+1} = y_n + h [(1 - γ) x_n + γ x_{n+1}]."""
    g = 0.5 - alpha
    y, x, f = 1.0, z, z  # rates in units of 1/h
    out = [y]
    for _ in range(n):
        y = (y + (1 - g) * x - g * alpha * f) / (1 - g * (1 + alpha) * z)
        x = (1 + alpha) * z * y - alpha * f
        f = z * y
        out.append(y)
    return np.array(out)


def test_hht_damps_a_stiff_mode():
    """Reference: linear stability theory of HHT-α (Hilber, Hughes & Taylor 1977) on the
    model's own linearisation. At a steady pure-rolling state (4000 N, no moment, no skew, no
    drag), a kick to roller 1's spin speed relaxes through the stiff traction coupling with the
    eigenvalue λ of the linearised DAE (generalised eigenproblem of the Jacobian and the mass,
    computed here). At h = 20 µs, h λ ≈ -14: average acceleration (α = 0) amplifies the kick by
    (1 + hλ/2)/(1 - hλ/2) ≈ -0.76 per step (undamped ringing as |hλ| grows), HHT-α = -1/3 by a
    spectral radius ≈ 0.3. The integrator must reproduce both scalar responses step by step."""
    m = build_model(load_scene("yang20_baseline", {
        "operating.moment_Nm": 0.0, "operating.radial_load_N": 4000.0,
        "physics.skew": False, "physics.drag": False}))
    y0, yp0 = initial_state(m)
    i = m.layout.index("spin_speed", 0)
    n = m.size
    rows, cols = m.layout.sparsity()
    jd, _ = _jacobian_work(m, sp.csc_matrix((np.ones(rows.size), (rows, cols)), shape=(n, n)))
    fill_jacobian(0.0, y0, yp0, 0.0, m.data, jd)
    lam, vec = sl.eig(-jd[0], np.diag(m.mass))
    finite = np.isfinite(lam)
    lam, vec = lam[finite], vec[:, finite]
    lam_spin = lam[np.argmax(np.abs(vec[i]) / np.linalg.norm(vec, axis=0))].real
    h, steps = 2e-5, 5
    z = h * lam_spin
    assert z < -10  # a stiff mode at this step
    t_out = h * np.arange(steps + 1)
    measured = {}
    for alpha in (0.0, -1.0 / 3.0):
        base = integrate(m, y0, yp0, t_out, hht(h, alpha, newton_tol=1e-12))
        y1 = y0.copy()
        y1[i] *= 1.0 + 1e-4
        kicked = integrate(m, y1, yp0, t_out, hht(h, alpha, newton_tol=1e-12))
        assert base.stats["step_halvings"] == kicked.stats["step_halvings"] == 0
        d = (kicked.y[:, i] - base.y[:, i]) / (kicked.y[0, i] - base.y[0, i])
        measured[alpha] = d
        np.testing.assert_allclose(d, hht_scalar_response(z, alpha, steps), atol=0.02)
    assert abs(measured[-1.0 / 3.0][-1]) < 0.1 * abs(measured[0.0][-1])
