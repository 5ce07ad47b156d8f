"""Cage whirl (theory.md §17) on the baseline and in its unstable regime.

References, each with the tolerance it supports:
- momentum balance of the cage over one cage revolution: its change of linear momentum
  m_c Δė and of angular momentum I_c Δω_c against the impulses of the forces and moments on it,
  assembled here independently of system/whirl.py from the pocket end forces the kernel reports,
  the pocket, land and churning laws (physics/*), integrated by the trapezoid rule on 20 000 -
  50 000 samples per revolution, at every sample: ≤ 1 % of the impulse's largest excursion;
- the 1-DOF cage: the mean cage speed of a whirling cage (20 cage revolutions) within 2 % of
  the rotating-only cage's on the baseline (24 cage revolutions, a run other modules share);
- geometry: the cage centre never leaves its guidance travel (land: C; roller guidance: the
  polygon of the pockets' radial lips, corner (c_p/2)/cos(π/Z))
  by more than the contact deformation (largest contact force / stiffness + 3 smoothing lengths);
- oil whirl (Newkirk & Taylor 1925, "Shaft whipping due to oil action in journal bearings",
  General Electric Review 28, 559-568; for the short bearing: Childs, *Turbomachinery
  Rotordynamics*, 1993, §2.4, and San Andrés, *Modern Lubrication Theory*, notes 5: an
  unloaded journal whirls at half the mean surface speed and the orbit grows, a journal loaded
  to a steady eccentricity ε₀ > 0.756 is stable at any speed): the unloaded land-guided cage at
  10 000 r/min whirls at 0.5 ± 0.03 of the cage speed with a growing orbit, the same cage
  under the baseline's 800 N sits still at ε > 0.756 (orbit trend < 1e-3 C per revolution);
- Newmark-β against IDA: whirl ratio within 2 % (docs/theory.md §12 cross-check).
"""

from __future__ import annotations

import numpy as np
import pytest
from physical_checks import power_balance

from bearingdae import load_scene, simulate
from bearingdae.analysis.result_variables import flat
from bearingdae.physics.cage import cage_annulus, pocket_damping, pocket_force, pocket_loads
from bearingdae.physics.cage_guidance import LAND_FRICTION, LAND_SPEED_SCALE_RAD_S, land_force
from bearingdae.physics.lubricant import cage_side_churning
from bearingdae.solvers.algebraic import initial_state
from bearingdae.solvers.ida import integrate
from bearingdae.system.layout import GLOBAL, LOCAL
from bearingdae.system.model import build_model
from bearingdae.system.residual import P_WH, PARAM_NAMES
from bearingdae.system.whirl import W_CDP, W_CR, W_EPSP, W_FP, W_KP

UNLOADED = {"physics.cage_whirl": True, "cage.guidance": "outer-land",
            "cage.land_clearance_mm": 0.09, "operating.speed_rpm": 10000.0,
            "operating.radial_load_N": 0.0, "operating.moment_Nm": 0.0}


def _cage_loads(model, t, y):
    """(F_x, F_y, M) [N, N, N m] on the cage at one scaled state: pockets (tangential push,
    radial friction, radial lips), land, churning; assembled from the laws, not system/whirl.py."""
    sc, g = model.scene, model.geometry
    full_l, full_g = model.layout.unpack(y * model.scale)
    G = dict(zip(GLOBAL, full_g))
    Z, Rm, r, L = g.rollers, g.pitch_radius_m, g.roller_radius_m, g.roller_length_m
    fp = model.diagnostics(t, y)["cage_force"]
    om = full_l[:, LOCAL.index("spin_speed")]
    psi = G["cage_angle"] + 2 * np.pi * np.arange(Z) / Z
    cp, sp = np.cos(psi), np.sin(psi)
    e_r = G["cage_x"] * cp + G["cage_y"] * sp
    e_t = -G["cage_x"] * sp + G["cage_y"] * cp
    F_cr, _, M_spin, _ = pocket_loads(fp[:, 0], fp[:, 1], om, L, r, Rm, sc.cage.friction,
                                      force_scale_N=sc.cage.spin_friction_force_scale_N)
    sg = om / np.sqrt(om**2 + 1e-2**2)
    f = -sc.cage.friction * sg * F_cr
    PW = model.params[P_WH:]
    nu_r = G["cage_vx"] * cp + G["cage_vy"] * sp
    F_rho = pocket_force(-e_r, -(nu_r + G["cage_speed"] * e_t), PW[W_CR], PW[W_KP], PW[W_CDP],
                         PW[W_EPSP], PW[W_FP])[0]
    Fx = np.sum(F_cr * sp + f * cp - F_rho * cp)
    Fy = np.sum(-F_cr * cp + f * sp - F_rho * sp)
    M = np.sum(-Rm * F_cr + M_spin + e_r * F_cr + e_t * f)
    if sc.cage.guidance != "roller":
        r_i, r_o, _ = cage_annulus(Rm, 2 * r, L)
        inner = sc.cage.guidance == "inner-land"
        K = sc.cage.pocket_stiffness_N_m
        lf = land_force(G["cage_x"], G["cage_y"], G["cage_vx"], G["cage_vy"], G["cage_speed"],
                        model.ring_speed(t) if inner else 0.0, -1.0 if inner else 1.0,
                        0.5 * sc.cage.land_clearance_m, r_i if inner else r_o,
                        sc.cage.land_width_m, sc.lubricant.viscosity_Pa_s, K,
                        pocket_damping(K, model.params[P_WH + 1], sc.cage.damping_ratio),
                        sc.cage.smoothing_m, friction=LAND_FRICTION,
                        speed_scale_rad_s=LAND_SPEED_SCALE_RAD_S)
        Fx, Fy, M = Fx + lf[0], Fy + lf[1], M + lf[2]
    if sc.physics.drag:
        cri, cro, _ = cage_annulus(Rm, 2 * r, L)
        p = dict(zip(PARAM_NAMES, model.params))
        M -= cage_side_churning(G["cage_speed"], cri, cro, p["rho_e"], p["mu_oil"])
    return Fx, Fy, M


def _momentum_balance(overrides, samples=20_000):
    scene = load_scene("yang20_baseline", overrides)
    m = build_model(scene)
    y0, yp0 = initial_state(m)
    period = 2 * np.pi / m.final_cage_speed()
    t = np.linspace(0.0, period, samples + 1)
    r = integrate(m, y0, yp0, t)
    assert r.success, r.message
    loads = np.array([_cage_loads(m, tk, y) for tk, y in zip(t, r.y)])
    full = np.array([m.layout.unpack(y * m.scale)[1] for y in r.y])
    mass, inertia = m.params[P_WH + 1], m.cage_inertia_kgm2
    v = full[:, [GLOBAL.index("cage_vx"), GLOBAL.index("cage_vy")]]
    w = full[:, GLOBAL.index("cage_speed")]
    # running impulse ∫_0^t (F, M) dt (trapezoid) against the change of momentum since t = 0,
    # at every sample; measured against the impulse's largest excursion over the revolution
    from scipy.integrate import cumulative_trapezoid

    impulse = cumulative_trapezoid(loads, t, axis=0, initial=0.0)
    dp = mass * (v - v[0]) - impulse[:, :2]
    dl = inertia * (w - w[0]) - impulse[:, 2]
    lin = np.hypot(*dp.T).max() / np.hypot(*impulse[:, :2].T).max()
    ang = np.abs(dl).max() / np.abs(impulse[:, 2]).max()
    return lin, ang


@pytest.mark.parametrize("overrides, samples", [
    (UNLOADED, 20_000),  # the whirling cage: film, growing orbit
    # roller guidance on the baseline: pocket impacts of a few µs, hence the finer sampling
    # (the trapezoid's error falls as h²: 1.5 % at 20 000 samples, 0.2 % at 50 000)
    pytest.param({"physics.cage_whirl": True}, 50_000,
                 marks=pytest.mark.slow),  # 10 s: the CI physics step
    pytest.param({"physics.cage_whirl": True, "cage.guidance": "outer-land"}, 50_000,
                 marks=pytest.mark.slow),  # held by the land's film on the baseline
], ids=["unloaded-outer-land", "baseline-roller", "baseline-outer-land"])
def test_cage_momentum_balance_over_a_revolution(overrides, samples):
    """m_c Δė = ∫F dt and I_c Δω_c = ∫M dt at every sample of one cage revolution from the
    consistent start, to 1 % of the impulse's largest excursion (measured: 2e-4 / 3e-4 for the
    unloaded case, 2.2e-3 / 2.0e-3 for the roller-guided baseline; leaving the land force out of
    the sum breaks the unloaded case's angular balance by 130 %, the pockets' radial lips the
    roller-guided linear balance by 100 %)."""
    lin, ang = _momentum_balance(overrides, samples)
    assert lin <= 1e-2 and ang <= 1e-2, (lin, ang)


# ---------------------------------------------------------------------------------------------
# Slow tier: the baseline over 20 cage revolutions, the stability study, Newmark against IDA
# ---------------------------------------------------------------------------------------------
TWENTY = {"numerics.cage_revolutions": 20.0}


def _run(overrides, solver=None):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # λ < 1 on the baseline (boundary lubrication)
        scene = load_scene("yang20_baseline", overrides)
        return scene, (simulate(scene, solver=solver) if solver else simulate(scene))


@pytest.fixture(scope="module")
def one_dof_cage(long_baseline):
    """The rotating-only cage: the baseline over 24 recorded revolutions (the whirling runs'
    20 and more), the run tests/solvers/test_newmark.py and test_statistical_equivalence.py
    read too (computed once per session: tests/conftest.py)."""
    scene, ds = long_baseline
    assert not scene.physics.cage_whirl and scene.dynamics.cage_revolutions >= 20
    return ds


def _contact_allowance(scene, ds) -> float:
    """Largest contact deformation [m]: the largest land or pocket force over the contact
    stiffness, plus three smoothing lengths (the regularised onset, physics/cage.py)."""
    force = float(np.abs(ds.cage_force).max())
    if "cage_land_force" in ds:
        force = max(force, float(ds.cage_land_force.max()))
    return force / scene.cage.pocket_stiffness_N_m + 3 * scene.cage.smoothing_m


@pytest.mark.slow
@pytest.mark.parametrize("guidance", ["roller", "outer-land"])
def test_baseline_whirl_over_twenty_revolutions(one_dof_cage, guidance):
    scene, ds = _run({**TWENTY, "physics.cage_whirl": True, "cage.guidance": guidance})
    a = flat(ds)
    speed, ref = a["mean_cage_speed_rad_s"], one_dof_cage["mean_cage_speed_rad_s"].item()
    radius = np.hypot(*ds.cage_center.values.T)
    travel = a["cage_guidance_clearance_m"]
    print(f"\n{guidance}: whirl ratio {a['cage_whirl_ratio']:.4g}, |e|/C mean "
          f"{a['cage_orbit_radius_over_clearance']:.4g} max "
          f"{a['cage_orbit_radius_over_clearance_max']:.4g}, trend "
          f"{a['cage_orbit_radius_over_clearance_trend_per_revolution']:.3g}/rev, land force "
          f"max {float(ds.cage_land_force.max()):.4g} N, pocket force max "
          f"{float(np.abs(ds.cage_force).max()):.4g} N, cage speed {speed:.5g} against "
          f"{ref:.5g} rad/s")
    assert abs(speed / ref - 1.0) <= 0.02
    assert radius.max() <= travel + _contact_allowance(scene, ds)
    assert ds.sizes["time"] >= 20 * scene.dynamics.samples_per_cage_revolution


@pytest.fixture(scope="module")
def unloaded():
    return _run({**UNLOADED, **TWENTY})


@pytest.mark.slow
def test_unloaded_land_guided_cage_whirls_at_half_speed_and_grows(unloaded):
    scene, ds = unloaded
    a = flat(ds)
    assert abs(a["cage_whirl_ratio"] - 0.5) <= 0.03
    assert a["cage_orbit_radius_over_clearance_trend_per_revolution"] > 0.02
    assert a["cage_orbit_radius_over_clearance_max"] >= 0.9
    radius = np.hypot(*ds.cage_center.values.T)
    assert radius.max() <= a["cage_guidance_clearance_m"] + _contact_allowance(scene, ds)


@pytest.mark.slow
def test_loaded_land_guided_cage_is_stable():
    """The same cage and speed under the baseline's 800 N and 3 N m: the roller set's net pocket
    force holds it at a steady eccentricity beyond the short bearing's 0.756."""
    over = {k: v for k, v in UNLOADED.items() if not k.startswith("operating.radial")
            and not k.startswith("operating.moment")}
    scene, ds = _run({**over, **TWENTY})
    a = flat(ds)
    assert a["cage_orbit_radius_over_clearance"] > 0.756
    assert abs(a["cage_orbit_radius_over_clearance_trend_per_revolution"]) < 1e-3
    radius = np.hypot(*ds.cage_center.values.T)
    assert radius.std() < 0.02 * a["cage_guidance_clearance_m"]


@pytest.mark.slow
def test_newmark_whirl_ratio_matches_ida(unloaded):
    _, ds = _run({**UNLOADED, **TWENTY}, solver="newmark")
    ida = unloaded[1]["cage_whirl_ratio"].item()
    assert abs(ds["cage_whirl_ratio"].item() / ida - 1.0) <= 0.02


@pytest.mark.parametrize("guidance", ["roller", "outer-land", "inner-land"])
def test_energy_balance_with_a_whirling_cage(guidance):
    """Reference: the energy balance of physics/power.py (every equation of motion times its
    speed): drive power = Σ losses + dE/dt, with the whirling cage's terms (the displaced
    pockets' work, the land's loss, ½ m_c |ė|², an inner land's moment in the drive). As
    tests/analysis/test_engineering.py: baseline after one warm-up revolution, a quarter
    revolution at 5000 samples per revolution, 1 % of the drive power."""
    _, ds = _run({"physics.cage_whirl": True, "cage.guidance": guidance,
                  "numerics.warmup_cage_revolutions": 1.0, "numerics.cage_revolutions": 0.25,
                  "numerics.samples_per_cage_revolution": 5000})
    drive, losses, stored = power_balance(ds)
    assert abs(drive - losses - stored) < 0.01 * drive, (drive, losses, stored)
    land = float(ds.power_loss_W.sel(loss_source="cage_land").mean())
    assert (land == 0.0) if guidance == "roller" else (land > 0.0)
