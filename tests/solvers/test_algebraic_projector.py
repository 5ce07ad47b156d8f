"""The compiled projector onto the algebraic equations (solvers/algebraic.AlgebraicProjector).

Reference: the static Newton (solvers/static.py, numpy, its own implementation of theory.md §5 with
line search and continuation) solves the same equations; both must land on the same algebraic
unknowns to well below the integrator's algebraic tolerance (1e-6 in scaled units), and the
projected state must satisfy the DAE's algebraic rows to the projector's tolerance.
"""

from __future__ import annotations

import numpy as np
import pytest

from bearingdae import load_scene
from bearingdae.solvers.algebraic import (PROJECTION_TOL_FLOOR, AlgebraicProjector,
                                          initial_state, project_algebraic)
from bearingdae.solvers.ida import IDA
from bearingdae.system.model import build_model


@pytest.fixture(scope="module")
def run():
    sc = load_scene("yang20_baseline")
    m = build_model(sc)
    y0, yp0 = initial_state(m)
    sol = IDA().integrate(m, y0, yp0, np.linspace(0.0, 2e-3, 21))
    assert sol.success
    return m, sol


def test_projector_matches_static_newton_on_run_samples(run):
    m, sol = run
    project = AlgebraicProjector(m)
    alg = project.alg
    for tk, y in zip(sol.t, sol.y):
        y_new, it_new = project(tk, y)
        y_ref, _ = project_algebraic(m, tk, y)
        # same differential unknowns, same algebraic solution (scaled units)
        assert np.array_equal(y_new[~m.layout.algebraic], y[~m.layout.algebraic])
        assert np.abs(y_new - y_ref).max() < 1e-8
        F = m.residual(tk, y_new, np.zeros(m.size))[alg]
        assert np.abs(F).max() <= max(m.scene.numerics.static_tolerance, PROJECTION_TOL_FLOOR)
        assert 1 <= it_new <= 3  # from an IDA output: Newton converges at once
    assert project.fallbacks == 0


def test_projector_repairs_a_state_far_off_the_manifold(run):
    """Every roller moved by 3 reference approaches, ring by 2, tilts by 0.5 of their scale:
    either the projector's Newton or its static fallback must bring it back to the manifold,
    to the same point as the static Newton."""
    m, sol = run
    tk, y = sol.t[-1], sol.y[-1].copy()
    alg = np.flatnonzero(m.layout.algebraic)
    rng = np.random.default_rng(1)
    y[alg] += rng.uniform(-3.0, 3.0, alg.size)
    project = AlgebraicProjector(m)
    y_new, _ = project(tk, y)
    y_ref, _ = project_algebraic(m, tk, y)
    assert np.abs(y_new - y_ref).max() < 1e-8
    assert np.abs(m.residual(tk, y_new, np.zeros(m.size))[alg]).max() <= 1e-12


def test_simulate_reports_projection_statistics():
    import json

    from bearingdae import simulate

    sc = load_scene("yang20_baseline", {"numerics.warmup_cage_revolutions": 0.0,
                                        "numerics.cage_revolutions": 0.02})
    ds = simulate(sc)
    stats = json.loads(ds.attrs["solver_statistics"])
    assert stats["projection_static_fallbacks"] == 0
    assert 1 <= stats["projection_newton_iterations"] / ds.sizes["time"] <= 3


def test_batch_projection_is_the_per_sample_projection_bit_for_bit(run):
    """The compiled batch (solvers/projection_kernel.py) runs the per-sample projector's
    Newton with the same kernels and the same linear solve: the projected states, iteration
    counts and diagnostics must be identical, not merely close (a streamed or resumed run's
    samples are those of an in-memory run)."""
    m, sol = run
    project = AlgebraicProjector(m)
    Y, its, settled, diag = project.batch(sol.t, sol.y)
    assert settled.all()
    for i, (tk, y) in enumerate(zip(sol.t, sol.y)):
        y_one, it_one = project(tk, y)
        assert np.array_equal(Y[i], y_one) and its[i] == it_one
        for name, value in m.diagnostics(tk, y_one).items():
            assert np.array_equal(diag[name][i], value), name


def test_batch_projection_marks_what_it_cannot_settle(run):
    """A state with a non-finite unknown is not settled by the batch (the caller hands it to
    the static Newton); the others of the batch are unaffected."""
    m, sol = run
    Yb = sol.y[:3].copy()
    Yb[1, np.flatnonzero(m.layout.algebraic)[0]] = np.nan
    Y, _, settled, _ = AlgebraicProjector(m).batch(sol.t[:3], Yb)
    assert settled.tolist() == [True, False, True]
    assert np.array_equal(Y[0], AlgebraicProjector(m)(sol.t[0], sol.y[0])[0])


@pytest.mark.parametrize("case, over", [
    ("yang20_baseline", {}),
    ("yang20_nj_axial", {}),  # flanges: 3 unknowns per roller, 5 global
    ("extreme/unbalance", {}),  # dynamic ring: no global algebraic unknown
])
def test_arrow_solve_is_the_dense_solve(case, over):
    """The block-arrow solve of the projection (Schur complement on the ring's unknowns)
    against LAPACK's dense solve of the same block, at states of a run and at a state far
    off the manifold: equal to a few units of round-off of the step (the block's condition
    number times eps bounds the difference of two backward-stable solves)."""
    from bearingdae.solvers.common import jacobian_filler
    from bearingdae.solvers.projection_kernel import arrow_shape, arrow_solve, arrow_work

    m = build_model(load_scene(case, over))
    y0, yp0 = initial_state(m)
    sol = IDA().integrate(m, y0, yp0, np.linspace(0.0, 1e-3, 6))
    alg = np.flatnonzero(m.layout.algebraic).astype(np.int64)
    b = arrow_shape(alg, m.layout.rollers, m.layout.n_local)
    aw = arrow_work(alg, m.layout.rollers, b)
    jd, fill, _ = jacobian_filler(m, "analytic")
    rng = np.random.default_rng(3)
    states = list(sol.y) + [sol.y[-1] + np.where(m.layout.algebraic, 0.5, 0.0)]
    for tk, y in zip(list(sol.t) + [sol.t[-1]], states):
        fill(tk, y, np.zeros(m.size), 0.0, m.data, jd)
        A = jd[0][np.ix_(alg, alg)]
        F = rng.standard_normal(alg.size)
        x = np.empty(alg.size)
        assert arrow_solve(jd[0], alg, b, F, x, *aw)
        ref = np.linalg.solve(A, -F)
        bound = 1e3 * np.finfo(float).eps * np.linalg.cond(A) * np.abs(ref).max()
        assert np.abs(x - ref).max() <= bound
        assert np.abs(A @ x + F).max() <= 1e-9 * np.abs(A).max() * np.abs(x).max()
