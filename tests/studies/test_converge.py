"""The convergence study (studies/converge.py, analysis/headline.py, ``bearingdae converge``):
the verdict on hand-made numbers, the error bars of the engineering outputs against
independent references, and the command end to end on a tiny window."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from bearingdae import load_scene
from bearingdae.analysis.rating_life import slice_life
from bearingdae.analysis.headline import headline_statistics, life_estimate, per_pass_minimum
from bearingdae.physics.geometry import make_geometry
from bearingdae.studies import converge as cv
from fuzzing import run_cli


def _table(base, refined, refinement="slices", floor=0.0, lower_bound=False):
    """A study of one output from (value, stderr) pairs: base and one refined setting."""
    scene = load_scene("yang20_baseline")
    plan = cv.settings(scene, refine=(refinement,))
    value = np.array([[base[0]], [refined[0]]], float)
    stderr = np.array([[base[1]], [refined[1]]], float)
    corr = np.array([[lower_bound], [False]])
    nan = np.full(2, np.nan)
    return cv.table(scene, plan, ["L10r"], value, stderr, corr, np.array([floor]), nan, nan,
                    ["ok", "ok"])


def test_verdict_compares_the_change_with_twice_the_combined_error():
    # base 100 ± 3, refined ± 4: the combined error is 5 (3-4-5), the threshold 10
    ds = _table((100.0, 3.0), (109.0, 4.0))
    assert ds.delta_stderr.sel(setting="slices").item() == pytest.approx(5.0)
    assert ds.delta.sel(setting="slices").item() == pytest.approx(9.0)
    assert ds.verdict.sel(setting="slices").item() == "converged"
    ds = _table((100.0, 3.0), (89.0, 4.0))  # |Δ| = 11 > 10
    assert ds.verdict.sel(setting="slices").item() == "not converged: raise numerics.slices"
    ds = _table((100.0, 3.0), (111.0, 4.0), refinement="rtol")
    assert ds.verdict.sel(setting="rtol").item() == "not converged: lower numerics.rtol"
    ds = _table((100.0, 3.0), (111.0, 4.0), refinement="samples", lower_bound=True)
    assert ds.verdict.sel(setting="samples").item() == (
        "not converged: raise numerics.samples_per_cage_revolution (error bar a lower bound: "
        "record longer)")
    assert ds.verdict.sel(setting="base").item() == "base"
    assert ds.delta.sel(setting="base").item() == 0.0


def test_a_significant_change_below_the_practical_tolerance_is_converged():
    """The baseline's case: a relative change of 1.3e-5, ten error bars wide, is converged at
    the default practical tolerance (1e-3 of the base value) and flagged without one."""
    ds = _table((100.0, 1e-4), (100.0013, 1e-4))
    assert abs(ds.delta.sel(setting="slices").item()) > 2 * ds.delta_stderr.sel(
        setting="slices").item()
    assert ds.verdict.sel(setting="slices").item() == "converged"
    assert ds.practical_tolerance.item() == pytest.approx(cv.PRACTICAL_REL_TOL * 100.0)
    scene = load_scene("yang20_baseline")
    plan = cv.settings(scene, refine=("slices",))
    strict = cv.table(scene, plan, ["L10r"], np.array([[100.0], [100.0013]]),
                      np.array([[1e-4], [1e-4]]), np.zeros((2, 1), bool), np.zeros(1),
                      np.full(2, np.nan), np.full(2, np.nan), ["ok", "ok"], tolerance=0.0)
    assert strict.verdict.sel(setting="slices").item().startswith("not converged")
    ds = _table((100.0, 1e-4), (100.2, 1e-4))  # 0.2 %: above the tolerance, significant
    assert ds.verdict.sel(setting="slices").item().startswith("not converged")


def test_the_base_runs_warnings_are_kept_as_text_not_printed_raw(recwarn):
    from bearingdae.analysis.guards import PlausibilityWarning

    said = []
    with cv._plausibility_quiet(False, said):
        import warnings

        warnings.warn("film: λ = 0.4 < 1 at the inner race\n  (mixed lubrication)",
                      PlausibilityWarning)
    assert said == ["film: λ = 0.4 < 1 at the inner race (mixed lubrication)"]
    assert not [w for w in recwarn if issubclass(w.category, PlausibilityWarning)]


def test_verdict_without_an_error_bar_is_undetermined_unless_below_the_floor():
    ds = _table((100.0, np.nan), (100.5, np.nan))
    assert ds.verdict.sel(setting="slices").item().startswith("undetermined")
    # a statistic zero to integration noise: the change is below what the base run resolves
    ds = _table((1e-14, 0.0), (3e-14, 0.0), floor=1e-11)
    assert ds.verdict.sel(setting="slices").item() == "converged"
    ds = _table((1e-14, 0.0), (3e-11, 0.0), floor=1e-11)
    assert ds.verdict.sel(setting="slices").item().startswith("not converged")


def test_settings_refine_one_at_a_time_and_refuse_bad_factors():
    scene = load_scene("yang20_baseline")
    plan = cv.settings(scene, {"slices": 3, "rtol": 100, "samples": 1.5})
    assert [s.name for s in plan] == ["base", "slices", "rtol", "samples"]
    assert plan[1].overrides == {"numerics.slices": 30}
    assert plan[2].overrides == {"numerics.rtol": pytest.approx(1e-8),
                                 "numerics.atol": pytest.approx(1e-10)}
    assert plan[3].overrides == {"numerics.samples_per_cage_revolution": 300}
    for factors, refine, match in [({"rtol": 0.5}, ("rtol",), "must be > 1"),
                                   ({"slices": 1.01}, ("slices",), "rounds to 10"),
                                   ({}, ("slice",), "allowed are slices, rtol, samples"),
                                   ({}, (), "none given")]:
        with pytest.raises(ValueError, match=match):
            cv.settings(scene, factors, refine)


def test_life_error_bar_matches_the_scatter_of_independent_records():
    """The delta-method error of L10r against the standard deviation of L10r over many
    independent records of uncorrelated slice loads (L computed directly by the standard's
    power means on the slices, rating_life.slice_life)."""
    scene = load_scene("yang20_baseline")
    g = make_geometry(scene)
    rng = np.random.default_rng(1)
    shape = (200, g.rollers, g.slices, 2)

    def record():
        q = 40.0 * (1.0 + 0.5 * rng.standard_normal(shape)).clip(0.0)
        return xr.Dataset({"contact_force": (("time", "roller", "slice", "race"), q)},
                          coords={"time": np.arange(shape[0]) * 1e-4})

    direct = []
    for _ in range(300):
        ds = record()
        direct.append(slice_life(scene, g, ds.contact_force.values, axes=(0, 1)))
    one = record()
    est = life_estimate(one, scene)
    assert est.mean == pytest.approx(slice_life(scene, g, one.contact_force.values,
                                                axes=(0, 1)), rel=1e-12)
    # one record's error bar scatters by ~18 % (blocking on 200 samples): the mean of 20, by
    # ~4 %, as does the scatter of the 300 direct lives
    errors = [est.stderr] + [life_estimate(record(), scene).stderr for _ in range(19)]
    assert np.mean(errors) == pytest.approx(np.std(direct, ddof=1), rel=0.15)


def test_per_pass_minimum_and_ring_rms_on_known_series():
    blocks = np.repeat(np.arange(12), 5)  # 12 roller passes of 5 samples
    x = np.full((60, 3), 99.0)
    x[np.arange(12) * 5 + 2, 1] = np.arange(12) + 1.0  # the smallest of pass k: k + 1
    x[7, 0] = np.nan  # an unloaded slice has no film
    est = per_pass_minimum(xr.DataArray(x, dims=("time", "slice")), blocks)
    assert est.mean == pytest.approx(6.5)  # mean of 1 .. 12
    # a circular ring vibration of amplitude A: |a| = A at every sample, so the RMS is A
    t = np.linspace(0.0, 0.1, 400)
    a = 3.0 * np.stack([np.cos(900 * t), np.sin(900 * t)], axis=-1)
    ds = xr.Dataset({"ring_acceleration": (("time", "direction"), a)}, coords={"time": t})
    out = headline_statistics(ds, load_scene("yang20_baseline"))
    assert list(out) == ["ring_vibration_rms"]
    assert out["ring_vibration_rms"].mean == pytest.approx(3.0)
    assert "ring_vibration_rms" not in headline_statistics(ds.drop_vars("ring_acceleration"),
                                                           load_scene("yang20_baseline"))


def test_command_on_a_tiny_window(tmp_path):
    nc, md = tmp_path / "c.nc", tmp_path / "c.md"
    rc, out, err = run_cli(["converge", "--set", "numerics.cage_revolutions=0.05", "--set",
                            "numerics.warmup_cage_revolutions=0", "--no-progress", "-o",
                            str(nc), "--table", str(md)])
    assert rc == 0, err
    ds = xr.open_dataset(nc)
    outputs = ["cage_slip", "peak_pocket_force_per_pass", "max_skew_per_pass", "L10r",
               "min_film_per_pass", "min_lambda_per_pass", "power_loss"]  # no dynamic ring
    assert list(ds.setting.values) == ["base", "slices", "rtol", "samples"]
    assert list(ds.output.values) == outputs
    for v in ("value", "stderr", "delta", "verdict"):
        assert ds[v].dims == ("setting", "output")
    assert ds.run_time_s.attrs["units"] == "s" and "CPU" in ds.run_time_s.attrs["long_name"]
    assert ds.output_units.sel(output="L10r").item() == "Mrev"
    assert "output_units" in ds.value.attrs["comment"]  # CF: no units per element
    assert ds.output_units.sel(output="power_loss").item() == "W"
    assert (ds.run_time_s > 0).all() and np.isfinite(ds.value).all()
    assert (ds.delta.sel(setting="base") == 0).all()
    assert ds.steps.sel(setting="rtol") > ds.steps.sel(setting="base")
    assert ds.attrs["slices"] == 10
    table = md.read_text(encoding="utf-8")
    rows = [line for line in table.splitlines() if line.startswith("| ")]
    assert len(rows) == 1 + len(outputs) + 2  # header, the outputs, wall and CPU times
    assert rows[-2].startswith("| run time [s wall]")
    assert rows[-1].startswith("| run time [s CPU]") and rows[0].count("|") == 6
    assert ds.attrs["kernels_wall_s"] > 0 and ds.attrs["study_wall_s"] >= ds.wall_time_s.sum()
    assert "kernels loaded or compiled before the runs" in out
    assert "converged" in out and (tmp_path / "c.png").stat().st_size > 0
    assert (tmp_path / "c.csv").exists()


@pytest.mark.parametrize("option, message", [
    (["--rtol-factor", "0.5"], "rtol factor 0.5: must be > 1"),
    (["--slices-factor", "1.01"], "slices factor 1.01"),
    (["--refine", "slices,bogus"], "refinement 'bogus'"),
    (["--samples-factor", "nan"], "samples factor nan"),
    (["--quick", "--set", "numerics.slices=1000"], "numerics.slices"),  # refined out of range
])
def test_bad_options_give_one_line_and_status_2(tmp_path, option, message):
    rc, out, err = run_cli(["converge", "-o", str(tmp_path / "x.nc"), *option])
    assert rc == 2
    assert err.startswith("bearingdae: error:") and message in err
    assert err.strip().count("\n") == 0
    assert not list(tmp_path.iterdir())  # nothing computed, nothing written


def test_ctrl_c_in_a_run_stops_the_study_with_status_130(tmp_path, monkeypatch):
    """The solver turns Ctrl-C into a failed run (solvers/base.py); the study must not go on
    to the next setting."""
    from bearingdae.api import SimulationError

    calls = []

    def interrupted(scene, **kwargs):
        calls.append(scene)
        raise SimulationError("interrupted by the user at t = 0.001 s", None)

    monkeypatch.setattr("bearingdae.api.simulate", interrupted)
    rc, out, err = run_cli(["converge", "--no-progress", "-o", str(tmp_path / "x.nc")])
    assert rc == 130 and "interrupted" in err
    assert len(calls) == 1  # the kernels' warm-up run: nothing after it
    assert not (tmp_path / "x.nc").exists()
