"""Quasi-static equilibrium of inner ring and rollers: damped Newton on theory.md §5.

Stage: scene -> geometry -> **static solve** -> Dataset. Rollers sit at their initial azimuths,
orbit at the epicyclic (pure-rolling) speed of the scene's speed at t = 0, so each carries the
centrifugal force F_c = m R_m Ω². The same solve gives the DAE its initial algebraic state.

Newton is run on the scaled system (lengths in units of the Hertz approach at a reference roller
load, forces in units of that load) with the analytic Jacobian; a backtracking line search on
the scaled residual norm and a step cap make it converge from far-off starts.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ..physics.contact import slice_stiffness
from ..physics.equilibrium import (
    ContactParams,
    ContactState,
    algebraic_equations,
    algebraic_jacobian,
    centrifugal_force,
    contact_state,
    ring_basis,
)
from ..physics.geometry import Geometry
from ..physics.ring import support_force
from ..system.layout import split_static as split  # z -> (u, β, ring); also static.split
from ..system.scales import reference_scales

MAX_BACKTRACKS = 40  # halvings of a Newton step before the line search gives up
# Largest Newton update: 50 reference approaches or twice the clearance, whichever is larger
# (a floating roller may have to cross the whole gap; beyond that, steps only overshoot).
STEP_CAP = 50.0
CONTINUATION_FACTOR = 8.0  # ε reduction per continuation stage
PLAIN_NEWTON_ITERATIONS = 40  # plain Newton needs < 15 when it works; past this, continue in ε


class StaticConvergenceError(RuntimeError):
    """Newton did not converge; carries the last iterate for diagnosis."""


@dataclass(frozen=True)
class StaticProblem:
    """Everything the algebraic equations need, with their scales."""

    geometry: Geometry
    contact: ContactParams
    azimuth_rad: np.ndarray  #: (Z,)
    centrifugal_N: np.ndarray  #: (Z,)
    loads: np.ndarray  #: (F_r, F_t, M, M_t)
    basis: np.ndarray = field(repr=False)  #: ring basis P (Z, k, 4)
    force_scale_N: float = 1.0  #: reference roller load Q_ref
    length_scale_m: float = 1e-6  #: Hertz approach at Q_ref
    #: False holds the ring at its start values and solves the rollers' unknowns alone (the
    #: algebraic rows of a dynamic ring, theory.md §15; the ring rows are then not solved)
    ring_free: bool = True
    #: stiffness of the ring's support to ground (a dynamic ring, theory.md §15) [N/m]
    support_N_m: float = 0.0

    @property
    def n_free(self) -> int:
        """Unknowns (and equations) Newton solves: all 2 Z + 4, or the rollers' 2 Z."""
        Z = self.geometry.rollers
        return 2 * Z + 4 if self.ring_free else 2 * Z

    @property
    def unknown_scale(self) -> np.ndarray:
        """Scale of z = (u (Z), β (Z), δ_r, δ_t, γ_r, γ_t)."""
        Z = self.geometry.rollers
        half = 0.5 * self.geometry.roller_length_m
        d = self.length_scale_m
        return np.concatenate([np.full(Z, d), np.full(Z, d / half), [d, d, d / half, d / half]])

    @property
    def equation_scale(self) -> np.ndarray:
        """Scale of (R (Z), T (Z), E (4)): forces by Q_ref, moments by Q_ref L/2."""
        Z = self.geometry.rollers
        half = 0.5 * self.geometry.roller_length_m
        f = self.force_scale_N
        return np.concatenate([np.full(Z, f), np.full(Z, f * half), [f, f, f * half, f * half]])


def contact_params(geometry: Geometry, smoothing_m: float) -> ContactParams:
    """Contact parameters of a geometry (both races share materials and slicing)."""
    return ContactParams(
        x_m=geometry.x_m,
        profile_drop_m=geometry.profile_drop_m,
        clearance_m=geometry.clearance_m,
        stiffness=slice_stiffness(
            geometry.slice_width_m, geometry.roller_length_m, geometry.compliance_m2_N
        ),
        smoothing_m=smoothing_m,
    )


def make_problem(
    geometry: Geometry,
    loads,
    speed_rad_s: float,
    smoothing_m: float,
    azimuth_rad: np.ndarray | None = None,
    orbit_speed_rad_s: np.ndarray | None = None,
    ring_free: bool = True,
    support_N_m: float = 0.0,
    separation_m: tuple | None = None,
) -> StaticProblem:
    """Static problem at the given azimuths (default: initial ones) and orbit speeds
    (default: epicyclic at the inner-ring speed ``speed_rad_s`` [rad/s]); ``separation_m``:
    the (inner, outer) separations (Z, k) of local defects and waviness at those azimuths
    (system/defects.separation_arrays), None for a healthy bearing."""
    az = geometry.azimuth0_rad if azimuth_rad is None else np.asarray(azimuth_rad, float)
    if orbit_speed_rad_s is None:
        orbit = np.full(geometry.rollers, geometry.epicyclic_orbit_speed(speed_rad_s))
    else:
        orbit = np.asarray(orbit_speed_rad_s, float)
    Fc = centrifugal_force(geometry.roller_mass_kg, geometry.pitch_radius_m, orbit)
    loads = np.asarray(loads, dtype=float)
    q_ref, d_ref = reference_scales(geometry, loads, Fc)
    return StaticProblem(
        geometry=geometry,
        contact=replace(contact_params(geometry, smoothing_m), separation_m=separation_m),
        azimuth_rad=az,
        centrifugal_N=Fc,
        loads=loads,
        basis=ring_basis(geometry.x_m, az),
        force_scale_N=q_ref,
        length_scale_m=d_ref,
        ring_free=ring_free,
        support_N_m=float(support_N_m),
    )


def evaluate(prob: StaticProblem, z: np.ndarray, jacobian: bool = True):
    """Residual F(z) (2Z+4,), its dense Jacobian (or None) and the contact state."""
    Z = prob.geometry.rollers
    u, beta, ring = split(z, Z)
    cs = contact_state(u, beta, ring, prob.azimuth_rad, prob.contact)
    R, T, E = algebraic_equations(cs, prob.centrifugal_N, prob.loads, prob.contact.x_m, prob.basis)
    k = prob.support_N_m
    if k:  # the support carries part of the load: E = loads + F_s - Σ shares
        E = E.copy()
        E[0] += support_force(k, 0.0, ring[0], 0.0)
        E[1] += support_force(k, 0.0, ring[1], 0.0)
    F = np.concatenate([R, T, E])
    if not jacobian:
        return F, None, cs
    roller, roller_ring, ring_roller, ring_ring = algebraic_jacobian(
        cs, prob.contact.x_m, prob.basis
    )
    n = 2 * Z + 4
    J = np.zeros((n, n))
    idx = np.arange(Z)
    for a in range(2):
        for b in range(2):
            J[a * Z + idx, b * Z + idx] = roller[:, a, b]
        J[a * Z : (a + 1) * Z, 2 * Z :] = roller_ring[:, a, :]
        J[2 * Z :, a * Z : (a + 1) * Z] = ring_roller[:, :, a]
    J[2 * Z :, 2 * Z :] = ring_ring
    if k:  # dF_s/dδ = -k (physics/ring.support_force)
        J[2 * Z, 2 * Z] -= k
        J[2 * Z + 1, 2 * Z + 1] -= k
    return F, J, cs


def default_start(prob: StaticProblem) -> np.ndarray:
    """Start: rollers against the outer race, ring pushed through half the clearance plus two
    Hertz approaches along the load, no tilts."""
    g = prob.geometry
    Z = g.rollers
    z = np.zeros(2 * Z + 4)
    F = np.hypot(prob.loads[0], prob.loads[1])
    if F > 0:
        reach = 0.5 * g.clearance_m + 2.0 * prob.length_scale_m
        z[2 * Z] = reach * prob.loads[0] / F
        z[2 * Z + 1] = reach * prob.loads[1] / F
    return z


@dataclass
class StaticSolution:
    z: np.ndarray
    residual: np.ndarray
    relative_residual: float  #: max |F| / F_scale, F_scale = max(load, contact load, F_c)
    iterations: int
    contact: ContactState
    problem: StaticProblem


def residual_scale(prob: StaticProblem, cs: ContactState) -> np.ndarray:
    """Per-equation scale for the *relative* residual: the largest force (moment) in play."""
    Z = prob.geometry.rollers
    half = 0.5 * prob.geometry.roller_length_m
    Fmax = max(
        float(np.abs(prob.loads[:2]).max()),
        float(np.abs(prob.loads[2:]).max()) / half,
        float(cs.load_inner_N.sum(axis=1).max()),
        float(cs.load_outer_N.sum(axis=1).max()),
        float(prob.centrifugal_N.max(initial=0.0)),
        1e-12,
    )
    return np.concatenate([np.full(Z, Fmax), np.full(Z, Fmax * half),
                           [Fmax, Fmax, Fmax * half, Fmax * half]])


def solve(prob: StaticProblem, z0: np.ndarray | None = None, tol: float = 1e-12,
          max_iter: int = 100) -> StaticSolution:
    """Equilibrium of theory.md §5: damped Newton, with ε-continuation as the fallback.

    Plain Newton converges in a handful of iterations from the default start. When it does
    not (far-off starts, or rollers floating in a large clearance, where the regularised
    contact tails make the Jacobian numerically singular), the contact smoothing length ε is
    raised above every gap, which makes the problem nearly linear, and lowered back to its
    target by factors of :data:`CONTINUATION_FACTOR`, each stage warm-started by the last.
    """
    z_start = default_start(prob) if z0 is None else np.array(z0, dtype=float)
    try:
        return _newton(prob, z_start, tol, min(max_iter, PLAIN_NEWTON_ITERATIONS))
    except StaticConvergenceError as first:
        eps_target = prob.contact.smoothing_m
        Z = prob.geometry.rollers
        lengths = np.concatenate([z_start[:Z], z_start[2 * Z : 2 * Z + 2]])
        eps = 4.0 * max(abs(prob.geometry.clearance_m), 10.0 * prob.length_scale_m,
                        float(np.abs(lengths).max(initial=0.0)))
        z = z_start
        iterations = 0
        try:
            while True:
                eps = max(eps, eps_target)
                stage = replace(prob, contact=replace(prob.contact, smoothing_m=eps))
                final = eps == eps_target
                sol = _newton(stage, z, tol if final else 1e-8, max_iter)
                z, iterations = sol.z, iterations + sol.iterations
                if final:
                    sol.iterations = iterations
                    return sol
                eps /= CONTINUATION_FACTOR
        except StaticConvergenceError as exc:
            raise StaticConvergenceError(
                f"{first}; continuation in the contact smoothing also failed at "
                f"eps = {eps:.3g} m: {exc}"
            ) from None


def _newton(prob: StaticProblem, z: np.ndarray, tol: float, max_iter: int) -> StaticSolution:
    """Damped Newton. Converged when max |F| / F_scale <= tol (F_scale: the largest force)."""
    nf = prob.n_free
    xs, fs = prob.unknown_scale[:nf], prob.equation_scale[:nf]
    z = np.array(z, dtype=float)
    cap = max(STEP_CAP, 2.0 * abs(prob.geometry.clearance_m) / prob.length_scale_m)
    F, J, cs = evaluate(prob, z)
    F, J = F[:nf], J[:nf, :nf]
    rel = np.abs(F / residual_scale(prob, cs)[:nf]).max()
    for it in range(1, max_iter + 1):
        Fs = F / fs
        Js = J * xs[None, :] / fs[:, None]
        try:
            step = -np.linalg.solve(Js, Fs)
        except np.linalg.LinAlgError:
            step = -np.linalg.lstsq(Js, Fs, rcond=None)[0]
        big = np.abs(step).max()
        if big > cap:
            step *= cap / big
        norm0 = np.linalg.norm(Fs)
        lam = 1.0
        for _ in range(MAX_BACKTRACKS):
            z_try = z.copy()
            z_try[:nf] += lam * step * xs
            F_try = evaluate(prob, z_try, jacobian=False)[0][:nf]
            if np.all(np.isfinite(F_try)) and np.linalg.norm(F_try / fs) <= (1 - 1e-4 * lam) * norm0:
                break
            lam *= 0.5
        else:
            # No decrease possible: accept the full step if we are at round-off level.
            if rel <= 1e2 * tol:
                break
            raise StaticConvergenceError(
                f"line search failed at Newton iteration {it}: relative residual {rel:.3e} "
                f"(tolerance {tol:.1e}); the scene may have no equilibrium (check loads and "
                "clearance)"
            )
        z = z_try
        F, J, cs = evaluate(prob, z)
        F, J = F[:nf], J[:nf, :nf]
        rel = np.abs(F / residual_scale(prob, cs)[:nf]).max()
        if rel <= tol and lam * np.abs(step).max() < 1e-6:
            break
    else:
        raise StaticConvergenceError(
            f"Newton did not converge in {max_iter} iterations: relative residual {rel:.3e} "
            f"(tolerance {tol:.1e}); raise numerics.static_max_iterations or check the scene"
        )
    return StaticSolution(z, F, float(rel), it, cs, prob)
