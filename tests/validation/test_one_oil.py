"""One oil with and without the thermal switch (scene/thermal_switch.py, system/thermal_network
.start_scene; theory.md §21): the switch changes the oil's temperatures, never the oil.

The reference is the limit of the network: with conductances so large that every node sits at
the inlet temperature, a thermal run is the run without the switch at an operating temperature
equal to the inlet temperature, so their losses agree."""

from __future__ import annotations

import pytest
from conftest import make_scene

from bearingdae import simulate
from bearingdae.system.model import build_model
from bearingdae.system.residual import PARAM_NAMES

#: an ISO VG 46 oil (ISO 3448 mid-point; 6.8 mm²/s at 100 °C, viscosity index ~100), read at
#: 50 °C: one description for both runs
OIL = {"lubricant.viscosity_40C_mm2_s": 46.0, "lubricant.viscosity_100C_mm2_s": 6.8,
       "lubricant.operating_temperature_C": 50.0}
#: the network's limit: every conductance at its maximum, the surroundings at the inlet's 50 °C
HUGE = {"thermal.oil_inlet_temperature_C": 50.0, "thermal.ambient_temperature_C": 50.0,
        "thermal.oil_flow_l_min": 1000.0, "thermal.housing_conductance_W_K": 1e4,
        "thermal.shaft_conductance_W_K": 1e4, "thermal.oil_heat_transfer_W_m2K": 1e5,
        "thermal.steel_conductivity_W_mK": 500.0}
RUN = {"operating.speed_rpm": 4000.0, "operating.radial_load_N": 800.0, "numerics.slices": 4,
       "numerics.samples_per_cage_revolution": 40, "numerics.cage_revolutions": 0.25,
       "numerics.warmup_cage_revolutions": 0.5, "numerics.steady_block_cage_revolutions": 0.5,
       "numerics.max_warmup_cage_revolutions": 10.0}


def _walther_Pa_s(nu40, nu100, t_C, rho):
    """ASTM D341 typed afresh: log log(ν + 0.7) linear in log T [K] through two points."""
    import math

    z = [math.log10(math.log10(n + 0.7)) for n in (nu40, nu100)]
    x = [math.log10(t + 273.15) for t in (40.0, 100.0)]
    zt = z[0] + (z[1] - z[0]) * (math.log10(t_C + 273.15) - x[0]) / (x[1] - x[0])
    return rho * (10.0 ** 10.0 ** zt - 0.7) * 1e-6


def test_without_the_switch_the_laws_read_the_oil_at_its_operating_temperature():
    scene = make_scene(OIL)
    assert scene.thermal is None
    mu = _walther_Pa_s(46.0, 6.8, 50.0, scene.lubricant.oil_density_kg_m3)
    model = build_model(scene)
    assert model.params[PARAM_NAMES.index("mu_oil")] == pytest.approx(mu, rel=1e-9)


@pytest.mark.slow
def test_same_oil_with_and_without_the_switch_gives_the_same_losses():
    """The Must-show of the one-oil rule: losses within 1 % (the network's nodes sit within
    milli-kelvins of the inlet: a viscosity within ~1e-4 of the operating one)."""
    plain = simulate(make_scene({**RUN, **OIL}), progress=False)
    hot = simulate(make_scene({**RUN, **OIL, **HUGE, "physics.thermal": "steady"}),
                   progress=False)
    T = hot.temperature.values
    assert abs(T - 50.0).max() < 0.05, T  # the limit holds: every node at the inlet
    a = float(plain.mean_power_loss_W)
    b = float(hot.mean_power_loss_W)
    print(f"\n[one oil] losses {a:.4g} W without the switch, {b:.4g} W with it")
    assert a > 0.0 and abs(b / a - 1.0) < 0.01
