"""The permissible axial load of a bearing with flanges (analysis/flange.py): the smallest of
the catalogue's rules, the rule that binds named, in the Dataset's attributes and the run
summary (theory.md §16).

Reference: the SKF catalogue's rules typed afresh here (C0 of ISO 76; F_ap = k1 C0 1e4 /
(n (d + D)) - k2 F_r with oil's k1 = 1.5, k2 = 0.15; flange strength 0.0023 D^1.7 kN;
F_a <= 0.5 F_r), on yang20 (Z = 20, D_w = 7 mm, L = 10 mm, d_m = 45 mm, d = 30 mm,
D = 60 mm read from its scene).
"""

from __future__ import annotations

import warnings

import pytest

from bearingdae.analysis.result_variables import flat
from bearingdae import simulate
from bearingdae.cli.run import _flange_lines_of
from bearingdae.analysis.flange import axial_capacity_attrs, permissible_axial_load_text
from conftest import make_scene


def _rules(scene, speed_rpm, radial_N):
    b = scene.bearing
    Dw, L, dm = b.roller_diameter_m * 1e3, b.roller_length_m * 1e3, b.pitch_diameter_m * 1e3
    d, D = b.bore_m * 1e3, b.outer_diameter_m * 1e3
    C0 = 44.0 * (1.0 - Dw / dm) * b.rollers * L * Dw
    return {"thermal": 1.5 * C0 * 1e4 / (speed_rpm * (d + D)) - 0.15 * radial_N,
            "strength": 1e3 * 0.0023 * D ** 1.7, "half_radial": 0.5 * radial_N}


def test_nup_at_800_N_radial_is_bound_by_half_the_radial_load():
    """yang20 NUP, 800 N radial, 2000 r/min: thermal 6695 N, flange strength 2424 N, 0.5 F_r
    = 400 N binds. The summary line reads 400 N and names the rule; the others follow."""
    scene = make_scene({"bearing.type": "NUP", "operating.axial_load_N": 200.0,
                        "numerics.warmup_cage_revolutions": 0.0,
                        "numerics.cage_revolutions": 0.02},
                       operating={"radial_load_N": 800.0, "moment_Nm": 3.0,
                                  "speed_rpm": 2000.0})
    ref = _rules(scene, 2000.0, 800.0)
    assert ref["half_radial"] < ref["strength"] < ref["thermal"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = simulate(scene, progress=False)
    a = flat(ds)
    assert a["permissible_axial_load_N"] == pytest.approx(400.0, rel=1e-12)
    assert a["permissible_axial_load_rule"] == "0.5 F_r"
    assert a["thermal_axial_load_limit_N"] == pytest.approx(ref["thermal"], rel=1e-12)
    assert a["flange_strength_limit_N"] == pytest.approx(ref["strength"], rel=1e-12)
    line = next(x for x in _flange_lines_of(ds) if "permissible axial load" in x)
    assert line.split()[3:6] == ["400", "N", "(0.5"], line
    assert "F_r binds" in line and "6695 N" in line and "2424 N" in line, line


@pytest.mark.parametrize("radial_N, speed_rpm, rule", [
    (10_000.0, 2000.0, "flange strength"),   # 0.5 F_r = 5000 N, thermal 5315 N
    (800.0, 40_000.0, "thermal F_ap (SKF)"),  # thermal 221 N, 0.5 F_r = 400 N
])
def test_the_smallest_rule_binds(radial_N, speed_rpm, rule):
    scene = make_scene({"bearing.type": "NJ", "operating.axial_load_N": 100.0},
                       operating={"radial_load_N": radial_N, "speed_rpm": speed_rpm})
    ref = _rules(scene, speed_rpm, radial_N)
    a = axial_capacity_attrs(scene)
    assert a["permissible_axial_load_N"] == pytest.approx(min(ref.values()), rel=1e-12)
    assert a["permissible_axial_load_rule"] == rule
    text = permissible_axial_load_text(a)
    assert text.startswith(f"{min(ref.values()):.4g} N ({rule} binds;"), text


def test_exceeding_the_binding_rule_warns_and_names_it():
    scene = make_scene({"bearing.type": "NJ", "operating.axial_load_N": 500.0},
                       operating={"radial_load_N": 800.0, "speed_rpm": 2000.0})
    with pytest.warns(UserWarning, match=r"permissible axial load 400 N .*\(0\.5 F_r;"):
        axial_capacity_attrs(scene)


def test_a_file_written_before_the_rules_reads_as_it_did():
    """A result of an earlier version holds the thermal limit as the permissible axial load
    and no rule: its summary line is the one it had."""
    old = {"permissible_axial_load_N": 6695.1, "flange_strength_limit_N": 2424.3}
    assert permissible_axial_load_text(old) == "6695 N (SKF, thermal), flange strength 2424 N"
