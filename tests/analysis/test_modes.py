"""The linearised DAE's modes (analysis/modes.py): the dynamic ring's four modes against the
quasi-static stiffness matrix and the ring's mass and tilt inertia (an eigenproblem typed here
on the static solver's K, not the DAE's Jacobian), with and without the support's damping;
and a roller's spin relaxation against IDA's own response to a kick."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.linalg as sl

from bearingdae import load_scene
from bearingdae.analysis.modes import LIGHT_DAMPING, family, linear_modes
from bearingdae.analysis.stiffness import scene_stiffness
from bearingdae.solvers.algebraic import initial_state
from bearingdae.solvers.ida import IDA
from bearingdae.system.model import build_model

MASS_KG, TILT_KG_M2 = 0.5, 2e-4  # stated, so that the reference needs none of the model's


def _ring_modes(damping_N_s_m: float):
    scene = load_scene("yang20_baseline", {
        "physics.ring": "dynamic", "ring.mass_kg": MASS_KG,
        "ring.tilt_inertia_kg_m2": TILT_KG_M2, "ring.support_damping_N_s_m": damping_N_s_m})
    model = build_model(scene)
    y0, yp0 = initial_state(model)
    modes = linear_modes(model, 0.0, y0, yp0)
    ring = [i for i in range(modes.eigenvalue_per_s.size)
            if family(modes.dominant[i]).startswith("ring") and modes.oscillating[i]
            and modes.eigenvalue_per_s[i].imag > 0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the slices' resolution of K is not the point here
        K = scene_stiffness(scene).stiffness.values  # radial, tangential, two tilts
    return modes, ring, K


@pytest.mark.parametrize("damping_N_s_m", [0.0, 300.0])
def test_ring_modes_are_those_of_the_static_stiffness(damping_N_s_m):
    """The rollers' radial positions are algebraic: the ring moves on the bearing's stiffness.
    Reference: K v + λ C v + λ² M v = 0 with the static solver's K (analysis/stiffness.py:
    the Schur complement of the static Newton), M = diag(m, m, I, I) and the support's
    damping C = diag(c, c, 0, 0), as a first-order pencil."""
    modes, ring, K = _ring_modes(damping_N_s_m)
    M = np.diag([MASS_KG, MASS_KG, TILT_KG_M2, TILT_KG_M2])
    C = np.diag([damping_N_s_m, damping_N_s_m, 0.0, 0.0])
    n = 4
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-K, -C]])
    B = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), M]])
    ref = sl.eigvals(A, B)
    ref = ref[ref.imag > 0]
    ref = ref[np.argsort(ref.imag)]
    got = modes.eigenvalue_per_s[ring]
    got = got[np.argsort(got.imag)]
    assert got.size == 4
    np.testing.assert_allclose(got.imag, ref.imag, rtol=1e-4)
    if damping_N_s_m:
        np.testing.assert_allclose(got.real, ref.real, rtol=1e-3)
        assert np.all(got.real < -1.0)  # every mode damped, the tilts through their coupling
    else:
        np.testing.assert_allclose(got.real, 0.0, atol=1e-6 * np.abs(got).max())
        i = modes.fastest_oscillation()  # undamped: the fastest ring mode is the fastest
        assert modes.damping_ratio[i] <= LIGHT_DAMPING
        assert family(modes.dominant[i]).startswith("ring")
        assert modes.frequency_Hz[i] == pytest.approx(ref.imag.max() / (2 * np.pi), rel=1e-4)


def test_a_relaxation_matches_a_kicked_run():
    """A steady pure-rolling state (4000 N, no moment, skew or drag), disturbed along its
    fastest mode (roller 0's spin against its traction): the disturbance decays as e^{λt}.
    Reference: IDA's own response at rtol 1e-10, the difference of a disturbed and an
    undisturbed run over two time constants."""
    model = build_model(load_scene("yang20_baseline", {
        "operating.moment_Nm": 0.0, "operating.radial_load_N": 4000.0,
        "physics.skew": False, "physics.drag": False,
        "numerics.rtol": 1e-10, "numerics.atol": 1e-14}))
    y0, yp0 = initial_state(model)
    modes = linear_modes(model, 0.0, y0, yp0)
    lam, v = modes.eigenvalue_per_s[0], modes.shapes[:, 0]
    assert modes.dominant[0] == "spin_speed[0]" and not modes.oscillating[0]
    assert lam.real < -1e5  # a stiff relaxation (time constant of a few µs)
    lam, v = lam.real, v.real / np.abs(v.real).max()
    t_out = np.array([0.0, 1.0, 2.0]) / -lam
    eps = 1e-5  # linear to ~1e-5, far above the runs' own error at rtol 1e-10
    base = IDA().integrate(model, y0, yp0, t_out).y
    kicked = IDA().integrate(model, y0 + eps * v, yp0 + eps * lam * v, t_out).y
    d = kicked - base
    fitted = np.log(np.linalg.norm(d[2]) / np.linalg.norm(d[1])) / (t_out[2] - t_out[1])
    assert fitted == pytest.approx(lam, rel=0.01)
    # and along the shape: the disturbance keeps the mode's shape as it decays
    np.testing.assert_allclose(d[2] / np.abs(d[2]).max(), v, atol=0.02)
