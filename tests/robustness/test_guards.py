"""Physical plausibility guards: scenes that leave the model's range of validity
warn with a PlausibilityWarning, the Dataset records it, the CLI prints it; a scene inside the
range warns about nothing.

Each triggering scene is built so that its quantity is far beyond the limit, and the recorded
value is checked against an independent estimate where one exists (Hertz pressure from the
slice load; the cage slip from the cage speed in the Dataset).
"""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest

from bearingdae import SimulationError, save, simulate, solve_static
from bearingdae.cli import main
from bearingdae.analysis.guards import (CAGE_SLIP_LIMIT, EDGE_PEAK_RATIO, PRESSURE_LIMIT_PA,
                               PlausibilityWarning, findings)

from conftest import make_scene

#: Short dynamic window (HELPERS.md): no warm-up, 0.1 cage revolution, 10 samples.
SHORT = {"numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 0.1,
         "numerics.samples_per_cage_revolution": 100}


#: The paper's baseline operating point (800 N, 2000 r/min), moment set per test; superfinished
#: surfaces (composite roughness 0.05 µm, λ ≈ 2) so that the film check stays silent where
#: another check is tested (the default 0.11 µm gives λ ≈ 1 there: test_film_parameter_...).
BASE = {"operating.radial_load_N": 800.0, "operating.speed_rpm": 2000.0,
        "materials.roughness_um": 0.05}


def run(fn, scene):
    """(Dataset, [PlausibilityWarning messages]) of ``fn(scene)``."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            ds = fn(scene)
        except SimulationError as exc:  # keep the partial result; the guards ran on it too
            ds = exc.dataset
    msgs = [str(w.message) for w in caught if issubclass(w.category, PlausibilityWarning)]
    return ds, msgs


def checks(ds) -> list[str]:
    return [f["check"] for f in findings(ds)]


def test_scene_inside_the_range_warns_about_nothing():
    """800 N, no moment, end-crown rollers at 2000 r/min: p ≈ 0.5 GPa, uniform slice loads,
    no warning, and the Dataset says which checks ran."""
    ds, msgs = run(solve_static, make_scene({**BASE, "operating.moment_Nm": 0.0}))
    assert msgs == [] and findings(ds) == []
    assert json.loads(ds.attrs["plausibility_checks"]) == ["scene_units", "contact_pressure",
                                                           "edge_loading", "film_parameter"]


def test_contact_pressure_above_4_GPa():
    """120 kN on the 20-roller yang20 bearing. Reference: the Hertz line-contact pressure of the
    heaviest slice, p = sqrt(q E* / (π w R')), recomputed here from the recorded slice load."""
    scene = make_scene({**BASE, "operating.radial_load_N": 120_000.0})
    ds, msgs = run(solve_static, scene)
    assert checks(ds) == ["contact_pressure"], findings(ds)
    f = findings(ds)[0]
    assert f["limit"] == PRESSURE_LIMIT_PA and f["value"] > PRESSURE_LIMIT_PA
    q = float(ds.contact_force.sel(race="inner").max())
    b, m = scene.bearing, scene.materials
    r, Rm = 0.5 * b.roller_diameter_m, 0.5 * b.pitch_diameter_m
    eta = 2 * (1 - m.poisson_ratio**2) / m.youngs_modulus_Pa
    w = b.roller_length_m / scene.numerics.slices
    p_inner = math.sqrt(q / (eta * math.pi * w / (1 / r + 1 / (Rm - r))))
    assert f["value"] == pytest.approx(p_inner, rel=1e-9)
    assert any("4 GPa" in m and "GPa" in m for m in msgs)


def test_edge_loading_end_slice_peak():
    """10 N·m on yang20 with 10 slices: the end slices sit at L_s/2 where the crown does not
    act (theory.md §3), and the end slice carries over twice the mean slice load."""
    ds, msgs = run(solve_static, make_scene({**BASE, "operating.moment_Nm": 10.0}))
    assert checks(ds) == ["edge_loading"], findings(ds)
    f = findings(ds)[0]
    q = ds.contact_force.sel(race="inner")
    ref = float(q.sum("slice").max()) / ds.sizes["slice"]
    end = float(q.isel(slice=[0, -1]).max())
    assert f["value"] == pytest.approx(end / ref, rel=1e-9) and f["value"] > EDGE_PEAK_RATIO
    assert "end slice carries" in msgs[0]


def test_paper_baseline_end_slices_are_not_flagged():
    """The paper's 3 N·m baseline peaks on the end slice too (Fig 12), but at 1.6 times the mean
    slice load: below the limit of 2 (a load falling linearly to zero at the far end)."""
    ds, msgs = run(solve_static, make_scene({**BASE, "operating.moment_Nm": 3.0}))
    assert msgs == []
    q = ds.contact_force.sel(race="inner")
    ratio = float(q.isel(slice=[0, -1]).max()) / (float(q.sum("slice").max()) / 10)
    assert 1.3 < ratio < EDGE_PEAK_RATIO


def test_edge_loading_contact_reaches_the_roller_end():
    """A flat roller under load touches along its whole length, so the contact reaches the end
    faces (the classic edge stress that crowning exists to remove); the same bearing with its
    end crown does not warn."""
    ds, msgs = run(solve_static, make_scene({**BASE, "bearing.profile": "flat",
                                             "operating.moment_Nm": 0.0}))
    assert checks(ds) == ["edge_loading"] and "reaches the roller end" in msgs[0]
    assert findings(ds)[0]["value"] > 0.0
    ds, msgs = run(solve_static, make_scene({**BASE, "operating.moment_Nm": 0.0}))
    assert msgs == []


def test_skew_beyond_the_pocket():
    """Zero pocket clearance with 1e3 N/m pockets: the skew moment of the 3 N·m moment load
    turns the roller until its ends pass the (soft) bars by tens of µm."""
    scene = make_scene({**BASE, **SHORT, "operating.moment_Nm": 3.0,
                        "cage.pocket_clearance_mm": 0.0, "cage.pocket_stiffness_N_m": 1e3})
    ds, msgs = run(simulate, scene)
    assert "skew_vs_pocket" in checks(ds), findings(ds)
    f = next(f for f in findings(ds) if f["check"] == "skew_vs_pocket")
    # independent of the guard's bookkeeping: the recorded skew times L/2
    excursion = float(np.abs(ds.skew_angle).max()) * 0.5 * scene.bearing.roller_length_m
    assert f["value"] == pytest.approx(excursion, rel=1e-12) and f["value"] > f["limit"]
    assert any("skew" in m for m in msgs)


def test_cage_slip_above_50_percent():
    """A start-up from rest to 10 000 r/min in 2 ms under 20 N with a heavy cage: the cage is
    still almost at rest when recording starts. Reference: the mean of the recorded cage speed
    against the epicyclic speed in the Dataset."""
    scene = make_scene({**BASE, **SHORT, "operating.moment_Nm": 0.0,
                        "operating.radial_load_N": 20.0,
                        "operating.speed_rpm": {"times_s": [0.0, 0.002],
                                                "values_rpm": [0.0, 10_000.0]},
                        "cage.density_kg_m3": 30_000.0})
    ds, msgs = run(simulate, scene)
    assert "cage_slip" in checks(ds), findings(ds)
    f = next(f for f in findings(ds) if f["check"] == "cage_slip")
    epi = ds["epicyclic_cage_speed_rad_s"].item()
    assert f["value"] == pytest.approx(1 - float(ds.cage_speed.mean()) / epi, rel=1e-12)
    assert f["value"] > CAGE_SLIP_LIMIT
    assert any("cage slip" in m for m in msgs)


def test_dynamic_scene_inside_the_range_warns_about_nothing(tmp_path):
    """The cheap dynamic scene used elsewhere (no moment, 800 N, 2000 r/min): cage slip well
    under 1 %, skew zero, no warning; the record survives the NetCDF round trip."""
    ds, msgs = run(simulate, make_scene({**BASE, **SHORT, "operating.moment_Nm": 0.0}))
    assert msgs == [] and findings(ds) == []
    assert set(json.loads(ds.attrs["plausibility_checks"])) == {
        "scene_units", "contact_pressure", "edge_loading", "skew_vs_pocket", "cage_slip",
        "film_parameter"}
    import xarray as xr

    path = save(ds, tmp_path / "d.nc")
    with xr.open_dataset(path) as back:
        assert findings(back) == [] and "plausibility_checks" in back.attrs


@pytest.mark.parametrize("override, key", [
    ({"bearing.radial_clearance_mm": 1e-5}, "bearing.radial_clearance_mm"),
    ({"cage.pocket_clearance_mm": 1e-4}, "cage.pocket_clearance_mm"),
    ({"lubricant.viscosity_Pa_s": 10.0}, "lubricant.viscosity_Pa_s"),
])
def test_unit_slips_where_tiny_values_are_legitimate_warn(override, key):
    ds, msgs = run(solve_static, make_scene({**BASE, **override, "operating.moment_Nm": 0.0}))
    assert checks(ds) == ["scene_units"] and f"'{key}'" in msgs[0] and " write " in msgs[0]


def test_cli_prints_warnings_as_one_paragraph_each(tmp_path, capsys):
    out = tmp_path / "s.nc"
    rc = main(["static", "yang20_baseline", "-o", str(out), "--set",
               "operating.radial_load_N=120000", "--set", "bearing.profile=flat", "--set",
               "materials.roughness_um=0.05"])
    err = capsys.readouterr().err
    assert rc == 0 and out.exists()
    lines = err.strip().splitlines()
    assert len(lines) == 2 and all(line.startswith("bearingdae: warning: ") for line in lines)
    assert any("GPa" in line for line in lines) and any("edge" in line for line in lines)


def test_film_parameter_below_one_on_the_paper_baseline():
    """The paper's baseline (800 N, 3 N·m, 2000 r/min, 10 mPa s oil) with the default composite
    roughness 0.11 µm: λ_min ≈ 0.98 on the heaviest end slice. The recorded value is the
    smallest λ of the Dataset, recomputed here from its minimum film and the roughness."""
    ds, msgs = run(solve_static, make_scene({**BASE, "operating.moment_Nm": 3.0,
                                             "materials.roughness_um": 0.11}))
    assert checks(ds) == ["film_parameter"], findings(ds)
    f = findings(ds)[0]
    assert f["value"] == pytest.approx(float(ds.film_thickness_min.min()) / 0.11e-6, rel=1e-12)
    assert f["value"] < 1.0 and "boundary lubrication" in msgs[0] and "slice 10" in msgs[0]
    # a smoother surface (or thicker oil) clears it
    ds, msgs = run(solve_static, make_scene({**BASE, "operating.moment_Nm": 3.0}))
    assert msgs == []


def test_film_finding_is_one_python_warning_without_a_path_and_one_summary_line(tmp_path,
                                                                                 capsys):
    """Programmatic use: one FilmParameterWarning per run, whose origin is the package (no path
    of the machine that ran it, no source line). The command line states λ_min, where it is and
    what λ < 1 means in the summary's film line instead, and prints no warning."""
    from bearingdae.analysis.guards import FilmParameterWarning

    scene = make_scene({**BASE, "operating.moment_Nm": 3.0, "materials.roughness_um": 0.11})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")  # Python's own default: once per place
        solve_static(scene)
        solve_static(scene)  # a second run warns again: once per run, not once per process
    film = [w for w in caught if issubclass(w.category, FilmParameterWarning)]
    assert len(film) == 2 and all(w.filename == "bearingdae" for w in film)
    assert "/" not in warnings.formatwarning(film[0].message, film[0].category,
                                             film[0].filename, film[0].lineno).split(":")[0]
    out = tmp_path / "s.nc"
    rc = main(["static", "yang20_baseline", "-o", str(out)])
    std = capsys.readouterr()
    assert rc == 0 and "warning" not in std.err
    line = next(x for x in std.out.splitlines() if "minimum film" in x)
    lam = float(line.split("λ = ")[1].split()[0])
    assert lam < 1.0 and "at roller" in line and "slice 10" in line
    assert "full film" in line
    assert 'physics.lubrication = "mixed"' in line  # the setting that models it


def test_film_line_says_the_mixed_model_is_in_use(tmp_path, capsys):
    """With ``physics.lubrication = "mixed"`` (theory.md §20) the summary's λ < 1 line says that
    the mixed-lubrication model is in use instead of that the EHL law assumes a full film."""
    out = tmp_path / "s.nc"
    rc = main(["static", "yang20_baseline", "-o", str(out), "--set",
               "physics.lubrication=mixed"])
    std = capsys.readouterr()
    assert rc == 0 and "warning" not in std.err
    line = next(x for x in std.out.splitlines() if "minimum film" in x)
    assert float(line.split("λ = ")[1].split()[0]) < 1.0
    assert "mixed-lubrication model is in use" in line and "full film" not in line


def _timed_dataset():
    import xarray as xr

    return xr.Dataset(coords={"time": ("time", np.linspace(0.0, 1e-3, 5))})


def test_defect_crossing_samples_against_the_rolling_speed_typed_here():
    """A contact runs over every surface at ω_c R_o (pure rolling): a defect of length l is
    crossed in N l / (2π R_o) samples, R_o = (D_pw + D_w)/2 (the roller spall: 1 mm)."""
    from bearingdae.analysis.guards import defect_crossing_samples

    for n in (500, 2000):
        scene = make_scene({"numerics.samples_per_cage_revolution": n, "defects": [
            {"on": "roller", "roller": 0, "angle_deg": 90.0, "length_mm": 1.0,
             "width_mm": 8.0, "depth_um": 20.0}]})
        b = scene.bearing
        r_o = 0.5 * (b.pitch_diameter_m + b.roller_diameter_m)
        want = n * 1e-3 / (2.0 * math.pi * r_o)
        assert defect_crossing_samples(scene) == [pytest.approx(want, rel=1e-3)]


@pytest.mark.parametrize("n", [200, 500, 1000])
def test_an_undersampled_defect_is_one_finding_naming_the_rate_that_resolves_it(n):
    from bearingdae.analysis.guards import (DEFECT_CROSSING_SAMPLES, defect_crossing_samples,
                                            defect_sampling)

    over = {"numerics.samples_per_cage_revolution": n, "defects": [
        {"on": "outer", "angle_deg": 0.0, "length_mm": 2.0, "width_mm": 8.0, "depth_um": 10.0},
        {"on": "outer", "angle_deg": 90.0, "length_mm": 0.5, "width_mm": 8.0,
         "depth_um": 10.0}]}
    scene = make_scene(over)
    per = defect_crossing_samples(scene)
    (f,) = defect_sampling(_timed_dataset(), scene)
    assert f.value == min(per) == per[1] < DEFECT_CROSSING_SAMPLES
    assert "\n" not in f.message and f.message.startswith("defect 2 (0.5 mm long)")
    need = int(f.message.split("numerics.samples_per_cage_revolution = ")[1].split()[0])
    assert need % 50 == 0
    assert defect_sampling(_timed_dataset(), make_scene(
        {**over, "numerics.samples_per_cage_revolution": need})) == []
    assert defect_sampling(_timed_dataset(), make_scene(
        {**over, "numerics.samples_per_cage_revolution": need - 50}))  # the least such
    # a static solve (no samples) and a scene without defects: not judged
    assert defect_sampling(_timed_dataset().isel(time=[]), scene) is None
    assert defect_sampling(_timed_dataset(), make_scene({})) is None


def test_the_bundled_defect_cases_resolve_their_defects():
    from bearingdae import load_scene
    from bearingdae.analysis.guards import defect_sampling

    for case in ("defects/roller_spall", "defects/outer_spall", "defects/inner_spall"):
        assert defect_sampling(_timed_dataset(), load_scene(case)) == [], case


@pytest.mark.slow
def test_a_run_of_an_undersampled_defect_prints_one_line_with_the_setting(tmp_path):
    from fuzzing import run_cli

    rc, stdout, stderr = run_cli([
        "run", "defects/roller_spall", "--no-plot", "-o", str(tmp_path / "r.nc"),
        "--set", "numerics.cage_revolutions=0.02", "--set",
        "numerics.warmup_cage_revolutions=0", "--set",
        "numerics.samples_per_cage_revolution=500"])
    assert rc == 0, stderr
    lines = [ln for ln in (stdout + stderr).splitlines() if "is crossed in" in ln]
    assert len(lines) == 1 and lines[0].startswith("bearingdae: warning: defect 1 (1 mm long)")
    assert "numerics.samples_per_cage_revolution = " in lines[0]
