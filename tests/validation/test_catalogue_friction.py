"""The bearing's friction torque against the SKF catalogue model.

Reference: SKF's model of the frictional moment (rolling + sliding, inlet shear heating,
kinematic starvation), typed apart from bearingdae in tools/skf_friction.py from the
catalogue's published formulae and constants. The catalogue model is a fit to measured
bearings (its spread is tens of per cent), so the tolerance is a factor: with the friction
switches on (EHL rolling resistance and mixed lubrication, thermal off so that the oil keeps
the catalogue's viscosity) every point of the speed x load grid of docs/user-guide.md
("Friction, power loss and temperature against the catalogue") should lie within a factor 1.5
of the catalogue; it reaches the catalogue's order of magnitude (a factor 10), and the factor
1.5 is an expected failure until the rolling resistance matches (the reason says where not). Like for like: the catalogue's moment of an oil-air lubricated bearing has no
drag term (it gives drag for an oil bath only), so the model's torque is taken without the
oil-air mixture's orbit drag and churning (studies/friction.DRAG_SOURCES), which the user
guide's table shows beside it. The paper's model (both switches off) is far below: it
misses the rolling friction the catalogue is made of.
"""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import pytest

from bearingdae.scene import load_scene

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))  # skf_friction.py: the SKF model, typed apart
import skf_friction as skf  # noqa: E402


def tool():
    spec = importlib.util.spec_from_file_location("catalogue_tool",
                                                  ROOT / "tools" / "catalogue_friction.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize("bearing", sorted(skf.BEARINGS_MM))
def test_reference_uses_the_scenes_bearing_and_oil(bearing):
    """The reference's d, D and ν = η/ρ are those of the scenes the study runs."""
    case = tool().CASES[bearing]
    src = load_scene(case).source
    assert (src["bearing"]["bore_mm"], src["bearing"]["outer_diameter_mm"]) == \
        skf.BEARINGS_MM[bearing]
    nu = skf.kinematic_viscosity_mm2_s(src["lubricant"]["viscosity_Pa_s"],
                                       src["lubricant"]["oil_density_kg_m3"])
    assert nu == pytest.approx(skf.kinematic_viscosity_mm2_s())


def test_reference_limits_and_exponents():
    """The typed model against its own limits: at low speed and viscosity both reduction
    factors tend to 1 and μ_sl to μ_bl; the rolling moment scales with F_r^0.31 and, free of
    the reduction factors, with (ν n)^0.6; the sliding one is linear in F_r."""
    d, D = skf.BEARINGS_MM["yang20"]
    assert skf.inlet_shear_factor(1e-3, 45.0, 1e-3) == pytest.approx(1.0, abs=1e-9)
    assert skf.replenishment_factor(1e-3, d, D, 1e-3) == pytest.approx(1.0, abs=1e-9)
    assert skf.sliding_coefficient(1e-3, 45.0, 1e-3) == pytest.approx(skf.MU_BL, rel=1e-9)
    assert skf.sliding_coefficient(1e5, 45.0, 100.0) == pytest.approx(skf.MU_EHL, rel=1e-9)
    nu = skf.kinematic_viscosity_mm2_s()
    a, b = (skf.frictional_moment_Nmm(2000.0, F, d, D, nu) for F in (1000.0, 8000.0))
    assert b["rolling"] / a["rolling"] == pytest.approx(8.0 ** 0.31, rel=1e-12)
    assert b["sliding"] / a["sliding"] == pytest.approx(8.0, rel=1e-12)
    lo, hi = (skf.frictional_moment_Nmm(n, 1000.0, d, D, 1e-2) for n in (1.0, 4.0))
    assert hi["rolling"] / lo["rolling"] == pytest.approx(4.0 ** 0.6, rel=1e-6)
    # the yang20 baseline point by hand: G_rr (ν n)^0.6 = 1.09e-6 · 45^2.41 · 800^0.31 ·
    # (11.494 · 2000)^0.6 = 34.5 N·mm before the reduction factors (≈ 0.98 and 0.96)
    M = skf.frictional_moment_Nmm(2000.0, 800.0, d, D, nu)
    raw = 1.09e-6 * 45.0 ** 2.41 * 800.0 ** 0.31 * (nu * 2000.0) ** 0.6
    assert 0.9 * raw < M["rolling"] < raw
    assert M["total"] * 1e-3 * 2000.0 * math.pi / 30.0 == pytest.approx(7.4, abs=0.05)  # W


#: grid points whose run fails in IDA, listed so that the test still checks every other point
#: and fails if one of them starts to run (then drop it here and from docs/user-guide.md):
#: none since IDA's fallback (yang20 at 500 r/min under 8000 N failed before it, in both
#: models) and the Lipschitz light-load rolling force (yang20 at 500 r/min, 2000 N)
KNOWN_FAILURES: set = set()


#: the test's shorter windows (the tool's: one cage revolution recorded after a warm-up of at
#: most 20): a quarter revolution recorded after at most 5. The friction torque is a steady
#: mean, not a chaotic statistic: with these windows every one of the 24 ratios to the
#: catalogue was within 0.4 % of docs/data/catalogue_friction.csv's (the five points that
#: reach the cap unsteady included), far inside the factor 10 and the factor 1.5 the tests
#: judge, at about a third of the CPU (524 s against the table's 1484 s)
WINDOW = {"numerics.cage_revolutions": 0.25, "numerics.max_warmup_cage_revolutions": 5.0}


@pytest.fixture(scope="module")
def switched_maps(tmp_path_factory):
    """The friction maps of both bearings with the friction switches on, freshly run on the
    tool's grid from its settings (steady from the torque-balance start) with the shorter
    windows of :data:`WINDOW`: {bearing: map Dataset}."""
    from bearingdae.studies.friction import run_friction_map

    t, folder = tool(), tmp_path_factory.mktemp("friction")
    return {bearing: run_friction_map(case, t.SPEEDS_RPM, t.LOADS_N, folder / f"{bearing}.nc",
                                      overrides={**t.MODELS["switches"], **WINDOW},
                                      scheduler="synchronous", progress=False)
            for bearing, case in t.CASES.items()}


def _ratios(maps) -> tuple[dict, list[str]]:
    """({(bearing, n, F): friction without drag / catalogue}, problems with the known
    failures) over the grid."""
    t = tool()
    ratios, problems = {}, []
    for bearing, ds in maps.items():
        for n in t.SPEEDS_RPM:
            for F in t.LOADS_N:
                pt = ds.sel(speed_rpm=n, radial_load_N=F)
                T = float(pt.friction_torque_N_m - pt.drag_torque_N_m)
                known = (bearing, n, F) in KNOWN_FAILURES
                if known == math.isfinite(T):
                    problems.append(f"{bearing} {n:.0f} r/min {F:.0f} N: " + (
                        "runs now: drop it from KNOWN_FAILURES" if known else "failed"))
                if math.isfinite(T):
                    ratios[(bearing, n, F)] = T / skf.friction_torque_N_m(bearing, n, F)
    return ratios, problems


def _outside(ratios: dict, factor: float) -> list[str]:
    return [f"{b} {n:.0f} r/min {F:.0f} N: {r:.2f} x the catalogue"
            for (b, n, F), r in ratios.items() if not 1.0 / factor <= r <= factor]


@pytest.mark.slow
def test_friction_torque_is_of_the_catalogues_order(switched_maps):
    """With the switches the friction reaches the catalogue's order of magnitude at every
    point (within a factor 10 either way), where the paper's model is 10^2-10^4 below it at
    all but the skidding points (docs/data/catalogue_friction.csv); every point runs but the
    known failures."""
    ratios, problems = _ratios(switched_maps)
    assert not problems, "\n".join(problems)
    bad = _outside(ratios, 10.0)
    assert not bad, "\n".join(bad)


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="few points within 1.5x: the EHL rolling resistance "
                   "(Biboulet & Houpert, fully flooded, per unit contact length) grows faster "
                   "with speed than the catalogue's starved oil-air rolling friction and sees "
                   "yang20's long rollers, which the catalogue does not; under 8000 N at 500 "
                   "r/min the catalogue's boundary sliding term leaves the model below it "
                   "(docs/user-guide.md, 'Friction, power loss and temperature against the "
                   "catalogue', and its calibrated table: a stated inlet film brings it in)")
def test_friction_torque_within_a_factor_of_the_catalogue(switched_maps):
    """The target: every point within a factor 1.5 of the catalogue either way."""
    bad = _outside(_ratios(switched_maps)[0], tool().FACTOR)
    assert not bad, "\n".join(bad)
