"""Steady-state summaries and orbit phase-folding, computed from a result Dataset only.

Each summary quantity of a dynamic run has exactly one function here; :func:`summary` collects
them (the CLI prints it, :mod:`bearingdae.studies.sweep` stores it per sweep point). All of them
describe the *recorded window* of the run (after ``numerics.warmup_cage_revolutions``), which is
all a dynamic Dataset holds. :func:`one_orbit` resamples one roller over one orbit onto its
azimuth, the abscissa of the paper's Figures 12-24.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from .result_variables import value as result_value

#: name -> (units, long_name) of every summary quantity, in the order of :func:`summary`.
SUMMARY_VARIABLES = {
    "epicyclic_cage_speed_rad_s": ("rad s-1", "epicyclic (pure-rolling) cage speed "
                                   "n/2 (1 - D_w/d_m)"),
    "mean_cage_speed_rad_s": ("rad s-1", "mean cage speed over the recorded window"),
    "cage_slip_ratio": ("1", "cage slip ratio 1 - mean cage speed / epicyclic speed"),
    "cage_speed_drift": ("1", "change of the cage speed across the recorded window (least-"
                         "squares slope x window) / epicyclic speed; ~0 in a steady state"),
    "max_abs_skew_rad": ("rad", "largest |skew angle| of any roller in the window"),
    "skew_amplitude_rad": ("rad", "skew amplitude: max_t |skew angle| per roller, mean over "
                           "rollers"),
    "max_abs_slip_m_s": ("m s-1", "largest |slip velocity| of any slice, roller, race"),
    "load_weighted_slip_m_s": ("m s-1", "load-weighted mean |slip velocity| "
                               "sum(q |V|) / sum(q) over slices, rollers, races and time"),
    "slice_slip_spread_m_s": ("m s-1", "largest difference of inner-race slip velocity "
                              "between the slices of one roller"),
    "slice_traction_spread_N": ("N", "largest difference of inner-race traction force between "
                                "the slices of one roller"),
    "peak_cage_force_N": ("N", "largest |pocket force| on any roller end (every solver step: "
                          "cage_force_max)"),
    "rms_cage_force_N": ("N", "root mean square of the pocket force over rollers, ends, time"),
    "peak_slice_load_N": ("N", "largest slice contact force"),
}


def _has(ds: xr.Dataset, name: str) -> bool:
    return name in ds and ds.sizes.get("time", 0) > 0


def epicyclic_cage_speed(ds: xr.Dataset) -> float:
    """Pure-rolling cage speed Ω_e = ω_i/2 (1 − D_w/d_m) [rad/s] (theory.md §13), from the run."""
    return float(result_value(ds, "epicyclic_cage_speed_rad_s"))


def mean_cage_speed(ds: xr.Dataset) -> float:
    """Time mean of the cage speed over the recorded window [rad/s]."""
    return float(ds.cage_speed.mean()) if _has(ds, "cage_speed") else np.nan


def cage_slip_ratio(ds: xr.Dataset) -> float:
    """1 − Ω̄_c / Ω_e: 0 for an epicyclic cage, > 0 when the cage skids behind it."""
    epi = epicyclic_cage_speed(ds)
    return 1.0 - mean_cage_speed(ds) / epi if epi > 0 else np.nan


def cage_speed_drift(ds: xr.Dataset) -> float:
    """Least-squares slope of the cage speed times the window length, over Ω_e.

    A run still spinning down from its epicyclic start (light load) shows a clearly negative
    drift; a steady state fluctuates about a constant mean and gives a drift near 0.
    """
    epi = epicyclic_cage_speed(ds)
    if not _has(ds, "cage_speed") or ds.sizes["time"] < 3 or not epi > 0:
        return np.nan
    t = ds.time.values
    slope = np.polyfit(t - t[0], ds.cage_speed.values, 1)[0]
    return float(slope * (t[-1] - t[0]) / epi)


def _peak(ds: xr.Dataset, name: str) -> float:
    """Largest |name| of the recorded window: from ``<name>_max`` (every solver step,
    results/extremes.py) when the run has it, else from the samples."""
    if name + "_max" in ds and ds.sizes.get("time", 0) > 0:
        return float(ds[name + "_max"].max())
    return float(np.abs(ds[name]).max()) if _has(ds, name) else np.nan


def max_abs_skew(ds: xr.Dataset) -> float:
    """max over time and rollers of |θz| [rad] (every solver step: ``skew_angle_max``)."""
    return _peak(ds, "skew_angle")


def skew_amplitude(ds: xr.Dataset) -> float:
    """Skew amplitude [rad]: each roller's max_t |θz| over the window, averaged over rollers.

    With a window of about one cage revolution each roller passes once round the bearing, so
    this is the paper's "skew angle amplitude" over an orbit (Figs 18, 22), averaged over the
    rollers to damp the roller-to-roller scatter of single impacts.
    """
    if "skew_angle_max" in ds and ds.sizes.get("time", 0) > 0:  # every solver step
        return float(ds.skew_angle_max.mean("roller"))
    if not _has(ds, "skew_angle"):
        return np.nan
    return float(np.abs(ds.skew_angle).max("time").mean("roller"))


def max_abs_slip(ds: xr.Dataset) -> float:
    """max |V| over time, rollers, slices and both races [m/s] (theory.md §6; every solver
    step: ``slip_velocity_max``)."""
    return _peak(ds, "slip_velocity")


def load_weighted_slip(ds: xr.Dataset) -> float:
    """Σ q|V| / Σ q over time, rollers, slices, races [m/s].

    The slip where the load is: unloaded rollers may slide fast without consequence, so the
    maximum slip (:func:`max_abs_slip`) is set by the unloaded zone. Weighting by the slice
    load gives the slip that makes traction and frictional power (Σ μ q |V| ∝ it).
    """
    if not (_has(ds, "slip_velocity") and _has(ds, "contact_force")):
        return np.nan
    q = ds.contact_force
    return float((q * np.abs(ds.slip_velocity)).sum() / q.sum())


def _slice_spread(da: xr.DataArray) -> float:
    inner = da.sel(race="inner")
    return float((inner.max("slice") - inner.min("slice")).max())


def slice_slip_spread(ds: xr.Dataset) -> float:
    """Largest max_λ V − min_λ V of one roller on the inner race [m/s] (conclusions (1)-(3):
    "the difference in relative sliding speed between slices")."""
    return _slice_spread(ds.slip_velocity) if _has(ds, "slip_velocity") else np.nan


def slice_traction_spread(ds: xr.Dataset) -> float:
    """Largest max_λ F − min_λ F of one roller on the inner race [N] (conclusions (1)-(3):
    "the difference in drag force between slices")."""
    return _slice_spread(ds.traction_force) if _has(ds, "traction_force") else np.nan


def peak_cage_force(ds: xr.Dataset) -> float:
    """max |F_a|, |F_b| over time and rollers [N] (theory.md §8; every solver step:
    ``cage_force_max``)."""
    return _peak(ds, "cage_force")


def rms_cage_force(ds: xr.Dataset) -> float:
    """sqrt(mean F²) of the pocket forces over time, rollers and both ends [N]."""
    return float(np.sqrt((ds.cage_force ** 2).mean())) if _has(ds, "cage_force") else np.nan


def peak_slice_load(ds: xr.Dataset) -> float:
    """max slice contact force q over time, rollers, slices, races [N] (theory.md §4; every
    solver step: ``contact_force_max``)."""
    return _peak(ds, "contact_force")


_FUNCTIONS = {
    "epicyclic_cage_speed_rad_s": epicyclic_cage_speed,
    "mean_cage_speed_rad_s": mean_cage_speed,
    "cage_slip_ratio": cage_slip_ratio,
    "cage_speed_drift": cage_speed_drift,
    "max_abs_skew_rad": max_abs_skew,
    "skew_amplitude_rad": skew_amplitude,
    "max_abs_slip_m_s": max_abs_slip,
    "load_weighted_slip_m_s": load_weighted_slip,
    "slice_slip_spread_m_s": slice_slip_spread,
    "slice_traction_spread_N": slice_traction_spread,
    "peak_cage_force_N": peak_cage_force,
    "rms_cage_force_N": rms_cage_force,
    "peak_slice_load_N": peak_slice_load,
}


def summary(ds: xr.Dataset) -> dict[str, float]:
    """Every quantity of :data:`SUMMARY_VARIABLES` that the run provides (others omitted)."""
    if not isinstance(ds, xr.Dataset):
        raise TypeError(f"summary: 'ds' must be an xarray.Dataset (a run's result: "
                        f"bearingdae.simulate, or a run file opened with xarray), not "
                        f"{type(ds).__name__}")
    out = {}
    for name, fn in _FUNCTIONS.items():
        value = fn(ds)
        if not np.isnan(value):
            out[name] = value
    return out


# ---------------------------------------------------------------------------------------------
# One roller over one orbit (the paper's abscissa θX)
# ---------------------------------------------------------------------------------------------
#: Dynamic variables that the orbit figures use; their roller dimension is selected away.
ORBIT_VARIABLES = ("contact_force", "spin_speed", "orbit_speed", "skew_angle", "slip_velocity",
                   "traction_force", "cage_force")


def declared_orbit_variables() -> tuple[str, ...]:
    """The output variables over the rollers of the effects registered from outside the
    package (system/extensions.py): a sweep stacks their orbit with the others."""
    from ..system.effects import EXTENSIONS

    return tuple(n for e in EXTENSIONS for n, (dims, _, _) in (e.variables or {}).items()
                 if dims == ("roller",))


def orbit_roller(ds: xr.Dataset, prefer: int = 1) -> tuple[int, int] | None:
    """(roller, k): a roller whose unwrapped azimuth covers [2πk, 2π(k+1)] in the window.

    ``prefer`` is tried first, then the rollers in order; None if no roller completes an orbit
    inside the window (record a little more than one cage revolution to have one).
    """
    if "roller_azimuth" not in ds or ds.sizes.get("time", 0) < 2:
        return None
    az = ds.roller_azimuth.values  # (time, roller), unwrapped
    order = [prefer - 1] + [j for j in range(az.shape[1]) if j != prefer - 1]
    for j in order:
        if not 0 <= j < az.shape[1]:
            continue
        k = int(np.ceil(az[0, j] / (2 * np.pi) - 1e-12))
        if az[:, j].max() >= 2 * np.pi * (k + 1):
            return j + 1, k
    return None


def one_orbit(ds: xr.Dataset, points: int = 360, prefer: int = 1) -> xr.Dataset:
    """One roller over one full orbit, resampled onto its azimuth θX = 0 … 360° (deg).

    θX is measured from the radial-load line (centre of the loaded zone) in the direction of
    rotation, as in the paper's Figs 12-24. The roller is ``prefer`` if its recorded window
    covers a whole orbit from θX = 0, else the first one that does (attribute ``roller``).
    Values are linearly interpolated in time onto ``points`` equally spaced azimuths; peaks
    between samples are therefore smoothed (summaries use the raw samples).
    Raises ValueError if no roller completes an orbit in the window.
    """
    found = orbit_roller(ds, prefer)
    if found is None:
        raise ValueError(
            "no roller completes an orbit inside the recorded window "
            f"({ds.sizes.get('time', 0)} samples); record at least ~1.2 cage revolutions "
            "(numerics.cage_revolutions) to draw the orbit figures")
    roller, k = found
    one = ds.sel(roller=roller)
    phi = one.roller_azimuth.values - 2 * np.pi * k
    grid_deg = np.arange(points) * (360.0 / points)
    grid = np.radians(grid_deg)
    # Interpolate in time: find the time at which the roller passes each grid azimuth. The
    # azimuth is monotone in practice (orbit speed > 0); np.maximum.accumulate guards against
    # a backward flicker so that np.interp sees a non-decreasing abscissa.
    phi_mono = np.maximum.accumulate(phi)
    t = one.time.values
    t_grid = np.interp(grid, phi_mono, t)
    out = {}
    for name in (*ORBIT_VARIABLES, *declared_orbit_variables()):
        if name not in one:
            continue
        out[name] = one[name].interp(time=t_grid).drop_vars("time", errors="ignore").rename(
            time="azimuth")
        out[name].attrs = dict(one[name].attrs)
    orbit = xr.Dataset(out).drop_vars("roller", errors="ignore")
    orbit = orbit.assign_coords(azimuth=("azimuth", grid_deg, {
        "units": "degree", "long_name": f"azimuth θX of roller {roller} from the radial-load "
        "line, in the direction of rotation"}))
    orbit = orbit.assign_coords(time_at_azimuth=("azimuth", t_grid, {
        "units": "s", "long_name": "time at which the roller passes the azimuth"}))
    keep = [c for c in ("slice", "race", "end", "slice_position", "slice_position_bounds")
            if c in ds.coords]
    orbit = orbit.assign_coords({c: ds[c] for c in keep})
    orbit.attrs.update({"roller": int(roller), "orbit_index": int(k)})
    return orbit
