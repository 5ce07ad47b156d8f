"""The thermal run's 0-d variables are entries of the one result-variable table
(analysis/result_variables.py), so a sweep stacks them (results_of) with the other results."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr

from bearingdae.analysis.result_variables import RESULT_VARIABLES, results_of
from bearingdae.physics.heat_network import NODES
from bearingdae.physics.oil_viscosity import rated_viscosity
from bearingdae.results.thermal_variables import thermal_lines, thermal_variables


def _scene(viscosity_Pa_s=0.0261, speed_rpm=2000.0):
    """What κ reads of a scene: the films' oil, the pitch diameter (45 mm), the speed."""
    return SimpleNamespace(
        lubricant=SimpleNamespace(viscosity_Pa_s=viscosity_Pa_s, oil_density_kg_m3=870.0),
        bearing=SimpleNamespace(pitch_diameter_m=0.045),
        operating=SimpleNamespace(speed_at=lambda t: speed_rpm))


def _model():
    coupling = SimpleNamespace(
        temperatures_C=np.array([50.0, 45.0, 60.0, 55.0, 52.0]), heat_W=np.ones(5),
        viscosity_Pa_s=0.012, kinematic_mm2_s=14.0,
        blocks=3, converged=True, last_change_K=0.05, tolerance_K=0.1)
    return SimpleNamespace(thermal=coupling, scene=_scene())


def test_a_sweep_keeps_kappa_and_the_oil_viscosity():
    ds = xr.Dataset(thermal_variables(_model()))
    stacked = results_of(ds)
    # ν = η/ρ = 30 mm²/s; ν₁ = 4500 (2000 · 45)^-0.5 = 15 mm²/s (ISO 281, n >= 1000 r/min)
    assert stacked["viscosity_ratio_kappa"] == pytest.approx(2.0, rel=1e-12)
    assert stacked["rated_viscosity"] == pytest.approx(4500.0 / math.sqrt(2000.0 * 45.0))
    # the record's mean speed, when given, is the one ν₁ reads
    at = xr.Dataset(thermal_variables(_model(), speed_rpm=500.0))
    assert float(at.rated_viscosity) == pytest.approx(45000.0 * 500.0 ** -0.83 / 45 ** 0.5)
    assert stacked["operating_viscosity_Pa_s"] == 0.012
    assert stacked["operating_kinematic_viscosity"] == 14.0
    assert stacked["thermal_blocks"] == 3
    for name in ("viscosity_ratio_kappa", "operating_viscosity_Pa_s", "thermal_blocks"):
        assert ds[name].attrs["units"] == RESULT_VARIABLES[name].units
        assert ds[name].attrs["long_name"] == RESULT_VARIABLES[name].long_name
    assert ds.thermal_blocks.attrs["converged"] == 1


def test_a_standstill_thermal_run_says_what_its_nan_rated_viscosity_means():
    """At n = 0 the rated viscosity and κ are NaN (ISO 281 defines ν₁ for a turning ring only),
    with the nan_meaning attribute other result variables carry, and the summary says so."""
    nodes = len(NODES)
    c = SimpleNamespace(temperatures_C=np.full(nodes, 40.0), heat_W=np.zeros(nodes),
                        viscosity_Pa_s=0.03, kinematic_mm2_s=35.0, blocks=1, converged=True,
                        last_change_K=0.0, tolerance_K=0.5)
    assert np.isnan(rated_viscosity(0.0, 45.0))
    ds = xr.Dataset(thermal_variables(SimpleNamespace(thermal=c, scene=_scene(speed_rpm=0.0))))
    for name in ("rated_viscosity", "viscosity_ratio_kappa"):
        assert np.isnan(ds[name].item()) and "stands still" in ds[name].attrs["nan_meaning"]
    assert any("κ undefined: the inner ring stands still" in ln for ln in thermal_lines(ds))
