"""What the thermal coupling reads off a block of samples, and its result variables
(physics.thermal = "steady"; theory.md §21).

Stage: results. :func:`block_inputs` is the coupling's view of a block (run/thermal.py calls
it through ``bearingdae.api``: the mean power loss by source, computed as the result's
``power_loss_W`` is, and the contacts' band areas); :func:`thermal_variables` are the 0-d and
per-node data variables of a thermal run, with units.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..physics import thermal as law
from ..system.layout import GLOBAL, LOCAL

#: the thermal run's output variables (scene.sections.output.OUTPUT_VARIABLES: switch "thermal")
THERMAL_VARIABLES = ("temperature", "heat_input_W", "operating_viscosity_Pa_s",
                     "operating_kinematic_viscosity", "rated_viscosity", "viscosity_ratio_kappa",
                     "thermal_blocks", "oil_temperature_last_change_K")


#: what a NaN rated viscosity (and κ) means: ISO 281 defines ν₁ for a turning ring only
STANDSTILL = "the inner ring stands still (ISO 281:2007 defines nu_1 for a turning ring only)"


def block_inputs(model, t, Ys) -> dict:
    """The mean power loss by source [W] and the summed contact band area of each race [m²]
    over a block's samples (times ``t``, scaled states ``Ys``): ``{"losses": {...},
    "band_area_m2": (inner, outer)}``."""
    from .dataset import sample_values
    from ..analysis.engineering import power_by_source

    t = np.asarray(t, dtype=float)
    Ys = np.asarray(Ys, dtype=float)
    diag = model.diagnostics_series(t, Ys)
    Z = model.geometry.rollers
    full_l, full_g = model.layout.unpack(Ys * model.scale)
    Y = (full_l.reshape(-1, Z, len(LOCAL)), full_g.reshape(-1, len(GLOBAL)))
    values = sample_values(model, t, Y, diag)
    P, _ = power_by_source(model, t, values)
    area = law.band_area(diag["contact_force"], diag["contact_pressure"],
                         model.geometry.slice_width_m)  # (n, Z, k, race)
    per_race = area.sum(axis=(1, 2)).mean(axis=0)
    return {"losses": {k: float(np.mean(v)) for k, v in P.items()},
            "band_area_m2": (float(per_race[0]), float(per_race[1]))}


def _var(dims, data, units, long_name, **extra):
    attrs = ({} if units is None else {"units": units}) | {"long_name": long_name, **extra}
    return xr.Variable(dims, np.asarray(data), attrs)


def thermal_variables(model, wanted=None) -> dict:
    """The data variables of a thermal run (``model.thermal``, run/thermal.py), those of
    ``wanted`` (None: all) only; {} without the coupling."""
    c = getattr(model, "thermal", None)
    if c is None or c.temperatures_C is None:
        return {}
    nodes = np.array(law.NODES)
    node = ("thermal_node",)
    note = "steady lumped network under the mean losses of the last warm-up block (theory.md §21)"
    out = {
        "thermal_node": _var(node, nodes, None, "node of the thermal network",
                             description="; ".join(f"{k}: {v}" for k, v in
                                                   law.NODE_NAMES.items())),
        "temperature": _var(node, c.temperatures_C, "degC", "temperature of each node of the "
                            "thermal network", comment=note),
        "heat_input_W": _var(node, c.heat_W, "W", "heat entering each node (mean power loss "
                             "by source, partitioned by physics/thermal.HEAT_PARTITION)"),
        "operating_viscosity_Pa_s": _var((), c.viscosity_Pa_s, "Pa s", "oil dynamic viscosity "
                                         "at the oil temperature (the record's)"),
        "operating_kinematic_viscosity": _var((), c.kinematic_mm2_s, "mm2 s-1", "oil kinematic "
                                              "viscosity at the oil temperature (ASTM D341)"),
        "rated_viscosity": _var((), c.rated_mm2_s, "mm2 s-1", "rated viscosity nu_1 of ISO "
                                "281:2007 at the speed and pitch diameter",
                                nan_meaning=STANDSTILL),
        "viscosity_ratio_kappa": _var((), c.rated_ratio, "1", "viscosity ratio kappa = nu / "
                                      "nu_1 (ISO 281:2007)", nan_meaning=STANDSTILL),
        "thermal_blocks": _var((), np.int32(c.blocks), "1", "warm-up blocks the thermal "
                               "coupling ran until the oil temperature was steady",
                               converged=int(c.converged)),
        "oil_temperature_last_change_K": _var((), c.last_change_K, "K", "change of the oil "
                                              "temperature over the last block",
                                              tolerance_K=c.tolerance_K),
    }
    if wanted is not None:
        out = {k: v for k, v in out.items() if k in wanted or k == "thermal_node"}
        if not any(v.dims == node for k, v in out.items() if k != "thermal_node"):
            out.pop("thermal_node", None)
    return out


def thermal_lines(ds) -> list[str]:
    """The run summary's lines of a thermal run: node temperatures, blocks, oil viscosity and
    κ (each from the variables it needs: output.variables may keep any)."""
    lines = []
    if "temperature" in ds and "thermal_node" in ds.coords:
        temps = ", ".join(f"{law.NODE_NAMES.get(str(n), str(n)).split(' (')[0]} {float(T):.1f}"
                          for n, T in zip(ds.thermal_node.values, ds.temperature.values))
        blocks = ""
        if "thermal_blocks" in ds:
            ok = ds.thermal_blocks.attrs.get("converged", 1)
            blocks = (f" ({'steady' if ok else 'NOT steady'} after "
                      f"{int(ds.thermal_blocks)} blocks)")
        lines.append(f"  {'temperatures (°C)':<24} {temps}{blocks}")
    if "operating_kinematic_viscosity" in ds:
        nu = float(ds.operating_kinematic_viscosity)
        kappa = (f", κ = ν/ν₁ = {float(ds.viscosity_ratio_kappa):.3g} (ν₁ "
                 f"{float(ds.rated_viscosity):.3g} mm²/s, ISO 281)"
                 if "viscosity_ratio_kappa" in ds and "rated_viscosity" in ds else "")
        if "rated_viscosity" in ds and np.isnan(float(ds.rated_viscosity)):
            kappa = ", κ undefined: the inner ring stands still (ISO 281's ν₁)"
        lines.append(f"  {'oil viscosity':<24} {nu:.4g} mm²/s{kappa}")
    return lines
