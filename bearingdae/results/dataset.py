"""Labelled xarray Datasets of a static solve and of a dynamic run (CF units, long names).

Pipeline: results (after solvers). Global attributes record the package, the scene as TOML text
and the regularisation scales; :mod:`.solution` builds a dynamic run's Dataset from a Solution.
"""

from __future__ import annotations

import datetime as _dt
import json

import numpy as np
import xarray as xr

from .. import __version__
from ..physics.contact import hertz_pressure
from ..physics.frequencies import characteristic_frequencies
from ..physics.loads import table_loads


RACES = ("inner", "outer")
DIRECTIONS = ("radial", "tangential")
ENDS = ("a", "b")
#: what the time coordinate of a dynamic result counts from (its ``comment``)
TIME_ORIGIN = ("t = 0 is the start of the integration, at the initial state; any speed ramp "
               "and the warm-up (numerics.warmup_cage_revolutions, or until steady) come "
               "first, and the record starts at record_start_s (a variable); the partial "
               "file of a failed run keeps the warm-up samples too")


def _var(dims, data, units: str | None, long_name: str, **extra) -> xr.Variable:
    """A variable with CF ``units`` and ``long_name``; ``units=None`` for a number or label
    that has none (an index such as ``roller``, a label such as ``race``): no ``units``
    attribute at all, so that xarray's plot labels do not read "[1]" or "[]"."""
    attrs = {"long_name": long_name} if units is None else {"units": units,
                                                           "long_name": long_name}
    attrs.update(extra)
    return xr.Variable(dims, np.asarray(data), attrs)


def index_coords(geometry) -> dict:
    """The coordinates every result shares: ``roller`` and ``slice`` numbers, the labels
    ``race``, ``end``, ``direction``, and ``slice_position`` (centre of each slice along the
    roller axis) with its CF cell bounds ``slice_position_bounds`` (CF 7.1)."""
    g = geometry
    k = g.slices
    centre = np.asarray(g.x_m, dtype=float)
    bounds = np.stack([centre - 0.5 * g.slice_width_m, centre + 0.5 * g.slice_width_m], axis=-1)
    return {
        "roller": _var("roller", np.arange(1, g.rollers + 1), None, "roller number"),
        "slice": _var("slice", np.arange(1, k + 1), None,
                      "slice number, end b to end a"),
        "race": _var("race", np.array(RACES), None, "raceway"),
        "end": _var("end", np.array(ENDS), None, "roller end (a: x = +L/2, b: x = -L/2)"),
        "direction": _var("direction", np.array(DIRECTIONS), None, "load direction"),
        "slice_position": _var("slice", centre, "m", "axial position x of the slice centre "
                               "from the roller centre (+x towards end a)",
                               bounds="slice_position_bounds"),
        # the b-side and a-side edges of each slice; no attributes of its own (CF 7.1: a
        # boundary variable shares those of its coordinate, units included)
        "slice_position_bounds": xr.Variable(("slice", "bounds"), bounds),
    }


def operating_attrs(scene, time_s: float | None = None) -> dict:
    """The operating point as global attributes (every result file): the loads on the inner
    ring and its speed [r/min] at ``time_s`` (a static solve: t = 0; a dynamic run: the start
    of the record; None: after any speed ramp)."""
    o = scene.operating
    speed = o.speed_at(time_s) if time_s is not None else (
        o.speed_rpm[1][-1] if isinstance(o.speed_rpm, tuple) else o.speed_rpm)
    loads = o.loads
    if o.load_history is not None:  # the history's loads at that time (applied_load: all)
        loads = table_loads(time_s if time_s is not None else o.load_history[-1][0],
                            np.array(o.load_history, float))
    attrs = {"radial_load_N": float(loads[0]),
             "tangential_load_N": float(loads[1]),
             "moment_Nm": float(loads[2]),
             "tangential_moment_Nm": float(loads[3]),
             "speed_rpm": float(speed)}
    if o.unbalance_N:
        attrs["unbalance_N"] = float(o.unbalance_N)
        attrs["unbalance_phase_deg"] = float(np.degrees(o.unbalance_phase_rad))
    if o.load_file is not None:
        attrs["load_file"] = o.load_file
        if o.load_file_sha256 is not None:  # which contents of it the run read
            attrs["load_file_sha256"] = o.load_file_sha256
    elif o.load_history is not None:
        attrs["load_history"] = "scene tables (operating.*_N / *_Nm); see applied_load"
    if isinstance(o.speed_rpm, tuple):  # a ramp: its points too (the TOML has them as well)
        attrs["speed_ramp"] = json.dumps({"times_s": list(o.speed_rpm[0]),
                                          "values_rpm": list(o.speed_rpm[1])})
    return attrs


def ring_attrs(model) -> dict:
    """The bearing's characteristic frequencies at the final inner-ring speed (JSON, Hz;
    physics/frequencies.py) and, for a dynamic ring, its mass, tilt inertia and support."""
    g, sc = model.geometry, model.scene
    f_s = float(model.ramp_w[-1]) / (2.0 * np.pi)
    attrs = {"characteristic_frequencies_Hz": json.dumps(characteristic_frequencies(
        g.rollers, 2.0 * g.roller_radius_m, 2.0 * g.pitch_radius_m, f_s))}
    if model.layout.ring_dynamic:
        from ..system.residual import PARAM_NAMES

        P = dict(zip(PARAM_NAMES, model.params))
        attrs.update({"ring_mass_kg": float(P["ring_m"]),
                      "ring_tilt_inertia_kg_m2": float(P["ring_I"]),
                      "ring_support_stiffness_N_m": sc.ring.support_stiffness_N_m,
                      "ring_support_damping_N_s_m": sc.ring.support_damping_N_s_m})
    return attrs


def contact_regularisation(scene) -> dict:
    """The contact-onset regularisation of a scene, as recorded in every output file."""
    return {
        "contact_onset": "s(d) = (d + sqrt(d^2 + eps^2))/2 replaces max(d, 0)",
        "contact_smoothing_m": scene.numerics.contact_smoothing_m,
    }


def base_attrs(scene, kind: str) -> dict:
    """Global attributes shared by every result file."""
    now = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")
    attrs = {
        "Conventions": "CF-1.10",
        "title": f"bearingdae {kind}: {scene.title}",
        "institution": "bearingdae (open source)",
        "source": f"bearingdae {__version__}",
        "history": f"{now} created by bearingdae {__version__} ({kind})",
        "references": "Yang, Wang, Wang & Wen, Lubricants 2024, 12(9), 317, "
                      "doi:10.3390/lubricants12090317, as read in bearingdae's docs/theory.md",
        "bearingdae_version": __version__,
        "scene_toml": scene.to_toml(complete=True),
        "regularisation": json.dumps(contact_regularisation(scene)),
        "output_precision": getattr(scene, "output_precision", "float64"),
    }
    if scene.preset_citation:
        attrs["preset_citation"] = scene.preset_citation
    if scene.physics.lubrication == "mixed":  # (the summary's film line says so)
        attrs["lubrication"] = "mixed"
    return attrs


def static_dataset(scene, geometry, solution) -> xr.Dataset:
    """Dataset of a quasi-static solution (dims roller, slice, race, direction)."""
    from ..system.layout import split_static

    g = geometry
    u, beta, ring = split_static(solution.z, g.rollers)
    cs = solution.contact
    force = np.stack([cs.load_inner_N, cs.load_outer_N], axis=-1)
    approach = np.stack([cs.approach_inner_m, cs.approach_outer_m], axis=-1)
    pressure = np.stack(
        [
            hertz_pressure(cs.load_inner_N, g.slice_width_m, g.reduced_radius_inner_m,
                           g.compliance_m2_N),
            hertz_pressure(cs.load_outer_N, g.slice_width_m, g.reduced_radius_outer_m,
                           g.compliance_m2_N),
        ],
        axis=-1,
    )
    prob = solution.problem
    coords = {name: var for name, var in index_coords(g).items() if name != "end"}
    coords["azimuth"] = _var("roller", prob.azimuth_rad, "rad",
                             "roller azimuth from the radial-load line, in the direction of "
                             "rotation")
    data = {
        "contact_force": _var(("roller", "slice", "race"), force, "N", "slice contact force"),
        "contact_pressure": _var(("roller", "slice", "race"), pressure, "Pa",
                                 "maximum Hertz pressure of the slice"),
        "approach": _var(("roller", "slice", "race"), approach, "m",
                         "slice contact approach (positive = overlap)"),
        "roller_radial_position": _var("roller", u, "m",
                                       "roller radial position u (outward; 0 = touching the "
                                       "outer race)"),
        "roller_tilt": _var("roller", beta, "rad",
                            "roller tilt beta (positive moves the +x end outward)"),
        "ring_displacement": _var("direction", ring[:2], "m", "inner ring displacement"),
        "ring_tilt": _var("direction", ring[2:], "rad", "inner ring tilt"),
        "centrifugal_force": _var("roller", prob.centrifugal_N, "N", "roller centrifugal force"),
    }
    attrs = base_attrs(scene, "quasi-static equilibrium")
    attrs.update(
        {
            "solver": "bearingdae damped Newton (analytic Jacobian)",
            "newton_iterations": int(solution.iterations),
            "residual_max_relative": float(solution.relative_residual),
            **operating_attrs(scene, 0.0),
        }
    )
    return xr.Dataset(data, coords=coords, attrs=attrs)


# ---------------------------------------------------------------------------------------------
# Dynamic results
# ---------------------------------------------------------------------------------------------

#: name -> (dims after time, units, long_name)
DYNAMIC_VARIABLES = {
    "cage_angle": ((), "rad", "cage angle (unwrapped)"),
    "cage_speed": ((), "rad s-1", "cage angular speed"),
    "inner_ring_speed": ((), "rad s-1", "inner ring angular speed"),
    "roller_azimuth": (("roller",), "rad", "roller azimuth from the load line (unwrapped)"),
    "orbit_speed": (("roller",), "rad s-1", "roller orbit (revolution) speed"),
    "spin_speed": (("roller",), "rad s-1",
                   "roller spin speed (positive when rolling forward on the inner race)"),
    "skew_angle": (("roller",), "rad", "roller skew angle about the radial axis"),
    "skew_rate": (("roller",), "rad s-1", "roller skew rate"),
    "roller_tilt": (("roller",), "rad", "roller tilt (positive moves the +x end outward)"),
    "roller_radial_position": (("roller",), "m",
                               "roller radial position (outward; 0 = touching the outer race)"),
    "contact_force": (("roller", "slice", "race"), "N", "slice contact force"),
    "contact_pressure": (("roller", "slice", "race"), "Pa", "maximum Hertz pressure of slice"),
    "slip_velocity": (("roller", "slice", "race"), "m s-1",
                      "tangential slip velocity, race surface minus roller surface"),
    "traction_force": (("roller", "slice", "race"), "N", "slice traction force on the roller"),
    "cage_force": (("roller", "end"), "N", "pocket force on the roller end, along the "
                   "direction of rotation"),
    "ring_displacement": (("direction",), "m", "inner ring displacement"),
    "ring_tilt": (("direction",), "rad", "inner ring tilt"),
    "applied_load": (("direction",), "N", "external force applied to the inner ring (load "
                     "history plus unbalance; radial: towards azimuth 0, tangential: towards "
                     "azimuth 90 degrees)"),
    "applied_moment": (("direction",), "N m", "external moment applied to the inner ring "
                       "(radial: loads the +x roller end at azimuth 0; tangential: at 90 "
                       "degrees)"),
    "ring_velocity": (("direction",), "m s-1", "inner ring velocity (dynamic ring)"),
    "ring_acceleration": (("direction",), "m s-2", "inner ring acceleration (dynamic ring), "
                          "low-passed below the samples' Nyquist frequency (theory.md §15)"),
    "roller_spin_angle_rad": (("roller",), "rad", "roller spin angle relative to the "
                              "orbiting frame, 0 at t = 0 (unwrapped; a scene with a defect "
                              "or waviness on a roller, theory.md §4)"),
}


def dynamic_dataset(model, t, Y, diag, info: dict) -> xr.Dataset:
    """Dataset of a dynamic run. ``Y``: unscaled full states as (full_l (n, Z, len(LOCAL)),
    full_g (n, len(GLOBAL))); ``diag``: stacked kernel diagnostics; ``info``: solver attributes."""
    from ..scene import OUTPUT_VARIABLES
    from ..system.layout import LOCAL
    from ..analysis.whirl import WHIRL_VARIABLES

    scene, g = model.scene, model.geometry
    full_l, full_g = Y
    L = {n: full_l[..., LOCAL.index(n)] for n in LOCAL}
    from ..system.samples import sample_values

    values = sample_values(model, t, Y, diag)
    FLANGE_VARIABLES = {}
    if model.layout.flange:  # roller end-flange contacts (analysis/flange.py)
        from ..analysis.flange import FLANGE_VARIABLES
    wanted = scene.output_variables or tuple(OUTPUT_VARIABLES)
    # What the assembled model actually has (tilt is also dropped with a single slice).
    present = {"cage": model.layout.cage, "skew": model.layout.skew, "tilt": model.layout.tilt,
               "ring": model.layout.ring_dynamic, "flange": model.layout.flange,
               "cage_whirl": model.layout.whirl, "roller_surface": model.layout.spin_angle}
    from ..system.effects import active  # the variables an effect declares with its own
    declared = {n: v for e in active(scene) if e.variables for n, v in e.variables.items()}
    present.update({OUTPUT_VARIABLES[n]: True for n in declared})
    data = {}
    for name in wanted:
        switch = OUTPUT_VARIABLES[name]
        table = DYNAMIC_VARIABLES if name in DYNAMIC_VARIABLES else FLANGE_VARIABLES
        if name in WHIRL_VARIABLES or name in declared:
            table = WHIRL_VARIABLES if name in WHIRL_VARIABLES else declared
        if name not in table or switch is not None and not present[switch]:
            continue
        dims, units, long_name = table[name]
        data[name] = _var(("time",) + dims, values[name], units, long_name)
    coords = {"time": _var("time", t, "s", "time since the start of the simulation",
                           comment=TIME_ORIGIN), **index_coords(g)}
    if len(t):
        coords["start_azimuth"] = _var(
            "roller", np.mod(L["azimuth"][0], 2.0 * np.pi), "rad",
            "roller azimuth at the first sample (time[0]), from the radial-load line in the "
            "direction of rotation")
    # life, film and power loss (analysis/engineering.py): from every sample, whatever is kept
    from ..analysis.engineering import dynamic_variables, source_coordinate

    extra, extra_attrs = dynamic_variables(model, np.asarray(t), values)
    data.update({n: v for n, v in extra.items() if scene.output_variables is None
                 or n in scene.output_variables})
    if any("loss_source" in v.dims for v in data.values()):
        coords["loss_source"] = source_coordinate(model.scene)
    ds = xr.Dataset(data, coords=coords)
    used = set()
    for v in ds.data_vars.values():
        used |= set(v.dims)
    ds = ds.drop_vars([c for c in ds.coords if c != "time" and not set(ds[c].dims) & used])
    ds.attrs.update(dynamic_attrs(model, info, extra_attrs))
    if model.layout.whirl and len(t):
        from ..analysis.whirl import whirl_attrs

        ds.attrs.update(whirl_attrs(model, t, values["cage_center"], values["cage_speed"]))
    return ds


def dynamic_attrs(model, info: dict, extra_attrs: dict) -> dict:
    """Global attributes of a dynamic run: the shared ones, the ring's, the solver's
    (``info``), the operating point at the start of the record and ``extra_attrs``."""
    attrs = base_attrs(model.scene, "dynamic simulation")
    attrs.update(ring_attrs(model))
    if model.layout.ring_dynamic:  # its natural frequencies against the sampling
        from ..analysis.vibration import vibration_attrs

        attrs.update(vibration_attrs(model))
    attrs.update(info)
    attrs.update(operating_attrs(model.scene, float(info.get("record_start_s", 0.0))))
    attrs.update(extra_attrs)
    if model.layout.flange:
        from ..analysis.flange import axial_capacity_attrs

        attrs.update(axial_capacity_attrs(model.scene))
    return attrs
