"""What an optional effect declares, once, for the rest of the package (system layer).

An effect (the flanges, the whirling cage, the dynamic ring, the rolling resistance, mixed
lubrication, the thermal network) is a law in physics/, keys in scene/sections/ (each key's
field names its switch: scene/switches.py) and one :class:`Effect` at the end of its system
module. The generic machinery of system/effects.py iterates over the declarations: the model's
parameters, the oil viscosity a thermal run updates, the power sources and where their heat
goes, the keys and output variables of each switch. A new effect adds a declaration; no other
module keeps a list of its names.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable


@dataclass(frozen=True)
class Source:
    """A power-loss source: its name (``loss_source`` coordinate), what it is, and where its
    heat goes: the shares of the thermal network's nodes (physics/heat_network.NODES: inner ring,
    outer ring, rollers, cage, oil), summing to 1 (theory.md §21 gives the reasoning)."""

    name: str
    long_name: str
    heat: tuple[float, float, float, float, float]


#: where a law's film forms, as the thermal network's nodes whose mean temperature it reads
#: (physics/heat_network.NODES): a raceway contact's film lies between its ring and a roller;
#: one parameter for both races reads the mean of the two races' (T_ring + T_rollers)/2
RACEWAY_FILM = ("inner_ring", "rollers", "outer_ring", "rollers")
#: the bulk oil of the drag and the churning
BULK_OIL = ("oil",)


@dataclass(frozen=True)
class Viscosity:
    """A parameter holding the oil's viscosity and where its law reads it: ``where`` the
    nodes whose mean temperature it is read at, or a function of the SI scene that returns
    them (a film whose surfaces depend on the scene)."""

    name: str
    where: tuple[str, ...] | Callable = RACEWAY_FILM

    def nodes(self, scene) -> tuple[str, ...]:
        return self.where(scene) if callable(self.where) else self.where


def viscosity_entry(entry) -> Viscosity:
    """A declared viscosity parameter as a :class:`Viscosity` (a bare name: a raceway film)."""
    return entry if isinstance(entry, Viscosity) else Viscosity(entry)


@dataclass(frozen=True)
class Effect:
    """One effect: everything the generic machinery needs to know about it.

    ``switch`` is the scene switch's name (scene/switches.py: ``physics.<switch>``, or
    ``flange`` for ``bearing.type``; None: the core model, always on). ``params`` are its
    entries of the kernel's parameter vector, in order; ``parameters(scene, geometry,
    context)`` their values ({name: value}, all 0 with the switch off), with ``context`` the
    model build's shared values (system/model.build_model). ``viscosity_params`` hold the
    oil's dynamic viscosity, each a :class:`Viscosity` saying where its law reads it (a bare
    name: where the raceway films form), and ``temperature_params`` its temperature-viscosity
    coefficient (read where the raceway films form); a thermal run updates both, where
    non-zero. ``unknowns`` are its layout names
    (system/layout.py), ``passes`` its residual and Jacobian passes. ``sources`` are the power
    sources it adds; ``power(model, t, values, own, P, drive)`` adds their power [W] per sample
    to ``P`` and its terms of the inner ring's drive torque [N m] to the list ``drive``
    (``drive_note`` names them in that variable's long name). ``values(model, t, full_l,
    full_g, own)`` are its sample values by output variable name (system/samples.py), from
    the unscaled full states and its parameters ``own``. ``compiled_apart``: its passes
    compile only for a scene that switches it on (system/optional.py's marker).
    ``film_share(model, values, own)`` (mixed lubrication) is the share of the raceway traction
    that leaves the film's sources for its own: (time, roller, slice, race) [N].
    ``section``, ``switch_description`` and ``variables``: an effect declared outside the
    package (system/extensions.py says what its passes take).
    """

    name: str
    switch: str | None
    params: tuple[str, ...] = ()
    parameters: Callable | None = None
    viscosity_params: tuple[str | Viscosity, ...] = ()
    temperature_params: tuple[str, ...] = ()
    unknowns: tuple[str, ...] = ()
    passes: tuple[Callable, ...] = ()
    sources: tuple[Source, ...] = ()
    power: Callable | None = None
    film_share: Callable | None = None
    values: Callable | None = None
    compiled_apart: bool = False
    drive_note: str = ""
    #: an effect declared outside the package (system/extensions.register_effect): the
    #: pydantic section of its keys (scene/extensions.py), what its switch means, and its
    #: output variables {name: (dims after time, units, long_name)}
    section: type | None = None
    switch_description: str = ""
    variables: dict | None = None

    def keys(self) -> tuple[str, ...]:
        """The scene keys that this effect's switch alone reads (their fields say so)."""
        from ..scene.switches import keys_of

        return () if self.switch is None else keys_of(self.switch)

    def outputs(self) -> tuple[str, ...]:
        """The output variables this effect's switch makes available."""
        from ..scene.schema import OUTPUT_VARIABLES

        return tuple(n for n, s in OUTPUT_VARIABLES.items()
                     if self.switch is not None and s == self.switch)
