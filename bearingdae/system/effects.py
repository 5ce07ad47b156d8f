"""The declared effects and the generic machinery that iterates over them (system layer).

Every effect declares itself once (system/effect.py, at the end of its module; the core model
and the dynamic ring, which have no module of their own, here). From :data:`EFFECTS` come: the
model's parameter values (:func:`effect_parameters`), the power sources of a scene and their
names, where their heat goes (:func:`heat_partition`), the power loss by source of recorded
samples (:func:`power_by_source`) and the oil viscosity a thermal run sets
(:func:`set_oil_temperature`). The order of :data:`EFFECTS` is the order of the sources in the
``loss_source`` coordinate and of the sums over effects.
"""

from __future__ import annotations

import numpy as np

from ..physics import power as law
from . import flange, mixed, rolling_resistance, thermal_network, whirl
from .effect import BULK_OIL, RACEWAY_FILM, Effect, Source, Viscosity, viscosity_entry
from .layout import RING_RATES
from .optional import APART, marker_of
from .residual import PARAM_NAMES

#: the dynamic ring's parameters (system/residual.py; the ring body of theory.md §15)
RING_PARAMS = ("ring_dyn", "ring_m", "ring_I", "sup_k", "sup_c")


def _core_power(model, t, values, p, P, drive) -> None:
    """The pockets' and the lubricant's sources of every run (physics/power.py); ``p`` the
    core's parameters by name. The raceway sources are :func:`power_by_source`'s."""
    orbit, spin = values["orbit_speed"], values["spin_speed"]
    zero = np.zeros(np.asarray(t).size)
    if p["has_cage"] > 0.5:
        P["pocket_friction"], P["pocket_impact"] = law.pocket_powers(
            values["cage_force"], orbit, spin, values["skew_rate"], values["cage_speed"],
            p["L"], p["r"], p["Rm"], p["mu_c"], p["spin_scale"], p["spin_f"])
    else:
        P["pocket_friction"] = P["pocket_impact"] = zero
    if p["has_drag"] > 0.5:
        wc = values["cage_speed"] if p["has_cage"] > 0.5 else zero
        P["orbit_drag"], P["roller_churning"], P["cage_churning"] = law.lubricant_powers(
            orbit, spin, wc, p["Rm"], p["r"], p["L"], p["cage_ri"], p["cage_ro"], p["rho_e"],
            p["mu_oil"])
    else:
        P["orbit_drag"] = P["roller_churning"] = P["cage_churning"] = zero


#: the core model's sources (docs/theory.md §6-9); raceway traction heats the two steel
#: surfaces of the contact equally (equal effusivities, Blok's partition at equal speeds),
#: pocket contacts roller and cage, drag and churning shear the oil
CORE_SOURCES = (
    Source("raceway_inner", "inner raceway traction (slip x traction force)",
           (0.5, 0.0, 0.5, 0.0, 0.0)),
    Source("raceway_outer", "outer raceway traction (slip x traction force)",
           (0.0, 0.5, 0.5, 0.0, 0.0)),
    Source("pocket_friction", "roller-cage pocket friction", (0.0, 0.0, 0.5, 0.5, 0.0)),
    Source("pocket_impact", "roller-cage pocket contact (damping and spring)",
           (0.0, 0.0, 0.5, 0.5, 0.0)),
    Source("orbit_drag", "oil-air drag on the orbiting rollers", (0.0, 0.0, 0.0, 0.0, 1.0)),
    Source("roller_churning", "churning of the roller end faces", (0.0, 0.0, 0.0, 0.0, 1.0)),
    Source("cage_churning", "churning of the cage side faces", (0.0, 0.0, 0.0, 0.0, 1.0)),
)

DYNAMIC_RING = Effect(name="dynamic_ring", switch="ring", params=RING_PARAMS,
                      unknowns=RING_RATES)

_OPTIONAL = (DYNAMIC_RING, flange.EFFECT, whirl.EFFECT, rolling_resistance.EFFECT,
             mixed.EFFECT, thermal_network.EFFECT)
CORE = Effect(name="core", switch=None,
              params=tuple(n for n in PARAM_NAMES
                           if not any(n in e.params for e in _OPTIONAL)),
              viscosity_params=(Viscosity("mu_oil", BULK_OIL),), sources=CORE_SOURCES, power=_core_power)
#: every effect, the core first, then those registered from outside the package
EFFECTS = (CORE, *_OPTIONAL)
#: the effects registered from outside the package (system/extensions.register_effect)
EXTENSIONS: tuple[Effect, ...] = ()
# the marker's entries (system/optional.py) are the effects compiled apart, in this order
assert tuple(PARAM_NAMES.index(e.params[0]) for e in EFFECTS if e.compiled_apart) == APART


def add_extension(effect: Effect) -> None:
    """Append an effect declared outside the package to :data:`EFFECTS` (its parameters after
    every other's in the kernel's parameter vector: :func:`param_names`)."""
    global EFFECTS, EXTENSIONS
    EXTENSIONS = (*EXTENSIONS, effect)
    EFFECTS = (*EFFECTS, effect)


def remove_extension(effect: Effect) -> None:
    """Undo :func:`add_extension`."""
    global EFFECTS, EXTENSIONS
    EXTENSIONS = tuple(e for e in EXTENSIONS if e is not effect)
    EFFECTS = tuple(e for e in EFFECTS if e is not effect)


def param_names() -> tuple[str, ...]:
    """The names of the kernel's parameter vector: the package's (system/param_vector.py),
    then those of the registered extensions."""
    return PARAM_NAMES + tuple(n for e in EXTENSIONS for n in e.params)


def is_on(effect: Effect, scene) -> bool:
    """Whether the SI scene ``scene`` switches ``effect`` on."""
    from ..scene.sections.output import switch_on

    if effect.switch is None:
        return True
    if effect in EXTENSIONS:
        return effect.switch in scene.extensions
    if effect.switch == "flange":
        return scene.bearing.flanges is not None
    return switch_on(scene.physics, effect.switch)


def active(scene) -> tuple[Effect, ...]:
    """The effects the scene switches on, in :data:`EFFECTS` order."""
    return tuple(e for e in EFFECTS if is_on(e, scene))


def apart_pattern(scene) -> tuple[bool, ...] | None:
    """Which of the effects compiled apart a scene switches on, one bool each in the order of
    system/optional.APART (None: none), what system/optional.py's marker says of its model,
    told before the model is built: a cold start begins compiling early."""
    pattern = tuple(is_on(e, scene) for e in EFFECTS if e.compiled_apart)
    return pattern if any(pattern) else None


def scene_marker(scene):
    """The marker (system/optional.marker_of) of a scene's model, extensions aside, told before
    the model is built, True in place of its defect table: the kernel variant a cold start
    compiles (run/integrate.compile_aside, a sweep's client)."""
    return marker_of(apart_pattern(scene),
                     table=True if scene.defects or scene.waviness else None)


def scene_has_optional(scene) -> bool:
    """Whether a scene's kernels need any of the passes compiled apart (:func:`apart_pattern`)."""
    return apart_pattern(scene) is not None


def param_slice(effect: Effect) -> slice:
    """Where ``effect``'s parameters lie in the kernel's parameter vector (empty: none)."""
    if not effect.params:
        return slice(0, 0)
    start = param_names().index(effect.params[0])
    return slice(start, start + len(effect.params))


def effect_parameters(scene, geometry, context: dict) -> dict:
    """The values of every optional effect's parameters ({name: value}; all 0 where the
    scene leaves the effect off), with the model build's shared ``context``."""
    out: dict = {}
    for e in (*_OPTIONAL, *EXTENSIONS):
        if e.parameters is not None:
            out.update(e.parameters(scene, geometry, context))
    return out


def sources(scene) -> tuple[Source, ...]:
    """The power sources of a scene's run, in the ``loss_source`` coordinate's order."""
    return tuple(s for e in active(scene) for s in e.sources)


def heat_partition() -> dict:
    """{source: shares of physics/heat_network.NODES} of every declared source."""
    return {s.name: s.heat for e in EFFECTS for s in e.sources}


def power_by_source(model, t, values) -> tuple[dict, list]:
    """(power loss [W] by source (time,), the terms of the inner ring's drive torque that
    effects add [N m]) of the samples' ``values`` (the names of results/dataset.py): the
    raceway sources Σ F V (less the share a film-share effect takes for its own source), then
    each active effect's power in :data:`EFFECTS` order."""
    on = active(model.scene)
    F, V = values["traction_force"], values["slip_velocity"]
    shares = [(e, e.film_share(model, values, model.params[param_slice(e)]))
              for e in on if e.film_share is not None]
    F_film = F
    for _, F_a in shares:
        F_film = F_film - F_a
    P = {"raceway_inner": law.raceway_power(F_film[..., 0], V[..., 0]),
         "raceway_outer": law.raceway_power(F_film[..., 1], V[..., 1])}
    for e, F_a in shares:
        P[e.sources[0].name] = (law.raceway_power(F_a[..., 0], V[..., 0])
                                + law.raceway_power(F_a[..., 1], V[..., 1]))
    drive: list = []
    for e in on:
        if e.power is None:
            continue
        own = model.params[param_slice(e)]
        p = {n: float(v) for n, v in zip(e.params, own)} if e is CORE else own
        e.power(model, t, values, p, P, drive)
    return P, drive


def viscosity_entries() -> tuple[Viscosity, ...]:
    """Every effect's viscosity parameters with where their laws read them."""
    return tuple(viscosity_entry(v) for e in EFFECTS for v in e.viscosity_params)


def viscosity_params() -> tuple[str, ...]:
    """The parameters that hold the oil's dynamic viscosity [Pa s], of every effect."""
    return tuple(v.name for v in viscosity_entries())


def temperature_params() -> tuple[str, ...]:
    """The parameters that hold the oil's temperature-viscosity coefficient β [1/K]."""
    return tuple(n for e in EFFECTS for n in e.temperature_params)


def set_viscosity(model, viscosity_Pa_s: float) -> None:
    """Set one oil viscosity everywhere the kernel and the post-processing read it, in place.
    An entry at 0 belongs to an effect the scene switched off (its parameters are all 0) and
    stays 0."""
    for name in viscosity_params():
        i = param_names().index(name)
        if model.params[i] != 0.0:
            model.params[i] = viscosity_Pa_s
    model.scene = thermal_network.with_viscosity(model.scene, viscosity_Pa_s)


def read_temperature_C(nodes, temperatures_C) -> float:
    """The mean temperature [°C] of ``nodes`` among the network's (``temperatures_C`` in
    physics/heat_network.NODES order)."""
    from ..physics.heat_network import NODES

    return float(np.mean([temperatures_C[NODES.index(n)] for n in nodes]))


def set_temperatures(model, temperatures_C) -> dict:
    """Set the oil's viscosity of each declared parameter at the temperature where its law
    reads it (:class:`~bearingdae.system.effect.Viscosity`: the mean of its nodes among
    ``temperatures_C``, in physics/heat_network.NODES order), β of the laws that read one at
    the raceway films' temperature, and the post-processing's viscosity (the EHL film, κ) at
    the raceway films' too. Entries at 0 belong to effects switched off and stay 0. Returns
    {"film": (T [°C], η [Pa s], ν [mm²/s]), "oil": the same at the oil node}."""
    scene = model.scene
    for v in viscosity_entries():
        i = param_names().index(v.name)
        if model.params[i] != 0.0:
            T = read_temperature_C(v.nodes(scene), temperatures_C)
            model.params[i] = thermal_network.oil_viscosity_Pa_s(scene, T)[0]
    read = {}
    for key, nodes in (("film", RACEWAY_FILM), ("oil", BULK_OIL)):
        T = read_temperature_C(nodes, temperatures_C)
        read[key] = (T, *thermal_network.oil_viscosity_Pa_s(scene, T))
    beta = thermal_network.oil_temperature_coefficient(scene, read["film"][0])
    for name in temperature_params():
        i = param_names().index(name)
        if model.params[i] != 0.0:  # 0: the effect is off
            model.params[i] = beta
    model.scene = thermal_network.with_viscosity(scene, read["film"][1])
    return read


def set_oil_temperature(model, temperature_C: float) -> tuple[float, float]:
    """Set every node of the oil at ``temperature_C`` (:func:`set_temperatures`); returns
    (η [Pa s], ν [mm²/s])."""
    from ..physics.heat_network import NODES

    _, mu, nu = set_temperatures(model, np.full(len(NODES), float(temperature_C)))["oil"]
    return mu, nu
