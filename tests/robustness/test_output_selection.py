"""Every selection of ``output.variables`` runs, summarises and writes its file.

The run summary, the engineering lines, the flange lines, the overview figure and the file's
end-of-run variables each read some variables of a block; a selection that keeps a derived
variable without its inputs (``power_loss_W`` without ``drive_power_W``, ``lambda_ratio``
without ``film_thickness_min``, an extreme without any per-roller series) must still run to
the end. Each output variable alone, in a scene that has its physics switch on, runs through
``bearingdae run`` (a window of 0.02 cage revolutions: a few samples) and its file holds it;
random selections do the same.
"""

from __future__ import annotations

import json

import pytest
import xarray as xr
from hypothesis import given
from hypothesis import strategies as st

from bearingdae.scene.schema import OUTPUT_VARIABLES
from fuzzing import fuzz, run_cli

TINY = ["--set", "numerics.warmup_cage_revolutions=0", "--set", "numerics.cage_revolutions=0.02",
        "--set", "numerics.samples_per_cage_revolution=100"]
#: a scene with each physics switch an output variable needs (scene/sections/output.OUTPUT_VARIABLES)
SCENES = {None: ["yang20_baseline"], "cage": ["yang20_baseline"], "skew": ["yang20_baseline"],
          "tilt": ["yang20_baseline"], "flange": ["yang20_nj_axial"],
          "ring": ["yang20_baseline", "--set", 'physics.ring="dynamic"'],
          "cage_whirl": ["yang20_baseline", "--set", "physics.cage_whirl=true",
                         "--set", "cage.guidance=outer-land"],
          "thermal": ["yang20_baseline", "--set", 'physics.thermal="steady"'],
          "roller_surface": ["defects/roller_spall"]}


def run_selection(tmp_path, case: list[str], names: list[str], plot: bool) -> xr.Dataset:
    out = tmp_path / "sel.nc"
    out.unlink(missing_ok=True)
    rc, stdout, stderr = run_cli(["run", *case, "-o", str(out), *TINY,
                                  *([] if plot else ["--no-plot"]),
                                  "--set", f"output.variables={json.dumps(names)}"])
    assert rc == 0 and "Traceback" not in stderr, (names, stderr)
    assert f"wrote {out}" in stdout
    assert (out.with_suffix(".png").is_file() if plot else True)
    return xr.load_dataset(out)


#: each thermal run alone takes a few seconds of coupled blocks: one in the fast tier, the
#: others in the slow tier (CI's physics step)
_FAST_THERMAL = "temperature"


@pytest.mark.parametrize("name", [
    pytest.param(n, marks=pytest.mark.slow)
    if OUTPUT_VARIABLES[n] == "thermal" and n != _FAST_THERMAL else n
    for n in sorted(OUTPUT_VARIABLES)])
def test_each_output_variable_alone_runs_and_is_written(tmp_path, name):
    ds = run_selection(tmp_path, SCENES[OUTPUT_VARIABLES[name]], [name], plot=True)
    assert name in ds.data_vars
    # nothing else of the selectable variables (their companions: an extreme's time)
    others = set(ds.data_vars) & set(OUTPUT_VARIABLES) - {name}
    assert not others, others


@fuzz(12)
@given(switch=st.sampled_from(sorted(SCENES, key=str)), data=st.data())
def test_random_selections_run_and_are_written(tmp_path_factory, switch, data):
    pool = sorted(n for n, s in OUTPUT_VARIABLES.items() if s in (None, switch)
                  or (switch is not None and s in ("cage", "skew", "tilt")))
    names = data.draw(st.lists(st.sampled_from(pool), min_size=1, max_size=5, unique=True))
    ds = run_selection(tmp_path_factory.mktemp("sel"), SCENES[switch], names, plot=False)
    assert set(names) <= set(ds.data_vars), names

