"""Every run file is read back by every reader, whatever switches wrote it.

A reader that keeps its own list of the dimensions a run may have refused every thermal run as
damaged ("unexpected dimension(s) thermal_node"): the readers now take a labelled dimension as
the file's own (results/readers.file_dimensions). The fast tests pin that rule; the slow one
writes a short run for each switch combination below through the command line (the writer
users meet) and reads it back with open_result, the figures, the spectrum and the summary. The
commands run in the test's process (tests/fuzzing.run_cli, as the command-line tests do): a
process of their own would load the compiled kernels and the plotting libraries anew for each
of the 39 commands; the program as a process is tests/cli's subject.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from bearingdae.results.readers import ResultFileError, file_dimensions, open_result
from fuzzing import run_cli

CASES = Path(__file__).resolve().parents[2] / "cases"
SHORT = ["numerics.cage_revolutions=0.05", "numerics.warmup_cage_revolutions=0.05"]
LAND = ["physics.cage_whirl=true", 'cage.guidance="outer-land"', "cage.land_clearance_mm=0.09"]
#: switch combinations (overrides of the baseline; "NJ": the flanged bearing of its own case)
COMBINATIONS = {
    "default": [],
    "no cage": ["physics.cage=false"],
    "no skew": ["physics.skew=false"],
    "no tilt": ["physics.tilt=false", "operating.moment_Nm=0"],  # a moment needs tilt
    "dynamic ring": ["physics.ring=dynamic"],
    "cage whirl": LAND,
    "mixed": ["physics.lubrication=mixed"],
    "rolling resistance": ["physics.rolling_resistance=true"],
    "thermal": ["physics.thermal=steady"],
    "thermal + rolling + mixed": ["physics.thermal=steady", "physics.rolling_resistance=true",
                                  "physics.lubrication=mixed"],
    "all on": ["physics.thermal=steady", "physics.rolling_resistance=true",
               "physics.lubrication=mixed", "physics.ring=dynamic", *LAND],
    "NJ flanges": ["NJ"],
    "NJ flanges thermal": ["NJ", "physics.thermal=steady"],
}


def _run_file(tmp_path) -> xr.Dataset:
    t = np.array([0.0, 1e-3, 2e-3])
    return xr.Dataset(
        {"cage_speed": ("time", np.ones(3)), "temperature": ("thermal_node", np.ones(2)),
         "slice_position_bounds": (("slice", "bounds"), np.zeros((2, 2)))},
        coords={"time": t, "slice": [1, 2], "thermal_node": ["oil", "cage"]},
        attrs={"Conventions": "CF-1.10", "bearingdae_version": "0"})


def test_a_labelled_dimension_is_the_files_own(tmp_path):
    """A dimension with a coordinate of its name (numbers or labels) is read; one without
    (other than the CF bounds) is still refused in one line."""
    ds = _run_file(tmp_path)
    assert file_dimensions(ds) >= {"time", "bounds", "slice", "thermal_node"}
    path = tmp_path / "run.nc"
    ds.to_netcdf(path)
    kind, back = open_result(path, ("run",))
    assert kind == "run" and back.temperature.dims == ("thermal_node",)
    bad = ds.assign(stray=(("time", "mystery"), np.zeros((3, 2))))
    bad.to_netcdf(tmp_path / "bad.nc")
    with pytest.raises(ResultFileError, match="unexpected dimension.*mystery"):
        open_result(tmp_path / "bad.nc", ("run",))


@pytest.mark.slow
@pytest.mark.parametrize("name", list(COMBINATIONS))
def test_every_switch_combination_reads_back_with_every_reader(tmp_path, name):
    sets = [s for s in COMBINATIONS[name] if s != "NJ"] + SHORT
    case = CASES / ("yang20_nj_axial.toml" if "NJ" in COMBINATIONS[name]
                    else "yang20_baseline.toml")
    out = tmp_path / "run.nc"
    args = ["run", str(case), "--no-plot", "-o", str(out)]
    for s in sets:
        args += ["--set", s]
    status, _, err = run_cli(args)
    assert status == 0 and out.exists(), err[-2000:]
    kind, ds = open_result(out, ("run",))  # the reader every command uses
    assert kind == "run"
    if "physics.thermal=steady" in sets:
        assert ds.temperature.dims == ("thermal_node",)
    from bearingdae.analysis.engineering import summary_lines

    assert summary_lines(ds)
    for extra in ([], ["--spectrum"]):  # every figure, then the spectrum
        status, _, text = run_cli(["plot", str(out), "-o", str(tmp_path / f"f{len(extra)}.png"),
                                   *extra])
        assert "Traceback" not in text and "damaged" not in text, text[-2000:]
        # 0: drawn; 1: nothing drawn (a 0.05-revolution record completes no orbit); 2: the
        # spectrum of a run without a dynamic ring is refused in one line
        assert status in (0, 1, 2)
        if status == 2:
            assert len(text.strip().splitlines()) == 1 and extra, text
