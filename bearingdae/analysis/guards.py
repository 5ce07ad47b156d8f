"""Physical plausibility guards: warn when a scene or result leaves the model's range of validity.

Pure functions over a scene and a result Dataset (static or dynamic); the pipeline calls
:func:`check_plausibility` last, which emits one :class:`PlausibilityWarning` per finding and
records every finding in the Dataset attribute ``plausibility_warnings`` (JSON), and the checks
that ran in ``plausibility_checks`` (JSON), so a file says whether it was checked and what tripped.

What is checked, and why the model is not trusted beyond it:

Pressure and skew are judged at every solver step where the Dataset has the per-step extremes
(``contact_pressure_max``, ``skew_angle_max``: a bound is about the peak, which samples miss),
else at the samples.

* ``contact_pressure``: a slice Hertz pressure above 4 GPa. Bearing steel yields in the subsurface
  near 4 GPa (ISO 76 uses 4 GPa as the static load rating's contact stress for roller bearings);
  Palmgren's elastic line-contact law (theory.md §4) and the traction fit (theory.md §7) stop there.
* ``edge_loading``: a slice model cannot resolve the stress concentration at a roller end.
  Flagged when (a) the end slice carries the roller's peak slice load and more than
  ``EDGE_PEAK_RATIO`` times the heaviest roller's mean slice load, or (b) the contact reaches the
  roller end face: the approach of the two outer slices, extrapolated to x = ±L/2 with the
  profile drop there, is positive (always so for a loaded flat roller; a crown that works keeps
  the contact inside the roller even when the crowned part carries load).
* ``skew_vs_pocket``: the pockets are springs (theory.md §8); a real bar stops a roller end after
  c_p/2 plus a small elastic deflection. Flagged when |θz| L/2 > c_p/2 + the allowance
  max(``POCKET_COMPLIANCE_FRACTION`` c_p/2, ``POCKET_COMPLIANCE_MIN_M``).
* ``cage_slip``: mean cage speed more than ``CAGE_SLIP_LIMIT`` (50 %) away from the epicyclic
  speed: gross skidding, where the traction law (fitted to slip of order 1 m/s) and the
  quasi-static oil-air drag are far outside their data.
* ``film_parameter``: the EHL film parameter λ = h_min/σ (analysis/engineering.py) below
  ``LAMBDA_LIMIT`` (1) on a loaded slice: the surfaces' asperities touch (boundary
  lubrication), where the traction law (fitted to EHL traction, docs/theory.md §7) and the rating life
  (which assumes a separating film) no longer hold; wear and surface distress take over.
* ``scene_units``: values a key admits but that are almost certainly a unit slip in a field
  where tiny values are legitimate (a clearance of 10 nm is 0.01 mm written in metres).
* ``defect_sampling``: a ``[[defects]]`` entry that a contact crosses in fewer than
  ``DEFECT_CROSSING_SAMPLES`` samples: the recorded force drop (its depth, duration and
  impulse) is then not resolved by the samples, whatever the solver resolved between them.
  At pure rolling every contact runs over every surface at ω_c R_o (cage speed times outer
  race radius: the inner race's (ω_i - ω_c) R_i and a roller's ω_R r are equal to it), so a
  defect of length l is crossed in N l / (2π R_o) samples at N samples per cage revolution,
  at any speed; the finding names the N that would give ``DEFECT_CROSSING_SAMPLES``.
"""

from __future__ import annotations

import json
import warnings
from dataclasses import asdict, dataclass

import numpy as np

from ..util.warning_lines import BearingdaeWarning
from .result_variables import value as result_value

PRESSURE_LIMIT_PA = 4e9
#: End-slice load over the heaviest roller's mean slice load above which an end-peaked roller
#: is flagged: a uniform load has 1, a load falling linearly to zero at the far end has 2, so
#: beyond 2 the far end has lifted off and the load piles up at the edge.
EDGE_PEAK_RATIO = 2.0
#: Rollers (per race and time) carrying less than this fraction of the largest roller load are
#: not judged: their slice loads are regularisation residue (theory.md §5).
LOADED_FRACTION = 0.01
POCKET_COMPLIANCE_FRACTION = 0.1
POCKET_COMPLIANCE_MIN_M = 1e-6
CAGE_SLIP_LIMIT = 0.5
#: Below these a positive clearance is not a manufactured one: probably metres in a mm key.
TINY_RADIAL_CLEARANCE_M = 1e-7
TINY_POCKET_CLEARANCE_M = 1e-6
#: Above this an oil "viscosity" is more likely mPa s (cP) than Pa s.
LARGE_VISCOSITY_PA_S = 1.0
#: Film parameter below which a loaded slice runs in boundary lubrication.
LAMBDA_LIMIT = 1.0
#: Samples per crossing of a defect below which its recorded force drop is under-resolved
#: (the module docstring). Measured on defects/roller_spall (CHANGELOG.md): at 13 samples per
#: crossing doubling the rate moved the drop's peak 1.1 % and its impulse 0.6 %, at 26 by
#: 0.25 % and 0.3 %; the limit lies between
DEFECT_CROSSING_SAMPLES = 18


class PlausibilityWarning(BearingdaeWarning):
    """A scene or result outside the model's range of validity (the run itself completed)."""


class FilmParameterWarning(PlausibilityWarning):
    """λ = h_min/σ < 1 on a loaded slice. A finding of its own class because the run and static
    summaries state it in their 'minimum film' line (analysis/engineering.py): the command line
    prints that line instead of the warning, so that a run which is only in mixed lubrication
    (the default scene's λ ≈ 1) does not warn every time."""


@dataclass(frozen=True)
class Finding:
    check: str  #: name of the check (see the module docstring)
    message: str  #: one paragraph for the user
    value: float  #: the offending quantity (SI)
    limit: float  #: the limit it passed (SI)
    where: str = ""  #: where it happened ('t = 0.26 s, roller 2, slice 10, inner race'), if known


def check_plausibility(ds, scene):
    """Run every check that ``ds`` has the variables for; warn and record. Returns ``ds``."""
    ran, found = run_checks(ds, scene)
    record_findings(ds.attrs, ran, found)
    return ds


def run_checks(ds, scene, names=None) -> tuple[list[str], list[Finding]]:
    """(the checks that ran, their findings) of the checks ``names`` (default: all) on ``ds``,
    without warning; a streamed run (results/streamed_record.py) runs those over the samples on each
    block and merges them with :func:`worst_findings`."""
    found, ran = [], []
    for name, fn in CHECKS:
        if names is not None and name not in names:
            continue
        result = fn(ds, scene)
        if result is None:  # the Dataset lacks what this check needs
            continue
        ran.append(name)
        found += result
    return ran, found


def record_findings(attrs: dict, ran, found) -> None:
    """Record the checks and findings in ``attrs``, in the order of :data:`CHECKS`, and warn
    once per finding."""
    order = [name for name, _ in CHECKS]
    ran = sorted(set(ran), key=order.index)
    found = sorted(found, key=lambda f: order.index(f.check))
    attrs["plausibility_checks"] = json.dumps(ran)
    attrs["plausibility_warnings"] = json.dumps([asdict(f) for f in found])
    for f in found:
        warn(f)


#: the file name Python's warning line shows: the package, not a path of the machine that ran
#: it (a gallery page built elsewhere would otherwise print the build machine's paths)
WARNING_ORIGIN = "bearingdae"


def warn(f: Finding) -> None:
    """One PlausibilityWarning (FilmParameterWarning for the film check) for the finding ``f``,
    shown as 'bearingdae:0: PlausibilityWarning: ...' (no source path, no source line)."""
    category = FilmParameterWarning if f.check == "film_parameter" else PlausibilityWarning
    warnings.warn_explicit(f.message, category, WARNING_ORIGIN, 0, module=__name__)


#: checks whose finding is the smallest value, not the largest
SMALLEST_IS_WORST = ("film_parameter", "defect_sampling")


def worst_findings(a: list[Finding], b: list[Finding]) -> list[Finding]:
    """Findings of two parts of one record merged: per check (and limit: edge loading has two
    kinds) the worst value, the earlier part's on a tie. What the whole record gives, as every
    check reports only its worst sample."""
    best: dict = {}
    for f in list(a) + list(b):
        key = (f.check, f.limit)
        if f.check == "scene_units":
            best.setdefault((f.check, f.message), f)
            continue
        held = best.get(key)
        worse = (held is None or (f.value < held.value if f.check in SMALLEST_IS_WORST
                                  else f.value > held.value))
        if worse:
            best[key] = f
    return list(best.values())


def findings(ds) -> list[dict]:
    """The findings recorded in a Dataset (also one read back from NetCDF)."""
    return json.loads(ds.attrs.get("plausibility_warnings", "[]"))


# ---------------------------------------------------------------------------------------------
# The checks: each returns a list of findings, or None when the Dataset lacks its variables
# ---------------------------------------------------------------------------------------------
def _where(da, index) -> str:
    """'roller 3, slice 10, inner race, t = 0.0123 s' for a flat index into ``da``."""
    parts = []
    for dim, i in zip(da.dims, np.unravel_index(index, da.shape)):
        if dim == "time":
            parts.append(f"t = {float(da[dim][i]):.6g} s")
        elif dim == "race":
            parts.append(f"{da[dim].values[i]} race")
        elif dim in da.coords and dim in ("roller", "slice"):
            parts.append(f"{dim} {int(da[dim][i])}")
        else:
            parts.append(f"{dim} {i + 1}")
    return ", ".join(parts)


def _largest(ds, name: str):
    """(|values|, flat index of the largest, where it is) of ``name`` over the run: from
    ``<name>_max`` (every solver step, results/extremes.py) when the Dataset has it, else from
    the samples; None when there is nothing finite to judge."""
    extreme = name + "_max"
    if extreme in ds and ds.sizes.get("time", 0) > 0:
        a = ds[extreme]
        if not np.isfinite(a.values).any():
            return None
        i = int(np.nanargmax(a.values))
        when = float(ds[extreme + "_time"].values.flat[i])
        return a, i, f"{_where(a, i)}, t = {when:.6g} s"
    a = np.abs(ds[name])
    if not np.isfinite(a.values).any():
        return None
    i = int(np.nanargmax(a.values))
    return a, i, _where(a, i)


def contact_pressure(ds, scene) -> list[Finding] | None:
    if "contact_pressure" not in ds or ds.contact_pressure.size == 0:
        return None
    found = _largest(ds, "contact_pressure")
    if found is None:
        return []
    p, i, where = found
    worst = float(p.values.flat[i])
    if not worst > PRESSURE_LIMIT_PA:
        return []
    return [Finding("contact_pressure", (
        f"slice contact pressure {worst / 1e9:.3g} GPa ({where}) exceeds "
        f"{PRESSURE_LIMIT_PA / 1e9:g} GPa: beyond the elastic range of bearing steel, where "
        "Palmgren's line-contact law and the traction law are not valid; reduce the load or "
        "use a larger bearing."), worst, PRESSURE_LIMIT_PA)]


def edge_loading(ds, scene) -> list[Finding] | None:
    if "contact_force" not in ds or ds.contact_force.size == 0 or ds.sizes.get("slice", 0) < 3:
        return None  # with 1 or 2 slices every slice is an end slice
    q = ds.contact_force.transpose(..., "roller", "slice")
    # (..., roller, slice), copied into this order: the reductions over slices below ran ~10x
    # slower on the transposed view (stride of the race axis) than the copy costs
    Q = np.ascontiguousarray(q.values)
    k = Q.shape[-1]
    total = Q.sum(axis=-1)  # (..., roller)
    heaviest = total.max(axis=-1, keepdims=True)  # per race (and time)
    loaded = total > LOADED_FRACTION * heaviest
    if not loaded.any():
        return []
    out = []
    # (a) the end slice carries the roller's peak, measured against the mean slice load of the
    # heaviest roller (so a light roller tipped onto its end is judged by its absolute load).
    ref = np.where(heaviest > 0, heaviest / k, np.inf)
    end = np.maximum(Q[..., 0], Q[..., -1])
    peak = Q.max(axis=-1)
    ratio = np.where(loaded & (end >= peak), end / ref, 0.0)
    i = int(np.argmax(ratio))
    if ratio.flat[i] > EDGE_PEAK_RATIO:
        out.append(Finding("edge_loading", (
            f"roller edge loading: the end slice carries the roller's peak load, "
            f"{ratio.flat[i]:.3g} times the mean slice load of the heaviest roller "
            f"({_where(total_of(q), i)}; limit {EDGE_PEAK_RATIO:g}, the value of a load falling "
            "linearly to zero at the far end): the sliced line contact cannot resolve the "
            "stress concentration at the roller end; a crowned or logarithmic profile (or more "
            "slices, to let a crown act) avoids it."), float(ratio.flat[i]), EDGE_PEAK_RATIO))
    # (b) the contact reaches the roller end: the approach, linear in x apart from the profile
    # drop (ring and roller tilt, theory.md §4), extrapolated from the two outer slices to x = ±L/2.
    reach, j = _end_approach(Q, loaded, scene)
    if reach is not None:
        out.append(Finding("edge_loading", (
            f"roller edge loading: the contact reaches the roller end ({_where(total_of(q), j)}):"
            f" the approach extrapolated to the end face is {reach * 1e6:.3g} µm > 0, so the "
            "real pressure peaks at the edge, which the sliced line contact cannot resolve; a "
            "crowned or logarithmic profile keeps the contact inside the roller length."),
            reach, 0.0))
    return out


def _end_approach(Q, loaded, scene):
    """Largest approach extrapolated to a roller end face [m], and where; (None, 0) if none
    reaches it. Slices carrying less than LOADED_FRACTION of their roller's peak are not in
    contact (regularisation residue), so only ends whose two outer slices are loaded count."""
    from ..physics.contact import PALMGREN_EXPONENT, slice_stiffness
    from ..physics.geometry import make_geometry, profile_drop

    g = make_geometry(scene)
    b = scene.bearing
    k = g.slices
    stiffness = slice_stiffness(g.slice_width_m, g.roller_length_m, g.compliance_m2_N)

    def delta(q):  # approach of slice loads q (Palmgren); only where it is needed: the power
        return (np.maximum(q, 0.0) / stiffness) ** (1.0 / PALMGREN_EXPONENT)  # is the cost
    with np.errstate(divide="ignore"):  # the logarithmic profile is infinite at the end face
        c_end = float(profile_drop(np.array([0.5 * g.roller_length_m]), b.profile,
                                   g.roller_length_m, b.effective_length_m, b.crown_radius_m,
                                   b.design_load_N, g.compliance_m2_N)[0])
    if not np.isfinite(c_end):
        return None, 0
    c = g.profile_drop_m
    peak = Q.max(axis=-1)
    best, where = 0.0, 0
    for last, inner in ((k - 1, k - 2), (0, 1)):
        in_contact = loaded & (np.minimum(Q[..., last], Q[..., inner]) > LOADED_FRACTION * peak)
        # linear part ℓ = δ + c at the two slices (spacing w), extrapolated half a slice out
        l_last, l_inner = delta(Q[..., last]) + c[last], delta(Q[..., inner]) + c[inner]
        at_end = np.where(in_contact, l_last + 0.5 * (l_last - l_inner) - c_end, -np.inf)
        i = int(np.argmax(at_end))
        if at_end.flat[i] > max(best, LOADED_FRACTION * float(delta(Q.reshape(-1, k)[i]).max())):
            best, where = float(at_end.flat[i]), i
    return (best, where) if best > 0.0 else (None, 0)


def total_of(q):
    """The slice-summed array (labels for messages)."""
    return q.sum("slice")


def skew_vs_pocket(ds, scene) -> list[Finding] | None:
    if "skew_angle" not in ds or ds.skew_angle.size == 0 or not scene.physics.cage:
        return None
    half_L = 0.5 * scene.bearing.roller_length_m
    half_cp = 0.5 * scene.cage.pocket_clearance_m
    limit = half_cp + max(POCKET_COMPLIANCE_FRACTION * half_cp, POCKET_COMPLIANCE_MIN_M)
    found = _largest(ds, "skew_angle")
    if found is None:
        return []
    s, i, where = found
    excursion = float(s.values.flat[i]) * half_L
    if not excursion > limit:
        return []
    return [Finding("skew_vs_pocket", (
        f"roller skew {float(s.values.flat[i]):.3g} rad ({where}) moves a roller end "
        f"{excursion * 1e6:.3g} µm, more than the pocket allows ({limit * 1e6:.3g} µm: half the "
        f"pocket clearance {half_cp * 1e6:.3g} µm plus the bar's elastic allowance): the roller "
        "passes through the cage bar, which the spring pocket model permits but a real cage "
        "does not; check cage.pocket_clearance_mm and cage.pocket_stiffness_N_m."),
        excursion, limit)]


def cage_slip(ds, scene) -> list[Finding] | None:
    epi = float(result_value(ds, "epicyclic_cage_speed_rad_s"))
    if "cage_speed" not in ds or ds.sizes.get("time", 0) == 0 or not epi > 0:
        return None
    mean = float(ds.cage_speed.mean())
    slip = (epi - mean) / epi
    if not abs(slip) > CAGE_SLIP_LIMIT:
        return []
    return [Finding("cage_slip", (
        f"cage slip {100 * slip:.3g} % (mean cage speed {mean:.4g} rad/s against the epicyclic "
        f"{epi:.4g} rad/s) is beyond {100 * CAGE_SLIP_LIMIT:g} %: gross skidding, where the "
        "traction law and the oil-air drag model are far outside the data they were fitted "
        "to."), slip, CAGE_SLIP_LIMIT)]


def scene_units(ds, scene) -> list[Finding]:
    """Legitimate-looking tiny or huge values that are probably a unit slip."""
    out = []
    pd = scene.bearing.clearance_m
    if 0.0 < abs(pd) < TINY_RADIAL_CLEARANCE_M:
        out.append(Finding("scene_units", (
            f"'bearing.radial_clearance_mm' = {pd * 1e3:.6g} is {abs(pd) * 1e9:.3g} nm, below "
            f"any manufactured clearance; the key is in mm: if {pd * 1e3:.6g} is in m, write "
            f"{pd * 1e6:.6g} (it is treated as {pd * 1e9:.3g} nm, practically zero)."),
            abs(pd), TINY_RADIAL_CLEARANCE_M))
    cp = scene.cage.pocket_clearance_m
    if 0.0 < cp < TINY_POCKET_CLEARANCE_M:
        out.append(Finding("scene_units", (
            f"'cage.pocket_clearance_mm' = {cp * 1e3:.6g} is {cp * 1e9:.3g} nm, far below any "
            f"cage pocket; the key is in mm: if {cp * 1e3:.6g} is in m, write {cp * 1e6:.6g}."),
            cp, TINY_POCKET_CLEARANCE_M))
    mu = scene.lubricant.viscosity_Pa_s
    if mu > LARGE_VISCOSITY_PA_S:
        out.append(Finding("scene_units", (
            f"'lubricant.viscosity_Pa_s' = {mu:g} Pa s is a paste rather than a bearing oil "
            f"(ISO VG 68 at 40 °C is about 0.06 Pa s); the key is in Pa s: if {mu:g} is in "
            f"mPa s (cP), write {mu * 1e-3:g}."), mu, LARGE_VISCOSITY_PA_S))
    return out


def defect_crossing_samples(scene) -> list[float]:
    """Samples per crossing of each ``[[defects]]`` entry by a contact: N l / (2π R_o) (the
    module docstring)."""
    from ..physics.geometry import make_geometry

    r_o = make_geometry(scene).outer_race_radius_m
    n = scene.dynamics.samples_per_cage_revolution
    return [n * d.length_m / (2.0 * np.pi * r_o) for d in scene.defects]


def defect_sampling(ds, scene) -> list[Finding] | None:
    """A defect crossed in fewer than :data:`DEFECT_CROSSING_SAMPLES` samples (None: no
    defects, or no samples: a static solve)."""
    if not scene.defects or ds.sizes.get("time", 0) == 0:
        return None
    per = defect_crossing_samples(scene)
    k = int(np.argmin(per))
    if per[k] >= DEFECT_CROSSING_SAMPLES:
        return []
    n = scene.dynamics.samples_per_cage_revolution
    need = int(50 * np.ceil(n * DEFECT_CROSSING_SAMPLES / per[k] / 50.0))
    return [Finding("defect_sampling", (
        f"defect {k + 1} ({scene.defects[k].length_m * 1e3:g} mm long) is crossed in "
        f"{per[k]:.3g} samples: its recorded force drop is under-resolved; "
        f"numerics.samples_per_cage_revolution = {need} would give "
        f"{DEFECT_CROSSING_SAMPLES}."), per[k], DEFECT_CROSSING_SAMPLES)]


def film_parameter(ds, scene) -> list[Finding] | None:
    if "lambda_ratio" not in ds:
        return None
    lam = ds.lambda_ratio
    values = np.where(np.isfinite(lam.values), lam.values, np.inf)  # nan: unloaded slice
    if values.size == 0 or not np.isfinite(values).any():
        return []
    i = int(np.argmin(values))
    low = float(values.flat[i])
    if low >= LAMBDA_LIMIT:
        return []
    traction = ("the mixed-lubrication model shares the load with the asperities, but it is "
                "outside" if scene is not None and scene.physics.lubrication == "mixed" else
                "outside the EHL traction law and")
    return [Finding("film_parameter",
                    f"film parameter λ = h_min/σ = {low:.3g} < {LAMBDA_LIMIT:g} at "
                    f"{_where(lam, i)}: boundary lubrication (the asperities touch), {traction} "
                    "the rating life's separating film; raise "
                    "'lubricant.viscosity_Pa_s' or check 'materials.roughness_um'",
                    low, LAMBDA_LIMIT, _where(lam, i))]


CHECKS = (
    ("scene_units", scene_units),
    ("contact_pressure", contact_pressure),
    ("edge_loading", edge_loading),
    ("skew_vs_pocket", skew_vs_pocket),
    ("cage_slip", cage_slip),
    ("film_parameter", film_parameter),
    ("defect_sampling", defect_sampling),
)
