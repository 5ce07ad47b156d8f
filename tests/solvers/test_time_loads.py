"""A run under loads that change in time (theory.md §14) with the quasi-static ring: every
sample balances the applied load (the inner-ring equations of theory.md §5, from the Dataset
alone), the applied load is the scene's history plus the unbalance in closed form, and IDA and
Newmark-β agree on it."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from bearingdae import simulate
from tests.conftest import make_scene

RAMP = {"times_s": [0.0, 0.004, 0.012], "values_N": [300.0, 300.0, 900.0]}


def _scene(**extra):
    return make_scene(operating={"speed_rpm": 2000.0, "radial_load_N": RAMP,
                                 "moment_Nm": {"times_s": [0.0, 0.012], "values_Nm": [0.0, 2.0]},
                                 "unbalance_N": 150.0, "unbalance_phase_deg": 40.0, **extra},
                      numerics={"warmup_cage_revolutions": 0.1, "cage_revolutions": 0.1,
                                "samples_per_cage_revolution": 200})


def _run(scene, solver="ida"):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return simulate(scene, solver=solver, progress=False)


@pytest.fixture(scope="module")
def ds():
    return _run(_scene())


def test_applied_load_is_history_plus_unbalance(ds):
    t = ds.time.values
    w = 2000.0 * 2 * math.pi / 60
    psi = w * t + math.radians(40.0)
    F = ds.applied_load.values
    np.testing.assert_allclose(F[:, 0], np.interp(t, RAMP["times_s"], RAMP["values_N"])
                               + 150.0 * np.cos(psi), rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(F[:, 1], 150.0 * np.sin(psi), rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(ds.applied_moment.values[:, 0], np.interp(t, [0, 0.012], [0, 2]),
                               rtol=1e-12, atol=1e-12)
    assert ds.applied_load.attrs["units"] == "N" and ds.applied_moment.attrs["units"] == "N m"
    assert ds["unbalance_N"].item() == 150.0


def test_every_sample_balances_the_applied_load(ds):
    """Σ_jλ q_i (cos φ, sin φ) = (F_r, F_t) and Σ_jλ x q_i (cos φ, sin φ) = (M, M_t) at each
    sample, to 1e-8 of the largest load (the projection solves them to round-off)."""
    q = ds.contact_force.sel(race="inner").values  # (time, roller, slice)
    phi = ds.roller_azimuth.values
    x = ds.slice_position.values
    Q, Mq = q.sum(-1), (q * x).sum(-1)
    F = np.stack([(Q * np.cos(phi)).sum(-1), (Q * np.sin(phi)).sum(-1)], axis=-1)
    M = np.stack([(Mq * np.cos(phi)).sum(-1), (Mq * np.sin(phi)).sum(-1)], axis=-1)
    scale = np.abs(ds.applied_load.values).max()
    np.testing.assert_allclose(F, ds.applied_load.values, rtol=0, atol=1e-8 * scale)
    np.testing.assert_allclose(M, ds.applied_moment.values, rtol=0,
                               atol=1e-8 * scale * float(x.max()))
    # the ring follows the rotating load: its displacement turns with the shaft
    d = ds.ring_displacement.values
    ang_d = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
    ang_F = np.unwrap(np.arctan2(F[:, 1], F[:, 0]))
    assert np.max(np.abs(ang_d - ang_F)) < 0.05  # rad: the bearing is nearly isotropic


def test_newmark_agrees_with_ida_under_changing_loads(ds):
    nm = _run(_scene(), solver="newmark")
    np.testing.assert_array_equal(nm.applied_load.values, ds.applied_load.values)
    rel = abs(float(nm.cage_speed.mean() / ds.cage_speed.mean()) - 1.0)
    assert rel < 1e-3  # the solver cross-check's cage-speed measure (theory.md §12)
    dr = np.abs(nm.ring_displacement.values - ds.ring_displacement.values).max()
    assert dr < 1e-2 * np.abs(ds.ring_displacement.values).max()
