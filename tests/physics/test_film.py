"""Line-contact EHL film (physics/film.py) and its use on a static solve (analysis/engineering.py).

References: Pan & Hamrock's fits (the law) are checked (1) against Dowson & Higginson's older
minimum-film fit H_min = 2.65 U^0.70 G^0.54 W'^-0.13 (Dowson & Higginson, *Elasto-
hydrodynamic Lubrication*, SI ed. 1977) on the bearing and oil of Hamrock's cylindrical roller
bearing example (Hamrock, *Fundamentals of Fluid Film Lubrication*, NASA RP-1255, 1991: rollers
16 mm, pitch diameter 80 mm, 16 mm long, inner race 524 rad/s, η₀ = 0.01 Pa s,
α = 2.2e-8 Pa⁻¹, E = 207.5 GPa, ν = 0.3), with a roller load of 4800 N — two independent fits of different
numerical solutions, which agree within ~10 % there; (2) by its exponents, against Dowson &
Higginson's; (3) on a static solve, slice by slice, from the recorded slice load and the
slice's reduced radius and entrainment speed recomputed here.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearingdae import solve_static
from bearingdae.physics import film
from bearingdae.scene import scene_from_dict

E_PRIME = 2.0 / (2 * (1 - 0.3**2) / 2.075e11)  # Hamrock's E' = 2.28e11 Pa


def hamrock_example(race):
    """(w' [N/m], R' [m], u [m/s]) of the example's heaviest roller, inner or outer race."""
    d, de, length = 0.016, 0.080, 0.016
    Rx = d * (de - d) / (2 * de) if race == "inner" else d * (de + d) / (2 * de)
    u = (de**2 - d**2) * 524.0 / (4 * de)  # mean surface speed, outer ring fixed
    return 4800.0 / length, Rx, u


def test_reduced_modulus_of_the_example():
    assert E_PRIME == pytest.approx(2.28e11, rel=1e-3)  # as printed: 2.28 x 10^11 Pa


@pytest.mark.parametrize("race", ["inner", "outer"])
def test_minimum_film_agrees_with_dowson_higginson(race):
    w, R, u = hamrock_example(race)
    h_c, h_min = film.line_contact_film(w, R, u, 0.01, 2.2e-8, E_PRIME)
    U, G, W = 0.01 * u / (E_PRIME * R), 2.2e-8 * E_PRIME, w / (E_PRIME * R)
    dowson = R * 2.65 * U**0.70 * G**0.54 * W**-0.13
    assert float(h_min) == pytest.approx(dowson, rel=0.10)
    assert 0.2e-6 < float(h_min) < 0.6e-6  # the example's order: a few tenths of a µm
    assert float(h_c) > float(h_min)


def test_film_exponents_are_dowson_and_higginsons():
    """The minimum film's log-slopes in speed, load and pressure-viscosity coefficient against
    Dowson & Higginson's independent fit (U^0.70, W'^-0.13, G^0.54): two fits of different
    numerical solutions, whose exponents agree within 0.01 in U and W' and 0.03 in G. The
    outlet constriction makes the minimum film thinner than the central one."""
    w, R, u = hamrock_example("inner")

    def h(w=w, u=u, alpha=2.2e-8):
        return film.line_contact_film(w, R, u, 0.01, alpha, E_PRIME)

    (hc1, hm1), (_, hm2), (_, hm3), (_, hm4) = h(), h(u=2 * u), h(w=2 * w), h(alpha=4.4e-8)
    assert math.log2(hm2 / hm1) == pytest.approx(0.70, abs=0.01)
    assert math.log2(hm3 / hm1) == pytest.approx(-0.13, abs=0.01)
    assert math.log2(hm4 / hm1) == pytest.approx(0.54, abs=0.03)
    assert float(hm1) < float(hc1)


def test_no_load_no_film_and_standstill_zero_film():
    h_c, h_min = film.line_contact_film(np.array([0.0, 1e5]), 1e-3, np.array([1.0, 0.0]),
                                        0.01, 2e-8, 2.28e11)
    assert np.isnan(h_min[0]) and h_min[1] == 0.0


def test_static_film_recomputed_from_the_slice_loads():
    scene = scene_from_dict({"bearing": {"preset": "yang20"},
                             "operating": {"radial_load_N": 2000.0, "speed_rpm": 3000.0},
                             "materials": {"roughness_um": 0.2},
                             "lubricant": {"pressure_viscosity_GPa_inv": 15.0}})
    ds = solve_static(scene)
    b, m = scene.bearing, scene.materials
    r, Rm = b.roller_diameter_m / 2, b.pitch_diameter_m / 2
    Ri, Ro = Rm - r, Rm + r
    wi = 3000.0 * 2 * math.pi / 60
    cage = 0.5 * wi * (1 - r / Rm)  # epicyclic orbit speed
    u = (wi - cage) * Ri  # pure rolling: race and roller surfaces move alike
    Ep = m.youngs_modulus_Pa / (1 - m.poisson_ratio**2)
    width = b.roller_length_m / scene.numerics.slices
    q = float(ds.contact_force.sel(race="outer").isel(roller=0, slice=4))
    Rp = 1 / (1 / r - 1 / Ro)
    # the law on the slice's inputs recomputed here (load per length, reduced radius,
    # entrainment speed): the run hands the law the right numbers
    h = float(film.line_contact_film(q / width, Rp, u, 0.01, 15e-9, Ep)[1])
    got = float(ds.film_thickness_min.sel(race="outer").isel(roller=0, slice=4))
    assert got == pytest.approx(h, rel=1e-9)
    # and the value against Dowson & Higginson's independent fit (within 10 %, as above)
    W, U, G = q / width / (Ep * Rp), 0.01 * u / (Ep * Rp), 15e-9 * Ep
    assert got == pytest.approx(Rp * 2.65 * U**0.70 * G**0.54 * W**-0.13, rel=0.10)
    assert float(ds.lambda_ratio.sel(race="outer").isel(roller=0, slice=4)) == \
        pytest.approx(h / 0.2e-6, rel=1e-9)
    # unloaded rollers (opposite the load) carry no film
    assert np.isnan(ds.film_thickness_min.sel(race="inner").isel(roller=10)).all()


def test_compiled_film_is_the_fits_powers():
    """The compiled film (exp and log of physics/elementary.py) against the fits' powers taken
    one by one with numpy, over the ranges of a run's slices (loads 1e2..1e7 N/m, speeds
    1e-3..30 m/s, both races' radii): within 1e-14 (a few units of round-off of exp(a ln W' +
    b ln U), |ln| <= 40), and the same zeros and NaNs."""
    rng = np.random.default_rng(7)
    w = 10 ** rng.uniform(2, 7, 2000)
    u = 10 ** rng.uniform(-3, 1.5, 2000) * rng.choice([-1.0, 1.0], 2000)
    R = rng.choice([3.2e-3, 5.1e-3], 2000)
    eta, alpha = 0.01, 2.2e-8
    h_c, h_min = film.line_contact_film(w, R, u, eta, alpha, E_PRIME)
    U, W, G = eta * np.abs(u) / (E_PRIME * R), w / (E_PRIME * R), alpha * E_PRIME
    # the evaluation, not the law (whose constants the fits above check): the module's own
    # constants taken as numpy powers one by one
    for (c, a, b, g), got in ((film._MIN, h_min), (film._CENTRAL, h_c)):
        assert np.allclose(got, R * c * W**a * U**b * G**g, rtol=1e-14, atol=0)
    h_c, h_min = film.line_contact_film(np.array([[0.0], [-5.0], [1e5]]), 1e-3,
                                        np.array([1.0, 0.0]), eta, alpha, E_PRIME)
    assert h_min.shape == (3, 2) and np.isnan(h_min[:2]).all() and np.isnan(h_c[:2]).all()
    assert h_min[2, 1] == 0.0 and h_c[2, 1] == 0.0 and h_min[2, 0] > 0.0
    h_c, h_min = film.line_contact_film(1e5, 1e-3, np.nan, eta, alpha, E_PRIME)
    assert np.isnan(h_min) and np.isnan(h_c)  # as the powers give: no speed, no film value
