"""The block-arrow LU (solvers/blockarrow.py) and its SUNDIALS wrapper (solvers/sundials/linsol.py).

Reference: numpy's dense LU solve (LAPACK dgesv) of the same iteration matrix, to the round-off
of a well-conditioned matrix (relative 1e-10 here, the matrix's condition number being ~1e4 at
c_j = 1e6); and IDA with SuperLU_MT (the default sparse direct solver) on the same run.
"""

from __future__ import annotations

import numpy as np
import pytest

from bearingdae import load_scene
from bearingdae.solvers import blockarrow
from bearingdae.solvers.algebraic import initial_state
from bearingdae.solvers.common import sparsity_pattern
from bearingdae.solvers.ida import IDA
from bearingdae.system.jacobian_analytic import analytic_work, fill_jacobian_analytic
from bearingdae.system.model import build_model


def iteration_matrix(m, y, yp, cj):
    coo = sparsity_pattern(m).tocoo()
    jd = analytic_work(m, coo.row.astype(np.int64), coo.col.astype(np.int64))
    fill_jacobian_analytic(0.0, y, yp, cj, m.data, jd)
    return jd[0].copy()


@pytest.fixture(scope="module")
def model_state():
    m = build_model(load_scene("yang20_baseline"))
    y0, yp0 = initial_state(m)
    return m, y0, yp0


@pytest.mark.parametrize("cj", [1e2, 1e6, 1e10])
def test_factor_and_solve_match_dense_lu(model_state, cj):
    m, y, yp = model_state
    J = iteration_matrix(m, y, yp, cj)
    lay = m.layout
    Z, nl, ng = lay.rollers, lay.n_local, lay.n_global
    work = blockarrow.work_arrays(Z, nl, ng)
    assert blockarrow.factor(J, Z, nl, ng, *work) == 0
    rng = np.random.default_rng(3)
    for _ in range(3):
        b = rng.standard_normal(m.size)
        x = np.empty_like(b)
        blockarrow.solve(Z, nl, ng, *work[:5], b, x)
        x_ref = np.linalg.solve(J, b)
        assert np.abs(x - x_ref).max() <= 1e-10 * np.abs(x_ref).max()


def test_zero_pivot_is_reported_not_divided(model_state):
    m, y, yp = model_state
    J = iteration_matrix(m, y, yp, 1e6)
    lay = m.layout
    Z, nl, ng = lay.rollers, lay.n_local, lay.n_global
    J[3 * nl:4 * nl, 3 * nl + 2] = 0.0  # a zero column in roller 4's block
    work = blockarrow.work_arrays(Z, nl, ng)
    assert blockarrow.factor(J, Z, nl, ng, *work) == 4


def test_ida_with_block_arrow_agrees_with_superlu(model_state):
    """Same integrator, another exact linear solver: the first 2 ms agree within the
    integration tolerance (the trajectories split only later, by round-off in the Newton
    updates re-routing the adaptive steps)."""
    m, y0, yp0 = model_state
    t_out = np.linspace(0.0, 0.002, 5)
    a = IDA("blockarrow").integrate(m, y0, yp0, t_out)
    b = IDA("sparse").integrate(m, y0, yp0, t_out)
    assert a.success and b.success
    rtol, atol = m.scene.dynamics.rtol, m.scene.dynamics.atol
    assert (np.abs(a.y - b.y) / (100 * atol + rtol * np.abs(b.y))).max() <= 1.0
    assert abs(a.stats["steps"] - b.stats["steps"]) <= 0.05 * b.stats["steps"]
