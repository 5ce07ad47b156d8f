"""The thermal network's laws (physics/thermal.py, theory.md §21) against analytic limits,
a balance and published data."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearingdae.physics import thermal as law


def test_one_node_network_is_the_analytic_steady_temperature():
    """One node with conductance G to an ambient temperature and heat P: T = T_amb + P / G."""
    G, P, T_amb = 3.7, 12.5, 21.0
    T = law.steady_temperatures(np.array([[G]]), [P], [G * T_amb])
    assert T[0] == pytest.approx(T_amb + P / G, rel=1e-14)


def test_two_links_in_series_are_the_series_conductance():
    """A node behind another (ambient - a - b, heat into b): T_b = T_amb + P (1/G1 + 1/G2)."""
    G1, G2, P, T_amb = 2.0, 5.0, 7.0, 10.0
    links = {("inner_ring", "oil"): G2}
    to_fixed = np.zeros(len(law.NODES))
    to_fixed[law.NODES.index("inner_ring")] = G1
    for node in ("outer_ring", "rollers", "cage"):  # the others tied to 0 °C, no heat
        to_fixed[law.NODES.index(node)] = 1.0
    fixed = to_fixed * np.where(np.array(law.NODES) == "inner_ring", T_amb, 0.0)
    q = np.zeros(len(law.NODES))
    q[law.NODES.index("oil")] = P
    T = law.steady_temperatures(law.conductance_matrix(links, to_fixed), q, fixed)
    assert T[law.NODES.index("oil")] == pytest.approx(T_amb + P * (1 / G1 + 1 / G2), rel=1e-12)
    assert law.series(G1, G2) == pytest.approx(1.0 / (1 / G1 + 1 / G2))


def test_a_network_without_a_path_to_a_fixed_temperature_is_refused():
    with pytest.raises(ValueError, match="no path"):
        law.steady_temperatures(law.conductance_matrix({("cage", "oil"): 1.0},
                                                       np.zeros(len(law.NODES))),
                                np.ones(len(law.NODES)), np.zeros(len(law.NODES)))


def test_node_heat_splits_each_source_by_its_row():
    """Each source's mean power goes to the nodes by its row (rows typed here: half the inner
    ring and half the rollers; all the oil); a source without a row is an error naming it
    (each declared source's row: tests/system/test_effect_declaration.py)."""
    rows = {"raceway_inner": (0.5, 0.0, 0.5, 0.0, 0.0), "orbit_drag": (0.0, 0.0, 0.0, 0.0, 1.0)}
    q = law.node_heat({"raceway_inner": 2.0, "orbit_drag": 3.0}, rows)
    assert q.sum() == pytest.approx(5.0)
    assert q[law.NODES.index("oil")] == 3.0 and q[law.NODES.index("inner_ring")] == 1.0
    with pytest.raises(KeyError, match="made_up"):
        law.node_heat({"made_up": 1.0}, rows)


def test_shell_conductance_is_the_cylinder_wall_of_fourier():
    """Radial conduction through a tube: Q = 2π k B ΔT / ln(r_o/r_i) (Incropera Eq. 3.27),
    checked against the sum of thin shells' resistances dr / (2π k B r)."""
    k, B, ri, ro = 46.0, 0.02, 0.015, 0.0205
    r = np.linspace(ri, ro, 200001)
    mid = 0.5 * (r[1:] + r[:-1])
    R = np.sum(np.diff(r) / (2 * np.pi * k * B * mid))
    assert law.shell_conductance(k, B, ri, ro) == pytest.approx(1.0 / R, rel=1e-9)


def test_band_area_is_the_hertz_line_contact_width():
    """b = sqrt(4 w' R / (π E*)) (Johnson, Contact Mechanics, Eq. 4.43) from the load per length
    w' and the maximum pressure p = 2 w' / (π b) the kernel reports."""
    E_star, R, w, q = 113.7e9, 1.8e-3, 2.3e-3, 150.0
    b = math.sqrt(4 * (q / w) * R / (math.pi * E_star))
    p = 2 * (q / w) / (math.pi * b)
    assert law.band_area(q, p, w) == pytest.approx(2 * b * w, rel=1e-12)
    assert law.band_area(0.0, 0.0, w) == 0.0


def test_walther_passes_through_the_two_given_viscosities():
    A, B = law.walther_constants(40.0, 32.0, 100.0, 5.4)
    assert law.walther_viscosity(40.0, A, B) == pytest.approx(32.0, rel=1e-12)
    assert law.walther_viscosity(100.0, A, B) == pytest.approx(5.4, rel=1e-12)
    assert law.walther_temperature(11.5, A, B) == pytest.approx(69.0, abs=0.2)
    nu = law.walther_viscosity(np.array([0.0, 20.0, 60.0, 120.0]), A, B)
    assert np.all(np.diff(nu) < 0)


def test_walther_against_a_published_point_of_an_iso_vg_32_oil():
    """Shell Tellus S2 M 32 (ISO VG 32, VI 99), technical data sheet: 32 mm²/s at 40 °C,
    5.4 mm²/s at 100 °C, and 338 mm²/s at 0 °C. Extrapolated from the two to 0 °C, ASTM D341
    gives 336 mm²/s; within 3 % (the data sheet's values are rounded "typical" values, and 0 °C
    is an extrapolation 40 K below the two points)."""
    A, B = law.walther_constants(40.0, 32.0, 100.0, 5.4)
    assert law.walther_viscosity(0.0, A, B) == pytest.approx(338.0, rel=0.03)


def test_rated_viscosity_of_iso_281():
    """ISO 281:2007: ν₁ = 45000 n^-0.83 d_m^-0.5 (n < 1000 r/min), 4500 n^-0.5 d_m^-0.5 above;
    the yang20 bearing (d_m = 45 mm) at 2000 r/min needs 15 mm²/s."""
    assert law.rated_viscosity(2000.0, 45.0) == pytest.approx(4500 / math.sqrt(2000 * 45))
    assert law.rated_viscosity(2000.0, 45.0) == pytest.approx(15.0, rel=1e-12)
    assert law.rated_viscosity(500.0, 100.0) == pytest.approx(45000 * 500 ** -0.83 / 10.0)
    assert math.isnan(law.rated_viscosity(0.0, 45.0))  # ISO 281: a turning ring only


def test_temperature_coefficient_is_the_slope_of_ln_viscosity():
    """β = −d ln ν/dT by ASTM D341, against central differences of the viscosity law."""
    A, B = law.walther_constants(40.0, 32.0, 100.0, 5.4)
    for T in (20.0, 60.0, 110.0):
        h = 1e-3
        slope = (math.log(law.walther_viscosity(T + h, A, B))
                 - math.log(law.walther_viscosity(T - h, A, B))) / (2 * h)
        assert law.walther_temperature_coefficient(T, A, B) == pytest.approx(-slope, rel=1e-6)


def test_a_standstill_thermal_run_says_what_its_nan_rated_viscosity_means():
    """At n = 0 the rated viscosity was stored as inf (and κ as 0) without a word: now NaN,
    with the nan_meaning attribute other result variables carry, and the summary says so."""
    from types import SimpleNamespace

    import numpy as np
    import xarray as xr

    from bearingdae.results.thermal import thermal_lines, thermal_variables

    nodes = len(law.NODES)
    c = SimpleNamespace(temperatures_C=np.full(nodes, 40.0), heat_W=np.zeros(nodes),
                        viscosity_Pa_s=0.03, kinematic_mm2_s=35.0,
                        rated_mm2_s=law.rated_viscosity(0.0, 45.0), blocks=1, converged=True,
                        last_change_K=0.0, tolerance_K=0.5)
    c.rated_ratio = c.kinematic_mm2_s / c.rated_mm2_s
    ds = xr.Dataset(thermal_variables(SimpleNamespace(thermal=c)))
    for name in ("rated_viscosity", "viscosity_ratio_kappa"):
        assert np.isnan(ds[name].item()) and "stands still" in ds[name].attrs["nan_meaning"]
    assert any("κ undefined: the inner ring stands still" in ln for ln in thermal_lines(ds))
