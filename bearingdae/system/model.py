"""Assemble the DAE of one scene: parameters, scales, work arrays, diagnostics (theory.md §11).

Stage: scene -> geometry -> **DAE model** -> solver. Only the unknowns the scene's ``[physics]``
switches ask for enter the compact state (system/layout.py).

Scaling: IDA sees y = Y / S with S the scale of each unknown (lengths by the Hertz approach at
the reference roller load, speeds by the epicyclic speed, ...), and every residual row divided
by a force, moment or rate scale, so that one ``atol`` (in units of each scale) suits all
unknowns. The scales are recorded in the output metadata (reference scales: system/scales.py).
The initial state and the projection onto the algebraic equations run the static Newton, a
solver: solvers/algebraic.py.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..physics.cage import (SPIN_SPEED_SCALE_RAD_S, cage_annulus, cage_mass_inertia,
                            pocket_damping)
from ..physics.contact import slice_stiffness
from ..physics.equilibrium import centrifugal_force
from ..physics.geometry import Geometry, make_geometry
from ..physics.loads import applied_load_series, applied_loads
from ..physics.lubricant import effective_density
from ..physics.ring import ring_mass_inertia
from ..scene import Scene
from .effects import effect_parameters, param_names
from .extensions import marker_entry
from .whirl import translating_mass
from .thermal_network import start_scene
from .layout import GLOBAL, LOCAL, RING, RING_RATES, Layout
from .residual import SCRATCH_ROWS, residual
from .optional import marker_table, optional_marker
from .defects import defect_table, has_roller_surface
from .work import flat_work
from .scales import reference_scales

SKEW_SCALE_RAD = 1e-3  # typical skew angle: sets the absolute tolerance of θz
STATIC_REFERENCE_PERIOD_S = 0.01  # time unit of a scene whose final speed is zero


#: The kernel's work arrays, in the order system/residual.py's ``full_evaluate`` unpacks them
#: (``data``): inputs, state and residual buffers, then the per-slice / per-end diagnostics.
WORK_SLOTS = ("params", "x_m", "profile_drop_m", "unknown_scale", "row_scale", "local_map",
              "global_map", "ramp_t", "ramp_w", "y_local", "yp_local", "y_global", "yp_global",
              "res_local", "res_global", "contributions", "contact_force", "contact_pressure",
              "slip_velocity", "traction_force", "cage_force", "load_table", "roller_scratch")
#: Quantities the kernel leaves in its work arrays at each evaluation [SI]: (Z, k, race) per
#: slice, (Z, end) per pocket contact.
DIAGNOSTICS = ("contact_force", "contact_pressure", "slip_velocity", "traction_force",
               "cage_force")


@dataclass
class Model:
    scene: Scene
    geometry: Geometry
    layout: Layout
    params: np.ndarray
    scale: np.ndarray  #: S, unknown scales (compact)
    row_scale: np.ndarray  #: residual row scales (compact)
    mass: np.ndarray  #: dF/dy' diagonal, scaled (compact)
    ramp_t: np.ndarray
    ramp_w: np.ndarray  #: inner-ring speed [rad/s] at ramp_t
    cage_mass_kg: float
    cage_inertia_kgm2: float
    force_scale_N: float
    length_scale_m: float
    #: work arrays of the kernel (views of ``work``), then the optional passes' marker
    data: tuple = field(repr=False, default=())
    work: tuple = field(repr=False, default=())  #: (W, I): ``data`` as two flat buffers
    #: a dynamic ring's displacement at sub-sample times of the last run (system/taps.py)
    ring_taps: object = field(repr=False, default=None)
    #: the taps a resumed run's replay restored, for the solver to continue (system/taps.py)
    ring_taps_carried: object = field(repr=False, default=None)
    #: the thermal coupling of a run with physics.thermal = "steady" (run/thermal_coupling.py)
    thermal: object = field(repr=False, default=None)

    @property
    def size(self) -> int:
        return self.layout.size

    def ring_speed(self, t: float) -> float:
        return float(np.interp(t, self.ramp_t, self.ramp_w))

    def loads_at(self, t: float) -> np.ndarray:
        """(F_r, F_t, M, M_t, F_a) applied to the inner ring at t [N, N, N m, N m, N]: the load
        history plus the unbalance (physics/loads.py, the kernel's own law)."""
        op = self.scene.operating
        return np.array(applied_loads(float(t), self.work_array("load_table"), self.ramp_t,
                                      self.ramp_w, op.unbalance_N, op.unbalance_phase_rad))

    def loads_series(self, t) -> np.ndarray:
        """:meth:`loads_at` at every time of ``t``, (n, 5)."""
        op = self.scene.operating
        return applied_load_series(t, self.work_array("load_table"), self.ramp_t, self.ramp_w,
                                   op.unbalance_N, op.unbalance_phase_rad)

    def final_cage_speed(self) -> float:
        """Epicyclic cage speed at the final inner-ring speed [rad/s]."""
        return self.geometry.epicyclic_orbit_speed(self.ramp_w[-1])

    def residual(self, t: float, y: np.ndarray, yp: np.ndarray) -> np.ndarray:
        res = np.empty(self.size)
        residual(t, y, yp, res, self.data)
        return res

    @property
    def defect_table(self) -> np.ndarray | None:
        """The kernel's defect table (system/defects.py; the marker holds it), None without."""
        return marker_table(self.data[-1])

    def work_array(self, name: str) -> np.ndarray:
        """The kernel's work array ``name`` (one of :data:`WORK_SLOTS`), a view."""
        return self.data[WORK_SLOTS.index(name)]

    def diagnostics(self, t: float, y: np.ndarray) -> dict[str, np.ndarray]:
        """The :data:`DIAGNOSTICS` at one scaled state (y' = 0; copies): the kernel writes them
        as it evaluates the residual."""
        res = np.empty(self.size)
        residual(t, y, np.zeros_like(y), res, self.data)
        return {name: self.work_array(name).copy() for name in DIAGNOSTICS}

    def diagnostics_series(self, t: np.ndarray, Y: np.ndarray) -> dict[str, np.ndarray]:
        """:meth:`diagnostics` of every sample (t (n,), scaled Y (n, N)), stacked over time;
        with a dynamic ring also ``ring_acceleration`` (n, 2) [m/s²]."""
        out = {name: np.empty((len(t),) + self.work_array(name).shape) for name in DIAGNOSTICS}
        for i, (tk, y) in enumerate(zip(t, Y)):
            for name, value in self.diagnostics(tk, y).items():
                out[name][i] = value
        if self.layout.ring_dynamic:
            out["ring_acceleration"] = np.array([self.ring_acceleration(tk, y)
                                                 for tk, y in zip(t, Y)]).reshape(len(t), 2)
        return out

    def ring_acceleration(self, t: float, y: np.ndarray) -> np.ndarray:
        """(δ_r'', δ_t'') [m/s²] of a dynamic ring at the scaled state y: its equation of motion
        (theory.md §15) solved for the acceleration, F(t, y, 0) = -f: v' = f / m."""
        res = self.residual(t, y, np.zeros_like(y))
        idx = [self.layout.index(n) for n in ("ring_vr", "ring_vt")]
        return np.array([-res[i] / self.mass[i] * self.scale[i] for i in idx])


def _speed_ramp(scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    w = scene.operating.speed_rad_s
    if isinstance(w, tuple):
        return np.array(w[0], float), np.array(w[1], float)
    return np.array([0.0]), np.array([float(w)])


def load_table(op) -> np.ndarray:
    """The kernel's load table (rows [t, F_r, F_t, M, M_t, F_a], physics/loads.py): the
    scene's history, or one row of constant loads."""
    if op.load_history is not None:
        return np.array(op.load_history, float)
    return np.array([[0.0, *op.loads, op.axial_load_N]], float)


def ring_body(scene: Scene, g: Geometry) -> tuple[float, float]:
    """(mass [kg], tilt inertia [kg m²]) of the inner ring: the scene's ``[ring]`` values, else
    the annulus of physics/ring.py (bore to inner raceway, roller length, ring density)."""
    m, I = ring_mass_inertia(scene.bearing.bore_m, g.inner_race_radius_m, g.roller_length_m,
                             scene.materials.density_kg_m3)
    r = scene.ring
    return (r.mass_kg if r.mass_kg is not None else m,
            r.tilt_inertia_kg_m2 if r.tilt_inertia_kg_m2 is not None else I)


def build_model(scene: Scene) -> Model:
    scene = start_scene(scene)  # physics.thermal = "steady": the oil at its inlet temperature
    g = make_geometry(scene)
    ph, tr, cg, lub, op = scene.physics, scene.traction, scene.cage, scene.lubricant, scene.operating
    # With one slice every slice sits at x = 0: tilt has no lever arm and its equations vanish
    # identically, so the tilt unknowns are dropped (a moment is refused by the scene check).
    dyn_ring = ph.ring == "dynamic"
    fl = scene.bearing.flanges
    table = load_table(op)
    # the ring's axial unknown is held by the axial load: assembled where it is ever non-zero
    ring_axial = fl is not None and bool(np.any(table[:, 5] != 0.0))
    layout = Layout(g.rollers, skew=ph.skew, cage=ph.cage, tilt=ph.tilt and g.slices > 1,
                    ring_dynamic=dyn_ring, flange=fl is not None, ring_axial=ring_axial,
                    whirl=ph.cage and ph.cage_whirl, spin_angle=has_roller_surface(scene))
    ring_m, ring_I = ring_body(scene, g)
    ramp_t, ramp_w = _speed_ramp(scene)
    r, L, Rm = g.roller_radius_m, g.roller_length_m, g.pitch_radius_m

    m_c, I_c = cage_mass_inertia(Rm, 2 * r, L, g.rollers, cg.pocket_clearance_m, cg.density_kg_m3)
    cri, cro, _ = cage_annulus(Rm, 2 * r, L)
    # reference scales from the loads at the start or, if larger, the history's median load
    # (and the unbalance): robust to a short peak, which would otherwise scale the start's
    # equilibrium (the static and flange Newton) by loads it does not carry; a constant load
    # gives that load. The axial load enters where flanges carry it (scales.reference_scales)
    history = np.abs(table[:, 1:6])
    loads = np.maximum(history[0], np.median(history, axis=0))
    loads[:2] += op.unbalance_N
    w_max = float(ramp_w.max())
    # scales at the largest speed: centrifugal force of rollers orbiting at the epicyclic speed
    Fc_max = centrifugal_force(g.roller_mass_kg, Rm, g.epicyclic_orbit_speed(w_max))
    q_ref, d_ref = reference_scales(g, loads[:4], Fc_max, loads[4] if ring_axial else 0.0)

    values = {
        "Z": g.rollers, "Rm": Rm, "Ri": g.inner_race_radius_m, "Ro": g.outer_race_radius_m,
        "r": r, "L": L, "mass": g.roller_mass_kg, "Ix": g.roller_inertia_axial_kgm2,
        "It": g.roller_inertia_transverse_kgm2, "Ic": I_c, "clearance": g.clearance_m,
        "K_w": slice_stiffness(g.slice_width_m, L, g.compliance_m2_N),
        "eps_c": scene.numerics.contact_smoothing_m, "w": g.slice_width_m,
        "Rp_in": g.reduced_radius_inner_m, "Rp_out": g.reduced_radius_outer_m,
        "eta": g.compliance_m2_N,
        "tr_law": 0.0 if tr.law == "paper" else 1.0, "tr_A": tr.A_s_m, "tr_B": tr.B_Pa * 1e-9,
        "tr_C": tr.C_s_m, "tr_D": tr.D, "tr_alt": float(tr.alternative_bracket),
        "tr_v": tr.velocity_scale_m_s,
        "sr_A": tr.slide_roll_A, "sr_B": tr.slide_roll_B, "sr_C": tr.slide_roll_C,
        "sr_D": tr.slide_roll_D, "sr_u0": tr.rolling_speed_floor_m_s,
        "slip_paper": float(ph.slip == "paper"), "orbit_paper": float(ph.orbit == "paper"),
        "gyro": float(ph.gyroscopic and ph.skew), "has_cage": float(ph.cage),
        "has_drag": float(ph.drag),
        "cp": cg.pocket_clearance_m, "Kp": cg.pocket_stiffness_N_m,
        "cdamp": pocket_damping(cg.pocket_stiffness_N_m, g.roller_mass_kg, cg.damping_ratio),
        "mu_c": cg.friction, "eps_p": cg.smoothing_m,
        "f_p": cg.pocket_stiffness_N_m * cg.smoothing_m, "spin_scale": SPIN_SPEED_SCALE_RAD_S,
        "spin_f": cg.spin_friction_force_scale_N,
        "rho_e": effective_density(lub.oil_fraction, lub.oil_density_kg_m3,
                                   lub.air_density_kg_m3),
        "mu_oil": lub.viscosity_Pa_s, "cage_ri": cri, "cage_ro": cro,
        "unb": op.unbalance_N, "unb_phase": op.unbalance_phase_rad,
        "ring_dyn": float(dyn_ring), "ring_m": ring_m, "ring_I": ring_I,
        "sup_k": scene.ring.support_stiffness_N_m, "sup_c": scene.ring.support_damping_N_s_m,
    }
    # the optional effects' parameters (system/effects.py), from what the build shares
    values.update(effect_parameters(scene, g, {
        "contact_stiffness_N_m": q_ref / d_ref, "ring_axial": ring_axial,
        "axial_loads_N": table[:, 5], "values": values, "cage_mass_kg": m_c}))
    P = np.array([float(values[n]) for n in param_names()])  # (then any extension's)

    # ---- scales of unknowns and rows, in full (kernel) order ----
    om_ref = max(g.epicyclic_orbit_speed(w_max), 1.0)
    # ring velocity scale: δ_ref times the contact natural frequency sqrt((Q_ref/δ_ref)/m)
    v_ring = float(np.sqrt(q_ref * d_ref / ring_m))
    spin_ref = om_ref * g.outer_race_radius_m / r
    half = 0.5 * L
    f_ref = q_ref
    unk = {"azimuth": 1.0, "orbit_speed": om_ref, "spin_speed": spin_ref,
           "skew_angle": SKEW_SCALE_RAD, "skew_rate": SKEW_SCALE_RAD * om_ref,
           "radial_position": d_ref, "tilt": d_ref / half, "cage_angle": 1.0,
           "cage_speed": om_ref, "ring_dr": d_ref, "ring_dt": d_ref, "ring_gr": d_ref / half,
           "ring_gt": d_ref / half, "ring_vr": v_ring, "ring_vt": v_ring,
           "ring_wr": v_ring / half, "ring_wt": v_ring / half, "axial_position": d_ref,
           "ring_axial": d_ref, "cage_x": d_ref, "cage_y": d_ref, "cage_vx": d_ref * om_ref,
           "cage_vy": d_ref * om_ref, "spin_angle": 1.0}
    rows = {"azimuth": om_ref, "orbit_speed": f_ref, "spin_speed": f_ref * r,
            "skew_angle": SKEW_SCALE_RAD * om_ref, "skew_rate": f_ref * half,
            "radial_position": q_ref, "tilt": q_ref * half, "cage_angle": om_ref,
            "cage_speed": f_ref * Rm, "ring_dr": q_ref, "ring_dt": q_ref,
            "ring_gr": q_ref * half, "ring_gt": q_ref * half, "axial_position": q_ref,
            "ring_axial": q_ref, "cage_x": d_ref * om_ref, "cage_y": d_ref * om_ref,
            "cage_vx": f_ref, "cage_vy": f_ref, "spin_angle": spin_ref}
    if dyn_ring:  # δ' - v rows by the velocity scale, momentum rows by the force scales
        for pos, vel in zip(RING, RING_RATES):
            rows[vel], rows[pos] = rows[pos], unk[vel]
    whirl_mass = translating_mass(values)  # the cage's translating mass (0: no whirl)
    orbit_mass = (g.roller_mass_kg * Rm**2 + g.roller_inertia_axial_kgm2 if ph.orbit == "paper"
                  else g.roller_mass_kg * Rm)
    masses = {"azimuth": 1.0, "orbit_speed": orbit_mass, "spin_speed": g.roller_inertia_axial_kgm2,
              "skew_angle": 1.0, "skew_rate": g.roller_inertia_transverse_kgm2,
              "radial_position": 0.0, "tilt": 0.0, "cage_angle": 1.0, "cage_speed": I_c,
              "ring_dr": float(dyn_ring), "ring_dt": float(dyn_ring), "ring_gr": float(dyn_ring),
              "ring_gt": float(dyn_ring), "ring_vr": ring_m, "ring_vt": ring_m,
              "ring_wr": ring_I, "ring_wt": ring_I, "axial_position": 0.0, "ring_axial": 0.0,
              "cage_x": 1.0, "cage_y": 1.0, "cage_vx": whirl_mass, "cage_vy": whirl_mass,
              "spin_angle": 1.0}

    def compact(table):
        loc = [table[n] for n in layout.local_names] * g.rollers
        return np.array(loc + [table[n] for n in layout.global_names], float)

    S, RS, Mraw = compact(unk), compact(rows), compact(masses)
    mass = Mraw * S / RS

    Z, k = g.rollers, g.slices
    nl, ng = len(LOCAL), len(GLOBAL)
    arrays = {
        "params": P, "x_m": g.x_m.copy(), "profile_drop_m": g.profile_drop_m.copy(),
        "unknown_scale": S, "row_scale": RS, "local_map": layout.local_map,
        "global_map": layout.global_map, "ramp_t": ramp_t, "ramp_w": ramp_w,
        "y_local": np.zeros((Z, nl)), "yp_local": np.zeros((Z, nl)), "y_global": np.zeros(ng),
        "yp_global": np.zeros(ng), "res_local": np.zeros((Z, nl)), "res_global": np.zeros(ng),
        "contributions": np.zeros((Z, ng)),
        "contact_force": np.zeros((Z, k, 2)), "contact_pressure": np.zeros((Z, k, 2)),
        "slip_velocity": np.zeros((Z, k, 2)), "traction_force": np.zeros((Z, k, 2)),
        "cage_force": np.zeros((Z, 2)), "load_table": load_table(op),
        "roller_scratch": np.zeros((SCRATCH_ROWS, Z)),
    }
    table = defect_table(scene, g)  # local defects and waviness (system/defects.py)
    extra = () if table is None else (table,)
    data, work = flat_work(tuple(arrays[name] for name in WORK_SLOTS) + extra)
    P, S, RS, ramp_t, ramp_w = (data[WORK_SLOTS.index(n)]  # the same memory
                                for n in ("params", "unknown_scale", "row_scale", "ramp_t",
                                          "ramp_w"))
    # the last entry of d: which of the passes compiled apart the kernels compile (flanges,
    # whirl, rolling resistance, mixed lubrication, the extensions', the defects' with their
    # table: system/optional.py)
    extension = marker_entry(scene)  # (refused with defects)
    data = data[:len(WORK_SLOTS)] + (
        optional_marker(P, extension, None if table is None else data[-1]),)
    return Model(scene, g, layout, P, S, RS, mass, ramp_t, ramp_w, m_c, I_c, q_ref, d_ref, data,
                 work)

