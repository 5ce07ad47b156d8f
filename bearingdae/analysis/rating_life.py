"""The ISO/TS 16281 rating life of a result, converged in laminae (post-processing).

Pipeline: analysis (reads a static solve's or a dynamic run's slice loads; the laws are in
physics/life.py; nothing here enters the DAE). docs/theory.md, "ISO/TS 16281 reference rating
life", states the method; in short:

* **On the slices** (:func:`slice_life`, :func:`lamina_power_sums`): the standard's sums with
  the run's slices as laminae — ``reference_rating_life_L10r_slices_Mrev``. With 10 slices this
  is not converged: on yang20 the end slice's centre lies where the crown begins, so the end
  slices are stiffer than the roller (the load distribution, not only the life sum, is off) and
  the edge factor 2.33 multiplies their unresolved peak (1.09e5 Mrev at 10 slices,
  9.58e5-9.59e5 at 320-1000).
* **Converged** (:func:`converged_life`): the same static problem (analysis/static_state.py:
  loads with the unbalance, the support, the flanges) solved again with n laminae as slices,
  n = 80, 160, 320, ... until L10r changes by less than :data:`LAMINAE_TOLERANCE`; the last
  change is the recorded error estimate (``reference_rating_life_L10r_error_Mrev``).
* **A dynamic run**: its own slice-level life (power means over every sample and roller) times
  the laminae's correction of the quasi-static life averaged over :data:`CORRECTION_PHASES`
  positions of the roller set, L_lam / L_slices, at the scene's loads and speed at t = 0.
* **Exponents** (:func:`ring_exponents`): 4 for the ring the load rotates against, 4.5 for
  the ring it stands still on: a stationary radial load (inner ring rotating), or, when an
  unbalance larger than the stationary radial load turns with the shaft, the other way round.
"""

from __future__ import annotations

import math

import numpy as np

from ..physics import life

#: first lamina count of the refinement (doubled until converged)
LAMINAE_START = 80
#: last lamina count tried (the life is then recorded with the change it still had)
LAMINAE_MAX = 1280
#: relative change of L10r between two lamina counts at which the refinement stops
LAMINAE_TOLERANCE = 0.01
#: positions of the roller set within one pitch for a dynamic run's lamina correction
CORRECTION_PHASES = 4


def rating(scene, geometry) -> tuple[float, str]:
    """(C [N], where it came from): the catalogue value or ISO 281 from the geometry."""
    e = scene.engineering
    if e.basic_dynamic_load_rating_N is not None:
        return float(e.basic_dynamic_load_rating_N), "bearing.basic_dynamic_load_rating_N"
    C = life.basic_dynamic_load_rating(geometry.rollers, 2.0 * geometry.roller_radius_m,
                                       geometry.roller_length_m, 2.0 * geometry.pitch_radius_m)
    return C, ("ISO 281:2007 Eq. 7 from the geometry: b_m = 1.1 (Table 1), f_c of Table 7 "
               "(its formula), L_we = roller length, one row")


def load_rotates_with_shaft(scene) -> bool:
    """True when the radial load turns with the inner ring: an unbalance larger than the
    largest stationary radial load |(F_r, F_t)| (of the load history, if any)."""
    o = scene.operating
    rows = o.load_history if o.load_history is not None else [(0.0, *o.loads)]
    stationary = max(math.hypot(r[1], r[2]) for r in rows)
    return o.unbalance_N > stationary


def ring_exponents(scene) -> tuple[float, float]:
    """(inner, outer) exponents of the equivalent lamina loads (ISO/TS 16281 Eqs. 61-64):
    4 for the ring rotating relative to the load, 4.5 for the ring stationary relative to it."""
    if load_rotates_with_shaft(scene):
        return life.EXPONENT_STATIONARY_RING, life.EXPONENT_ROTATING_RING
    return life.EXPONENT_ROTATING_RING, life.EXPONENT_STATIONARY_RING


def _edge_factors(scene, g) -> np.ndarray:
    return (life.edge_stress_factors(g.slices) if scene.engineering.edge_stress_factors
            else np.ones(g.slices))


def lamina_power_sums(scene, geometry, contact_force_N) -> tuple[np.ndarray, np.ndarray]:
    """Σ (f q)^p per slice over (sample, roller) of slice loads (sample, roller, slice, race),
    inner and outer ring (their exponents): a streamed run adds them up block by block and
    gives the means to :func:`life_attrs` (``equivalent``)."""
    f = _edge_factors(scene, geometry)
    p_i, p_o = ring_exponents(scene)
    q = np.maximum(f * np.asarray(contact_force_N, dtype=float).swapaxes(-1, -2), 0.0)
    return np.sum(q[..., 0, :] ** p_i, axis=(0, 1)), np.sum(q[..., 1, :] ** p_o, axis=(0, 1))


def slice_life(scene, geometry, contact_force_N, axes, equivalent=None) -> float:
    """L10r [10⁶ rev] with the slices of the loads (..., roller, slice, race) as laminae;
    ``axes``: the axes of the standard's means. ``equivalent``: the equivalent lamina loads
    (inner, outer) instead, ``contact_force_N`` then unused."""
    q_ci, q_ce = _lamina_ratings(scene, geometry)
    qe_i, qe_o = equivalent_loads(scene, geometry, contact_force_N, axes, equivalent)
    return float(life.reference_rating_life(qe_i, qe_o, q_ci, q_ce))


def _lamina_ratings(scene, g) -> tuple[float, float]:
    return life.lamina_ratings(rating(scene, g)[0], g.rollers,
                               g.roller_radius_m / g.pitch_radius_m, g.slice_width_m,
                               g.roller_length_m)


def equivalent_loads(scene, g, contact_force_N, axes, equivalent=None):
    """(inner, outer) equivalent lamina loads of :func:`slice_life`'s arguments."""
    if equivalent is not None:
        return equivalent
    f = _edge_factors(scene, g)
    p_i, p_o = ring_exponents(scene)
    q = np.asarray(contact_force_N)
    return (life.equivalent_lamina_load(f * q[..., 0], p_i, axes),
            life.equivalent_lamina_load(f * q[..., 1], p_o, axes))


def viscosity_ratio(scene, speed_rpm: float) -> tuple[float, float, float]:
    """(κ, ν [mm²/s], ν₁ [mm²/s]) of ISO 281:2007, the one place the record's κ = ν/ν₁ is
    computed (the modified life's ``kappa``, a thermal run's ``viscosity_ratio_kappa``): ν the
    kinematic viscosity the raceway films read, η/ρ of the scene's oil (with the thermal switch
    the films' temperature the run ended on: system/effects.set_temperatures); ν₁ of ISO 281
    at ``speed_rpm`` and the pitch diameter (physics/oil_viscosity.py). NaN κ and ν₁ where ν₁
    is undefined (a ring standing still)."""
    from ..physics.oil_viscosity import rated_viscosity

    oil = scene.lubricant
    nu_mm2_s = oil.viscosity_Pa_s / oil.oil_density_kg_m3 * 1e6
    nu1_mm2_s = rated_viscosity(speed_rpm, scene.bearing.pitch_diameter_m * 1e3)
    return nu_mm2_s / nu1_mm2_s, nu_mm2_s, nu1_mm2_s


def mean_speed_rpm(ring_sum_rad_s: float, samples: int) -> float:
    """The record's mean inner-ring speed [r/min] from the sum of its samples' speeds [rad/s]:
    the speed of a dynamic run's life hours and of its κ (:func:`viscosity_ratio`)."""
    return ring_sum_rad_s / samples * 60.0 / (2.0 * np.pi)


def modification(scene, geometry, speed_rpm: float) -> dict | None:
    """What the modified life needs (None without ``lubricant.contamination_factor``): κ of
    :func:`viscosity_ratio` at ``speed_rpm``, C_u (ISO 281 from ISO 76's C0) and e_C C_u / C."""
    from ..physics.flange import basic_static_load_rating

    e_c = scene.lubricant.contamination_factor
    if e_c is None:
        return None
    b = scene.bearing
    C0 = basic_static_load_rating(b.rollers, b.roller_diameter_m, b.roller_length_m,
                                  b.pitch_diameter_m)
    C_u = life.fatigue_load_limit(C0, b.pitch_diameter_m)
    return {"kappa": viscosity_ratio(scene, speed_rpm)[0], "contamination_factor": float(e_c),
            "fatigue_load_limit_Cu_N": C_u,
            "ec_cu_over_c": e_c * C_u / rating(scene, geometry)[0]}


def modified_slice_life(scene, geometry, contact_force_N, axes, mod: dict,
                        equivalent=None) -> float:
    """L_nmr [10⁶ rev] with the slices as laminae (physics/life.py): each lamina's life scaled
    by its a_ISO at κ and its own load ratio; arguments as :func:`slice_life`'s, ``mod`` of
    :func:`modification`."""
    q_ci, q_ce = _lamina_ratings(scene, geometry)
    qe_i, qe_o = equivalent_loads(scene, geometry, contact_force_N, axes, equivalent)
    n = np.size(qe_i) + np.size(qe_o)  # the laminae of the sum, both rings
    a_i = life.a_iso(mod["kappa"], life.lamina_load_ratio(mod["ec_cu_over_c"], qe_i, q_ci, n))
    a_o = life.a_iso(mod["kappa"], life.lamina_load_ratio(mod["ec_cu_over_c"], qe_o, q_ce, n))
    return float(life.modified_reference_rating_life(qe_i, qe_o, q_ci, q_ce, a_i, a_o))


def position_loads(scene, geometry, fractions, starts=None):
    """Static slice loads (position, roller, slice, race) [N] with the roller set turned by
    each of ``fractions`` of a roller pitch (analysis/static_state.py: the scene's loads,
    support and flanges), and the solutions' unknowns (warm starts of a finer solve)."""
    from .static_state import scene_static, turned_azimuths

    loads, zs = [], []
    for i, fraction in enumerate(fractions):
        z0 = None if starts is None else starts[i]
        sol = scene_static(scene, geometry, turned_azimuths(geometry, fraction), z0,
                           newton_count=False)[0]
        cs = sol.contact
        loads.append(np.stack([cs.load_inner_N, cs.load_outer_N], axis=-1))
        # with flanges z is the flange state, a poor start of the plain Newton: none then
        zs.append(sol.z if scene.bearing.flanges is None else None)
    return np.array(loads), zs


#: the last :func:`converged_life` answers, newest last: (key, answer); a notebook, a study or a
#: test session that runs one bearing several times (other windows, tolerances or outputs)
#: solves its static problems once; ~0.1-0.3 s of static solves a run
_MEMO: list = []
_MEMO_SIZE = 32


def _memo_key(scene, fractions, mod: dict | None) -> tuple:
    """What :func:`converged_life` depends on: the scene without the keys it never reads
    (the run's window, IDA's tolerances and step limit, the outputs, the title), the
    positions and the modification's inputs. Everything else counts, so that a scene that
    differs in anything the static problem could read is solved afresh."""
    from dataclasses import replace

    window = replace(scene.dynamics, rtol=0.0, atol=0.0, warmup_cage_revolutions=0.0,
                     cage_revolutions=0.0, samples_per_cage_revolution=0, max_steps=0)
    neutral = replace(scene, title="", output_variables=None, output_precision="float64",
                      dynamics=window)
    return (neutral, tuple(float(f) for f in fractions),
            None if mod is None else tuple(sorted(mod.items())))


def converged_life(scene, fractions, mod: dict | None = None) -> dict:
    """:func:`solve_converged_life`, remembered for the last :data:`_MEMO_SIZE` problems (the
    same numbers: a deterministic solve of the same problem)."""
    key = _memo_key(scene, fractions, mod)
    for i, (k, answer) in enumerate(_MEMO):
        if k == key:
            _MEMO.append(_MEMO.pop(i))
            return dict(answer)
    answer = solve_converged_life(scene, fractions, mod)
    _MEMO.append((key, dict(answer)))
    del _MEMO[:-_MEMO_SIZE]
    return answer


def solve_converged_life(scene, fractions, mod: dict | None = None) -> dict:
    """The quasi-static L10r averaged over the positions ``fractions`` (of a roller pitch),
    on the scene's slices and converged in laminae: {"slices", "laminae_Mrev", "laminae",
    "error_Mrev", "converged"}; with ``mod`` (:func:`modification`) also L_nmr on the same
    laminae, {"modified_slices", "modified_Mrev", "modified_error_Mrev"} (its change between
    the last two counts). Each lamina count n is the same static problem solved with n
    slices (the previous count's unknowns as its start). A solve that fails ends the
    refinement with the last count that worked and an infinite error estimate (the run's own
    result is kept whatever happens here)."""
    from ..physics.geometry import make_geometry
    from ..solvers.flange_static import FlangeSettleError
    from ..solvers.static import StaticConvergenceError
    from .static_state import with_slices

    failures = (StaticConvergenceError, FlangeSettleError, np.linalg.LinAlgError)
    g = make_geometry(scene)
    try:
        q, starts = position_loads(scene, g, fractions)
        L = slice_life(scene, g, q, (0, 1))
    except failures:
        return {"slices": math.nan, "laminae_Mrev": math.nan, "laminae": g.slices,
                "error_Mrev": math.inf, "converged": False, "modified_slices": math.nan,
                "modified_Mrev": math.nan, "modified_error_Mrev": math.inf}
    out = {"slices": L}
    lnm = [modified_slice_life(scene, g, q, (0, 1), mod)] if mod is not None else None
    n, previous, change = max(LAMINAE_START, g.slices), None, math.inf
    while True:
        sc = with_slices(scene, n)
        gn = make_geometry(sc)
        try:
            q, starts = position_loads(sc, gn, fractions, starts)
        except failures:
            if previous is None:
                n, L, change = g.slices, out["slices"], math.inf
            else:
                n, L, change = n // 2, previous, math.inf
            if lnm is not None:
                lnm.append(None)  # failed: the last count's life, an infinite error
            break
        L = slice_life(sc, gn, q, (0, 1))
        if lnm is not None:
            lnm.append(modified_slice_life(sc, gn, q, (0, 1), mod))
        if previous is not None:  # (an unloaded bearing: inf at every count, no change)
            change = 0.0 if L == previous else abs(L - previous)
        if change <= LAMINAE_TOLERANCE * L or n >= LAMINAE_MAX:
            break
        previous, n = L, 2 * n
    out.update(laminae_Mrev=L, laminae=n, error_Mrev=change,
               converged=bool(change <= LAMINAE_TOLERANCE * L))
    if lnm is not None:
        out.update(_modified_refinement(lnm))
    return out


def _modified_refinement(lnm: list) -> dict:
    """L_nmr of :func:`converged_life` from its values at each count (the slices' first; None
    for a count whose solve failed): the last value and its change from the one before (as
    L10r's error estimate)."""
    if lnm[-1] is None:
        return {"modified_slices": lnm[0], "modified_Mrev": lnm[-2],
                "modified_error_Mrev": math.inf}
    last = lnm[-1]
    change = math.inf if len(lnm) < 3 else (0.0 if last == lnm[-2] else abs(last - lnm[-2]))
    return {"modified_slices": lnm[0], "modified_Mrev": last, "modified_error_Mrev": change}


def _corrected(run_slices_Mrev: float, slices_Mrev: float, laminae_Mrev: float,
               error_Mrev: float) -> tuple[float, float, float]:
    """(correction, life, error) of a dynamic run's slice-level life ``run_slices_Mrev``: times
    the laminae's correction of the quasi-static life (its life on the slices and on converged
    laminae), with the quasi-static life's relative error."""
    correction = laminae_Mrev / slices_Mrev if slices_Mrev > 0 else 1.0
    if not np.isfinite(correction):  # an unloaded bearing (inf / inf), a failed solve
        correction = 1.0
    L = run_slices_Mrev * correction
    if error_Mrev == 0.0:
        err = 0.0
    elif np.isfinite(laminae_Mrev) and laminae_Mrev > 0:
        err = L * error_Mrev / laminae_Mrev  # the same relative error
    else:
        err = math.inf
    return correction, L, err


def life_attrs(scene, geometry, life_Mrev: float, slices_Mrev: float, laminae: int,
               error_Mrev: float, speed_rpm: float, method: str,
               modified: tuple | None = None) -> dict:
    """The life attributes of a result from its converged L10r (``life_Mrev``); a life whose
    error estimate stays above :data:`LAMINAE_TOLERANCE` at :data:`LAMINAE_MAX` laminae (a
    flat roller loaded to its ends: the edge factors converge at first order) is recorded
    with ``rating_life_converged = 0`` and its error. ``modified``: (L_nmr [Mrev], its error
    [Mrev], :func:`modification`'s dict), with ``lubricant.contamination_factor`` only."""
    C, origin = rating(scene, geometry)
    p_i, p_o = ring_exponents(scene)
    turning = "the load turns with the inner ring" if load_rotates_with_shaft(scene) else \
        "the load stands still (the inner ring turns against it)"
    attrs = {
        "reference_rating_life_L10r_Mrev": float(life_Mrev),
        "reference_rating_life_L10r_h": float(life.life_hours(life_Mrev, speed_rpm)),
        "reference_rating_life_L10r_error_Mrev": float(error_Mrev),
        "reference_rating_life_L10r_slices_Mrev": float(slices_Mrev),
        "rating_life_laminae": int(laminae),
        "rating_life_converged": int(bool(error_Mrev <= LAMINAE_TOLERANCE * life_Mrev)),
        "rating_life_exponent_inner": float(p_i),
        "rating_life_exponent_outer": float(p_o),
        "equivalent_reference_load_N": float(life.equivalent_reference_load(C, life_Mrev)),
        "basic_dynamic_load_rating_N": float(C),
        "basic_dynamic_load_rating_source": origin,
        "edge_stress_factors": int(scene.engineering.edge_stress_factors),
        "rating_life_method": (
            f"ISO/TS 16281:2008 laminae, {method}; {turning}: equivalent lamina loads with "
            f"exponent {p_i:g} (inner ring), {p_o:g} (outer ring); converged when L10r "
            f"changes by less than {LAMINAE_TOLERANCE:.0%} between n/2 and n laminae (error "
            "estimate: that change); modified life a_ISO not applied"),
    }
    if modified is not None:  # (L10r itself stays without a_ISO)
        attrs["rating_life_method"] = attrs["rating_life_method"].replace(
            "modified life a_ISO not applied", "a_ISO applied in L_nmr alone "
            "(modified_rating_life_method)")
    return attrs | _modified_attrs(modified, speed_rpm)


def _modified_attrs(modified: tuple | None, speed_rpm: float) -> dict:
    """The modified life's attributes (none without it); the method text says how."""
    if modified is None:
        return {}
    L, err, mod = modified
    return {
        "modified_rating_life_Lnmr_Mrev": float(L),
        "modified_rating_life_Lnmr_error_Mrev": float(err),
        "modified_rating_life_Lnmr_h": float(life.life_hours(L, speed_rpm)),
        "kappa": float(mod["kappa"]),
        "fatigue_load_limit_Cu_N": float(mod["fatigue_load_limit_Cu_N"]),
        "modified_rating_life_method": (
            f"ISO 16281:2025 from the laminae: each lamina's life scaled by its a_ISO (ISO "
            f"281:2007, radial roller bearings) at kappa = {mod['kappa']:.4g} and its own load "
            "ratio e_C C_u/P_k, P_k = C N^(4/15) (q_e/q_c)^(6/5) the reference load of N laminae "
            f"all loaded as it is, e_C = {mod['contamination_factor']:g}, C_u = C0/8.2 "
            "(C0 of ISO 76 from the geometry); error estimate: its change between the last "
            "two lamina counts, as L10r's"),
    }


def static_life_attrs(scene, geometry, speed_rpm: float) -> dict:
    """Life attributes of a static solve: the standard's one position, converged."""
    mod = modification(scene, geometry, speed_rpm)
    c = converged_life(scene, [0.0], mod)
    modified = (c["modified_Mrev"], c["modified_error_Mrev"], mod) if mod else None
    return life_attrs(scene, geometry, c["laminae_Mrev"], c["slices"], c["laminae"],
                      c["error_Mrev"], speed_rpm, "the static problem solved again with the "
                      "laminae as slices", modified)


def dynamic_life_attrs(scene, geometry, slices_Mrev: float, samples: int,
                       speed_rpm: float, equivalent=None) -> dict:
    """Life attributes of a dynamic run from its slice-level L10r (power means over every
    sample and roller) and the laminae's correction of the phase-averaged quasi-static life;
    L_nmr likewise from the run's equivalent slice loads ``equivalent`` (inner, outer; needed
    with ``lubricant.contamination_factor`` only)."""
    mod = modification(scene, geometry, speed_rpm)
    c = converged_life(scene, np.arange(CORRECTION_PHASES) / CORRECTION_PHASES, mod)
    correction, L, err = _corrected(slices_Mrev, c["slices"], c["laminae_Mrev"],
                                    c["error_Mrev"])
    modified = None
    if mod is not None:
        run = modified_slice_life(scene, geometry, None, None, mod, equivalent)
        modified = (*_corrected(run, c["modified_slices"], c["modified_Mrev"],
                                c["modified_error_Mrev"])[1:], mod)
    attrs = life_attrs(scene, geometry, L, slices_Mrev, c["laminae"], err, speed_rpm,
                       f"the run's slice-level life times the laminae's correction "
                       f"{correction:.6g} of the quasi-static life averaged over "
                       f"{CORRECTION_PHASES} positions of the roller set (scene loads and "
                       "speed at t = 0)", modified)
    attrs["rating_life_lamina_correction"] = float(correction)
    attrs["rating_life_time_average"] = (
        "power means of the slice loads over every recorded sample and roller "
        f"({samples} samples x {geometry.rollers} rollers)")
    return attrs


def summed_life_attrs(model, sums, samples: int, ring_sum_rad_s: float) -> dict:
    """The life attributes of a dynamic run from sums over the record's blocks: ``sums`` of
    :func:`lamina_power_sums` (inner, outer), the number of samples and the sum of the
    inner-ring speed over them (a streamed run; equal to the whole record's to round-off)."""
    g, scene = model.geometry, model.scene
    if samples == 0:
        return {}
    n = samples * g.rollers
    p_i, p_o = ring_exponents(scene)
    qe = ((sums[0] / n) ** (1.0 / p_i), (sums[1] / n) ** (1.0 / p_o))
    speed_rpm = mean_speed_rpm(ring_sum_rad_s, samples)
    L = slice_life(scene, g, None, None, equivalent=qe)
    return dynamic_life_attrs(scene, g, L, samples, speed_rpm, qe)
