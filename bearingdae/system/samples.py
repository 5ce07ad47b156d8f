"""A run's samples by output variable name, and what a block of them hands to the thermal
network (system layer: the kernel's own laws at recorded states).

:func:`sample_values` are every dynamic quantity of the samples by the name of its output
variable (results/dataset.py selects and labels them; analysis/engineering.py reads the power
loss off them); each active effect adds its own (its declaration's ``values``).
:func:`block_inputs` is what the thermal coupling (run/thermal_coupling.py) reads off a block:
the mean power loss by source, computed as the record's ``power_loss_W`` is, and the contacts'
band areas.
"""

from __future__ import annotations

import numpy as np

from ..physics import heat_network as law
from .effects import active, param_slice, power_by_source
from .layout import GLOBAL, LOCAL


def sample_values(model, t, Y, diag) -> dict:
    """Every dynamic output quantity of the samples by its variable's name (before the
    ``output.variables`` selection), from the unscaled full states ``Y`` and the kernel's
    diagnostics ``diag``."""
    full_l, full_g = Y
    L = {n: full_l[..., LOCAL.index(n)] for n in LOCAL}
    G = {n: full_g[..., GLOBAL.index(n)] for n in GLOBAL}
    values = {
        "cage_angle": G["cage_angle"], "cage_speed": G["cage_speed"],
        "inner_ring_speed": np.interp(np.asarray(t, dtype=float), model.ramp_t, model.ramp_w),
        "roller_azimuth": L["azimuth"], "orbit_speed": L["orbit_speed"],
        "spin_speed": L["spin_speed"], "skew_angle": L["skew_angle"], "skew_rate": L["skew_rate"],
        "roller_tilt": L["tilt"], "roller_radial_position": L["radial_position"],
        "contact_force": diag["contact_force"], "contact_pressure": diag["contact_pressure"],
        "slip_velocity": diag["slip_velocity"], "traction_force": diag["traction_force"],
        "cage_force": diag["cage_force"],
        "ring_displacement": np.stack([G["ring_dr"], G["ring_dt"]], axis=-1),
        "ring_tilt": np.stack([G["ring_gr"], G["ring_gt"]], axis=-1),
    }
    for e in active(model.scene):  # the effects' own (flanges, cage whirl)
        if e.values is not None:
            values.update(e.values(model, t, full_l, full_g, model.params[param_slice(e)]))
    applied = model.loads_series(t)
    values["applied_load"], values["applied_moment"] = applied[:, :2], applied[:, 2:4]
    if model.layout.spin_angle:  # a defect or waviness on a roller (system/defects.py)
        values["roller_spin_angle_rad"] = L["spin_angle"]
    if model.layout.ring_dynamic:
        values["ring_velocity"] = np.stack([G["ring_vr"], G["ring_vt"]], axis=-1)
        values["ring_acceleration"] = diag["ring_acceleration"]
    return values


def block_inputs(model, t, Ys) -> dict:
    """The mean power loss by source [W] and the summed contact band area of each race [m²]
    over a block's samples (times ``t``, scaled states ``Ys``): ``{"losses": {...},
    "band_area_m2": (inner, outer)}``."""
    t = np.asarray(t, dtype=float)
    Ys = np.asarray(Ys, dtype=float)
    diag = model.diagnostics_series(t, Ys)
    Z = model.geometry.rollers
    full_l, full_g = model.layout.unpack(Ys * model.scale)
    Y = (full_l.reshape(-1, Z, len(LOCAL)), full_g.reshape(-1, len(GLOBAL)))
    P, _ = power_by_source(model, t, sample_values(model, t, Y, diag))
    area = law.band_area(diag["contact_force"], diag["contact_pressure"],
                         model.geometry.slice_width_m)  # (n, Z, k, race)
    per_race = area.sum(axis=(1, 2)).mean(axis=0)
    return {"losses": {k: float(np.mean(v)) for k, v in P.items()},
            "band_area_m2": (float(per_race[0]), float(per_race[1]))}
