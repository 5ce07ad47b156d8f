"""Each law reads the oil's viscosity where its film forms (system/effect.Viscosity,
system/effects.set_temperatures; theory.md §21): the raceway contacts' laws at the mean of
their ring and roller nodes, the cage's land film at the cage and its guiding ring, the drag
and churning at the oil node. The reference is a hand computation: ASTM D341 typed afresh, and
each law's temperature written out from the node temperatures."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import make_scene

from bearingdae.physics.heat_network import NODES
from bearingdae.system import effects
from bearingdae.system.model import build_model
from bearingdae.system.residual import PARAM_NAMES

ALL_ON = {"bearing.type": "NUP", "physics.cage_whirl": True, "cage.guidance": "outer-land",
          "physics.rolling_resistance": True, "physics.lubrication": "mixed",
          "physics.thermal": "steady", "lubricant.viscosity_40C_mm2_s": 46.0,
          "lubricant.viscosity_100C_mm2_s": 6.8}
#: distinct node temperatures [°C]: every law's mean differs from every other's
NODE_C = {"inner_ring": 61.0, "outer_ring": 47.0, "rollers": 73.0, "cage": 55.0, "oil": 41.0}


def _nu_mm2_s(t_C):
    """ASTM D341 through (40 °C, 46) and (100 °C, 6.8), typed afresh."""
    z40, z100 = (math.log10(math.log10(n + 0.7)) for n in (46.0, 6.8))
    x40, x100 = (math.log10(t + 273.15) for t in (40.0, 100.0))
    z = z40 + (z100 - z40) * (math.log10(t_C + 273.15) - x40) / (x100 - x40)
    return 10.0 ** 10.0 ** z - 0.7


def test_each_law_reads_the_viscosity_where_its_film_forms():
    model = build_model(make_scene(ALL_ON))
    rho = model.scene.lubricant.oil_density_kg_m3
    read = effects.set_temperatures(model, np.array([NODE_C[n] for n in NODES]))
    p = dict(zip(PARAM_NAMES, model.params))
    # the raceways: inner film between inner ring and rollers, outer between outer ring and
    # rollers; one parameter for both reads the mean of the two films' temperatures
    film_C = 0.5 * (0.5 * (61.0 + 73.0) + 0.5 * (47.0 + 73.0))  # 63.5 °C
    expect = {"mu_oil": 41.0, "rr_eta0": film_C, "mx_visc": film_C,
              "wh_visc": 0.5 * (55.0 + 47.0)}  # the cage on the outer ring's land
    for name, t_C in expect.items():
        assert p[name] == pytest.approx(rho * _nu_mm2_s(t_C) * 1e-6, rel=1e-9), name
    # β = -d ln ν/dT at the films' temperature (central difference of the typed law)
    h = 1e-3
    beta = -(math.log(_nu_mm2_s(film_C + h)) - math.log(_nu_mm2_s(film_C - h))) / (2 * h)
    assert p["rr_beta"] == pytest.approx(beta, rel=1e-6)
    # the post-processing's film (λ, κ) reads the raceways' viscosity
    assert model.scene.lubricant.viscosity_Pa_s == pytest.approx(p["rr_eta0"], rel=1e-12)
    assert read["film"][0] == pytest.approx(film_C) and read["oil"][0] == 41.0
    # the films run warmer than the oil here, so their oil is thinner than the drag's
    assert p["rr_eta0"] < p["mu_oil"]


def test_with_every_node_at_one_temperature_every_law_reads_the_same_oil():
    model = build_model(make_scene(ALL_ON))
    effects.set_oil_temperature(model, 70.0)
    held = [model.params[PARAM_NAMES.index(n)] for n in effects.viscosity_params()]
    assert np.ptp(held) == 0.0 and held[0] > 0.0
