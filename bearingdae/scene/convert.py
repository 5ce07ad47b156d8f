"""Checked input -> frozen SI :class:`~bearingdae.scene.si.Scene` (pipeline stage 1).

:func:`_to_si` converts every user unit to SI exactly once and runs the cross-field checks that
need the geometry (rollers that fit, clearance against roller size, pockets, Newmark stability,
the until_steady block); parameters.py gives the presets, load_history.py the loads as one
history, pockets.py whether the pockets fit.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from .parameters import PRESETS, preset_names
from .load_history import axial_history, load_history
from .pockets import check_pockets_fit, pockets_fit
from .errors import SceneError
from .extensions import REGISTERED  # (their switches: Scene.extensions)
from .defects import check_defects
from .flanges import check_flanges
from .whirl import check_whirl
from .titles import DEFAULT_TITLE, expand_title
from .arguments import newmark_beta_min
from .schema import NumericsInput, RPM_TO_RAD_S, SceneInput, SpeedRamp
from .si import (Bearing, Cage, Dynamics, Engineering, Materials,
                 Numerics, Operating, Physics, Ring, Scene, Traction)
from .friction_model import apply_friction_model, rolling_law
from .switches import refuse_unswitched, refuse_unswitched_outputs, switched_resolved
from .thermal_switch import check_thermal

_REQUIRED_BEARING = (
    "rollers",
    "outer_diameter_mm",
    "bore_mm",
    "roller_diameter_mm",
    "roller_length_mm",
    "radial_clearance_mm",
)


def _to_si(m: SceneInput, origin: str) -> Scene:
    m, model_switches = apply_friction_model(m)  # "full": ordinary switches from here on
    b, o = m.bearing, m.operating
    missing = [k for k in _REQUIRED_BEARING if getattr(b, k) is None]
    if missing:
        raise SceneError(
            f"invalid scene ({origin}): [bearing] needs "
            + ", ".join(f"'bearing.{k}'" for k in missing)
            + f" (or a 'bearing.preset', one of {', '.join(preset_names())})."
        )
    mm = 1e-3
    profile = b.profile or ("end-crown" if b.crown_radius_mm else "flat")
    L = b.roller_length_mm
    Ls = b.effective_length_mm if b.effective_length_mm is not None else L
    Dw = b.roller_diameter_mm
    dm = b.pitch_diameter_mm if b.pitch_diameter_mm is not None else 0.5 * (
        b.outer_diameter_mm + b.bore_mm
    )
    refuse_unswitched(m, origin)  # a key without the switch that alone reads it
    errs: list[str] = []

    def bad(key: str, value: Any, rule: str) -> None:
        errs.append(f"  - 'bearing.{key}' = {value!r}: {rule}.")

    if b.bore_mm >= b.outer_diameter_mm:
        bad("bore_mm", b.bore_mm, f"must be smaller than outer_diameter_mm = {b.outer_diameter_mm}")
    if not (b.bore_mm + Dw < dm < b.outer_diameter_mm - Dw):
        bad(
            "roller_diameter_mm" if b.pitch_diameter_mm is None else "pitch_diameter_mm",
            Dw if b.pitch_diameter_mm is None else dm,
            f"the raceways (pitch diameter {dm:g} mm -/+ roller diameter {Dw:g} mm) must lie "
            f"between the bore {b.bore_mm:g} mm and the outer diameter {b.outer_diameter_mm:g} mm",
        )
    # Rollers fit on the pitch circle when the chord between neighbours exceeds D_w.
    chord = dm * math.sin(math.pi / b.rollers)
    if chord <= Dw:
        zmax = max(3, int(math.pi / math.asin(min(1.0, Dw / dm))) if Dw < dm else 0)
        bad(
            "rollers",
            b.rollers,
            f"{b.rollers} rollers of {Dw:g} mm do not fit on a {dm:g} mm pitch circle; "
            f"allowed range is 3..{zmax}",
        )
    if not (abs(b.radial_clearance_mm) < Dw):
        bad("radial_clearance_mm", b.radial_clearance_mm,
            f"must lie in (-{Dw:g}, {Dw:g}) mm (smaller than the roller diameter)")
    if Ls > L:
        bad("effective_length_mm", Ls, f"must not exceed roller_length_mm = {L:g}")
    crown = b.crown_radius_mm
    if profile in ("end-crown", "full-crown") and crown is None:
        bad("crown_radius_mm", None, f"is required for profile '{profile}' (in mm, > 0)")
    if profile == "end-crown" and crown is not None and (L - Ls) / 2 >= crown:
        bad("crown_radius_mm", crown,
            f"must exceed the crowned end length (L - L_s)/2 = {(L - Ls) / 2:g} mm")
    if profile == "full-crown" and crown is not None and L / 2 >= crown:
        bad("crown_radius_mm", crown, f"must exceed half the roller length, {L / 2:g} mm")
    if errs:
        raise SceneError(f"invalid scene ({origin}):\n" + "\n".join(errs))
    if isinstance(o.speed_rpm, SpeedRamp):
        if len(o.speed_rpm.times_s) != len(o.speed_rpm.values_rpm):
            raise SceneError(
                f"invalid scene ({origin}): 'operating.speed_rpm' ramp has "
                f"{len(o.speed_rpm.times_s)} times_s but {len(o.speed_rpm.values_rpm)} values_rpm;"
                " they must have the same length."
            )
        speed: Any = (tuple(o.speed_rpm.times_s), tuple(o.speed_rpm.values_rpm))
        speed_si: Any = (speed[0], tuple(v * RPM_TO_RAD_S for v in speed[1]))
    else:
        speed = float(o.speed_rpm)
        speed_si = speed * RPM_TO_RAD_S

    history, load_file, axial_in_file, load_file_sha256 = load_history(o, origin)
    # the loads at t = 0 (floats), and the largest |value| of each column of the history
    first = [float(v) for v in history[0][1:]] if history is not None else None
    peak = np.max(np.abs(history.rows), axis=0) if history is not None else None
    flanges, flange_resolved = check_flanges(
        b, axial_history(o, history, axial_in_file), origin, Dw)
    design = b.design_load_N
    if design is None:
        # Johns-Gohar/Lundberg profiles are designed for a roller load; Stribeck's maximum roller
        # load 4.08 F_r / Z (zero clearance, line contact) is the usual choice (a history: its
        # largest radial load).
        f_r = float(peak[1]) if history is not None else o.radial_load_N
        design = max(4.08 * f_r / b.rollers, 1.0)

    moments = ((float(peak[3]), float(peak[4])) if history is not None
               else (o.moment_Nm, o.tangential_moment_Nm))
    if any(moments):
        where = f"the load file '{o.load_file}'" if load_file else "'operating.moment_Nm'"
        if not m.physics.tilt:
            raise SceneError(
                f"invalid scene ({origin}): 'physics.tilt' = false cannot carry "
                f"{where} = {moments[0]:g} / 'operating."
                f"tangential_moment_Nm' = {moments[1]:g}: a moment needs the "
                "tilt unknowns; set physics.tilt = true or the moments to 0."
            )
        if m.numerics.slices < 2:
            raise SceneError(
                f"invalid scene ({origin}): 'numerics.slices' = {m.numerics.slices} cannot carry "
                f"{where} = {moments[0]:g}: one slice sits at x = 0 and "
                "has no lever arm; use at least 2 slices (allowed range [2, 1000] with a moment)."
            )
    refuse_unswitched_outputs(m, origin)  # an output variable without its switch
    cp = m.cage.pocket_clearance_mm
    if cp is None:
        cp = PRESETS[b.preset]["cage"]["pocket_clearance_mm"] if b.preset else 0.10
    if m.cage.pocket_clearance_mm is not None:  # a default that does not fit: build_model's
        check_pockets_fit(b.rollers, dm, Dw, L, cp, origin)  # error (static runs need no cage)
    # the complete TOML writes a derived clearance only where it fits: written out, a value
    # that does not fit is refused, and the stored scene would not load again
    cp_resolved = ({"pocket_clearance_mm": cp} if m.cage.pocket_clearance_mm is not None
                   or pockets_fit(b.rollers, dm, Dw, L, cp) else {})
    whirl, whirl_resolved = check_whirl(m, origin, cp, dm, Dw, L)
    t, n, c = m.traction, m.numerics, m.cage
    defects, waviness = check_defects(m, origin, b.rollers, dm, Dw, L)
    source = m.model_dump(exclude_none=True, mode="json")
    for table in ("defects", "waviness"):  # none: out of the TOML (default scenes keep their
        if not source[table]:  # text, sweep hashes and result files)
            source.pop(table)
    source["bearing"]["profile"] = profile
    if not source.get("life"):  # an empty [life] (every key at its default) stays out of the
        source.pop("life", None)  # TOML: default scenes keep their text and sweep hashes
    thermal, lubricant, thermal_resolved = check_thermal(m, origin, source)
    if m.lubricant.inlet_film_um is not None:  # (refused above without rolling resistance)
        lubricant = dataclasses.replace(lubricant, inlet_film_m=m.lubricant.inlet_film_um * 1e-6)
    newmark = _newmark_settings(n, origin)
    engineering = _engineering(m)
    # What defaults and other keys decided, for the complete TOML of the result files.
    resolved = {
        "bearing": {"pitch_diameter_mm": dm, "effective_length_mm": Ls, **flange_resolved,
                    **({"design_load_N": design} if profile == "logarithmic" else {})},
        "materials": {"roughness_um": round(engineering.roughness_m * 1e6, 12)},
        "cage": {**cp_resolved, **whirl_resolved},
        "lubricant": {"pressure_viscosity_GPa_inv":
                      round(engineering.pressure_viscosity_Pa_inv * 1e9, 12)},
        "life": {"edge_stress_factors": engineering.edge_stress_factors,
                 "phase_positions": engineering.phase_positions},
        "numerics": {"newmark_beta": newmark["newmark_beta"],
                     "newmark_gamma": newmark["newmark_gamma"]},
        "output": {"precision": m.output.precision or "float64"},
    }
    if model_switches:
        resolved.setdefault("physics", {}).update(model_switches)
    for table, values in (*switched_resolved(m).items(), *thermal_resolved.items()):
        resolved.setdefault(table, {}).update(values)
    _check_resolved(resolved, origin)
    scene = Scene(
        title=m.title or DEFAULT_TITLE,
        bearing=Bearing(
            rollers=b.rollers,
            outer_diameter_m=b.outer_diameter_mm * mm,
            bore_m=b.bore_mm * mm,
            pitch_diameter_m=dm * mm,
            roller_diameter_m=Dw * mm,
            roller_length_m=L * mm,
            effective_length_m=Ls * mm,
            crown_radius_m=(crown if crown is not None else math.inf) * mm,
            profile=profile,
            clearance_m=b.radial_clearance_mm * mm,
            design_load_N=design,
            flanges=flanges,
        ),
        materials=Materials(
            youngs_modulus_Pa=m.materials.youngs_modulus_GPa * 1e9,
            poisson_ratio=m.materials.poisson_ratio,
            density_kg_m3=m.materials.density_kg_m3,
        ),
        operating=Operating(
            speed_rpm=speed,
            speed_rad_s=speed_si,
            radial_load_N=first[0] if first is not None else o.radial_load_N,
            moment_Nm=first[2] if first is not None else o.moment_Nm,
            tangential_load_N=first[1] if first is not None else o.tangential_load_N,
            tangential_moment_Nm=first[3] if first is not None else o.tangential_moment_Nm,
            unbalance_N=o.unbalance_N,
            unbalance_phase_rad=math.radians(o.unbalance_phase_deg),
            load_history=history,
            load_file=load_file,
            load_file_sha256=load_file_sha256,
            axial_load_N=first[4] if first is not None else (o.axial_load_N or 0.0),
        ),
        numerics=Numerics(
            slices=m.numerics.slices,
            contact_smoothing_m=m.numerics.contact_smoothing_nm * 1e-9,
            static_tolerance=m.numerics.static_tolerance,
            static_max_iterations=m.numerics.static_max_iterations,
        ),
        physics=Physics(**{**m.physics.model_dump(exclude={"friction_model", *REGISTERED}),
                           "cage_whirl": bool(m.physics.cage_whirl),
                           "lubrication": m.physics.lubrication or "full-film",
                           "rolling_resistance": rolling_law(m.physics.rolling_resistance)}),
        traction=Traction(
            law=t.law, A_s_m=t.A_s_m, B_Pa=t.B_GPa * 1e9, C_s_m=t.C_s_m, D=t.D,
            alternative_bracket=t.bracket == "exp(-B/p)",
            velocity_scale_m_s=t.velocity_scale_m_s, slide_roll_A=t.slide_roll_A,
            slide_roll_B=t.slide_roll_B, slide_roll_C=t.slide_roll_C,
            slide_roll_D=t.slide_roll_D, rolling_speed_floor_m_s=t.rolling_speed_floor_m_s,
        ),
        cage=Cage(
            pocket_clearance_m=cp * mm, pocket_stiffness_N_m=c.pocket_stiffness_N_m,
            damping_ratio=c.damping_ratio, friction=c.friction, density_kg_m3=c.density_kg_m3,
            smoothing_m=c.smoothing_um * 1e-6,
            spin_friction_force_scale_N=c.spin_friction_force_scale_N, **whirl,
        ),
        lubricant=lubricant,
        engineering=engineering,
        ring=Ring(**m.ring.model_dump()),
        thermal=thermal,
        defects=defects,
        waviness=waviness,
        dynamics=Dynamics(
            rtol=n.rtol, atol=n.atol, warmup_cage_revolutions=n.warmup_cage_revolutions,
            cage_revolutions=n.cage_revolutions, defect_edges=n.defect_edges,
            samples_per_cage_revolution=n.samples_per_cage_revolution, max_steps=n.max_steps,
            **newmark, **_steady_settings(n, origin),
        ),
        output_variables=tuple(m.output.variables) if m.output.variables is not None else None,
        output_precision=m.output.precision or "float64",
        source=source,
        resolved=resolved,
        preset_citation=PRESETS[b.preset]["citation"] if b.preset else None,
    )
    return dataclasses.replace(scene, title=expand_title(scene.title, scene.operating))


def _check_resolved(resolved: dict, origin: str) -> None:
    """Every value a default or another key decided lies in its own key's range: the result
    file's complete TOML states it, and that text must load again (the same scene). One
    SceneError naming the key, its derived value and the range otherwise."""
    from .messages import in_field_range
    from .schema import _SECTIONS, allowed_range

    for table, values in resolved.items():
        model = _SECTIONS.get(table)
        if model is None or not isinstance(values, dict):
            continue
        for name, value in values.items():
            key = f"{table}.{name}"
            if (name not in model.model_fields or isinstance(value, bool)
                    or not isinstance(value, (int, float))):
                continue
            if not (math.isfinite(value) and in_field_range(key, value)):
                raise SceneError(
                    f"invalid scene ({origin}): '{key}', not given, is derived from the other "
                    f"keys as {value:.6g}, outside its allowed range {allowed_range(key)}; "
                    f"give '{key}' a value in that range or change the keys it derives from.")


def _engineering(m: SceneInput) -> Engineering:
    """Inputs of life and film in SI; absent keys take the defaults of si.Engineering."""
    kw: dict[str, Any] = {"basic_dynamic_load_rating_N": m.bearing.basic_dynamic_load_rating_N}
    if m.materials.roughness_um is not None:
        kw["roughness_m"] = m.materials.roughness_um * 1e-6
    if m.lubricant.pressure_viscosity_GPa_inv is not None:
        kw["pressure_viscosity_Pa_inv"] = m.lubricant.pressure_viscosity_GPa_inv * 1e-9
    if m.life.edge_stress_factors is not None:
        kw["edge_stress_factors"] = m.life.edge_stress_factors
    if m.life.phase_positions is not None:
        kw["phase_positions"] = m.life.phase_positions
    return Engineering(**kw)


def _newmark_settings(n: NumericsInput, origin: str) -> dict:
    """β and γ (defaults from hht_alpha: β = (1 - α)²/4, γ = 1/2 - α, Hilber et al. 1977),
    checked for unconditional stability of the linear scheme: γ ≥ 1/2, β ≥ (γ + 1/2)²/4."""
    a = n.hht_alpha
    beta = n.newmark_beta if n.newmark_beta is not None else 0.25 * (1.0 - a) ** 2
    gamma = n.newmark_gamma if n.newmark_gamma is not None else 0.5 - a
    beta_min = newmark_beta_min(gamma)
    if beta < beta_min * (1.0 - 1e-12):
        raise SceneError(
            f"invalid scene ({origin}): 'numerics.newmark_beta' = {beta!r} with newmark_gamma = "
            f"{gamma!r} is not unconditionally stable; allowed range [{beta_min:.6g}, 0.5] "
            "(β ≥ (γ + 1/2)²/4)."
        )
    return {"newmark_step_s": n.newmark_step_s, "newmark_beta": float(beta),
            "newmark_gamma": float(gamma), "hht_alpha": float(a),
            "newmark_error_estimate": n.newmark_error_estimate}


def _steady_settings(n: NumericsInput, origin: str) -> dict:
    """The until_steady keys (bearingdae/run/steady.py); the cap must hold at least one block."""
    if n.max_warmup_cage_revolutions < n.steady_block_cage_revolutions:
        raise SceneError(
            f"invalid scene ({origin}): 'numerics.max_warmup_cage_revolutions' = "
            f"{n.max_warmup_cage_revolutions!r} is shorter than one block "
            f"('numerics.steady_block_cage_revolutions' = {n.steady_block_cage_revolutions!r});"
            f" allowed range [{n.steady_block_cage_revolutions:g}, 1e+05].")
    return {"until_steady": n.until_steady, "steady_tolerance": n.steady_tolerance,
            "steady_block_cage_revolutions": n.steady_block_cage_revolutions,
            "max_warmup_cage_revolutions": n.max_warmup_cage_revolutions,
            "initial_speeds": _initial_speeds(n)}


def _initial_speeds(n: NumericsInput) -> str:
    """'auto' resolved: a search for the steady state starts from the torque-balance estimate
    of it (within ~0.05 % of the steady cage speed where measured, against a slow spin-down of
    tens of blocks from pure rolling); a plain run keeps the pure-rolling start."""
    if n.initial_speeds == "auto":
        return "torque_balance" if n.until_steady else "epicyclic"
    return n.initial_speeds
