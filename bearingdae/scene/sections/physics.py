"""``[physics]`` (the model's switches) and ``[ring]`` (the dynamic ring body), as written."""

from __future__ import annotations

from typing import Literal

from pydantic import ConfigDict, Field, field_validator

from ..histories import _Section


#: the rolling-resistance laws a scene may name (physics/rolling_resistance.LAW_CODES); the
#: first is what ``true`` means
ROLLING_LAWS = ("biboulet_houpert", "goksem_hargreaves", "zhou_hoeprich")


class PhysicsInput(_Section):
    """Switches: a switched-off effect removes its unknowns and equations (not just zeros)."""

    skew: bool = Field(default=True, description="roller skew θz, ζ (unknowns and equations)")
    cage: bool = Field(default=True, description="cage rotation and roller-pocket contact")
    drag: bool = Field(default=True, description="lubricant orbit drag and churning moments")
    tilt: bool = Field(default=True, description="roller tilt β and ring tilts γ (needed by "
                       "moment loads)")
    gyroscopic: bool = Field(default=True, description="gyroscopic term of the skew equation")
    slip: Literal["rigid", "paper"] = Field(default="rigid", description="slip kinematics "
                                             "(theory.md §6): rigid-body, or the paper's r_λ")
    orbit: Literal["newton", "paper"] = Field(default="newton", description="orbit equation "
                                               "(theory.md §10): Newton on the roller centre, or "
                                               "the paper's moment form")
    ring: Literal["quasi-static", "dynamic"] = Field(
        default="quasi-static", json_schema_extra={"on": "dynamic", "effect": "a dynamic ring"},
        description="inner ring (theory.md §15): massless, in "
        "quasi-static equilibrium (the paper's), or a body whose displacement (and tilt) "
        "are differential unknowns with velocities (section [ring])")
    # None (not False) by default, so that a scene without whirl keeps its TOML text and hashes
    cage_whirl: bool | None = Field(
        default=None, json_schema_extra={"on": True, "effect": "a whirling cage"},
        description="cage whirl (theory.md §17): the cage centre's two in-plane "
        "translations and velocities are unknowns, held by the pockets or a guiding land "
        "(section [cage] guidance); default false: the cage only rotates")
    # None (= "full-film") by default, so that every existing scene keeps its TOML text
    lubrication: Literal["full-film", "mixed"] | None = Field(
        default=None, json_schema_extra={"on": "mixed", "effect": "mixed lubrication"},
        description="raceway lubrication (theory.md §20): \"full-film\", the "
        "EHL traction law carries the whole slice load; \"mixed\", below λ = 3 the "
        "asperities carry a share of it at lubricant.boundary_friction (default "
        "\"full-film\")")
    # None (not False) by default, so that a scene without it keeps its TOML text and hashes
    rolling_resistance: Literal["biboulet_houpert", "goksem_hargreaves",
                                "zhou_hoeprich"] | None = Field(
        default=None, json_schema_extra={"on": True, "effect": "the rolling resistance"},
        description="EHL rolling resistance of the slice contacts (theory.md §19): a force "
        "against the entrainment on roller and ring and a moment on the roller, by the law "
        "named: \"biboulet_houpert\" (Biboulet & Houpert 2010, rigid-isoviscous to EHL; what "
        "true means), \"goksem_hargreaves\" (1978, the law of true before) or "
        "\"zhou_hoeprich\" (1991); default false: the traction law is the whole raceway "
        "friction")
    thermal: Literal["off", "steady"] = Field(
        default="off", json_schema_extra={"on": "steady", "effect": "the thermal network"},
        description="temperatures (theory.md §21): \"off\" uses "
        "lubricant.viscosity_Pa_s; \"steady\" runs in blocks, solves a lumped thermal "
        "network (section [thermal]) under each block's losses and sets the oil viscosity "
        "from the oil temperature (lubricant.viscosity_40C_mm2_s, viscosity_100C_mm2_s) until "
        "the oil temperature is steady")
    @field_validator("rolling_resistance", mode="before")
    @classmethod
    def _rolling_law(cls, v):
        """true is Biboulet & Houpert's law, false off (None); one line for anything else."""
        if v is True:
            return ROLLING_LAWS[0]
        if v is False or v is None or v in ROLLING_LAWS:
            return None if v is False else v
        raise ValueError("must be true, false or one of "
                         + ", ".join(f'"{n}"' for n in ROLLING_LAWS))

    # None (= "paper") by default, so that every existing scene keeps its TOML text
    friction_model: Literal["paper", "full"] | None = Field(
        default=None, description="\"paper\" (default): the paper's friction, each switch "
        "as set; \"full\": rolling_resistance = \"biboulet_houpert\" (with "
        "lubricant.inlet_film_um if given), lubrication = \"mixed\" and thermal = \"steady\" "
        "(theory.md §19-21), each unless that switch is set explicitly")


class RingInput(_Section):
    """The inner ring as a body (``physics.ring = "dynamic"``; theory.md §15): its mass, tilt
    inertia and an optional elastic support to ground (shaft / housing) in parallel with the
    bearing."""

    model_config = ConfigDict(json_schema_extra={"switch": "ring"})  # every key: its switch

    mass_kg: float | None = Field(default=None, ge=1e-3, le=1e5, description="mass moved with "
                                  "the inner ring (default: the ring from its geometry, bore to "
                                  "inner raceway over the roller length, at materials."
                                  "density_kg_m3; add the shaft's share here)")
    tilt_inertia_kg_m2: float | None = Field(default=None, ge=1e-9, le=1e4, description=
                                             "moment of inertia about a diameter (tilt; "
                                             "default: the ring's, from its geometry)")
    support_stiffness_N_m: float = Field(default=0.0, ge=0.0, le=1e12, description="stiffness "
                                         "of an elastic support of the ring to ground, radial "
                                         "(both directions); 0: none, the load acts on the "
                                         "ring alone")
    support_damping_N_s_m: float = Field(default=0.0, ge=0.0, le=1e8, description="viscous "
                                         "damping of that support, radial (both directions)")
