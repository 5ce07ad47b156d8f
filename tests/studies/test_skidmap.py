"""The skid-map command on a tiny grid: the NetCDF and PNG it writes, and its bad input."""

from __future__ import annotations

import numpy as np
import pytest

# ---- skid maps -------------------------------------------------------------------------------
SHORT_MAP = ["--set", "numerics.slices=3", "--set", "numerics.samples_per_cage_revolution=24",
             "--set", "numerics.steady_block_cage_revolutions=0.5",
             "--set", "numerics.max_warmup_cage_revolutions=1", "--set",
             "numerics.cage_revolutions=0.125", "--scheduler", "synchronous", "--no-progress"]


def test_skidmap_cli_writes_a_valid_netcdf_and_png(tmp_path, capsys):
    """A 2 x 2 map with a 1-revolution cap (two blocks: too few for the criterion, so every
    point is marked not steady): the NetCDF has every map variable on (speed_rpm,
    radial_load_N) with units and long_name, and the PNG is a PNG."""
    import xarray as xr

    from bearingdae.cli import main
    from bearingdae.studies.skidmap import MAP_VARIABLES

    out = tmp_path / "map.nc"
    status = main(["skidmap", "yang20_baseline", "--speeds", "2000", "6000", "--loads", "400",
                   "1600", "-o", str(out)] + SHORT_MAP)
    assert status == 0, capsys.readouterr().err
    with xr.open_dataset(out) as ds:
        assert ds.cage_slip_ratio.dims == ("speed_rpm", "radial_load_N")
        assert ds.sizes == {"speed_rpm": 2, "radial_load_N": 2}
        for name in MAP_VARIABLES:
            a = ds[name].attrs  # units, or a 0/1 flag's CF flag_values and flag_meanings
            assert ("units" in a or "flag_meanings" in a) and a["long_name"], name
        assert np.all(np.isfinite(ds.cage_slip_ratio)) and np.all(ds.status == "completed")
        assert np.all(ds.steady_state_reached == 0)  # the cap is below 4 blocks
        assert np.all(ds.skew_rms_rad > 0) and np.all(ds.peak_pocket_force_N >= 0)
        assert ds.attrs["runs_not_steady"] == 4 and ds.attrs["skid_boundary_cage_slip"] == 0.01
    assert out.with_suffix(".png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    printed = capsys.readouterr().out
    assert "not steady" in printed
    # the sweep behind the map: said, and `bearingdae plot` draws its trends at one speed
    sweep_file = tmp_path / "map_sweep.nc"
    assert f"wrote {sweep_file}" in printed.splitlines()
    png = tmp_path / "trends_2000.png"
    assert main(["plot", str(sweep_file), "--select", "speed_rpm=2000", "--figure", "trends",
                 "-o", str(png)]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("args, expect", [
    (["--speeds", "2000", "--loads", "400", "800"], "--speeds: give at least 2"),
    (["--speeds", "2000", "6000", "--loads", "400", "800", "--boundary", "1.5"],
     "--boundary 1.5"),
    (["--speeds", "2000", "6000", "--loads", "400", "800", "--set",
      "numerics.steady_tolerance=2"], "numerics.steady_tolerance"),
])
def test_skidmap_bad_input_is_one_clear_error(tmp_path, capsys, args, expect):
    from bearingdae.cli import main

    status = main(["skidmap", "yang20_baseline", "-o", str(tmp_path / "m.nc")] + args
                  + ["--scheduler", "synchronous", "--no-progress"])
    err = capsys.readouterr().err
    assert status == 2 and expect in err and "Traceback" not in err, err
    assert not (tmp_path / "m.nc").exists()
