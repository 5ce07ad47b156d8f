"""The numbers a result states, as data variables with units: one table, one conversion.

Pipeline: analysis (below results/, which writes with it, and read by analysis/, plots/ and
the studies); the last step before a Dataset is handed out or written. The producers of
a result (statistics, rating life, extremes, the operating point, the solver, the cage whirl,
the flanges, the until-steady warm-up, ...) hand their numbers over as a flat dict keyed by the
names of :data:`RESULT_VARIABLES`; :func:`split_results` turns every entry of that table into a
0-d data variable with CF ``units`` and ``long_name`` (and ``standard_name`` where CF has one),
and leaves the rest (provenance, solver options, the scene, method texts) as global
attributes. A statistic's error is its own variable, named in the statistic's CF
``ancillary_variables``: a standard error carries ``standard_name = "<parent's> standard_error"``
(CF's modifier) where the parent has a standard name, else a long name "standard error of ...";
another kind of error (the rating life's discretisation error) says what it is in its long name.

Adding a statistic is one entry in :data:`RESULT_VARIABLES`: its name (the variable's and the
producer's key), units, long name, standard name (None: CF has none) and the name of its error
partner (None: it has none). (CF's standard-name table, version 93, names no quantity of a
rolling bearing: every entry has None today; the modifier form is tested on a made-up one.)
The JSON-valued numbers (the characteristic frequencies, the ring's
natural frequencies, the warm-up's block means) are variables over a label or index dimension
(:data:`LIST_VARIABLES`).

A file written before results were variables (they were global attributes, and the power loss's
dimension was called ``source``) is read by :func:`upgrade`, which applies the same table.
"""

from __future__ import annotations

import json
from typing import NamedTuple

import numpy as np
import xarray as xr

from ..physics.frequencies import DEFECT_LABELS, DEFECT_MEANINGS, DEFECT_NAMES


def defect_variable(key: str, pure_rolling: bool = False) -> str:
    """The result variable of defect frequency ``key`` (physics/frequencies.DEFECT_NAMES):
    measured, or of pure rolling (analysis/defect_frequencies.py)."""
    return f"defect_frequency_{key}{'_pure_rolling' if pure_rolling else ''}_Hz"


class Quantity(NamedTuple):
    """One result: ``units`` (UDUNITS), ``long_name``, CF ``standard_name`` (None: none) and
    the name of its error variable (None: none), whose kind ``error_kind`` is
    ``"standard_error"`` (a statistic's) or ``"discretisation"``; ``nan_meaning`` says what a
    NaN value means where one can occur (None: it cannot). A 0/1 flag names what 0 and 1
    mean in ``flags`` (CF ``flag_meanings``, with ``flag_values`` 0 and 1, and no units)."""

    units: str
    long_name: str
    standard_name: str | None = None
    error: str | None = None
    error_kind: str = "standard_error"
    nan_meaning: str | None = None
    flags: str | None = None


def _stat(units, long_name, error):
    return Quantity(units, long_name, None, error)


#: every number a result states: variable name -> :class:`Quantity` (the module docstring)
RESULT_VARIABLES: dict[str, Quantity] = {
    # the kinematic reference (results/solution.py)
    "epicyclic_cage_speed_rad_s": Quantity("rad s-1", "epicyclic (pure-rolling) cage speed "
                                           "at the final inner-ring speed"),
    # time means and RMS over the recorded window, blocking errors (results/statistics.py)
    "mean_cage_speed_rad_s": _stat("rad s-1", "mean cage angular speed over the recorded "
                                   "window", "mean_cage_speed_stderr_rad_s"),
    "cage_slip_ratio": _stat("1", "cage slip ratio 1 - mean cage speed / epicyclic speed",
                             "cage_slip_ratio_stderr"),
    "mean_roller_spin_speed_rad_s": _stat("rad s-1", "mean roller spin speed relative to the "
                                          "cage over rollers and the recorded window",
                                          "mean_roller_spin_speed_stderr_rad_s"),
    "skew_rms_rad": _stat("rad", "root mean square of the roller skew angle over rollers and "
                          "time", "skew_rms_stderr_rad"),
    "rms_cage_force_N": _stat("N", "root mean square of the pocket force over rollers, ends "
                              "and time", "rms_cage_force_stderr_N"),
    # the mean peaks per roller pass (results/statistics.py)
    "roller_pass_peak_cage_force_N": _stat(
        "N", "mean over roller-pass periods of the largest |pocket force|",
        "roller_pass_peak_cage_force_stderr_N"),
    "roller_pass_peak_contact_pressure_Pa": _stat(
        "Pa", "mean over roller-pass periods of the largest slice Hertz pressure",
        "roller_pass_peak_contact_pressure_stderr_Pa"),
    "roller_pass_peak_skew_angle_rad": _stat(
        "rad", "mean over roller-pass periods of the largest |skew angle|",
        "roller_pass_peak_skew_angle_stderr_rad"),
    "roller_pass_peak_slip_velocity_m_s": _stat(
        "m s-1", "mean over roller-pass periods of the largest |slip velocity|",
        "roller_pass_peak_slip_velocity_stderr_m_s"),
    # the power loss and the friction torque over the window, all sources (statistics.py)
    "mean_power_loss_W": _stat("W", "mean total power loss over the recorded window",
                               "mean_power_loss_stderr_W"),
    "mean_friction_torque_N_mm": Quantity(
        "N mm", "mean total friction torque referred to the inner ring over the recorded "
        "window, in the catalogues' N mm", None, "mean_friction_torque_stderr_N_mm",
        nan_meaning="the inner ring stands still"),
    # rating life (results/rating_life.py): its error is that of the laminae (discretisation)
    "reference_rating_life_L10r_Mrev": Quantity(
        "1e6", "reference rating life L10r (ISO/TS 16281) in millions of revolutions", None,
        "reference_rating_life_L10r_error_Mrev", "discretisation"),
    "reference_rating_life_L10r_h": Quantity("h", "reference rating life L10r in hours at "
                                             "the inner-ring speed",
                                             nan_meaning="the inner ring stands still"),
    "reference_rating_life_L10r_slices_Mrev": Quantity(
        "1e6", "reference rating life L10r with the slices as laminae, in millions of "
        "revolutions"),
    "reference_rating_life_L10r_phase_averaged_Mrev": Quantity(
        "1e6", "reference rating life L10r averaged over positions of the roller set "
        "(engineering.phase_positions), in millions of revolutions"),
    "rating_life_laminae": Quantity("1", "number of laminae of the converged rating life"),
    "rating_life_converged": Quantity("1", "whether the rating life converged in laminae",
                                      flags="not_converged converged"),
    "rating_life_exponent_inner": Quantity("1", "exponent of the equivalent lamina loads, "
                                           "inner ring (ISO/TS 16281)"),
    "rating_life_exponent_outer": Quantity("1", "exponent of the equivalent lamina loads, "
                                           "outer ring (ISO/TS 16281)"),
    "rating_life_lamina_correction": Quantity("1", "laminae's correction of the run's "
                                              "slice-level rating life"),
    # the modified life (analysis/rating_life.py; with lubricant.contamination_factor only)
    "modified_rating_life_Lnmr_Mrev": Quantity(
        "1e6", "modified reference rating life L_nmr (ISO 16281, a_ISO of ISO 281 per lamina) "
        "in millions of revolutions", None, "modified_rating_life_Lnmr_error_Mrev",
        "discretisation"),
    "modified_rating_life_Lnmr_h": Quantity("h", "modified reference rating life L_nmr in "
                                            "hours at the inner-ring speed",
                                            nan_meaning="the inner ring stands still"),
    "kappa": Quantity("1", "viscosity ratio kappa = nu / nu_1 (ISO 281:2007) of the modified "
                      "life: nu of the raceway films, nu_1 at the record's mean inner-ring "
                      "speed (a thermal run's viscosity_ratio_kappa is the same number)"),
    "fatigue_load_limit_Cu_N": Quantity("N", "fatigue load limit C_u = C0 / 8.2 (ISO 281)"),
    "equivalent_reference_load_N": Quantity("N", "dynamic equivalent reference load P_ref "
                                            "(ISO/TS 16281)"),
    "basic_dynamic_load_rating_N": Quantity("N", "basic dynamic load rating C"),
    "edge_stress_factors": Quantity("1", "whether the ISO/TS 16281 edge stress factors were "
                                    "applied", flags="not_applied applied"),
    # the operating point (results/dataset.py)
    "radial_load_N": Quantity("N", "radial load on the inner ring at the start of the record"),
    "tangential_load_N": Quantity("N", "tangential load on the inner ring at the start of the "
                                  "record"),
    "moment_Nm": Quantity("N m", "moment on the inner ring at the start of the record"),
    "tangential_moment_Nm": Quantity("N m", "tangential moment on the inner ring at the "
                                     "start of the record"),
    "speed_rpm": Quantity("min-1", "inner-ring speed at the start of the record"),
    "unbalance_N": Quantity("N", "rotating unbalance force on the inner ring"),
    "unbalance_phase_deg": Quantity("degree", "phase of the unbalance force"),
    "axial_load_N": Quantity("N", "axial load on the inner ring"),
    # the solver (results/solution.py) and the start of its record
    "record_start_s": Quantity("s", "time at which the recorded window starts"),
    "initial_cage_speed_rad_s": Quantity("rad s-1", "cage speed of the torque-balance start"),
    # a static solve (results/dataset.py)
    "newton_iterations": Quantity("1", "Newton iterations of the quasi-static solve"),
    "residual_max_relative": Quantity("1", "largest relative residual of the quasi-static "
                                      "solve"),
    # a dynamic ring (results/dataset.py, results/vibration.py)
    "ring_mass_kg": Quantity("kg", "mass of the inner ring and shaft"),
    "ring_tilt_inertia_kg_m2": Quantity("kg m2", "tilt inertia of the inner ring and shaft"),
    "ring_support_stiffness_N_m": Quantity("N m-1", "stiffness of the inner ring's support"),
    "ring_support_damping_N_s_m": Quantity("N s m-1", "damping of the inner ring's support"),
    "nyquist_frequency_Hz": Quantity("Hz", "Nyquist frequency of the samples"),
    # cage whirl (results/whirl.py)
    "cage_guidance_clearance_m": Quantity("m", "radial clearance of the cage guidance"),
    "cage_whirl_speed_rad_s": Quantity("rad s-1", "mean whirl speed of the cage centre"),
    "cage_whirl_ratio": Quantity("1", "cage whirl speed / mean cage speed"),
    "cage_orbit_radius_max_m": Quantity("m", "largest radius of the cage centre's orbit"),
    "cage_orbit_radius_over_clearance": Quantity("1", "mean cage orbit radius / guidance "
                                                 "clearance"),
    "cage_orbit_radius_over_clearance_max": Quantity("1", "largest cage orbit radius / "
                                                     "guidance clearance"),
    "cage_orbit_radius_over_clearance_trend_per_revolution": Quantity(
        "1", "trend of the cage orbit radius / guidance clearance per cage revolution "
        "(> 0: growing orbit)"),
    # axial-load limits of a flanged bearing (results/flange.py)
    "static_load_rating_C0_N": Quantity("N", "basic static load rating C0"),
    "permissible_axial_load_N": Quantity("N", "permissible axial load of the catalogue (the "
                                         "smallest of its rules)"),
    "thermal_axial_load_limit_N": Quantity("N", "thermally permissible axial load F_ap "
                                           "(SKF)"),
    "flange_strength_limit_N": Quantity("N", "axial load limit of the flange strength"),
    "radial_axial_load_limit_N": Quantity("N", "axial load limit 0.5 F_r"),
    # until-steady warm-up (run/steady.py)
    "steady_state_reached": Quantity("1", "whether the warm-up met the steady-state criterion "
                                     "(numerics.until_steady) or hit the cap",
                                     flags="cap_reached steady"),
    "warmup_cage_revolutions_used": Quantity("1", "warm-up cage revolutions run before "
                                             "recording"),
    "steady_last_change": Quantity("1", "change of the block-mean cage speed over the last "
                                   "warm-up block / epicyclic speed"),
    "steady_drift_per_block": Quantity("1", "drift of the block-mean cage speed per warm-up "
                                       "block / epicyclic speed"),
    "steady_remaining_estimate": Quantity("1", "extrapolated remaining change of the cage "
                                          "speed / epicyclic speed (0: fluctuating, no drift)"),
    # the thermal network's oil (physics.thermal = "steady"; results/thermal_variables.py)
    "operating_viscosity_Pa_s": Quantity("Pa s", "oil dynamic viscosity where the raceway "
                                         "films form (mean of the ring and roller nodes; the "
                                         "record's)"),
    "operating_kinematic_viscosity": Quantity("mm2 s-1", "oil kinematic viscosity where the "
                                              "raceway films form (ASTM D341)"),
    "rated_viscosity": Quantity("mm2 s-1", "rated viscosity nu_1 of ISO 281:2007 at the "
                                "record's mean inner-ring speed and the pitch diameter"),
    "viscosity_ratio_kappa": Quantity("1", "viscosity ratio kappa = nu / nu_1 (ISO 281:2007) "
                                      "of the raceway films: the modified life's kappa, "
                                      "written with or without it"),
    "thermal_blocks": Quantity("1", "warm-up blocks the thermal coupling ran until the oil "
                               "temperature was steady"),
    "oil_temperature_last_change_K": Quantity("K", "largest change of a node temperature "
                                              "over the last block"),
    # the characteristic defect frequencies, measured and of pure rolling
    # (analysis/defect_frequencies.py)
    **{defect_variable(k): Quantity("Hz", f"{DEFECT_MEANINGS[k]} ({DEFECT_LABELS[k]}), from "
                                    "the run's mean cage and roller spin speeds over the "
                                    "recorded window (slip included), outer ring fixed")
       for k in DEFECT_NAMES},
    **{defect_variable(k, True): Quantity("Hz", f"{DEFECT_MEANINGS[k]} ({DEFECT_LABELS[k]}) "
                                          "of pure rolling at the final inner-ring speed, "
                                          "outer ring fixed")
       for k in DEFECT_NAMES},
    # a sweep's run (studies/sweep/worker.py)
    "run_cpu_time_s": Quantity("s", "CPU time of the worker for the whole run"),
}

#: numbers given as JSON: name -> (dimension, units, long name); a dict's keys label the
#: dimension (a string coordinate), a list's positions number it (from 1)
LIST_VARIABLES = {
    "characteristic_frequencies_Hz": ("frequency_name", "Hz", "characteristic frequency of "
                                      "the bearing at the final inner-ring speed (outer ring "
                                      "fixed)"),
    "ring_natural_frequencies_Hz": ("ring_mode", "Hz", "natural frequency of the inner ring "
                                    "on its support and the roller contacts"),
    "steady_block_means": ("warmup_block", "1", "block-mean cage speed of each warm-up block "
                           "/ epicyclic speed"),
}
#: the label coordinates those dimensions get (long names)
LIST_LABELS = {"frequency_name": "name of the characteristic frequency",
               "ring_mode": "ring mode number", "warmup_block": "warm-up block number"}


def run_variable(name: str) -> tuple[str, str]:
    """(units, long_name) of a run's result variable, for the studies' maps that carry it
    per point (one wording in one place)."""
    q = RESULT_VARIABLES[name]
    return q.units, q.long_name


def cf_attrs(name: str, units: str = "1", long_name: str = "", dtype=float) -> dict:
    """The CF attributes of result variable ``name`` (units and long name; a 0/1 flag's
    ``flag_values`` in ``dtype`` and ``flag_meanings`` instead of units); a name outside
    :data:`RESULT_VARIABLES` takes the ``units`` and ``long_name`` given."""
    q = RESULT_VARIABLES.get(name)
    if q is None:
        return {"units": units, "long_name": long_name}
    if q.flags:
        a = {"long_name": q.long_name, "flag_values": np.array([0, 1], dtype=dtype),
             "flag_meanings": q.flags}
    else:
        a = {"units": q.units, "long_name": q.long_name}
    if q.standard_name:
        a["standard_name"] = q.standard_name
    if q.nan_meaning:
        a["nan_meaning"] = q.nan_meaning
    return a


def error_names() -> dict[str, str]:
    """error variable -> the statistic it is the error of."""
    return {q.error: name for name, q in RESULT_VARIABLES.items() if q.error}


def error_attrs(parent: str) -> dict:
    """The attributes of the error variable of ``parent`` (the module docstring)."""
    q = RESULT_VARIABLES[parent]
    what = q.long_name
    if q.error_kind == "standard_error":
        attrs = {"units": q.units, "long_name": f"standard error of the {what}"}
        if q.standard_name:
            attrs["standard_name"] = f"{q.standard_name} standard_error"
        return attrs
    return {"units": q.units, "long_name": f"{q.error_kind} error estimate of the {what}"}


def result_names() -> set[str]:
    """Every name :func:`split_results` turns into a variable."""
    return set(RESULT_VARIABLES) | set(error_names()) | set(LIST_VARIABLES)


def split_results(attrs: dict) -> tuple[dict, dict]:
    """(variables, the other attributes) of a flat dict of a result's numbers and metadata:
    the entries of :data:`RESULT_VARIABLES` (and their errors) as 0-d variables, those of
    :data:`LIST_VARIABLES` as variables over their dimension (with its coordinate)."""
    rest, variables = dict(attrs), {}
    errors = error_names()
    for name, q in RESULT_VARIABLES.items():
        if name not in rest:
            continue
        value = _number(rest.pop(name))
        a = cf_attrs(name, dtype=value.dtype)
        if q.error and q.error in rest:
            a["ancillary_variables"] = q.error
        variables[name] = xr.Variable((), value, a)
    for name, parent in errors.items():
        if name in rest:
            variables[name] = xr.Variable((), _number(rest.pop(name)), error_attrs(parent))
    for name, (dim, units, long_name) in LIST_VARIABLES.items():
        if name in rest:
            variables.update(_list_variable(name, rest.pop(name), dim, units, long_name))
    return variables, rest


def _number(value):
    """An attribute's number as stored: ints stay ints, the rest float64."""
    v = np.asarray(value)
    return v.astype(np.int64) if v.dtype.kind in "iub" else v.astype(np.float64)


#: the dimensions of :data:`LIST_VARIABLES` labelled by name (their JSON is an object)
NAMED = ("frequency_name",)


def _list_variable(name, text, dim, units, long_name) -> dict:
    """The variable of a JSON number list (or, on a named dimension, object); ValueError
    naming the attribute when it is anything else."""
    values = json.loads(text) if isinstance(text, str) else text
    named = dim in NAMED
    if not isinstance(values, dict if named else list) or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool)
            for v in (values.values() if named else values)):
        raise ValueError(f"attribute '{name}' is not a JSON "
                         f"{'object' if named else 'list'} of numbers")
    if named:
        labels = np.array(list(values), dtype=object)
        numbers = np.array([float(v) for v in values.values()])
    else:
        numbers = np.array(values, dtype=float)
        labels = np.arange(1, numbers.size + 1)
    return {name: xr.Variable(dim, numbers, {"units": units, "long_name": long_name}),
            dim: xr.Variable(dim, labels, {"long_name": LIST_LABELS[dim]})}


def with_result_variables(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` with the results among its global attributes moved into variables."""
    variables, rest = split_results(ds.attrs)
    if not variables:
        return ds
    out = ds.assign(variables)
    out.attrs = rest
    return out


def value(ds: xr.Dataset, name: str, default=np.nan):
    """The result ``name`` of ``ds`` as a Python number: its variable, or (a Dataset still
    being made, or a file of the older format) its global attribute; ``default`` if neither."""
    if name in ds.variables and ds[name].ndim == 0:
        return ds[name].values.item()
    return ds.attrs.get(name, default)


def results_of(ds: xr.Dataset) -> dict:
    """name -> number of every 0-d result variable of ``ds`` (the summary a sweep stacks)."""
    names = set(RESULT_VARIABLES) | set(error_names())
    return {n: ds[n].values.item() for n in ds.data_vars if n in names and ds[n].ndim == 0}


def is_old_format(ds: xr.Dataset) -> bool:
    """True for a file whose results are global attributes and none a variable (or whose power
    loss is over ``source``): written before results were variables. A file with result
    variables is of the current format, whatever stray attribute it carries (a damaged or
    hand-edited one: :func:`stray_result_attributes`)."""
    if "source" in ds.dims:
        return True
    names = result_names()
    return bool(names & set(ds.attrs)) and not names & set(ds.data_vars)


def stray_result_attributes(ds: xr.Dataset) -> list[str]:
    """The global attributes of a current-format file named as results (no writer puts them
    there: a damaged or hand-edited file)."""
    return [] if is_old_format(ds) else sorted(result_names() & set(ds.attrs))


def upgrade(ds: xr.Dataset) -> xr.Dataset:
    """A Dataset of the older format (:func:`is_old_format`) in the current one: its results
    as variables, the power loss over ``loss_source``; a current one unchanged."""
    if not is_old_format(ds):
        return ds
    if "source" in ds.dims:
        ds = ds.rename({"source": "loss_source"})
    return with_result_variables(ds)


def flat(ds: xr.Dataset) -> dict:
    """The global attributes and the 0-d variables of ``ds`` as one dict of numbers and texts
    (what a summary line reads)."""
    out = dict(ds.attrs)
    out.update({str(n): ds[n].values.item() for n in ds.data_vars if ds[n].ndim == 0})
    return out
