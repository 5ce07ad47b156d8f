"""The band of the published rolling laws (studies/rolling_band.py): Biboulet & Houpert's moment
summed afresh over the static loads, and starvation lowering every law's moment."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from bearingdae import load_scene, solve_static
from bearingdae.physics.contact import slice_stiffness
from bearingdae.physics.geometry import make_geometry
from bearingdae.physics.rolling_resistance import light_load_per_length
from bearingdae.studies.rolling_band import LAWS, rolling_moments_N_m

CASE = "yang20_baseline"
POINT = {"operating.speed_rpm": 2000.0, "operating.radial_load_N": 2000.0}


@pytest.fixture(scope="module")
def moments():
    return rolling_moments_N_m(CASE, POINT, (None, 1.0))


def _bh_force_per_length(w, R, u, eta, E):
    """B&H eq. (42) in their Hertzian units (typed here): T* = M^-1.5 1.4 sqrt(M) /
    (1 + ((1.4/1.45) sqrt(M))^10)^0.1 with U = 2 eta u/(E'R) (their factor 2), W = w/(E'R),
    M = W/sqrt(U); moment per length T* p_h b^2 with p_h b^2 = E'R^2 (8W/pi)^1.5 / 4 (eq. 14);
    the force is the moment over R (eq. 31)."""
    U = 2.0 * eta * u / (E * R)
    W = w / (E * R)
    M = W / np.sqrt(U)
    T = M ** -1.5 * 1.4 * np.sqrt(M) / (1.0 + (1.4 / 1.45 * np.sqrt(M)) ** 10) ** 0.1
    return T * E * R * (8.0 * W / np.pi) ** 1.5 / 4.0


def test_biboulet_houpert_summed_afresh_over_the_static_loads(moments):
    """Each slice at pure rolling dissipates f * width * 2u (u the same on both races:
    (w - Omega) R_i = Omega R_o); the moment on the inner ring is the sum over omega_i."""
    scene = load_scene(CASE, {**POINT, "physics.rolling_resistance": "biboulet_houpert"})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        q = solve_static(scene).contact_force.transpose("roller", "slice", "race").values
    g = make_geometry(scene)
    w = 2000.0 * np.pi / 30.0
    Ri, Ro = g.inner_race_radius_m, g.outer_race_radius_m
    orbit = w * Ri / (Ri + Ro)
    u = orbit * Ro
    E = 2.0 / g.compliance_m2_N
    eta = scene.lubricant.viscosity_Pa_s
    # the regularisation (theory.md §19): sqrt(w') -> w'/sqrt(w' + w_c); it matters on the
    # rollers that carry only their centrifugal force (w' ~ w_c on the outer race)
    w_c = light_load_per_length(
        slice_stiffness(g.slice_width_m, g.roller_length_m, g.compliance_m2_N),
        scene.numerics.contact_smoothing_m, g.slice_width_m)
    P = 0.0
    for c, R in ((0, g.reduced_radius_inner_m), (1, g.reduced_radius_outer_m)):
        load = q[..., c] / g.slice_width_m
        load = load[load > 0.0]
        f = _bh_force_per_length(load, R, u, eta, E) * np.sqrt(load / (load + w_c))
        P += np.sum(f) * g.slice_width_m * 2 * u
    # the speed floor u0 = 1 mm/s against u ~ 3 m/s: 1e-7
    assert moments[("biboulet_houpert", None)] == pytest.approx(P / w, rel=1e-6)


def test_an_inlet_film_lowers_every_law(moments):
    for law in LAWS:
        assert 0.0 < moments[(law, 1.0)] < moments[(law, None)]
