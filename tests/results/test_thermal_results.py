"""The thermal run's 0-d variables are entries of the one result-variable table
(analysis/result_variables.py), so a sweep stacks them (results_of) with the other results."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import xarray as xr

from bearingdae.analysis.result_variables import RESULT_VARIABLES, results_of
from bearingdae.results.thermal import thermal_variables


def _model():
    coupling = SimpleNamespace(
        temperatures_C=np.array([50.0, 45.0, 60.0, 55.0, 52.0]), heat_W=np.ones(5),
        viscosity_Pa_s=0.012, kinematic_mm2_s=14.0, rated_mm2_s=7.0, rated_ratio=2.0,
        blocks=3, converged=True, last_change_K=0.05, tolerance_K=0.1)
    return SimpleNamespace(thermal=coupling)


def test_a_sweep_keeps_kappa_and_the_oil_viscosity():
    ds = xr.Dataset(thermal_variables(_model()))
    stacked = results_of(ds)
    assert stacked["viscosity_ratio_kappa"] == 2.0
    assert stacked["operating_viscosity_Pa_s"] == 0.012
    assert stacked["operating_kinematic_viscosity"] == 14.0
    assert stacked["thermal_blocks"] == 3
    for name in ("viscosity_ratio_kappa", "operating_viscosity_Pa_s", "thermal_blocks"):
        assert ds[name].attrs["units"] == RESULT_VARIABLES[name].units
        assert ds[name].attrs["long_name"] == RESULT_VARIABLES[name].long_name
    assert ds.thermal_blocks.attrs["converged"] == 1
