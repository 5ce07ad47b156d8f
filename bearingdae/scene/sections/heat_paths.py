"""``[thermal]``: the lumped thermal network of ``physics.thermal = "steady"`` (theory.md §21),
as written. Without it the section must stay empty (the oil viscosity is
``lubricant.viscosity_Pa_s``)."""

from __future__ import annotations

from pydantic import ConfigDict, Field

from ..histories import _Section


class ThermalInput(_Section):
    """Heat paths and oil supply of the thermal network (physics/heat_network.py): the shaft and
    the housing at the ambient temperature, the oil flow from its inlet temperature."""

    model_config = ConfigDict(json_schema_extra={"switch": "thermal"})  # every key: its switch

    oil_inlet_temperature_C: float = Field(default=40.0, ge=-60.0, le=250.0, description=
                                           "temperature of the oil entering the bearing")
    oil_flow_l_min: float = Field(default=0.1, ge=0.0, le=1000.0, description="circulating oil "
                                  "flow through the bearing; 0: an oil bath, cooled through "
                                  "the rings only")
    ambient_temperature_C: float = Field(default=20.0, ge=-60.0, le=250.0, description=
                                         "temperature of the shaft and housing far from the "
                                         "bearing")
    housing_conductance_W_K: float = Field(default=2.0, ge=0.0, le=1e4, description=
                                           "conductance from the outer ring's outside "
                                           "diameter to ambient through the housing")
    shaft_conductance_W_K: float = Field(default=1.0, ge=0.0, le=1e4, description=
                                         "conductance from the inner ring's bore to ambient "
                                         "through the shaft")
    oil_specific_heat_J_kgK: float = Field(default=2000.0, gt=100.0, le=1e4, description=
                                           "oil specific heat c_p (mineral oils 1.8-2.1 kJ/(kg K))")
    oil_heat_transfer_W_m2K: float = Field(default=200.0, ge=1.0, le=1e5, description=
                                           "convection coefficient h between the bearing's "
                                           "surfaces and the oil")
    steel_conductivity_W_mK: float = Field(default=46.0, ge=1.0, le=500.0, description=
                                           "thermal conductivity of rings and rollers (100Cr6 "
                                           "about 46 W/(m K))")
    temperature_tolerance_K: float = Field(default=0.5, ge=1e-3, le=50.0, description=
                                           "the coupling stops when the oil temperature "
                                           "changes by less than this between two blocks")
