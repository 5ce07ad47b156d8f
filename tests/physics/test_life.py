"""ISO/TS 16281 rating life of a static solve against an independent implementation.

Reference: a second, loop-by-loop implementation of ISO/TS 16281:2008 clause 6 written here
from the standard's equations (laminae approach of the ring, Eqs. 38-41; equilibrium of
radial load and moment, Eqs. 45-46, solved with scipy's root finder; lamina ratings
Eqs. 47-57; edge-stress factors Eq. 60; equivalent lamina loads Eqs. 61-64; life Eq. 65),
following the structure of the public minzhun/ISO16281 code (RollerBearing.py). It shares
nothing with bearingdae but the geometry numbers: its own load distribution (lumped lamina
stiffness, no roller unknowns), its own ratings and means. With zero clearance and a flat
roller the load distribution does not depend on the contact stiffness (the equations are
homogeneous in it), so the two must agree to the static solve's tolerance; we ask 2 % (the
agreement asked of an independent implementation) and see ~1e-4. The life on the scene's slices
(``reference_rating_life_L10r_slices_Mrev``) meets it with n_s = the slices; the converged life
(``reference_rating_life_L10r_Mrev``, analysis/rating_life.py) with n_s = the laminae it used.

Second reference, for the laminae: a uniformly loaded line contact (flat roller, no moment, no
edge factors) has lamina lives independent of their number: Σ_k (q_k/q_c)^(9/2) with
q_k = Q/n and q_c = Q_c n^(-7/9) is (Q/Q_c)^(9/2) for every n, so L10r is the roller-level
closed form [(Q_ei/Q_ci)^(9/2) + (Q_ee/Q_ce)^(9/2)]^(-8/9) of the roller loads Q_j.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import optimize

from bearingdae import solve_static
from bearingdae.analysis.result_variables import flat
from bearingdae.physics import life
from bearingdae.scene import scene_from_dict

#: How far another machine may put a static solve's life [relative]: Newton stops at a force
#: residual of 1e-12 of the largest force (solvers/static.py), another CPU's sums differ at
#: ~1e-12; a life goes with the 9th-10th power of the loads: 1e-6 bounds that with room. The
#: theory page's numbers are checked within half a unit of their last printed digit plus this.
STATIC_SPREAD_REL = 1e-6


def printed_within(printed: float, value: float, unit: float) -> bool:
    """``printed`` (rounded to ``unit``) is ``value`` within the rounding and the spread."""
    return abs(printed - value) <= 0.5 * unit + STATIC_SPREAD_REL * abs(value)


def _scene(load_N, moment_Nm=0.0, edge=True, slices=10, C=40_000.0):
    return scene_from_dict({
        "bearing": {"preset": "yang20", "profile": "flat", "radial_clearance_mm": 0.0,
                    "basic_dynamic_load_rating_N": C},
        "operating": {"radial_load_N": load_N, "moment_Nm": moment_Nm},
        "numerics": {"slices": slices},
        "life": {"edge_stress_factors": edge},
    })


def iso16281_reference(Z, Dwe, Dpw, Lwe, C, Fr, M, ns, edge):
    """L10r [10⁶ rev] of a radial cylindrical roller bearing (mm, N, N mm), loops only."""
    gamma = Dwe / Dpw
    phi = [2 * math.pi * j / Z for j in range(Z)]
    xk = [(k + 0.5) * Lwe / ns - Lwe / 2 for k in range(ns)]
    cs = 35948.0 * Lwe ** (8 / 9) / ns  # lamina stiffness of the standard (cancels here)

    def lamina_loads(dr, psi):
        q = [[0.0] * ns for _ in range(Z)]
        for j in range(Z):
            tilt = math.atan(math.tan(psi) * math.cos(phi[j]))
            for k in range(ns):
                d = dr * math.cos(phi[j]) - xk[k] * math.tan(tilt)
                q[j][k] = cs * d ** (10 / 9) if d > 0 else 0.0
        return q

    def equilibrium(v):
        q = lamina_loads(v[0] * 1e-3, v[1] * 1e-4)
        f = sum(q[j][k] * math.cos(phi[j]) for j in range(Z) for k in range(ns))
        m = sum(-q[j][k] * xk[k] * math.cos(phi[j]) for j in range(Z) for k in range(ns))
        return [(Fr - f) / Fr, (M - m) / Fr]

    sol = optimize.root(equilibrium, [5.0, 0.0], method="hybr", tol=1e-13)
    assert sol.success, sol.message
    q = lamina_loads(sol.x[0] * 1e-3, sol.x[1] * 1e-4)
    r = ((1 - gamma) / (1 + gamma)) ** (143 / 108)
    Qci = C / (0.83 * 0.378 * Z) * (1 + (1.038 * r) ** 4.5) ** (2 / 9)
    Qce = C / (0.83 * 0.364 * Z) * (1 + (1.038 * r) ** -4.5) ** (2 / 9)
    qci, qce = Qci * ns ** (-7 / 9), Qce * ns ** (-7 / 9)
    total = 0.0
    for k in range(ns):
        f = 1.0
        if edge and 2 * (k + 1) != ns + 1:
            f = 1 - 0.01 / math.log(1.985 * abs((2 * (k + 1) - ns - 1) / (2 * ns - 2)))
        qei = (sum((f * q[j][k]) ** 4 for j in range(Z)) / Z) ** (1 / 4)
        qee = (sum((f * q[j][k]) ** 4.5 for j in range(Z)) / Z) ** (1 / 4.5)
        total += (qei / qci) ** 4.5 + (qee / qce) ** 4.5
    return total ** (-8 / 9)


@pytest.mark.parametrize("load_N, moment_Nm, edge", [
    (500.0, 0.0, True), (2_000.0, 0.0, True), (8_000.0, 0.0, True), (8_000.0, 0.0, False),
    (2_000.0, 3.0, True), (4_000.0, -6.0, False)])
def test_static_life_matches_an_independent_iso16281(load_N, moment_Nm, edge):
    scene = _scene(load_N, moment_Nm, edge)
    ds = solve_static(scene)
    b = scene.bearing
    ref = iso16281_reference(b.rollers, b.roller_diameter_m * 1e3, b.pitch_diameter_m * 1e3,
                             b.roller_length_m * 1e3, 40_000.0, load_N, moment_Nm * 1e3,
                             scene.numerics.slices, edge)
    got = ds["reference_rating_life_L10r_slices_Mrev"].item()
    assert got == pytest.approx(ref, rel=0.02)
    assert got == pytest.approx(ref, rel=1e-3)  # what it actually reaches (static tolerance)
    converged = ds["reference_rating_life_L10r_Mrev"].item()
    assert ds["equivalent_reference_load_N"].item() == pytest.approx(40_000.0 * converged ** -0.3)


@pytest.mark.parametrize("load_N, moment_Nm, edge", [(2_000.0, 3.0, True), (4_000.0, -6.0, False)])
def test_converged_life_matches_an_independent_iso16281_at_its_laminae(load_N, moment_Nm, edge):
    """The converged life is the standard's sum on the laminae it records. A flat roller
    loaded to its ends with the edge factors converges only at first order (the end lamina's
    factor 2.33 over a width L/n): not within 1 % by 1280 laminae, and the result says so."""
    scene = _scene(load_N, moment_Nm, edge)
    a = flat(solve_static(scene))
    b = scene.bearing
    n = a["rating_life_laminae"]
    error = a["reference_rating_life_L10r_error_Mrev"] / a["reference_rating_life_L10r_Mrev"]
    assert a["rating_life_converged"] == int(error <= 0.01)
    assert a["rating_life_converged"] == (0 if edge else 1)
    if edge and moment_Nm == 3.0:  # docs/theory.md: "an error estimate of 3.5 %"
        assert n == 1280 and error == pytest.approx(0.035, abs=5e-4)
    ref = iso16281_reference(b.rollers, b.roller_diameter_m * 1e3, b.pitch_diameter_m * 1e3,
                             b.roller_length_m * 1e3, 40_000.0, load_N, moment_Nm * 1e3, n, edge)
    assert a["reference_rating_life_L10r_Mrev"] == pytest.approx(ref, rel=1e-3)


def test_uniform_line_contact_life_is_the_closed_form_for_any_lamina_count():
    """Flat roller, no moment, no edge factors: every lamina count gives the roller-level
    closed form of the roller loads (module docstring), typed here from ISO/TS 16281."""
    C = 40_000.0
    lives = []
    for slices in (10, 40):
        ds = solve_static(_scene(3_000.0, edge=False, slices=slices))
        Q = ds.contact_force.sum("slice").values  # (roller, race), uniform along each roller
        b = _scene(3_000.0).bearing
        Z, g = b.rollers, b.roller_diameter_m / b.pitch_diameter_m
        r = ((1 - g) / (1 + g)) ** (143 / 108)
        Qci = C / (0.83 * 0.378 * Z) * (1 + (1.038 * r) ** 4.5) ** (2 / 9)
        Qce = C / (0.83 * 0.364 * Z) * (1 + (1.038 * r) ** -4.5) ** (2 / 9)
        Qei = np.mean(Q[:, 0] ** 4) ** (1 / 4)
        Qee = np.mean(Q[:, 1] ** 4.5) ** (1 / 4.5)
        closed = ((Qei / Qci) ** 4.5 + (Qee / Qce) ** 4.5) ** (-8 / 9)
        a = flat(ds)
        assert a["reference_rating_life_L10r_slices_Mrev"] == pytest.approx(closed, rel=1e-9)
        assert a["reference_rating_life_L10r_Mrev"] == pytest.approx(closed, rel=1e-9)
        assert a["reference_rating_life_L10r_error_Mrev"] < 1e-9 * closed
        lives.append(a["reference_rating_life_L10r_Mrev"])
    assert lives[0] == pytest.approx(lives[1], rel=1e-9)


def test_baseline_life_does_not_depend_on_the_slices():
    """yang20 baseline (end crown; at 10 slices the end slice's centre sits where the crown
    begins): the life on the slices moves 8x between 10 and 40 slices, the converged one stays
    within 2 % (and its error estimate within 1 %)."""
    from bearingdae import load_scene

    a10, a40 = (flat(solve_static(load_scene("yang20_baseline", {"numerics.slices": k})))
                for k in (10, 40))
    assert a40["reference_rating_life_L10r_slices_Mrev"] > 5 * a10[
        "reference_rating_life_L10r_slices_Mrev"]  # the defect the laminae remove
    L10, L40 = a10["reference_rating_life_L10r_Mrev"], a40["reference_rating_life_L10r_Mrev"]
    assert L10 == pytest.approx(L40, rel=0.02)
    assert a10["reference_rating_life_L10r_error_Mrev"] <= 0.01 * L10


def test_an_unbalance_larger_than_the_radial_load_swaps_the_exponents():
    """A load turning with the shaft stands still on the inner ring (exponent 4.5) and turns
    against the outer ring (exponent 4); the slice-level life recomputed here with them."""
    from bearingdae import load_scene

    scene = load_scene("yang20_baseline", {"operating.unbalance_N": 1_000.0})
    ds = solve_static(scene)
    a = flat(ds)
    assert (a["rating_life_exponent_inner"], a["rating_life_exponent_outer"]) == (4.5, 4.0)
    assert "turns with the inner ring" in a["rating_life_method"]
    b = scene.bearing
    k = scene.numerics.slices
    g = b.roller_diameter_m / b.pitch_diameter_m
    r = ((1 - g) / (1 + g)) ** (143 / 108)
    C, Z = a["basic_dynamic_load_rating_N"], b.rollers
    qci = C / (0.83 * 0.378 * Z) * (1 + (1.038 * r) ** 4.5) ** (2 / 9) * k ** (-7 / 9)
    qce = C / (0.83 * 0.364 * Z) * (1 + (1.038 * r) ** -4.5) ** (2 / 9) * k ** (-7 / 9)
    f = life.edge_stress_factors(k)
    q = ds.contact_force.values
    qei = np.mean((f * q[..., 0]) ** 4.5, axis=0) ** (1 / 4.5)
    qee = np.mean((f * q[..., 1]) ** 4, axis=0) ** (1 / 4)
    ref = np.sum((qei / qci) ** 4.5 + (qee / qce) ** 4.5) ** (-8 / 9)
    assert a["reference_rating_life_L10r_slices_Mrev"] == pytest.approx(ref, rel=1e-12)
    low = flat(solve_static(load_scene("yang20_baseline", {"operating.unbalance_N": 300.0})))
    assert (low["rating_life_exponent_inner"], low["rating_life_exponent_outer"]) == (4.0, 4.5)


def test_edge_stress_factors_shorten_the_life_of_a_flat_roller():
    """A flat roller loads its end laminae fully; the factors (≈ 2.33 there) must cut L10r:
    on 10 slices by more than half (an end slice is a tenth of the roller), converged in
    laminae still (the factors rise towards the ends, Eq. 60, at any lamina count)."""
    on = flat(solve_static(_scene(2_000.0, edge=True)))
    off = flat(solve_static(_scene(2_000.0, edge=False)))
    slices = "reference_rating_life_L10r_slices_Mrev"
    assert on[slices] < 0.5 * off[slices]
    assert on["reference_rating_life_L10r_Mrev"] < 0.9 * off["reference_rating_life_L10r_Mrev"]


def test_edge_stress_factor_values():
    """Eq. 60: f = 1 - 0.01/ln(1.985 |(2k - n_s - 1)/(2 n_s - 2)|); ends: 1 - 0.01/ln(0.9925)."""
    f = life.edge_stress_factors(11)
    assert f[5] == 1.0 and f[0] == f[-1] == pytest.approx(1 - 0.01 / math.log(0.9925))
    assert np.all(np.diff(f[:6]) < 0)


@pytest.mark.parametrize("gamma, table", [(0.01, 52.1), (0.05, 74.1), (0.10, 84.2), (0.20, 88.7),
                                          (0.30, 83.8)])
def test_iso281_fc_reproduces_table_7(gamma, table):
    """ISO 281:2007 Table 7 (radial roller bearings) prints f_c to 0.1."""
    assert float(life.iso281_fc(gamma)) == pytest.approx(table, abs=0.06)


def test_life_scales_with_the_load_rating_and_load():
    """L10r ∝ C^4 at a fixed load distribution (the laminae life exponent, 4.5 x 8/9), and
    P_ref = C L10r^(-3/10), i.e. (C/P_ref)^(10/3) = L10r, by definition."""
    a = flat(solve_static(_scene(2_000.0, C=40_000.0)))
    b = flat(solve_static(_scene(2_000.0, C=80_000.0)))
    assert b["reference_rating_life_L10r_Mrev"] / a["reference_rating_life_L10r_Mrev"] == \
        pytest.approx(2.0 ** 4, rel=1e-12)
    assert (40_000.0 / a["equivalent_reference_load_N"]) ** (10 / 3) == pytest.approx(
        a["reference_rating_life_L10r_Mrev"], rel=1e-12)


def _iso_life(q_inner, q_outer, C, Z, gamma, n, edge=True, p=(4.0, 4.5)):
    """Eq. 65 from lamina loads (roller, lamina) of both races, typed from the standard."""
    r = ((1 - gamma) / (1 + gamma)) ** (143 / 108)
    qci = C / (0.83 * 0.378 * Z) * (1 + (1.038 * r) ** 4.5) ** (2 / 9) * n ** (-7 / 9)
    qce = C / (0.83 * 0.364 * Z) * (1 + (1.038 * r) ** -4.5) ** (2 / 9) * n ** (-7 / 9)
    k = np.arange(1, n + 1)
    with np.errstate(divide="ignore"):
        f = 1 - 0.01 / np.log(1.985 * np.abs((2 * k - n - 1) / (2 * n - 2))) if edge else 1.0
    qei = np.mean((f * q_inner) ** p[0], axis=0) ** (1 / p[0])
    qee = np.mean((f * q_outer) ** p[1], axis=0) ** (1 / p[1])
    return np.sum((qei / qci) ** 4.5 + (qee / qce) ** 4.5) ** (-8 / 9)


def test_the_theory_page_numbers_of_the_baseline_laminae():
    """docs/theory.md, "laminae, converged" and "dynamic runs": the numbers it prints."""
    from bearingdae import load_scene
    from bearingdae.physics.geometry import profile_drop
    from bearingdae.physics.geometry import make_geometry
    from bearingdae.analysis.rating_life import converged_life, position_loads, slice_life
    from bearingdae.analysis.static_state import with_slices

    def static(slices):
        return solve_static(load_scene("yang20_baseline", {"numerics.slices": slices}))

    on_slices = {k: static(k)["reference_rating_life_L10r_slices_Mrev"].item()
                 for k in (10, 20, 40, 80)}
    for k, printed in ((10, 1.09e5), (20, 8.9e5), (40, 9.1e5), (80, 9.4e5)):
        assert printed_within(printed, on_slices[k], 10 ** (np.floor(np.log10(printed))
                                                           - (2 if k == 10 else 1)))
    a = {k: v.item() for k, v in static(10).data_vars.items() if v.ndim == 0}
    assert a["rating_life_laminae"] == 320 and a["rating_life_converged"] == 1
    assert printed_within(9.58e5, a["reference_rating_life_L10r_Mrev"], 1e3)
    assert printed_within(0.004, a["reference_rating_life_L10r_error_Mrev"] / 9.58e5, 1e-3)
    scene = load_scene("yang20_baseline")
    for k in (320, 640, 1000):  # "320-1000 slices give 9.58e5-9.59e5": the life on them
        fine = with_slices(scene, k)
        g = make_geometry(fine)
        L_k = slice_life(fine, g, position_loads(fine, g, [0.0])[0], (0, 1))
        assert 9.575e5 <= L_k < 9.595e5
    four = converged_life(scene, np.arange(4) / 4)
    eight = converged_life(scene, np.arange(8) / 8)
    ratio4, ratio8 = (c["laminae_Mrev"] / c["slices"] for c in (four, eight))
    assert printed_within(8.555, ratio4, 1e-3)
    assert printed_within(0.0004, abs(ratio4 / ratio8 - 1), 1e-4)

    # "re-evaluating the lamina loads on a finer grid from each roller's approach and tilt
    # ... gives 1.62e6": the 10-slice approaches' straight lines δ + c(x), 320 laminae
    ds = solve_static(scene)
    b, n = scene.bearing, 320
    L, x = b.roller_length_m, ds.slice_position.values
    drop = profile_drop(x, b.profile, L, b.effective_length_m, b.crown_radius_m)
    ell = ds.approach.values + drop[None, :, None]  # (roller, slice, race)
    slope = np.sum(ell * x[None, :, None], axis=1) / np.sum(x * x)
    mean = ell.mean(axis=1)
    xl = -L / 2 + (np.arange(n) + 0.5) * L / n
    cl = profile_drop(xl, b.profile, L, b.effective_length_m, b.crown_radius_m)
    eta = 2 * (1 - scene.materials.poisson_ratio ** 2) / scene.materials.youngs_modulus_Pa
    A = 1.36 * eta ** 0.9  # Palmgren: δ = A Q^0.9 / l^0.8
    d = mean[:, None, :] + slope[:, None, :] * xl[None, :, None] - cl[None, :, None]
    q = (L / n) * np.maximum(d, 0.0) ** (10 / 9) / (A ** (10 / 9) * L ** (1 / 9))
    re = _iso_life(q[..., 0], q[..., 1], a["basic_dynamic_load_rating_N"], b.rollers,
                   b.roller_diameter_m / b.pitch_diameter_m, n)
    assert printed_within(1.62e6, re, 1e4)


def test_a_remembered_converged_life_is_the_fresh_solve_of_the_same_problem():
    """converged_life remembers its last answers by the scene without the keys the static
    problem never reads: another window, tolerance, output selection or title reuses the
    answer, which must equal a fresh solve of that scene; a scene that differs in anything
    else (a load, the slices) is solved afresh."""
    from bearingdae import load_scene
    from bearingdae.analysis import rating_life as rl

    phases = np.arange(2) / 2
    first = load_scene("yang20_baseline")
    again = load_scene("yang20_baseline", {
        "numerics.cage_revolutions": 0.5, "numerics.warmup_cage_revolutions": 0.0,
        "numerics.samples_per_cage_revolution": 64, "numerics.rtol": 1e-4,
        "output.variables": ["cage_speed"], "title": "another title"})
    heavier = load_scene("yang20_baseline", {"operating.radial_load_N": 1600.0})
    finer = load_scene("yang20_baseline", {"numerics.slices": 12})

    rl._MEMO.clear()
    answer = rl.converged_life(first, phases)
    assert rl.converged_life(again, phases) == answer
    assert len(rl._MEMO) == 1  # a hit: nothing solved
    assert rl.solve_converged_life(again, phases) == answer  # what a fresh solve gives
    for other in (heavier, finer):
        fresh = rl.converged_life(other, phases)
        assert fresh == rl.solve_converged_life(other, phases)
        assert fresh["slices"] != answer["slices"]
    assert len(rl._MEMO) == 3
    # the positions and the modification's inputs are part of the problem too
    assert rl.converged_life(first, [0.0]) != answer
    assert len(rl._MEMO) == 4
