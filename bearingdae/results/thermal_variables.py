"""What the thermal coupling reads off a block of samples, and its result variables
(physics.thermal = "steady"; theory.md §21).

Stage: results. :func:`thermal_variables` are the 0-d and per-node data variables of a thermal
run, with units (what a block hands to the network is system/samples.block_inputs).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..physics import heat_network as law

#: what a NaN rated viscosity (and κ) means: ISO 281 defines ν₁ for a turning ring only
STANDSTILL = "the inner ring stands still (ISO 281:2007 defines nu_1 for a turning ring only)"


def _var(dims, data, units, long_name, **extra):
    attrs = ({} if units is None else {"units": units}) | {"long_name": long_name, **extra}
    return xr.Variable(dims, np.asarray(data), attrs)


def _result(name, data, **extra):
    """A 0-d thermal variable with its entry of analysis/result_variables.RESULT_VARIABLES."""
    from ..analysis.result_variables import run_variable

    units, long_name = run_variable(name)
    return _var((), data, units, long_name, **extra)


def thermal_variables(model, wanted=None, speed_rpm=None) -> dict:
    """The data variables of a thermal run (``model.thermal``, run/thermal_coupling.py), those of
    ``wanted`` (None: all) only; {} without the coupling. κ and ν₁ are the modified life's
    (analysis/rating_life.viscosity_ratio) at ``speed_rpm``, the record's mean inner-ring
    speed (None, a record without samples: the speed the scene ends on)."""
    from ..analysis.rating_life import viscosity_ratio

    c = getattr(model, "thermal", None)
    if c is None or c.temperatures_C is None:
        return {}
    if speed_rpm is None:
        speed_rpm = model.scene.operating.speed_at(float("inf"))
    kappa, _, rated = viscosity_ratio(model.scene, speed_rpm)
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
                             "by source, partitioned as each source declares)"),
        # the 0-d ones: the result-variable table's units and names (a sweep stacks them)
        "operating_viscosity_Pa_s": _result("operating_viscosity_Pa_s", c.viscosity_Pa_s),
        "operating_kinematic_viscosity": _result("operating_kinematic_viscosity",
                                                 c.kinematic_mm2_s),
        "rated_viscosity": _result("rated_viscosity", rated, nan_meaning=STANDSTILL),
        "viscosity_ratio_kappa": _result("viscosity_ratio_kappa", kappa,
                                         nan_meaning=STANDSTILL),
        "thermal_blocks": _result("thermal_blocks", np.int32(c.blocks),
                                  converged=int(c.converged)),
        "oil_temperature_last_change_K": _result("oil_temperature_last_change_K",
                                                 c.last_change_K, tolerance_K=c.tolerance_K),
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
        lines.append(f"  {'oil viscosity (raceways)':<24} {nu:.4g} mm²/s{kappa}")
    return lines
