"""Fixed-step Newmark-β / HHT-α integrator over the DAE residual (theory.md §12): the paper's
integrator, kept as an independent cross-check of IDA (solvers/ida.py).

The residual is F(t, y, y') = M y' - f(t, y) with a constant diagonal M (system/residual.py;
zero on the algebraic rows). Its unknowns fall into four kinds (system/layout.py):

* kinematic pairs (q, v) = (azimuth, orbit_speed), (skew_angle, skew_rate), (cage_angle,
  cage_speed), for a dynamic ring (ring_dr, ring_vr) and the other three ring pairs, for cage
  whirl (cage_x, cage_vx) and (cage_y, cage_vy), with a defect on a roller (spin_angle,
  spin_speed):
  second-order coordinates with acceleration a = v';
* first-order rates (spin_speed without a spin angle): the γ (trapezoidal) rule (the same
  rule as a pair's velocity: a spin angle leaves the spin speed's update as it was);
* algebraic unknowns (radial_position, tilt, ring_*): solved at t_{n+1}.

Per step of size h the unknowns x are the new accelerations a_{n+1}, the new first-order rates
w'_{n+1} and the new algebraic unknowns z_{n+1}, with (in each pair's own units; the scaled
state of the model converts with c = S_v / S_q)

    q_{n+1} = q_n + h v_n + h² [(1/2 - β) a_n + β a_{n+1}]
    v_{n+1} = v_n + h [(1 - γ) a_n + γ a_{n+1}]              (also w for the first-order rates)
    q'_{n+1} = v_{n+1}                                        (kinematic rows hold identically)

and the equations, HHT-α weighted on the differential rows (Hilber, Hughes & Taylor 1977;
α = 0 is plain Newmark), the algebraic rows enforced at t_{n+1}:

    M x - (1 + α) f(t_{n+1}, y_{n+1}) + α f(t_n, y_n) = 0      (differential rows)
    F_alg(t_{n+1}, y_{n+1}) = 0                               (algebraic rows)

solved together by one modified Newton iteration. Its matrix is

    J = W (∂F/∂y) (∂y/∂x) + M (∂y'/∂x),   W = diag(1 + α on differential rows, 1 elsewhere)

with ∂F/∂y from the structured finite-difference Jacobian of system/jacobian.py (c_j = 0) and
a scipy SuperLU factorisation kept across iterations and steps; it is refreshed when Newton
converges slowly or fails, and the step is halved when Newton fails with a fresh matrix
(SOLVER-NOTES "Newmark-β prototype lessons": max-norm test in scaled units, step halving).

Output times are hit exactly: each output interval is cut into the fewest equal steps not
longer than h. With ``error_estimate`` a second solution at h/2 runs beside the first (two
half steps per step, never resynchronised) and the Richardson estimate of the first solution's
global error, 4/3 (y_h - y_{h/2}) for a second-order method, is reported per output time.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import asdict, dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from ..scene.arguments import check_argument, newmark_beta_min
from ..system.extremes import H_FROM, H_SIZE, Extremes
from ..system.layout import CAGE_CENTRE, CAGE_CENTRE_RATES, RING, RING_RATES
from ..system.model import Model
from .algebraic import project_algebraic
from . import newmark_kernel as kern
from .base import IntegrationResult, Solution, Solver  # noqa: F401  (IntegrationResult: old name)
from .common import JACOBIANS, algebraic_atol, check_choice, jacobian_filler
from .native_call import residual_entry

# Newton tolerance: weighted max-norm of the state correction, weight 1/(tol |y| + tol) in the
# model's scaled units (unknowns are O(1) there; algebraic ones get IDA's looser atol).
# Measured on the baseline (8 ms, h = 1-4 µs): 1e-8, 1e-9 and 1e-10 give the same errors to 3
# digits and 1.5-2.1, 1.75-2.6, 2.1-2.9 Newton iterations per step; 1e-9 keeps a margin for the
# Newton errors that add up over 1e5 steps.
NEWTON_TOL = 1e-9
NEWTON_MAXITER = 8  # iterations before a step counts as failed
SLOW_ITERATIONS = 3  # a step needing more refreshes the matrix for the next step
MAX_HALVINGS = 12  # deepest step halving (h / 4096) before giving up
H_REFACTOR = 1e-3  # relative change of h that forces a new factorisation
PREDICTOR_ORDER = 2  # Newton start: quadratic extrapolation of the unknowns


#: NewmarkOptions field -> the scene key whose type and range it shares
_SCENE_KEYS = {"step_s": "numerics.newmark_step_s", "beta": "numerics.newmark_beta",
               "gamma": "numerics.newmark_gamma", "alpha": "numerics.hht_alpha",
               "error_estimate": "numerics.newmark_error_estimate"}


#: The result type of earlier versions: the contract's Solution (it has ``error_estimate``).
NewmarkResult = Solution


@dataclass(frozen=True)
class NewmarkOptions:
    step_s: float = 2e-6
    beta: float = 0.25
    gamma: float = 0.5
    alpha: float = 0.0  #: HHT-α in [-1/3, 0]
    error_estimate: bool = False
    newton_tol: float = NEWTON_TOL  #: Newton tolerance (relative and absolute, scaled units)

    def __post_init__(self):
        """Type and range of each option, from the scene key it stands for (one definition:
        bearingdae/scene/sections/numerics.py), plus β's stability bound for this γ."""
        for attr, key in _SCENE_KEYS.items():
            value = check_argument(key, getattr(self, attr), f"NewmarkOptions.{attr}")
            object.__setattr__(self, attr, value)
        tol = self.newton_tol
        if isinstance(tol, bool) or not isinstance(tol, (int, float, np.floating, np.integer)):
            raise TypeError(f"NewmarkOptions.newton_tol = {tol!r}: expected a number in (0, 1), "
                            f"got {type(tol).__name__}")
        if not 0.0 < float(tol) < 1.0:
            raise ValueError(f"NewmarkOptions.newton_tol = {tol!r}: outside the allowed range "
                             "(0, 1)")
        object.__setattr__(self, "newton_tol", float(tol))
        beta_min = newmark_beta_min(self.gamma)
        if self.beta < beta_min * (1.0 - 1e-12):
            raise ValueError(f"NewmarkOptions.beta = {self.beta!r} with gamma = {self.gamma!r} "
                             f"is not unconditionally stable; allowed range [{beta_min:.6g}, "
                             "0.5] (beta >= (gamma + 1/2)^2/4)")

    @classmethod
    def from_scene(cls, scene) -> "NewmarkOptions":
        d = scene.dynamics
        return cls(d.newmark_step_s, d.newmark_beta, d.newmark_gamma, d.hht_alpha,
                   d.newmark_error_estimate)


class _Structure:
    """Index maps between the model state y (N) and the Newton unknowns x (N - #pairs)."""

    def __init__(self, model: Model):
        lay, S, n = model.layout, model.scale, model.size
        pairs = [("azimuth", "orbit_speed"), ("skew_angle", "skew_rate"),
                 ("spin_angle", "spin_speed")]  # (a defect on a roller only)
        pos, vel = [], []
        for q, v in pairs:
            if q in lay.local_names:
                for j in range(lay.rollers):
                    pos.append(lay.index(q, j)), vel.append(lay.index(v, j))
        if "cage_angle" in lay.global_names:
            pos.append(lay.index("cage_angle")), vel.append(lay.index("cage_speed"))
        for q, v in zip(RING + CAGE_CENTRE, RING_RATES + CAGE_CENTRE_RATES):
            if v in lay.global_names:  # a dynamic ring (theory.md §15), cage whirl (§17)
                pos.append(lay.index(q)), vel.append(lay.index(v))
        self.pos, self.vel = np.array(pos), np.array(vel)
        self.c = S[self.vel] / S[self.pos]  # q' (scaled) = c v (scaled)
        keep = np.ones(n, bool)
        keep[self.pos] = False
        self.U = np.flatnonzero(keep)  # unknowns and equations of the Newton system
        where = np.full(n, -1)
        where[self.U] = np.arange(self.U.size)
        self.mass = model.mass
        self.diff = model.mass > 0  # differential rows (incl. kinematic ones)
        self.dU = np.flatnonzero(self.diff[self.U])  # differential unknowns, x-indices
        self.aU = np.flatnonzero(~self.diff[self.U])  # algebraic unknowns, x-indices
        self.src = where.copy()  # x-index each y_i depends on
        self.src[self.pos] = where[self.vel]
        self.mass_U = model.mass[self.U]
        # Pattern of the Newton matrix, CSC order: rows U, columns mapped through src, plus
        # the diagonal (mass) — built once, so a factorisation only gathers its values.
        r_pat, c_pat = model.layout.sparsity()
        ok = where[r_pat] >= 0
        rr = np.concatenate([where[r_pat[ok]], np.arange(self.U.size)])
        cc = np.concatenate([self.src[c_pat[ok]], np.arange(self.U.size)])
        key = np.unique(cc * self.U.size + rr)
        self.prow, self.pcol = key % self.U.size, key // self.U.size
        self.indices = self.prow.astype(np.int32)
        self.indptr = np.searchsorted(self.pcol, np.arange(self.U.size + 1)).astype(np.int32)


class _Stepper:
    """One Newmark solution: state (t, y, y', f), its factorised matrix, and the compiled
    stepping loop (solvers/newmark_kernel.py) that asks for a new matrix when it needs one."""

    def __init__(self, model: Model, st: _Structure, opts: NewmarkOptions, counts: dict,
                 t: float, y: np.ndarray, yp: np.ndarray, jacobian: str = "analytic"):
        self.m, self.s, self.o, self.k = model, st, opts, counts
        self.d = model.data
        self.t, self.y, self.yp = t, y.copy(), yp.copy()
        n, nU = model.size, st.U.size
        # ∂F/∂y as IDA gets it (solvers/ida.py), filled with c_j = 0
        self.jd, self.fill, self.evals_per_jac = jacobian_filler(model, jacobian)
        # f(t_n, y_n) on the differential rows, for HHT-α: F = M y' - f.
        res = model.residual(t, y, np.zeros(n))
        counts["residual_calls"] += 1
        self.f = np.where(st.diff, -res, 0.0)
        self.x_hist = np.zeros((2, nU))  # unknowns at the last two step starts ...
        self.h_hist = np.zeros(2)  # ... and those steps' sizes (0: none yet)
        self.lu = None
        self.h_lu = 0.0
        # Newton's absolute tolerance per component; the algebraic unknowns get IDA's looser
        # one (solvers/ida.py): a floating roller's position and tilt are fixed only by the
        # tiny regularised contact loads, and do not matter for anything else.
        self.atol = np.where(st.diff, opts.newton_tol, algebraic_atol(opts.newton_tol))
        self.P = (st.pos, st.vel, st.c, st.U, st.dU, st.aU, st.src, model.mass)
        self.opts = np.array([opts.beta, opts.gamma, opts.alpha, opts.newton_tol, opts.newton_tol,
                              NEWTON_MAXITER, SLOW_ITERATIONS, PREDICTOR_ORDER], float)
        # base, coef, y1, yp1, res | x, x0, x_start, G, dx | LU work
        self.w = tuple(np.zeros(n) for _ in range(5)) + tuple(np.zeros(nU) for _ in range(5)) \
            + (np.zeros(nU),)
        self.kcounts = np.zeros(3, dtype=np.int64)
        #: running extremes (system/extremes.py); a window from +inf keeps none
        self.E = np.full(H_SIZE, np.nan)
        self.E[H_FROM] = np.inf
        self.calls = np.array(residual_entry(self.d), np.int64)  # advance's residual

    def _factor(self, h):
        """Factorise J = W ∂F/∂y ∂y/∂x + M ∂y'/∂x at the predicted state of a step h."""
        s, a, o = self.s, self.o.alpha, self.o
        base, coef, y1, yp1 = self.w[:4]
        x = self.w[5]
        kern.setup(h, self.y, self.yp, o.beta, o.gamma, s.pos, s.vel, s.c, s.U, s.dU, s.aU,
                   base, coef)
        kern.predict(h, self.y, self.yp, self.x_hist, self.h_hist, PREDICTOR_ORDER, s.U, s.dU,
                      s.aU, x)
        kern.state(x, base, coef, s.src, s.pos, s.vel, s.c, s.U, s.dU, y1, yp1)
        self.k["jacobian_calls"] += 1
        self.k["residual_calls_in_jacobian"] += self.evals_per_jac
        self.fill(self.t + h, y1, yp1, 0.0, self.d, self.jd)
        A = self.jd[0][s.U]
        # ∂y/∂x has one entry per column of A: y_i depends on x[src[i]] with slope coef[i]
        # (positions on their pair's acceleration), so the product is a scaled column gather.
        J = A[:, s.U] * coef[s.U]
        J[:, s.src[s.pos]] += A[:, s.pos] * coef[s.pos]
        J[s.dU] *= 1.0 + a
        J[s.dU, s.dU] += s.mass_U[s.dU]
        self.k["lu_factorisations"] += 1
        n = s.U.size
        lu = splu(sp.csc_matrix((J[s.prow, s.pcol], s.indices, s.indptr), shape=(n, n)))
        L, U = lu.L, lu.U  # CSC, int32 indices
        self.lu = (L.data, L.indices, L.indptr, U.data, U.indices, U.indptr, lu.perm_r,
                   lu.perm_c)
        self.h_lu = h

    def _run(self, h, n, depth=0) -> bool:
        """n steps of size h; a step whose Newton fails with a fresh matrix is done as two
        half steps (recursively); False when even h / 2^MAX_HALVINGS fails."""
        while n > 0:
            fresh = self.lu is None or abs(h / self.h_lu - 1.0) > H_REFACTOR
            if fresh:
                self._factor(h)
            code, done, self.t = kern.advance(
                self.t, h, n, fresh, self.y, self.yp, self.f, self.x_hist, self.h_hist,
                self.atol, self.d, self.P, self.lu, self.opts, self.kcounts, self.w, self.E,
                self.calls)
            if done:
                self.k["smallest_step_s"] = min(self.k["smallest_step_s"], h)
            n -= done
            if code == kern.NEED_MATRIX:
                self.lu = None
            elif code == kern.FAILED:
                if depth >= MAX_HALVINGS:
                    return False
                self.k["step_halvings"] += 1
                self.lu = None
                if not (self._run(0.5 * h, 2, depth + 1)):
                    return False
                self.lu = None  # back to h
                n -= 1
        return True

    def advance_to(self, t_end: float, h_max: float) -> bool:
        n = max(1, math.ceil((t_end - self.t) / h_max * (1.0 - 1e-9)))
        ok = self._run((t_end - self.t) / n, n)
        for key, v in zip(("steps", "newton_iterations", "residual_calls"), self.kcounts):
            self.k[key] += int(v)
        self.kcounts[:] = 0
        if ok:
            self.t = t_end  # remove round-off drift of t
        return ok


def _new_counts() -> dict:
    return {"steps": 0, "newton_iterations": 0, "residual_calls": 0, "jacobian_calls": 0,
            "residual_calls_in_jacobian": 0, "lu_factorisations": 0, "step_halvings": 0,
            "smallest_step_s": math.inf}


def consistent_start(model: Model, y0: np.ndarray, t: float = 0.0
                     ) -> tuple[np.ndarray, np.ndarray]:
    """(y, y') at ``t``: algebraic unknowns projected onto their equations, y' = f / M."""
    y, _ = project_algebraic(model, t, y0)
    res = model.residual(t, y, np.zeros_like(y))
    yp = np.zeros_like(y)
    diff = model.mass > 0
    yp[diff] = -res[diff] / model.mass[diff]
    return y, yp


class Newmark(Solver):
    """Fixed-step Newmark-β / HHT-α over the DAE residual (theory.md §12), the cross-check of IDA.

    ``options``: :class:`NewmarkOptions`, or None for the scene's ``numerics.newmark_*`` and
    ``hht_alpha`` (read at each run). ``jacobian``: ∂F/∂y ``"analytic"``
    (system/jacobian_analytic.py, default) or by structured finite differences (``"fd"``).
    With ``error_estimate`` the :class:`~bearingdae.solvers.base.Solution` carries the
    Richardson estimate of the global error of ``y`` (scaled units) per sample.
    """

    name = "newmark"

    def __init__(self, options: NewmarkOptions | None = None, jacobian: str = "analytic"):
        if options is not None and not isinstance(options, NewmarkOptions):
            raise TypeError(f"options: expected NewmarkOptions or None, got "
                            f"{type(options).__name__}")
        check_choice(jacobian, JACOBIANS, "jacobian")
        self.options, self.jacobian = options, jacobian
        self._last: dict = {}  # statistics and error estimates of the last run

    def resolved(self, scene) -> NewmarkOptions:
        """The options a run on ``scene`` uses."""
        return self.options or NewmarkOptions.from_scene(scene)

    def describe(self) -> dict:
        o = self.options
        opts = {"jacobian": self.jacobian}
        if o is None:
            opts["options_from"] = "scene numerics.newmark_*, hht_alpha"
            step = "scene's"
        else:
            opts.update(newmark_step_s=o.step_s, newmark_beta=o.beta, newmark_gamma=o.gamma,
                        hht_alpha=o.alpha, newmark_error_estimate=o.error_estimate,
                        newton_tol=o.newton_tol)
            step = f"{o.step_s:g} s"
        return {"solver": self.name,
                "solver_description": (f"bearingdae Newmark-beta / HHT-alpha, fixed step "
                                       f"({step}), modified Newton on accelerations + algebraic "
                                       f"unknowns, SuperLU, {self.jacobian} Jacobian"),
                "options": opts}

    def dataset_attrs(self, model, solution) -> dict:
        """Newmark's settings as resolved against the scene; its tolerances are the Newton
        tolerances of each step, not an error control."""
        o = self.resolved(model.scene)
        return {
            "solver": (f"bearingdae Newmark-beta (beta = {o.beta:g}, gamma = {o.gamma:g}, "
                       f"HHT alpha = {o.alpha:g}), fixed step {o.step_s:g} s, modified "
                       f"Newton on accelerations + algebraic unknowns, SuperLU, "
                       f"{self.jacobian} Jacobian"),
            "sundials_version": "not used (solver = newmark)",
            "scikit_sundae_version": "not used (solver = newmark)",
            "rtol": o.newton_tol,
            "atol": o.newton_tol,
            "atol_algebraic": o.newton_tol,
            "atol_units": "Newmark: rtol/atol are the Newton tolerances of each step (weighted "
                          "max-norm of the state correction) in units of each unknown's scale "
                          "(unknown_scales); the step size, not a tolerance, sets the accuracy",
            "options": {"rtol": o.newton_tol, "atol": o.newton_tol,
                        "atol_algebraic": o.newton_tol, "newmark_step_s": o.step_s,
                        "newmark_beta": o.beta, "newmark_gamma": o.gamma,
                        "hht_alpha": o.alpha, "newmark_error_estimate": o.error_estimate,
                        "newton_tol": o.newton_tol, "jacobian": self.jacobian},
        }

    def extra_stats(self) -> dict:
        return dict(self._last.get("stats", {}))

    def error_estimate(self, n_samples: int):
        E = self._last.get("E")
        if E is None:
            return None
        return np.array(E[:n_samples]).reshape(n_samples, -1)

    def _run(self, model, y0, yp0, t_out, t_start, emit):
        o = self.resolved(model.scene)
        st = _Structure(model)
        counts = _new_counts()
        self._last = {"stats": {}, "E": [] if o.error_estimate else None}
        grid = np.concatenate([[t_start], t_out[t_out > t_start]])
        needed = int(np.ceil(np.diff(grid) / o.step_s * (1.0 - 1e-9)).sum())
        max_steps = model.scene.dynamics.max_steps
        if needed > max_steps:  # a fixed step knows its cost in advance: refuse, do not hang
            self._finish(counts, None, o)
            return (False, f"Newmark needs {needed} steps of at most numerics.newmark_step_s = "
                    f"{o.step_s:g} s, more than numerics.max_steps = {max_steps}; raise "
                    f"max_steps or the step", t_start)
        y, yp = consistent_start(model, y0, t_start)
        main = _Stepper(model, st, o, counts, t_start, y, yp, self.jacobian)
        if self._extremes_from is not None:
            self._extremes = Extremes(model.layout.rollers, model.geometry.slices,
                                      self._extremes_from)
            main.E = self._extremes.buffer
        fine = None
        if o.error_estimate:
            fine = _Stepper(model, st, o, _new_counts(), t_start, y, yp, self.jacobian)
        E = self._last["E"]

        def record():
            if fine is not None:
                E.append(4.0 / 3.0 * (main.y - fine.y))
            emit(main.t, main.y, main.yp)

        t_iter = t_out
        if t_out[0] == t_start:
            record()
            t_iter = t_out[1:]
        try:
            for tk in t_iter:
                good = main.advance_to(float(tk), o.step_s)
                if good and fine is not None:
                    good = fine.advance_to(float(tk), 0.5 * o.step_s)
                if not good:
                    return (False, f"Newmark failed at t = {main.t:.6g} s: Newton did not "
                            f"converge even after {MAX_HALVINGS} step halvings (h = "
                            f"{o.step_s / 2 ** MAX_HALVINGS:.3g} s)", float(main.t))
                if not np.all(np.isfinite(main.y)):
                    return False, f"Newmark: non-finite state at t = {main.t:.6g} s", float(main.t)
                record()
        finally:  # also on Ctrl-C: the counters stay right
            self._finish(counts, fine, o)
        return True, "completed", None

    def _finish(self, counts: dict, fine, o: NewmarkOptions) -> None:
        """Counters (base) and Newmark's own statistics of the run."""
        total = dict(counts)
        if fine is not None:
            for key in ("residual_calls", "jacobian_calls", "residual_calls_in_jacobian"):
                total[key] += fine.k[key]
        c = self.counters
        c.steps = counts["steps"]
        c.residual_calls = total["residual_calls"]
        c.jacobian_calls = total["jacobian_calls"]
        c.residual_calls_in_jacobian = total["residual_calls_in_jacobian"]
        stats = {k: v for k, v in counts.items() if k not in asdict(c)}
        if not math.isfinite(stats["smallest_step_s"]):
            stats["smallest_step_s"] = 0.0
        stats.update({"jacobian": self.jacobian, "step_s": o.step_s, "beta": o.beta,
                      "gamma": o.gamma, "hht_alpha": o.alpha, "newton_tol": o.newton_tol,
                      "newton_iterations_per_step":
                          counts["newton_iterations"] / max(counts["steps"], 1)})
        if fine is not None:
            fk = dict(fine.k)
            if not math.isfinite(fk["smallest_step_s"]):
                fk["smallest_step_s"] = 0.0
            stats["error_estimate_solution_statistics"] = fk
        self._last["stats"] = stats


def integrate(model: Model, y0: np.ndarray, yp0: np.ndarray, t_out: np.ndarray,
              options: NewmarkOptions | None = None, progress=None,
              jacobian: str = "analytic") -> Solution:
    """Deprecated: ``Newmark(options, jacobian).integrate(model, y0, yp0, t_out,
    progress=progress)`` (the contract of solvers/base.py)."""
    warnings.warn("bearingdae.solvers.newmark.integrate is deprecated; use "
                  "Newmark(options, jacobian=...).integrate(model, y0, yp0, t_out)",
                  DeprecationWarning, stacklevel=2)
    return Newmark(options, jacobian).integrate(model, y0, yp0, t_out, progress=progress)
