"""The modified life: ISO 281's a_ISO (physics/life.py) and L_nmr from the laminae
(analysis/rating_life.py), behind ``lubricant.contamination_factor``.

References: a_ISO typed afresh here from ISO 281:2007 (Eq. 11, Table 11, radial roller
bearings) as a scalar loop with its own band table, on every κ band, at the clamps of κ and
at the cap; ISO 281's rated viscosity ν1 typed afresh for κ; and the identity that holds by
construction of the laminae's sum, L_nmr = a_ISO L10r when every lamina has the same κ and
load ratio.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearingdae import solve_static
from bearingdae.analysis import rating_life
from bearingdae.analysis.engineering import summary_lines
from bearingdae.cli import main
from bearingdae.physics import life
from bearingdae.scene import SceneError
from conftest import make_scene


def reference_a_iso(kappa: float, ratio: float) -> float:
    """ISO 281:2007 a_ISO of a radial roller bearing, one value at a time."""
    kappa = min(max(kappa, 0.1), 4.0)
    if kappa < 0.4:
        c2, c3 = 1.3993, 0.054381
    elif kappa < 1.0:
        c2, c3 = 1.2348, 0.19087
    else:
        c2, c3 = 1.2348, 0.071739
    inner = 1.0 - (1.5859 - c2 / kappa ** c3) * ratio ** 0.4
    if inner <= 0.0:  # below the fatigue limit: ISO 281's limit a_ISO <= 50
        return 50.0
    return min(0.1 * inner ** -9.185, 50.0)


KAPPAS = [0.1, 0.2, 0.3999, 0.4, 0.7, 0.9999, 1.0, 2.0, 4.0]
RATIOS = [0.0, 0.005, 0.02, 0.1, 0.3, 0.6]


@pytest.mark.parametrize("kappa", KAPPAS)
def test_a_iso_matches_an_independent_implementation_on_every_band(kappa):
    got = life.a_iso(np.full(len(RATIOS), kappa), np.array(RATIOS))
    want = [reference_a_iso(kappa, x) for x in RATIOS]
    np.testing.assert_allclose(got, want, rtol=1e-13)
    assert got.shape == (len(RATIOS),)


def test_a_iso_clamps_kappa_and_caps_at_50():
    x = np.array([0.01, 0.1, 0.5])
    np.testing.assert_array_equal(life.a_iso(0.01, x), life.a_iso(0.1, x))
    np.testing.assert_array_equal(life.a_iso(25.0, x), life.a_iso(4.0, x))
    # the cap: a_ISO reaches 50 before the bracket closes, and stays 50 past it
    assert life.a_iso(4.0, 2.0) == 50.0 == reference_a_iso(4.0, 2.0)
    assert life.a_iso(1.0, 1e3) == 50.0 and life.a_iso(1.0, np.inf) == 50.0
    # no contamination (e_C = 0) or an infinite load: the floor 0.1 of the formula
    assert life.a_iso(1.0, 0.0) == pytest.approx(0.1, rel=1e-12)
    assert math.isnan(float(life.a_iso(math.nan, 0.1)))
    # the middle band's c3 is 0.19087 (not 0.019087) and the bracket has no exponent:
    # at κ = 0.5, e_C C_u/P = 0.1 the value typed afresh is 0.2353...
    k, r = 0.5, 0.1
    by_hand = 0.1 * (1.0 - (1.5859 - 1.2348 / k ** 0.19087) * r ** 0.4) ** -9.185
    assert float(life.a_iso(k, r)) == pytest.approx(by_hand, rel=1e-14)


def test_fatigue_load_limit_is_c0_over_8_2_with_the_size_factor_above_100_mm():
    assert life.fatigue_load_limit(82_000.0, 0.08) == pytest.approx(10_000.0)
    assert life.fatigue_load_limit(82_000.0, 0.1) == pytest.approx(10_000.0)
    assert life.fatigue_load_limit(82_000.0, 0.2) == pytest.approx(10_000.0 * 0.5 ** 0.3)


@pytest.mark.parametrize("kappa, ratio", [(0.2, 0.05), (0.7, 0.02), (2.0, 0.5)])
def test_lnmr_is_l10r_times_a_iso_when_every_lamina_sees_the_same_ratio(kappa, ratio):
    """Laminae all alike (one q_e/q_c on both rings): L_nmr = a_ISO(κ, e_C C_u/P_ref) L10r,
    ISO 281's modified life, with P_ref = C L10r^(-3/10) typed here."""
    scene = make_scene({"lubricant.contamination_factor": 0.6})
    from bearingdae.physics.geometry import make_geometry

    g = make_geometry(scene)
    q_ci, q_ce = rating_life._lamina_ratings(scene, g)
    C = rating_life.rating(scene, g)[0]
    mod = {"kappa": kappa, "ec_cu_over_c": 0.6 * 0.1}
    r = ratio  # q_e/q_c of every lamina, inner and outer ring
    qe = (np.full(g.slices, r * q_ci), np.full(g.slices, r * q_ce))
    L10r = rating_life.slice_life(scene, g, None, None, equivalent=qe)
    P_ref = C * L10r ** -0.3
    Lnmr = rating_life.modified_slice_life(scene, g, None, None, mod, equivalent=qe)
    a = reference_a_iso(kappa, mod["ec_cu_over_c"] * C / P_ref)
    assert 0.1 < a < 50.0
    assert Lnmr == pytest.approx(L10r * a, rel=1e-12)


def test_the_lamina_ratio_does_not_depend_on_the_lamina_count():
    """q_e ∝ 1/N and q_c ∝ N^(-7/9) at a fixed load: P_k is the same at every count."""
    one = [float(life.lamina_load_ratio(0.1, 1000.0 / n, 5e4 * n ** (-7 / 9), 2 * n))
           for n in (10, 80, 640)]
    np.testing.assert_allclose(one, one[0], rtol=1e-12)


def test_an_unloaded_lamina_adds_no_damage_whatever_its_a_iso():
    """At κ = 0.1 ISO's rounded constants make 1.5859 - c2/κ^c3 slightly negative, so an
    unloaded lamina (load ratio inf) gets a_ISO = 0; its damage is still 0, not NaN."""
    a = life.a_iso(0.1, [np.inf, 1.0])
    assert a[0] == 0.0
    got = life.modified_reference_rating_life([0.0, 1.0], [1.0, 0.0], 1.0, 1.0, a, a[::-1])
    assert got == pytest.approx(2.0 ** (-8.0 / 9.0) * float(a[1]), rel=1e-12)


@pytest.mark.parametrize("value, shown", [(1.5, "1.5"), (-0.1, "-0.1"), ("dirty", "dirty"),
                                          (2, "2")])
def test_contamination_factor_out_of_range_is_one_line_naming_key_value_range(value, shown):
    with pytest.raises(SceneError) as err:
        make_scene({"lubricant.contamination_factor": value})
    msg = str(err.value)
    assert len(msg.strip().splitlines()) == 2, msg  # the scene's name, then the one finding
    for word in ("contamination_factor", shown):
        assert word in msg, (word, msg)
    if not isinstance(value, str):
        assert "[0, 1]" in msg, msg


def test_the_cli_refuses_a_bad_contamination_factor_with_status_2(capsys):
    rc = main(["static", "cases/yang20_baseline.toml", "--set",
               "lubricant.contamination_factor=3", "-o", "/dev/null"])
    err = capsys.readouterr().err
    assert rc == 2 and "contamination_factor" in err and "Traceback" not in err


def test_the_key_stays_out_of_default_scenes():
    s = make_scene()
    assert s.lubricant.contamination_factor is None
    assert "contamination_factor" not in s.to_toml(complete=True)
    given = make_scene({"lubricant.contamination_factor": 0.3})
    assert "contamination_factor = 0.3" in given.to_toml(complete=True)


NEW = ("modified_rating_life_Lnmr_Mrev", "modified_rating_life_Lnmr_error_Mrev",
       "modified_rating_life_Lnmr_h", "kappa", "fatigue_load_limit_Cu_N")


BASELINE = {"operating.speed_rpm": 2000.0, "operating.radial_load_N": 800.0}


def test_static_result_has_the_modified_life_with_the_key_and_not_without():
    plain = solve_static(make_scene(BASELINE))
    assert not any(n in plain for n in NEW)
    assert not any("modified life" in line for line in summary_lines(plain))
    scene = make_scene({**BASELINE, "lubricant.contamination_factor": 0.5})
    ds = solve_static(scene)
    for n in NEW:
        assert n in ds and ds[n].attrs["units"] and ds[n].attrs["long_name"], n
    assert (ds.modified_rating_life_Lnmr_Mrev.attrs["ancillary_variables"]
            == "modified_rating_life_Lnmr_error_Mrev")
    # κ = ν/ν1: ν = η/ρ of the scene's oil, ν1 = 4500 n^-0.5 d_m^-0.5 (ISO 281, n >= 1000)
    b, oil = scene.bearing, scene.lubricant
    nu = oil.viscosity_Pa_s / oil.oil_density_kg_m3 * 1e6
    nu1 = 4500.0 / math.sqrt(scene.operating.speed_rpm) / math.sqrt(b.pitch_diameter_m * 1e3)
    assert float(ds.kappa) == pytest.approx(nu / nu1, rel=1e-12)
    # the same laminae, the same L10r as without the key; L_nmr within [0.1, 50] L10r
    L10r = float(ds.reference_rating_life_L10r_Mrev)
    assert L10r == float(plain.reference_rating_life_L10r_Mrev)
    Lnmr = float(ds.modified_rating_life_Lnmr_Mrev)
    assert 0.1 * L10r * (1 - 1e-9) <= Lnmr <= 50.0 * L10r * (1 + 1e-9)
    err = float(ds.modified_rating_life_Lnmr_error_Mrev)
    assert 0.0 <= err <= rating_life.LAMINAE_TOLERANCE * Lnmr
    line = next(x for x in summary_lines(ds) if "modified life" in x)
    assert f"{Lnmr:.4g}" in line and "κ" in line


def test_a_heavier_load_and_dirtier_oil_give_a_lower_a_iso():
    """At 8 kN the baseline's laminae are below the cap: L_nmr/L10r falls with e_C."""
    ratios = []
    for e_c in (0.8, 0.2):
        ds = solve_static(make_scene({**BASELINE, "lubricant.contamination_factor": e_c,
                                      "operating.radial_load_N": 8000.0}))
        ratios.append(float(ds.modified_rating_life_Lnmr_Mrev)
                      / float(ds.reference_rating_life_L10r_Mrev))
    assert 0.1 < ratios[1] < ratios[0] < 50.0, ratios


@pytest.mark.slow
def test_a_run_prints_the_modified_life_beside_l10r_and_records_it(tmp_path):
    import xarray as xr

    from fuzzing import run_cli

    out = tmp_path / "run.nc"
    rc, stdout, _ = run_cli(["run", "cases/yang20_baseline.toml", "--no-plot", "-o", str(out),
                             "--set", "numerics.cage_revolutions=0.05", "--set",
                             "numerics.warmup_cage_revolutions=0", "--set",
                             "lubricant.contamination_factor=0.5"])
    assert rc == 0, stdout
    lines = stdout.splitlines()
    at = next(i for i, line in enumerate(lines) if "rating life L10r" in line)
    assert "modified life L_nmr" in lines[at + 1], lines[at:at + 2]
    with xr.open_dataset(out) as ds:
        L, err = float(ds.modified_rating_life_Lnmr_Mrev), float(
            ds.modified_rating_life_Lnmr_error_Mrev)
        L10r = float(ds.reference_rating_life_L10r_Mrev)
        assert 0.1 * L10r <= L <= 50.0 * L10r * (1 + 1e-9)
        assert 0.0 <= err <= rating_life.LAMINAE_TOLERANCE * L
        assert ds.kappa.attrs["units"] == "1" and float(ds.kappa) > 0.0


#: a converged thermal run at constant speed: the films' temperatures differ from the oil's
#: (the rollers' and the rings' nodes), so ν at the film, not at the oil node, is checked
THERMAL_RUN = {
    "physics.thermal": "steady", "lubricant.contamination_factor": 0.5,
    "operating.speed_rpm": 1400.0,
    "operating.radial_load_N": 800.0, "numerics.slices": 4,
    "numerics.samples_per_cage_revolution": 40, "numerics.cage_revolutions": 0.25,
    "numerics.warmup_cage_revolutions": 0.5, "numerics.steady_block_cage_revolutions": 0.5,
    "numerics.max_warmup_cage_revolutions": 10.0}


def _walther_nu_mm2_s(T_C: float, nu40: float = 32.0, nu100: float = 5.4) -> float:
    """ASTM D341 through (40 °C, ν40) and (100 °C, ν100), typed afresh: the default oil."""
    z = [math.log10(math.log10(n + 0.7)) for n in (nu40, nu100)]
    x = [math.log10(t + 273.15) for t in (40.0, 100.0)]
    B = (z[0] - z[1]) / (x[1] - x[0])
    A = z[0] + B * x[0]
    return 10.0 ** (10.0 ** (A - B * math.log10(T_C + 273.15))) - 0.7


def _iso281_nu1_mm2_s(n_rpm: float, dm_mm: float) -> float:
    """ISO 281:2007 rated viscosity, typed afresh."""
    return (45000.0 * n_rpm ** -0.83 if n_rpm < 1000.0 else 4500.0 * n_rpm ** -0.5) / dm_mm ** 0.5


@pytest.mark.slow
def test_a_thermal_run_writes_one_kappa_the_films_over_iso_281(tmp_path):
    """With physics.thermal = "steady" and the contamination factor, the modified life's
    ``kappa`` and the thermal result's ``viscosity_ratio_kappa`` are one number (in memory and
    in a streamed file): ν by ASTM D341 at the raceway films' temperature (the mean of the
    ring nodes and twice the roller node, the recorded network temperatures of a converged
    run), ν₁ by ISO 281 at the inner ring's speed. (ν₁ at the record's mean speed rather
    than a speed history's last value: the unit tests of rating_life.viscosity_ratio.)"""
    import warnings

    from bearingdae import simulate

    scene = make_scene(THERMAL_RUN)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        results = [simulate(scene, progress=False),
                   simulate(scene, progress=False, output=tmp_path / "run.nc")]
    for ds in results:
        assert ds.thermal_blocks.attrs["converged"] == 1
        T = {str(n): float(v) for n, v in zip(ds.thermal_node.values, ds.temperature.values)}
        film_C = 0.25 * (T["inner_ring"] + T["outer_ring"] + 2.0 * T["rollers"])
        # the films are not at the oil's temperature: reading ν at the oil node would fail
        assert abs(film_C - T["oil"]) > 1.0
        n_rpm = 1400.0
        want = _walther_nu_mm2_s(film_C) / _iso281_nu1_mm2_s(n_rpm, 45.0)
        assert float(ds.kappa) == pytest.approx(want, rel=1e-9)
        assert float(ds.viscosity_ratio_kappa) == pytest.approx(want, rel=1e-9)
        assert float(ds.kappa) == float(ds.viscosity_ratio_kappa)  # one computation
        assert "modified_rating_life_Lnmr_Mrev" in ds
        # the long names say they are one quantity
        assert "viscosity_ratio_kappa" in ds.kappa.attrs["long_name"]
        assert "kappa" in ds.viscosity_ratio_kappa.attrs["long_name"]
    ds.close()
