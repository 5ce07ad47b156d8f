"""The linearised bearing's modes at a state of a run: what sets an integrator's step.

Stage: system (the analytic Jacobian) -> **analysis**. The DAE is linear in y' with a diagonal
mass, F(t, y, y') = M y' + f(t, y) (docs/theory.md §10; M is zero on the algebraic rows).
A small deviation v e^{λt} from a state (t, y, y') obeys (f_y + λ M) v = 0 to first order, so
the modes are the finite eigenvalues of the pencil (-f_y, M): the algebraic rows give the
infinite ones (their unknowns follow the others at once). The rollers' positions move slowly
against the fastest modes, so these are the motion's modes over a few of their periods.

A complex pair λ = -ζω ± iω√(1 - ζ²) is an oscillation of frequency f = Im λ / 2π [Hz] and
damping ratio ζ = -Re λ / |λ|; a real λ < 0 a relaxation with time constant -1/λ. A BDF
method of order q resolves an oscillation to a local error of about (hω)^{q+1} of its
amplitude per step h, so the fastest lightly damped mode a run keeps excited sets its step;
stiff relaxations (ζ = 1, large |λ|) do not (BDF is stable on them at any step).

Each mode is named by the unknown that moves most in it (eigenvector entries in the scaled
unknowns of ``system/scales.py``, so a displacement and a speed compare by their reference
scales), e.g. ``skew_rate[7]``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: a mode at most this damped counts as "lightly damped" (an oscillation that rings)
LIGHT_DAMPING = 0.2


@dataclass(frozen=True)
class Modes:
    """The finite modes of the linearised DAE at one state, fastest (largest |λ|) first."""

    eigenvalue_per_s: np.ndarray  #: λ [1/s], complex
    dominant: tuple  #: the unknown that moves most in each mode, e.g. "skew_rate[7]"
    shapes: np.ndarray  #: the modes' shapes in the scaled unknowns (n, modes), unit columns

    @property
    def frequency_Hz(self) -> np.ndarray:
        """Oscillation frequency |Im λ| / 2π [Hz] (0 for a relaxation)."""
        return np.abs(self.eigenvalue_per_s.imag) / (2.0 * np.pi)

    @property
    def oscillating(self) -> np.ndarray:
        """True for a complex pair: |Im λ| above round-off (1e-6 |λ|; an eigensolver returns
        a real double root as a pair with an imaginary part of that order)."""
        lam = self.eigenvalue_per_s
        return np.abs(lam.imag) > 1e-6 * np.abs(lam)

    @property
    def damping_ratio(self) -> np.ndarray:
        """ζ = -Re λ / |λ| (1: a relaxation; below 0: a growing mode)."""
        lam = self.eigenvalue_per_s
        return -lam.real / np.maximum(np.abs(lam), 1e-300)

    def fastest_oscillation(self, light: float = LIGHT_DAMPING) -> int | None:
        """Index of the highest-frequency oscillation (:attr:`oscillating`) with ζ <= ``light``
        (None if there is none)."""
        ok = np.flatnonzero(self.oscillating & (self.damping_ratio <= light))
        return None if ok.size == 0 else int(ok[np.argmax(self.frequency_Hz[ok])])


def linear_modes(model, t: float, y: np.ndarray, yp: np.ndarray) -> Modes:
    """The modes of ``model``'s DAE linearised at the scaled state (t, y, y') (module
    docstring), from the analytic Jacobian f_y (its c_j term at 0) and the mass M."""
    import scipy.linalg as sl

    from ..solvers.common import jacobian_filler

    y = np.ascontiguousarray(y, dtype=float)
    yp = np.ascontiguousarray(yp, dtype=float)
    if y.shape != (model.size,) or yp.shape != (model.size,):
        raise ValueError(f"y, yp: expected shape ({model.size},) for this model, got "
                         f"{y.shape} and {yp.shape}")
    jd, fill, _ = jacobian_filler(model, "analytic")
    fill(float(t), y, yp, 0.0, model.data, jd)
    lam, vec = sl.eig(-jd[0], np.diag(model.mass))
    finite = np.isfinite(lam)
    lam, vec = lam[finite], vec[:, finite]
    order = np.argsort(-np.abs(lam), kind="stable")
    lam, vec = lam[order], vec[:, order]
    names = model.layout.names()
    dominant = tuple(names[i] for i in np.argmax(np.abs(vec), axis=0))
    return Modes(lam, dominant, vec / np.linalg.norm(vec, axis=0))


def family(name: str) -> str:
    """The unknown's name without its roller index: ``skew_rate[7]`` -> ``skew_rate``."""
    return name.split("[", 1)[0]
