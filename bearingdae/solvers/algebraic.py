"""The algebraic unknowns of a dynamic state, solved by the static Newton (theory.md §5, §11).

Stage: system (DAE model) -> **solvers** -> results. The algebraic rows of the DAE are exactly
the quasi-static equations of theory.md §5 at the rollers' current azimuths and orbit speeds, so
the static Newton of solvers/static.py solves them: for the initial state of a run
(:func:`initial_state`) and, after a run, to project every output sample onto them
(:func:`project_algebraic`, results.from_solution). Speeds are SI (rad/s) throughout.

Projecting a run's samples is done by :class:`AlgebraicProjector`: Newton on the algebraic rows
of the compiled DAE residual (system/residual.py) with the algebraic block of the analytic DAE
Jacobian (system/jacobian_analytic.py), the same equations as the static Newton's, evaluated by
the kernels IDA uses: ~0.1 ms per sample against ~2 ms for the numpy static Newton (before it,
the projection was ~1.2 s of the 10 s default run). A sample it cannot settle in a few
iterations falls back to the static Newton with its line search and continuation.
"""

from __future__ import annotations

import numpy as np

from ..system.layout import GLOBAL, LOCAL, RING, SPIN_ANGLE
from ..system.defect_sides import has_sharp
from ..system.defects import separation_arrays
from ..system.model import Model
from . import static

#: Newton iterations of :class:`AlgebraicProjector` before it hands a sample to the static
#: Newton (from an integrator's output, 1-2 iterations reach round-off)
PROJECTION_MAX_ITERATIONS = 8
#: floor of the projector's tolerance on the scaled algebraic rows: the round-off of the slice
#: sums (20 rollers x 10 slices of O(1) scaled loads) is ~1e-14
PROJECTION_TOL_FLOOR = 1e-13


#: full global indices of the ring's position unknowns (δ_r, δ_t, γ_r, γ_t)
_RING = [GLOBAL.index(n) for n in RING]


def support_stiffness(scene) -> float:
    """The ring support's stiffness [N/m]: a dynamic ring's, else 0 (no support)."""
    return scene.ring.support_stiffness_N_m if scene.physics.ring == "dynamic" else 0.0


def _solve(model: Model, t: float, azimuth_rad, orbit_speed_rad_s, z0=None,
           ring_free: bool = True, spin_angle_rad=None):
    """The static Newton at time t; ``ring_free=False`` holds the ring at z0's values (a dynamic
    ring: only the rollers' algebraic unknowns are solved); ``spin_angle_rad``: the rollers'
    spin angles where a defect sits on a roller (None: their reference 0, as at t = 0)."""
    sc, g = model.scene, model.geometry
    table = model.defect_table  # (the sides IDA froze: system/defect_sides.py)
    prob = static.make_problem(g, model.loads_at(t)[:4], model.ring_speed(t),  # radial loads
                               sc.numerics.contact_smoothing_m,
                               azimuth_rad=azimuth_rad, orbit_speed_rad_s=orbit_speed_rad_s,
                               ring_free=ring_free, support_N_m=support_stiffness(sc),
                               separation_m=separation_arrays(
                                   sc, g, t, azimuth_rad, model.ramp_t, model.ramp_w,
                                   spin_angle_rad, table if has_sharp(table) else None))
    return static.solve(prob, z0, tol=sc.numerics.static_tolerance,
                        max_iter=sc.numerics.static_max_iterations)


def initial_state(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """Scaled (y0, yp0): quasi-static equilibrium at pure-rolling (epicyclic) speeds, zero skew,
    rollers centred in their pockets, cage at the epicyclic speed, spin angles at their
    reference 0 (theory.md §11, §4); y'0 of the
    differential unknowns from the equations of motion, of the algebraic ones zero (IDA's
    consistent initialisation then corrects both)."""
    g, lay = model.geometry, model.layout
    w0 = model.ring_speed(0.0)
    Om = g.epicyclic_orbit_speed(w0)
    sol = _solve(model, 0.0, g.azimuth0_rad, np.full(g.rollers, Om))
    u, beta, ring = static.split(sol.z, g.rollers)

    full_l = np.zeros((g.rollers, len(LOCAL)))
    full_g = np.zeros(len(GLOBAL))
    full_l[:, LOCAL.index("azimuth")] = g.azimuth0_rad
    full_l[:, LOCAL.index("orbit_speed")] = Om
    full_l[:, LOCAL.index("spin_speed")] = g.pure_rolling_spin(w0)
    full_l[:, LOCAL.index("radial_position")] = u
    full_l[:, LOCAL.index("tilt")] = beta
    full_g[GLOBAL.index("cage_speed")] = Om
    full_g[_RING] = ring  # a dynamic ring starts at rest in this equilibrium
    y0 = lay.pack(full_l, full_g) / model.scale
    if lay.flange:  # the axial unknowns and the flange contacts (theory.md §16), with a
        # dynamic ring's balance under the flange forces too
        from .flange_static import with_flanges
        y0 = with_flanges(model, 0.0, y0)
    # y' from F(y, 0) = -f(y): y'_i = f_i / mass_i for the differential rows.
    res0 = model.residual(0.0, y0, np.zeros_like(y0))
    yp0 = np.zeros_like(y0)
    diff = model.mass > 0
    yp0[diff] = -res0[diff] / model.mass[diff]
    return y0, yp0


def project_algebraic(model: Model, t: float, y: np.ndarray) -> tuple[np.ndarray, int]:
    """Solve the algebraic equations (theory.md §5) for the algebraic unknowns of the scaled state
    ``y``, its differential unknowns held fixed; returns (y, Newton iterations).

    The static Newton (solvers/static.py) warm-started from the integrator's value: outputs
    then satisfy the algebraic equations to round-off, independently of its tolerance.
    """
    lay, g = model.layout, model.geometry
    if lay.flange:  # the flange contacts couple the axial unknowns in (theory.md §16)
        from .flange_static import settle
        return settle(model, t, y)
    full_l, full_g = lay.unpack(y * model.scale)
    z0 = np.concatenate([full_l[:, LOCAL.index("radial_position")],
                         full_l[:, LOCAL.index("tilt")], full_g[_RING]])
    sol = _solve(model, t, full_l[:, LOCAL.index("azimuth")],
                 full_l[:, LOCAL.index("orbit_speed")], z0, ring_free=not lay.ring_dynamic,
                 spin_angle_rad=full_l[:, LOCAL.index(SPIN_ANGLE)])
    u, beta, ring = static.split(sol.z, g.rollers)
    full_l[:, LOCAL.index("radial_position")] = u
    full_l[:, LOCAL.index("tilt")] = beta
    full_g[_RING] = ring
    return lay.pack(full_l, full_g) / model.scale, sol.iterations


class AlgebraicProjector:
    """Projection of scaled states onto the algebraic equations, with the compiled kernels.

    ``projector(t, y) -> (y, iterations)`` does what :func:`project_algebraic` does: the
    algebraic unknowns (radial positions, tilts, ring displacement and tilt) solve the algebraic
    rows F_a(t, y, 0) = 0 (theory.md §5) with the differential unknowns held fixed. Newton on the
    scaled rows, the Jacobian block dF_a/dy_a refreshed every iteration; converged when
    max |F_a| <= max(static_tolerance, 1e-13) in units of the force (moment) scale and the last
    update moved no unknown by more than 1e-6 of its scale (the static Newton's test). Anything
    else (no convergence in :data:`PROJECTION_MAX_ITERATIONS`, a non-finite value) falls back to
    the static Newton, whose iterations are then counted.
    """

    def __init__(self, model: Model):
        from ..system.residual import residual
        from .common import jacobian_filler

        self._residual = residual
        self.model = model
        self.alg = np.flatnonzero(model.layout.algebraic)
        if not np.all(model.mass[self.alg] == 0.0):
            raise AssertionError("algebraic unknowns and algebraic rows differ in the layout")
        self.jd, self.fill, _ = jacobian_filler(model, "analytic")
        from .projection_kernel import arrow_shape, arrow_work

        lay = model.layout
        self._b = arrow_shape(self.alg, lay.rollers, lay.n_local)
        self._aw = arrow_work(self.alg, lay.rollers, self._b)
        self._alg64 = self.alg.astype(np.int64)
        self._step = np.empty(self.alg.size)
        self.tol = max(model.scene.numerics.static_tolerance, PROJECTION_TOL_FLOOR)
        self._yp = np.zeros(model.size)
        self._res = np.empty(model.size)
        self.fallbacks = 0  #: samples handed to the static Newton
        self._calls = None  #: the kernels project_batch calls (projection_kernel.kernel_entries)

    def batch(self, t: np.ndarray, Y: np.ndarray, compile_only: bool = False
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict]:
        """Every sample at once (solvers/projection_kernel.py): (projected Y, iterations,
        settled mask, diagnostics per sample). The samples not settled are left as given,
        for :meth:`__call__` (its static-Newton fallback) and ``Model.diagnostics``."""
        from ..system.model import DIAGNOSTICS
        from .projection_kernel import SETTLED, kernel_entries, project_batch

        m = self.model
        t = np.ascontiguousarray(t, dtype=float)
        Y = np.ascontiguousarray(Y, dtype=float).reshape(t.size, m.size)
        out = Y.copy()
        its = np.zeros(t.size, np.int64)
        status = np.zeros(t.size, np.int64)
        diag = {name: np.zeros((t.size,) + m.work_array(name).shape) for name in DIAGNOSTICS}
        if t.size or compile_only:
            if self._calls is None:
                self._calls = kernel_entries(m.data, self.jd, self._alg64, self._b, self._aw)
            project_batch(t, Y, m.data, self.jd, self._alg64, self._b,
                          self._aw, self.tol, PROJECTION_MAX_ITERATIONS, out, its, status,
                          tuple(diag[name] for name in DIAGNOSTICS), self._calls)
        return out, its, status == SETTLED, diag

    def prepare(self) -> None:
        """Compile (or load from numba's cache) the batch projection for this model's array
        types, by projecting no sample: a streamed run does this before its integration
        starts, so that its first block of samples compiles nothing (cold start)."""
        self.batch(np.empty(0), np.empty((0, self.model.size)), compile_only=True)

    def _rows(self, t: float, y: np.ndarray) -> np.ndarray:
        self._residual(t, y, self._yp, self._res, self.model.data)
        return self._res[self.alg]

    def __call__(self, t: float, y: np.ndarray) -> tuple[np.ndarray, int]:
        from .projection_kernel import arrow_solve

        alg = self.alg
        y_start = np.asarray(y, dtype=float)
        y = y_start.copy()
        F = self._rows(t, y)
        moved = np.inf
        for it in range(PROJECTION_MAX_ITERATIONS + 1):
            if not np.all(np.isfinite(F)):
                break
            if np.abs(F).max() <= self.tol and moved <= 1e-6:
                return y, it
            if it == PROJECTION_MAX_ITERATIONS:
                break
            self.fill(t, y, self._yp, 0.0, self.model.data, self.jd)
            step = self._step
            if not arrow_solve(self.jd[0], self._alg64, self._b, F, step, *self._aw):
                break
            y[alg] += step
            moved = np.abs(step).max()
            F = self._rows(t, y)
        self.fallbacks += 1
        return project_algebraic(self.model, t, y_start)


def static_state(model: Model):
    """The quasi-static state with flanges at t = 0 (rollers at their initial azimuths and
    epicyclic speeds, no skew): (scaled y, full local (Z, len(LOCAL)), full global (11) unscaled,
    max |scaled algebraic row|)."""
    y, _ = initial_state(model)
    full_l, full_g = model.layout.unpack(y * model.scale)
    res = model.residual(0.0, y, np.zeros_like(y))
    return y, full_l, full_g, float(np.abs(res[model.layout.algebraic]).max())
