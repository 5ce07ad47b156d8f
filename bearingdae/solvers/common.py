"""What every solver of the DAE shares (stage: system -> **solvers**): the absolute tolerance of
the algebraic unknowns, the block-arrow sparsity pattern and the choice of Jacobian filler.

IDA (solvers/ida.py) hands the pattern and a filler to SUNDIALS; Newmark (solvers/newmark.py)
and the scipy peers (solvers/scipy_peers.py) fill the same dense ∂F/∂y + c_j ∂F/∂y' themselves;
the fillers are system/jacobian_analytic.py (analytic, the default) and system/jacobian.py
(structured finite differences, the cross-check). :func:`check_jacobian` holds either against
central differences of the residual.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..system.jacobian import fill_jacobian
from ..system.layout import GLOBAL, LOCAL
from ..system.jacobian_analytic import analytic_work, fill_jacobian_analytic
from ..system.model import Model

def check_choice(value, allowed, argument: str) -> str:
    """A solver option that names one of ``allowed`` (TypeError for a non-string, ValueError
    for an unknown name; both name the argument and the choices)."""
    choices = ", ".join(map(repr, allowed))
    if not isinstance(value, str):
        raise TypeError(f"{argument} = {value!r:.100}: expected one of {choices}, got "
                        f"{type(value).__name__}")
    if value not in allowed:
        raise ValueError(f"{argument} = {value!r:.100}: allowed are {choices}")
    return value


def check_flag(value, argument: str) -> bool:
    """A True/False solver option (a string such as "no" would count as True: refused)."""
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{argument} = {value!r:.100}: expected True or False, got "
                        f"{type(value).__name__}")
    return bool(value)


# Absolute tolerance of the algebraic unknowns, as a multiple of atol: the error test need not
# resolve their steep (but quasi-static) change as a roller enters the loaded zone, because they
# follow from the differential unknowns; outputs are projected onto the algebraic equations
# anyway. Measured on yang20 (40 ms): factor 1 -> 44.5k residual calls, 1e2 -> 36.6k; 1e4 failed
# with the near-exact traction sign.
ALG_ATOL_FACTOR = 1e2
# ... but never looser than 1e-6 of the unknown's scale: an effective 1e-4 (factor 1e4) or 1e-3
# (atol = 1e-5) let IDA's Newton stop with inaccurate contact states and fail within 1 ms.
# 3e-5 saves 14-22 % of the steps on short windows at no loss of accuracy, but fails the
# benchmark run (1 + 3 cage revolutions) at 0.227 s; 1e-4 fails it at 67 ms.
ALG_ATOL_MAX = 1e-6


def algebraic_atol(atol: float) -> float:
    """Absolute tolerance of the algebraic unknowns (scaled units) for a given ``atol``."""
    return max(atol, min(ALG_ATOL_FACTOR * atol, ALG_ATOL_MAX))


def _jacobian_work(model: Model, pattern: sp.csc_matrix):
    """Work arrays of system/jacobian.py and the pattern in the CSC order IDA's JJ uses
    (column-major, rows sorted within each column; int32 indices, as sksundae requires)."""
    n = model.size
    Z = model.layout.rollers
    csc = pattern.tocsc()
    csc.sort_indices()
    cols = np.repeat(np.arange(n), np.diff(csc.indptr)).astype(np.int64)
    rows = csc.indices.astype(np.int64)
    return (np.zeros((n, n)), rows, cols, model.mass.copy(), np.zeros(n), np.zeros(n),
            np.zeros((Z, len(LOCAL))), np.zeros((Z, len(GLOBAL))), np.zeros(n)), csc


def sparsity_pattern(model: Model) -> sp.csc_matrix:
    """The block-arrow pattern of ∂F/∂y + c_j ∂F/∂y' (model.layout.sparsity) as a CSC matrix."""
    n = model.size
    r_pat, c_pat = model.layout.sparsity()
    return sp.csc_matrix((np.ones(r_pat.size), (r_pat, c_pat)), shape=(n, n))


def jacobian_filler(model: Model, kind: str, key: str = "jacobian"):
    """(work arrays, dense ∂F/∂y + c_j ∂F/∂y' filler, residual calls per fill) for the solvers
    that fill the DAE Jacobian themselves (Newmark, the scipy peers): ``kind`` "analytic"
    (system/jacobian_analytic.py) or "fd" (structured differences, system/jacobian.py);
    ``key`` names the option in the error."""
    jd, _ = _jacobian_work(model, sparsity_pattern(model))
    if kind == "analytic":
        return analytic_work(model, jd[1], jd[2]), fill_jacobian_analytic, 0
    if kind == "fd":
        return jd, fill_jacobian, model.layout.n_local + model.layout.n_global + 1
    raise ValueError(f"{key} = {kind!r}: allowed are 'analytic' and 'fd'")


JACOBIANS = ("analytic", "fd")


def check_jacobian(model: Model, y: np.ndarray, yp: np.ndarray, cj: float = 1e3,
                   jacobian: str = "fd", rel_step: float = 1e-6) -> float:
    """Max difference between a Jacobian of ours (``"fd"``: structured finite differences,
    ``"analytic"``) and central differences of the residual, relative to each column's largest
    entry (a diagnostic and a test hook). ``rel_step`` must resolve the shortest regularisation
    length in play (a roller pressed into a pocket bar bends its force over 0.1 µm)."""
    n = model.size
    jd, fill, _ = jacobian_filler(model, jacobian)
    fill(0.0, y, yp, cj, model.data, jd)
    J = jd[0]
    ref = np.zeros((n, n))
    for j in range(n):
        h = rel_step * max(abs(y[j]), 1.0)
        e = np.zeros(n)
        e[j] = h
        ref[:, j] = (model.residual(0.0, y + e, yp + cj * e)
                     - model.residual(0.0, y - e, yp - cj * e)) / (2 * h)
    # Forward differences carry round-off of order sqrt(eps) times the column's magnitude, so
    # the error is measured against the largest entry of each column.
    scale = np.abs(ref).max(axis=0) + 1e-300
    return float(np.max(np.abs(J - ref) / scale[None, :]))
