"""What an xarray user reads in a result without the docs: slice positions with CF bounds, the
rollers' start azimuth, the operating point in every file, no units on index numbers and
labels, the complete scene as TOML, and where time counts from."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
import xarray as xr

from bearingdae import load_scene, save, simulate, solve_static
from bearingdae.scene import SceneInput, scene_from_dict

SHORT = {"numerics.warmup_cage_revolutions": 0.1, "numerics.cage_revolutions": 0.05,
         "numerics.samples_per_cage_revolution": 100}
OPERATING = ("radial_load_N", "tangential_load_N", "moment_Nm", "tangential_moment_Nm",
             "speed_rpm")


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """A short dynamic run of the baseline, in memory and read back from its file."""
    scene = load_scene("yang20_baseline", SHORT)
    ds = simulate(scene, progress=False)
    path = save(ds, tmp_path_factory.mktemp("meta") / "run.nc")
    with xr.open_dataset(path) as back:
        return scene, ds, back.load()


@pytest.fixture(scope="module")
def static():
    scene = load_scene("yang20_baseline")
    return scene, solve_static(scene)


def test_slice_position_has_cf_bounds_that_tile_the_roller(run, static):
    """Slice k of n along the roller of length L: centre -L/2 + (k - 1/2) L/n, bounds its
    edges; the bounds tile [-L/2, L/2] without gap, in the file as in memory."""
    scene = run[0]
    L, n = scene.bearing.roller_length_m, scene.numerics.slices
    for ds in (run[1], run[2], static[1]):
        pos = ds.slice_position
        assert pos.dims == ("slice",) and pos.attrs["units"] == "m"
        assert pos.attrs["bounds"] == "slice_position_bounds"
        b = ds[pos.attrs["bounds"]]
        assert b.dims == ("slice", "bounds") and "slice_position_bounds" in ds.coords
        np.testing.assert_allclose(pos, -L / 2 + (np.arange(n) + 0.5) * L / n, rtol=0,
                                   atol=1e-15)
        np.testing.assert_allclose(b.mean("bounds"), pos, rtol=0, atol=1e-15)
        assert b[0, 0] == pytest.approx(-L / 2) and b[-1, 1] == pytest.approx(L / 2)
        np.testing.assert_allclose(b[1:, 0], b[:-1, 1], rtol=0, atol=1e-15)  # no gaps
    xr.testing.assert_identical(run[2].slice_position_bounds, run[1].slice_position_bounds)


def test_index_and_label_coordinates_carry_no_units(run, static):
    for ds in (run[1], run[2], static[1]):
        for name in ("roller", "slice", "race", "end", "direction"):
            if name in ds.coords:
                assert "units" not in ds[name].attrs, name
                assert ds[name].attrs["long_name"], name


def test_xarray_plot_labels_read_names_and_units(run):
    """`ds.contact_force.isel(time=-1, race=0).plot()` on the file: its axes and colour bar
    say what they show, with units where there are any (no "[1]", no "[]")."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ds = run[2]
    ds.contact_force.isel(time=-1, race=0).plot()
    fig = plt.gcf()
    ax, cax = fig.axes
    labels = [ax.get_xlabel(), ax.get_ylabel(), cax.get_ylabel()]
    plt.close(fig)
    assert labels == ["slice number, end b to end a", "roller number",
                      "slice contact force [N]"]
    ds.slice_position.plot()
    ax = plt.gca()
    assert ax.get_ylabel().endswith("[m]") and "[" not in ax.get_xlabel()
    plt.close(plt.gcf())


def test_start_azimuth_is_each_rollers_azimuth_at_the_first_sample(run):
    ds = run[1]
    az = ds.start_azimuth
    assert az.dims == ("roller",) and az.attrs["units"] == "rad"
    np.testing.assert_allclose(az, np.mod(ds.roller_azimuth.isel(time=0), 2 * np.pi),
                               rtol=0, atol=1e-15)
    assert ((az >= 0) & (az < 2 * np.pi)).all()
    xr.testing.assert_identical(run[2].start_azimuth, az)


def test_time_says_where_it_counts_from(run):
    """t = 0 is the start of the integration; the record starts after the warm-up, at the
    global attribute record_start_s, which is the first sample."""
    ds = run[1]
    assert ds.time.attrs["long_name"] == "time since the start of the simulation"
    assert "record_start_s" in ds.time.attrs["comment"]
    assert "warm-up" in ds.time.attrs["comment"]
    assert ds.time.values[0] == pytest.approx(ds["record_start_s"].item(), abs=1e-15)
    assert ds["record_start_s"].item() > 0  # 0.1 cage revolution of warm-up


def test_every_result_file_states_its_operating_point(run, static):
    scene = run[0]
    o = scene.operating
    expected = {"radial_load_N": o.radial_load_N, "tangential_load_N": o.tangential_load_N,
                "moment_Nm": o.moment_Nm, "tangential_moment_Nm": o.tangential_moment_Nm,
                "speed_rpm": 2000.0}
    for ds in (run[1], run[2], static[1]):
        assert {k: ds[k].item() for k in OPERATING} == expected
        assert all(ds[k].attrs["units"] for k in OPERATING)


def test_operating_point_of_a_speed_ramp_is_the_recorded_speed():
    """A ramp 1800 -> 2000 r/min over 2 ms: the record (after it) runs at 2000 r/min; the
    ramp itself is stated too."""
    scene = load_scene("yang20_baseline", {
        **SHORT, "numerics.cage_revolutions": 0.02,
        "operating.speed_rpm": {"times_s": [0.0, 0.002], "values_rpm": [1800.0, 2000.0]}})
    ds = simulate(scene, progress=False)
    assert ds["speed_rpm"].item() == 2000.0
    assert '"values_rpm": [1800.0, 2000.0]' in ds.attrs["speed_ramp"]
    assert solve_static(scene)["speed_rpm"].item() == 1800.0  # the static solve is at t = 0


def test_scene_toml_is_complete(run, static):
    """The scene TOML of a result states every key: values a preset or a default decided
    (the pocket clearance, the pitch diameter, Newmark β and γ, the precision, the title) as
    well; read back, it gives the same scene. Only two keys may be absent: the logarithmic
    profile's design load (unused by this profile), output.variables (absent = all) and
    operating.load_file (absent = no load file)."""
    for scene, ds in ((run[0], run[1]), static):
        data = tomllib.loads(ds.attrs["scene_toml"])
        assert data["cage"]["pocket_clearance_mm"] == 0.10  # yang20's, from the preset
        missing = [f"{table}.{key}" for table, field in SceneInput.model_fields.items()
                   if hasattr(field.annotation, "model_fields")
                   for key in field.annotation.model_fields if key not in data.get(table, {})]
        # and the catalogue rating C: without it the result computes C from the geometry and
        # records it (attribute basic_dynamic_load_rating_N, analysis/engineering.py)
        # (and operating.load_file: absent = no load file; the ring's mass and tilt inertia:
        # absent = from the ring geometry, recorded as ring_mass_kg by a dynamic-ring run)
        # (and the flange keys: absent = the paper's flangeless bearing, no axial load)
        flange = ["bearing.flange_angle_deg", "bearing.flange_clearance_mm",
                  "bearing.flange_friction", "bearing.flange_height_mm",
                  "bearing.roller_corner_radius_mm", "bearing.roller_end",
                  "bearing.roller_end_radius_mm", "bearing.type", "operating.axial_load_N"]
        # (and the cage whirl keys: absent = the cage only rotates)
        whirl = ["physics.cage_whirl", "cage.mass_kg", "cage.guidance",
                 "cage.land_clearance_mm", "cage.land_width_mm", "cage.land_friction"]
        # (and the rolling resistance's keys: absent = off, its oil keys need it)
        rolling = ["physics.rolling_resistance", "lubricant.temperature_viscosity_K_inv",
                   "lubricant.thermal_conductivity_W_m_K", "lubricant.inlet_film_um"]
        # (and the mixed-lubrication keys: absent = full film, theory.md §20)
        mixed = ["physics.lubrication", "lubricant.boundary_friction"]
        # (and the thermal keys: absent = the fixed viscosity, physics.thermal = "off")
        # (and the oil's viscosity-temperature data: absent = lubricant.viscosity_Pa_s)
        thermal = ["physics.thermal", "lubricant.viscosity_40C_mm2_s",
                   "lubricant.viscosity_100C_mm2_s", "lubricant.operating_temperature_C",
                   *(f"thermal.{k}" for k in SceneInput.model_fields["thermal"]
                     .annotation.model_fields)]
        # (and the contamination factor: absent = no modified life; the friction model: the
        # switches it sets are written one by one)
        assert sorted(missing) == sorted(["physics.friction_model",
                                          "bearing.basic_dynamic_load_rating_N",
                                          "bearing.design_load_N", "operating.load_file",
                                          "lubricant.contamination_factor",
                                          "output.variables", "ring.mass_kg",
                                          "ring.tilt_inertia_kg_m2", *flange, *whirl, *rolling,
                                          *mixed, *thermal])
        assert scene_from_dict(data) == scene
        assert data["title"] == scene.title  # with the values set: "... [set: ...]"
    # the plain TOML (checkpoints, sweep run keys) keeps only the keys as given
    assert "pocket_clearance_mm" not in run[0].to_toml()


def test_logarithmic_profile_records_its_design_load():
    scene = scene_from_dict({"bearing": {"preset": "yang20", "profile": "logarithmic"},
                             "operating": {"radial_load_N": 1000.0}})
    data = tomllib.loads(scene.to_toml(complete=True))
    assert data["bearing"]["design_load_N"] == pytest.approx(4.08 * 1000.0 / 20)
    assert scene_from_dict(data) == scene
