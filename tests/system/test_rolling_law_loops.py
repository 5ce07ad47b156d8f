"""The kernels' rolling-resistance loops (system/rolling_resistance.py) run each fully flooded
law in a loop of its own, the law's code a compile-time constant so that it vectorises; a
starved contact takes the general loop. Each of them must be the law itself: slice by slice,
the residual's forces and the Jacobian's slopes equal, bit for bit, the law evaluated with its
code passed at run time (physics/rolling_resistance.py), on both races, for every law."""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit

from bearingdae.physics import rolling_resistance as law
from bearingdae.scene import load_scene
from bearingdae.system import rolling_resistance as rr
from bearingdae.system.model import build_model
from bearingdae.system.param_vector import P_RR


@njit(cache=False)
def _kernel_loops(q, s, PR, H, Hq, Hs):
    rr._forces(q, s.copy(), PR, H, H)
    rr._slopes(q, s, PR, Hq, Hs)


@njit(cache=False)
def _law_per_slice(q, s, w, Rpi, Rpo, eta, alpha, E, beta, k, u0, wc, code, hfac, ha, out):
    for i in range(q.shape[0]):
        out[:, i] = np.array(law._slice_rolling_force(
            q[i], s[i], w, Rpo if i % 2 == 1 else Rpi, eta, alpha, E, beta, k, u0, wc, code,
            hfac, ha))


@pytest.mark.parametrize("inlet_film_um", [None, 0.3], ids=["flooded", "starved"])
@pytest.mark.parametrize("name", ["biboulet_houpert", "goksem_hargreaves", "zhou_hoeprich"])
def test_each_laws_loop_is_the_law(name, inlet_film_um):
    over = {"physics.rolling_resistance": name}
    if inlet_film_um is not None:
        over["lubricant.inlet_film_um"] = inlet_film_um
    m = build_model(load_scene("yang20_baseline", over))
    PR = np.ascontiguousarray(m.params[P_RR:P_RR + len(rr.RR_PARAM_NAMES)])
    assert PR[rr.RR_LAW] == law.law_code(name) and (PR[rr.RR_HA] > 0) == (inlet_film_um
                                                                           is not None)
    rng = np.random.default_rng(7)
    n = 2 * 2 * 10  # contacts, the races alternating as in the kernel
    # loads from none to heavy, rolling sums of both signs and near the speed floor
    q = np.concatenate([[0.0, 1e-9], 10.0 ** rng.uniform(-3, 2.5, n - 2)])
    s = np.concatenate([[1e-6, -1e-6],
                        rng.choice([-1, 1], n - 2) * 10.0 ** rng.uniform(-3, 1, n - 2)])
    H, Hq, Hs = np.empty(n), np.empty(n), np.empty(n)
    _kernel_loops(q, s, PR, H, Hq, Hs)
    ref = np.empty((3, n))
    _law_per_slice(q, s, *(PR[i] for i in (rr.RR_W, rr.RR_RPI, rr.RR_RPO, rr.RR_ETA,
                                             rr.RR_ALPHA, rr.RR_E, rr.RR_BETA, rr.RR_K,
                                             rr.RR_U0, rr.RR_WC, rr.RR_LAW, rr.RR_HFAC,
                                             rr.RR_HA)), ref)
    assert np.all(np.isfinite(ref)) and np.count_nonzero(ref[0]) > n // 2
    np.testing.assert_array_equal(H, ref[0])
    np.testing.assert_array_equal(Hq, ref[1])
    np.testing.assert_array_equal(Hs, ref[2])
