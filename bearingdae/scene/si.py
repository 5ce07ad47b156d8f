"""The frozen scene in SI units handed to the physics (pipeline stage 1, layer 2).

Frozen dataclasses only (no validation here: :mod:`bearingdae.scene.convert` builds them from
the checked input, converting every unit exactly once).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np
import tomli_w

# --------------------------------------------------------------------------------------------
# Layer 2: the frozen, SI scene handed to the physics
# --------------------------------------------------------------------------------------------
from .flanges import Flanges  # noqa: E402  (re-exported with the SI scene)
from .defects import Defect, Waviness  # noqa: E402,F401  (re-exported with the SI scene)

@dataclass(frozen=True)
class Bearing:
    rollers: int
    outer_diameter_m: float
    bore_m: float
    pitch_diameter_m: float
    roller_diameter_m: float
    roller_length_m: float
    effective_length_m: float
    crown_radius_m: float
    profile: str
    clearance_m: float  #: diametral radial clearance P_d (negative = preload)
    design_load_N: float  #: logarithmic profile design load (unused by other profiles)
    #: roller end-flange contact geometry (scene/flanges.py); None: no flanges (the paper's)
    flanges: Flanges | None = None


class LoadHistory:
    """A load history's rows (t [s], F_r, F_t [N], M, M_t [N m], F_a [N]) as one read-only
    float array (n, 6): a load file of millions of samples costs 48 bytes a row (as a tuple
    of Python tuples it cost ~10 times that and seconds to build). Rows index and iterate as
    arrays (``history[0][1:]``: the loads at t = 0), ``np.asarray(history)`` is the table;
    equal when the tables are (value for value), hashable (a frozen scene's field)."""

    __slots__ = ("rows", "_hash")

    def __init__(self, rows):
        a = np.array(rows, dtype=float, copy=True)
        if a.ndim != 2 or a.shape[1] != 6:
            raise ValueError(f"a load history has rows of 6 values, not shape {a.shape}")
        a.flags.writeable = False
        self.rows = a
        self._hash = None

    def __array__(self, dtype=None, copy=None):
        return self.rows if dtype is None else self.rows.astype(dtype, copy=False)

    def __len__(self) -> int:
        return self.rows.shape[0]

    def __getitem__(self, i):
        return self.rows[i]

    def __iter__(self):
        return iter(self.rows)

    def __eq__(self, other) -> bool:
        if not isinstance(other, LoadHistory):
            return NotImplemented
        return self.rows.shape == other.rows.shape and bool(np.all(self.rows == other.rows))

    def __hash__(self) -> int:
        if self._hash is None:
            self._hash = hash((self.rows.shape, self.rows.tobytes()))
        return self._hash

    def __getstate__(self):
        return self.rows

    def __setstate__(self, rows):
        self.__init__(rows)

    def __repr__(self) -> str:
        return f"LoadHistory({len(self)} rows, t = {self.rows[0, 0]:g} ... {self.rows[-1, 0]:g} s)"


@dataclass(frozen=True)
class Materials:
    youngs_modulus_Pa: float
    poisson_ratio: float
    density_kg_m3: float


@dataclass(frozen=True)
class Operating:
    #: inner-ring speed as written in the scene [r/min] (kept for outputs and sweeps)
    speed_rpm: float | tuple[tuple[float, ...], tuple[float, ...]]
    radial_load_N: float
    moment_Nm: float
    tangential_load_N: float
    tangential_moment_Nm: float
    #: the same speed in SI [rad/s] (a constant, or (times [s], speeds [rad/s]) of a ramp): the
    #: one conversion from r/min, done here at the boundary; everything downstream uses it
    speed_rad_s: float | tuple[tuple[float, ...], tuple[float, ...]]
    #: amplitude [N] and phase at t = 0 [rad] of the load rotating with the shaft (theory.md §14)
    unbalance_N: float = 0.0
    unbalance_phase_rad: float = 0.0
    #: load history: rows (t [s], F_r, F_t [N], M, M_t [N m], F_a [N]) on one time grid,
    #: piecewise linear and held at its ends (physics/loads.py); None: the constant loads
    load_history: LoadHistory | None = None
    #: the load file the history was read from (absolute path), None for scene tables
    load_file: str | None = None
    #: SHA-256 of the load file's bytes as read: the file's contents are part of the scene
    #: (Scene.identity), not only its name
    load_file_sha256: str | None = None
    #: axial load F_a on the inner ring along +X [N] (needs flanges; with a load history, its
    #: first row, as the four loads above)
    axial_load_N: float = 0.0

    @property
    def loads(self) -> tuple[float, float, float, float]:
        """External loads on the inner ring (F_r, F_t, M, M_t) [N, N, N m, N m] (theory.md §5)
        without the unbalance; with a load history, its first row (the loads at t = 0)."""
        return (self.radial_load_N, self.tangential_load_N, self.moment_Nm,
                self.tangential_moment_Nm)

    @property
    def axial_load_max_N(self) -> float:
        """Largest |F_a| of the axial load [N] (over its history, if it has one)."""
        if self.load_history is None:
            return abs(self.axial_load_N)
        return float(np.max(np.abs(self.load_history.rows[:, 5])))

    def speed_at(self, time_s: float) -> float:
        """Inner-ring speed [r/min] at ``time_s`` (piecewise-linear ramp, held at the end); for
        outputs: computations use :meth:`speed_rad_s_at`."""
        if isinstance(self.speed_rpm, tuple):
            times, values = self.speed_rpm
            return float(np.interp(time_s, times, values))
        return float(self.speed_rpm)

    def speed_rad_s_at(self, time_s: float) -> float:
        """Inner-ring speed [rad/s] at ``time_s`` (piecewise-linear ramp, held at the end)."""
        if isinstance(self.speed_rad_s, tuple):
            times, values = self.speed_rad_s
            return float(np.interp(time_s, times, values))
        return float(self.speed_rad_s)


@dataclass(frozen=True)
class Numerics:
    slices: int
    contact_smoothing_m: float
    static_tolerance: float
    static_max_iterations: int


@dataclass(frozen=True)
class Physics:
    skew: bool
    cage: bool
    drag: bool
    tilt: bool
    gyroscopic: bool
    slip: str
    orbit: str
    ring: str = "quasi-static"  #: "quasi-static" (massless ring) or "dynamic" (theory.md §15)
    cage_whirl: bool = False  #: the cage centre moves (theory.md §17)
    lubrication: str = "full-film"  #: "full-film" or "mixed" (theory.md §20)
    #: EHL rolling resistance of the slices (theory.md §19): False (off) or its law's name
    #: (physics/rolling_resistance.LAW_CODES)
    rolling_resistance: bool | str = False
    thermal: str = "off"  #: "off" or "steady": the oil temperature sets the viscosity (§21)


@dataclass(frozen=True)
class Ring:
    """The inner ring as a body (used with ``physics.ring = "dynamic"``); None: from the ring
    geometry (physics/ring.py)."""

    mass_kg: float | None = None
    tilt_inertia_kg_m2: float | None = None
    support_stiffness_N_m: float = 0.0
    support_damping_N_s_m: float = 0.0


@dataclass(frozen=True)
class Traction:
    law: str
    A_s_m: float
    B_Pa: float
    C_s_m: float
    D: float
    alternative_bracket: bool  #: True reads the bracket as [1 - exp(-B/p)]
    velocity_scale_m_s: float
    slide_roll_A: float = -0.04  #: slide-to-roll law μ(s) = (A + B s) e^(-C s) + D
    slide_roll_B: float = 2.8
    slide_roll_C: float = 25.0
    slide_roll_D: float = 0.04
    rolling_speed_floor_m_s: float = 1e-3  #: u₀ of s = |V| / sqrt(u² + u₀²)


@dataclass(frozen=True)
class Cage:
    pocket_clearance_m: float
    pocket_stiffness_N_m: float
    damping_ratio: float
    friction: float
    density_kg_m3: float
    smoothing_m: float
    spin_friction_force_scale_N: float = 1e-6  #: f of the smooth |F| in the spin friction
    # cage whirl (theory.md §17; used with physics.cage_whirl only)
    mass_kg: float | None = None  #: None: the annulus's mass (physics/cage.py)
    guidance: str = "roller"  #: "roller" | "outer-land" | "inner-land"
    land_clearance_m: float = 0.0  #: diametral clearance on the land
    land_width_m: float = 0.0  #: width of each of the two guiding rims
    land_friction: float | None = None  #: None: physics/cage_guidance.LAND_FRICTION


@dataclass(frozen=True)
class Lubricant:
    oil_fraction: float
    oil_density_kg_m3: float
    air_density_kg_m3: float
    viscosity_Pa_s: float
    boundary_friction: float = 0.1  #: asperity friction of mixed lubrication (theory.md §20)
    #: β = -d ln η / dT [1/K] and k [W/(m K)] of the rolling resistance's thermal factor
    #: (theory.md §19): a mineral oil's, β ≈ 0.03 K⁻¹ near 40 °C (VG 10-100), k ≈ 0.13
    temperature_viscosity_K_inv: float = 0.03
    thermal_conductivity_W_m_K: float = 0.13
    #: e_C of ISO 281's a_ISO (the modified life, analysis/rating_life.py); None: not computed
    contamination_factor: float | None = None
    #: h_a [m], the oil film at a raceway contact's inlet (theory.md §19); None: fully flooded
    inlet_film_m: float | None = None
    #: the oil's viscosity-temperature data (ASTM D341's two points [mm²/s]) and where the laws
    #: read it without physics.thermal [°C] (scene/thermal_switch.py); None: viscosity_Pa_s
    viscosity_40C_mm2_s: float | None = None
    viscosity_100C_mm2_s: float | None = None
    operating_temperature_C: float | None = None


@dataclass(frozen=True)
class Thermal:
    """The thermal network of ``physics.thermal = "steady"`` in SI (physics/heat_network.py,
    theory.md §21); temperatures in °C as the network's boundary values."""

    oil_inlet_temperature_C: float = 40.0
    oil_flow_m3_s: float = 0.1e-3 / 60.0
    ambient_temperature_C: float = 20.0
    housing_conductance_W_K: float = 2.0
    shaft_conductance_W_K: float = 1.0
    oil_specific_heat_J_kgK: float = 2000.0
    oil_heat_transfer_W_m2K: float = 200.0
    steel_conductivity_W_mK: float = 46.0
    temperature_tolerance_K: float = 0.5
    viscosity_40C_mm2_s: float = 32.0  #: ASTM D341's two points (an ISO VG 32 mineral oil)
    viscosity_100C_mm2_s: float = 5.4
    #: lubricant.operating_temperature_C: where the first block starts (None: the network's
    #: answer to the start state's losses, run/thermal_coupling.ThermalCoupling.start_from)
    start_temperature_C: float | None = None


@dataclass(frozen=True)
class Engineering:
    """Inputs of the post-processed life and film (analysis/engineering.py); not the DAE."""

    basic_dynamic_load_rating_N: float | None = None  #: None: ISO 281 from the geometry
    roughness_m: float = 0.11 * 1e-6  #: composite RMS roughness σ of λ = h_min / σ (as converted)
    pressure_viscosity_Pa_inv: float = 22.0 * 1e-9  #: oil pressure-viscosity coefficient α
    edge_stress_factors: bool = True  #: ISO/TS 16281 edge-stress factors on the lamina loads
    phase_positions: int = 0  #: static: roller-set positions of the phase-averaged life (0: off)


@dataclass(frozen=True)
class Dynamics:
    """IDA, Newmark-β and output-window settings."""

    rtol: float
    atol: float
    warmup_cage_revolutions: float
    cage_revolutions: float
    samples_per_cage_revolution: int
    max_steps: int
    newmark_step_s: float = 2e-6
    newmark_beta: float = 0.25
    newmark_gamma: float = 0.5
    hht_alpha: float = 0.0
    newmark_error_estimate: bool = False
    until_steady: bool = False
    steady_tolerance: float = 1e-3
    steady_block_cage_revolutions: float = 1.0
    max_warmup_cage_revolutions: float = 200.0
    initial_speeds: str = "epicyclic"
    defect_edges: str = "smooth"  #: "smooth" | "locate" (system/defect_sides.py)


@dataclass(frozen=True)
class Scene:
    """A validated scene in SI units. Build it with :func:`load_scene` or :func:`scene_from_dict`."""

    title: str
    bearing: Bearing
    materials: Materials
    operating: Operating
    numerics: Numerics
    physics: Physics
    traction: Traction
    cage: Cage
    lubricant: Lubricant
    dynamics: Dynamics
    output_variables: tuple[str, ...] | None
    source: Mapping[str, Any] = field(repr=False, compare=False)
    preset_citation: str | None = field(default=None, repr=False)
    output_precision: str = "float64"  #: NetCDF type of the data variables (results.save)
    ring: Ring = Ring()  #: the inner ring as a body (physics.ring = "dynamic")
    #: the values a default or another key decided (pocket clearance of the preset, pitch
    #: diameter, Newmark β and γ, ...), by table, in the file's units: ``to_toml(complete=True)``
    resolved: Mapping[str, Any] = field(default_factory=dict, repr=False, compare=False)
    engineering: Engineering = field(default_factory=Engineering)  #: life, film inputs
    #: the thermal network (physics.thermal = "steady"); None: off, the viscosity is fixed
    thermal: Thermal | None = None
    #: local defects and waviness of the rolling surfaces (scene/defects.py); none by default
    defects: tuple[Defect, ...] = ()
    waviness: tuple[Waviness, ...] = ()
    #: the sections of the effects registered from outside the package that the scene switches
    #: on (scene/extensions.py), checked, by switch; none by default
    extensions: Mapping[str, Any] = field(default_factory=dict)

    def input_files(self) -> dict[str, tuple[str, str | None]]:
        """The files the scene read besides its own text, by key: ``{key: (absolute path,
        SHA-256 of the bytes read)}`` (today the load file; empty without)."""
        o = self.operating
        if o.load_file is None:
            return {}
        return {"operating.load_file": (o.load_file, o.load_file_sha256)}

    def identity(self) -> str:
        """What identifies the scene in checkpoints and sweep run keys: its TOML text
        (:meth:`to_toml`) and the contents (SHA-256) of every file it read
        (:meth:`input_files`), so that a changed load file is another scene. A scene that
        reads no file: its TOML text alone (the identities of earlier versions)."""
        return self.to_toml() + self.inputs_text()

    def inputs_text(self) -> str:
        """The input files' part of :meth:`identity` ('' without input files)."""
        return "".join(f"\0{key}\0{path}\0sha256:{digest}"
                       for key, (path, digest) in sorted(self.input_files().items()))

    def to_toml(self, complete: bool = False) -> str:
        """The scene as TOML text in the file's own units (presets resolved).

        ``complete=True`` adds every value that the file left to a default or derived from
        other keys (``resolved``), so that the text alone states the whole scene; the result
        files record that one. The plain text (the keys as given), with the contents of the
        files the scene read, identifies a scene in checkpoints and sweep run keys
        (:meth:`identity`).
        """
        data = copy.deepcopy(dict(self.source))
        if complete:
            for table, values in self.resolved.items():
                if isinstance(values, Mapping):
                    data.setdefault(table, {})
                    for key, value in values.items():
                        data[table].setdefault(key, value)
                else:
                    data.setdefault(table, values)
            data.pop("title", None)  # the title as it reads: values --set (scene/load.py)
            data = {"title": self.title, **data}  # and {operating} filled in (scene/titles.py)
        return tomli_w.dumps(data)
