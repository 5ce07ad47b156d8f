"""The algebraic block of the analytic iteration matrix filled alone
(system/jacobian_algebraic.py) against the full matrix (system/jacobian_analytic.py).

Reference: ``fill_jacobian_analytic`` at c_j = 0, itself checked against central differences of
the residual (tests/system/test_jacobian.py). The block must be equal bit for bit: the
projection of output samples uses it and the default run's samples must not change.
"""

from __future__ import annotations

import numpy as np
import pytest

from bearingdae import load_scene
from bearingdae.solvers.algebraic import initial_state
from bearingdae.solvers.common import jacobian_filler
from bearingdae.solvers.ida import IDA
from bearingdae.system.jacobian_algebraic import fill_jacobian_algebraic
from bearingdae.system.model import build_model


@pytest.mark.parametrize("over", [{}, {"physics.tilt": False, "operating.moment_Nm": 0.0}, {"numerics.slices": 3,
                                                                   "operating.moment_Nm": 0.0,
                                                                   "physics.cage": False},
                                  # roller end-flange contacts (theory.md §16)
                                  {"bearing.type": "NJ", "operating.axial_load_N": 200.0},
                                  {"bearing.type": "NUP", "operating.axial_load_N": -300.0},
                                  {"bearing.type": "NJ", "operating.axial_load_N": {
                                      "times_s": [0.0, 2e-3], "values_N": [0.0, 800.0]}}])
def test_block_equals_the_full_matrix_bit_for_bit(over):
    m = build_model(load_scene("yang20_baseline", over))
    y0, yp0 = initial_state(m)
    sol = IDA().integrate(m, y0, yp0, np.linspace(0.0, 2e-3, 5))
    alg = np.flatnonzero(m.layout.algebraic)
    jd, fill, _ = jacobian_filler(m, "analytic")
    block = np.zeros_like(jd[0])
    rng = np.random.default_rng(3)
    for tk, y in zip(sol.t, sol.y):
        for yy in (y, y + 1e-3 * rng.standard_normal(y.size)):
            fill(tk, yy, np.zeros_like(yy), 0.0, m.data, jd)
            fill_jacobian_algebraic(tk, yy, m.data, block, jd[3])
            full = jd[0][np.ix_(alg, alg)]
            assert np.array_equal(block[np.ix_(alg, alg)], full)
            assert np.abs(full).max() > 0
