"""Assemble the DAE of one scene: parameters, scales, work arrays, initial state (MODEL §11).

Stage: scene -> geometry -> **DAE model** -> solver. Only the unknowns the scene's ``[physics]``
switches ask for enter the compact state (system/layout.py).

Scaling: IDA sees y = Y / S with S the scale of each unknown (lengths by the Hertz approach at
the reference roller load, speeds by the epicyclic speed, ...), and every residual row divided
by a force, moment or rate scale, so that one ``atol`` (in units of each scale) suits all
unknowns. The scales are recorded in the output metadata.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..physics.cage import (SPIN_SPEED_SCALE_RAD_S, cage_annulus, cage_mass_inertia,
                            pocket_damping)
from ..physics.contact import slice_stiffness
from ..physics.geometry import Geometry, make_geometry
from ..physics.lubricant import effective_density
from ..scene import Scene
from ..solvers import static
from .layout import GLOBAL, LOCAL, Layout
from .residual import PARAM_NAMES, flat_work, residual

RPM = 2.0 * np.pi / 60.0
SKEW_SCALE_RAD = 1e-3  # typical skew angle: sets the absolute tolerance of θz
STATIC_REFERENCE_PERIOD_S = 0.01  # time unit of a scene whose final speed is zero


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
    data: tuple = field(repr=False, default=())  #: work arrays of the kernel (views of ``work``)
    work: tuple = field(repr=False, default=())  #: (W, I): ``data`` as two flat buffers

    @property
    def size(self) -> int:
        return self.layout.size

    def ring_speed(self, t: float) -> float:
        return float(np.interp(t, self.ramp_t, self.ramp_w))

    def final_cage_speed(self) -> float:
        """Epicyclic cage speed at the final inner-ring speed [rad/s]."""
        return self.geometry.epicyclic_orbit_speed(self.ramp_w[-1])

    def residual(self, t: float, y: np.ndarray, yp: np.ndarray) -> np.ndarray:
        res = np.empty(self.size)
        residual(t, y, yp, res, self.data)
        return res

    def diagnostics(self, t: float, y: np.ndarray) -> dict[str, np.ndarray]:
        """Per-slice and per-end quantities at one state (copies of the kernel's work arrays)."""
        res = np.empty(self.size)
        residual(t, y, np.zeros_like(y), res, self.data)
        q, pr, v, f, fp = self.data[16:21]
        return {"contact_force": q.copy(), "contact_pressure": pr.copy(),
                "slip_velocity": v.copy(), "traction_force": f.copy(), "cage_force": fp.copy()}


def _speed_ramp(scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    n = scene.operating.speed_rpm
    if isinstance(n, tuple):
        return np.array(n[0], float), np.array(n[1], float) * RPM
    return np.array([0.0]), np.array([float(n) * RPM])


def build_model(scene: Scene) -> Model:
    g = make_geometry(scene)
    ph, tr, cg, lub, op = scene.physics, scene.traction, scene.cage, scene.lubricant, scene.operating
    # With one slice every slice sits at x = 0: tilt has no lever arm and its equations vanish
    # identically, so the tilt unknowns are dropped (a moment is refused by the scene check).
    layout = Layout(g.rollers, skew=ph.skew, cage=ph.cage, tilt=ph.tilt and g.slices > 1)
    ramp_t, ramp_w = _speed_ramp(scene)
    r, L, Rm = g.roller_radius_m, g.roller_length_m, g.pitch_radius_m

    m_c, I_c = cage_mass_inertia(Rm, 2 * r, L, g.rollers, cg.pocket_clearance_m, cg.density_kg_m3)
    cri, cro, _ = cage_annulus(Rm, 2 * r, L)
    loads = op.loads
    w_max = float(ramp_w.max())
    prob = static.make_problem(g, loads, w_max / RPM, scene.numerics.contact_smoothing_m)
    q_ref, d_ref = prob.force_scale_N, prob.length_scale_m

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
        "Fr": loads[0], "Ft": loads[1], "M": loads[2], "Mt": loads[3],
    }
    P = np.array([float(values[n]) for n in PARAM_NAMES])

    # ---- scales of unknowns and rows, in full (kernel) order ----
    om_ref = max(g.epicyclic_orbit_speed(w_max), 1.0)
    spin_ref = om_ref * g.outer_race_radius_m / r
    half = 0.5 * L
    f_ref = q_ref
    unk = {"azimuth": 1.0, "orbit_speed": om_ref, "spin_speed": spin_ref,
           "skew_angle": SKEW_SCALE_RAD, "skew_rate": SKEW_SCALE_RAD * om_ref,
           "radial_position": d_ref, "tilt": d_ref / half, "cage_angle": 1.0,
           "cage_speed": om_ref, "ring_dr": d_ref, "ring_dt": d_ref, "ring_gr": d_ref / half,
           "ring_gt": d_ref / half}
    rows = {"azimuth": om_ref, "orbit_speed": f_ref, "spin_speed": f_ref * r,
            "skew_angle": SKEW_SCALE_RAD * om_ref, "skew_rate": f_ref * half,
            "radial_position": q_ref, "tilt": q_ref * half, "cage_angle": om_ref,
            "cage_speed": f_ref * Rm, "ring_dr": q_ref, "ring_dt": q_ref,
            "ring_gr": q_ref * half, "ring_gt": q_ref * half}
    orbit_mass = (g.roller_mass_kg * Rm**2 + g.roller_inertia_axial_kgm2 if ph.orbit == "paper"
                  else g.roller_mass_kg * Rm)
    masses = {"azimuth": 1.0, "orbit_speed": orbit_mass, "spin_speed": g.roller_inertia_axial_kgm2,
              "skew_angle": 1.0, "skew_rate": g.roller_inertia_transverse_kgm2,
              "radial_position": 0.0, "tilt": 0.0, "cage_angle": 1.0, "cage_speed": I_c,
              "ring_dr": 0.0, "ring_dt": 0.0, "ring_gr": 0.0, "ring_gt": 0.0}

    def compact(table):
        loc = [table[n] for n in layout.local_names] * g.rollers
        return np.array(loc + [table[n] for n in layout.global_names], float)

    S, RS, Mraw = compact(unk), compact(rows), compact(masses)
    mass = Mraw * S / RS

    Z, k = g.rollers, g.slices
    data, work = flat_work((
        P, g.x_m.copy(), g.profile_drop_m.copy(), S, RS, layout.local_map, layout.global_map,
        ramp_t, ramp_w,
        np.zeros((Z, len(LOCAL))), np.zeros((Z, len(LOCAL))), np.zeros(len(GLOBAL)),
        np.zeros(len(GLOBAL)), np.zeros((Z, len(LOCAL))), np.zeros(len(GLOBAL)),
        np.zeros((Z, len(GLOBAL))),
        np.zeros((Z, k, 2)), np.zeros((Z, k, 2)), np.zeros((Z, k, 2)), np.zeros((Z, k, 2)),
        np.zeros((Z, 2)),
    ))
    P, S, RS, ramp_t, ramp_w = data[0], data[3], data[4], data[7], data[8]  # the same memory
    return Model(scene, g, layout, P, S, RS, mass, ramp_t, ramp_w, m_c, I_c, q_ref, d_ref, data,
                 work)


def initial_state(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """Scaled (y0, yp0): quasi-static equilibrium at pure-rolling (epicyclic) speeds, zero skew,
    rollers centred in their pockets, cage at the epicyclic speed (MODEL §11); y'0 of the
    differential unknowns from the equations of motion, of the algebraic ones zero (IDA's
    consistent initialisation then corrects both)."""
    g, sc, lay = model.geometry, model.scene, model.layout
    w0 = model.ring_speed(0.0)
    Om = g.epicyclic_orbit_speed(w0)
    op = sc.operating
    loads = op.loads
    prob = static.make_problem(g, loads, w0 / RPM, sc.numerics.contact_smoothing_m)
    sol = static.solve(prob, tol=sc.numerics.static_tolerance,
                       max_iter=sc.numerics.static_max_iterations)
    u, beta, ring = static.split(sol.z, g.rollers)

    full_l = np.zeros((g.rollers, len(LOCAL)))
    full_g = np.zeros(len(GLOBAL))
    full_l[:, LOCAL.index("azimuth")] = g.azimuth0_rad
    full_l[:, LOCAL.index("orbit_speed")] = Om
    full_l[:, LOCAL.index("spin_speed")] = g.pure_rolling_spin(w0)
    full_l[:, LOCAL.index("radial_position")] = u
    full_l[:, LOCAL.index("tilt")] = beta
    full_g[GLOBAL.index("cage_speed")] = Om
    full_g[2:] = ring
    y0 = lay.pack(full_l, full_g) / model.scale
    # y' from F(y, 0) = -f(y): y'_i = f_i / mass_i for the differential rows.
    res0 = model.residual(0.0, y0, np.zeros_like(y0))
    yp0 = np.zeros_like(y0)
    diff = model.mass > 0
    yp0[diff] = -res0[diff] / model.mass[diff]
    return y0, yp0


def project_algebraic(model: Model, t: float, y: np.ndarray) -> tuple[np.ndarray, int]:
    """Solve the algebraic equations (MODEL §5) for the algebraic unknowns of the scaled state
    ``y``, its differential unknowns held fixed; returns (y, Newton iterations).

    The algebraic rows of the DAE are exactly the quasi-static equations at the rollers' current
    azimuths and orbit speeds, so this is the static Newton (solvers/static.py) warm-started
    from IDA's value: outputs then satisfy them to round-off, independently of IDA's tolerance.
    """
    lay, g = model.layout, model.geometry
    full_l, full_g = lay.unpack(y * model.scale)
    sc = model.scene
    op = sc.operating
    loads = op.loads
    prob = static.make_problem(
        g, loads, 0.0, sc.numerics.contact_smoothing_m,
        azimuth_rad=full_l[:, LOCAL.index("azimuth")],
        orbit_speed_rad_s=full_l[:, LOCAL.index("orbit_speed")],
    )
    z0 = np.concatenate([full_l[:, LOCAL.index("radial_position")],
                         full_l[:, LOCAL.index("tilt")], full_g[2:]])
    sol = static.solve(prob, z0, tol=sc.numerics.static_tolerance,
                       max_iter=sc.numerics.static_max_iterations)
    u, beta, ring = static.split(sol.z, g.rollers)
    full_l[:, LOCAL.index("radial_position")] = u
    full_l[:, LOCAL.index("tilt")] = beta
    full_g[2:] = ring
    return lay.pack(full_l, full_g) / model.scale, sol.iterations
