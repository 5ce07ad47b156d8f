"""The thermal network's laws (physics/heat_network.py, theory.md §21) against analytic limits
and a balance."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearingdae.physics import heat_network as law


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
