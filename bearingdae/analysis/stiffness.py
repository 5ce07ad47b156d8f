"""Quasi-static stiffness matrix of the bearing: the tangent of the inner ring's reaction with
respect to its displacement and tilt at the scene's equilibrium (docs/theory.md §18).

Stage: solvers (the static Newton's analytic Jacobian) -> **analysis**. The static problem
F(z) = 0 of §5 splits into the rollers' rows G(q, r) = 0 (q: radial positions and tilts of
every roller) and the ring's rows E = f - S(q, r), f the applied loads, S the rollers' shares,
r = (δ_r, δ_t, γ_r, γ_t). By the implicit-function theorem the rollers follow the ring
(dq/dr = -G_q⁻¹ G_r), so the reaction's total derivative is the Schur complement

    K = dS/dr = -(E_r - E_q G_q⁻¹ G_r),

the rollers' equilibrium eliminated, not frozen. Centrifugal force, clearance and profile
enter through the equilibrium at which the Jacobian is taken. With flanges (§16) the same
complement is taken on the algebraic block of the compiled DAE's analytic Jacobian, at the
quasi-static state with flanges (:func:`dae_stiffness`). A support of a dynamic ring
(§15) acts in parallel with the bearing and is not part of K (its k adds to K's diagonal).
"""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np

from ..util.warning_lines import BearingdaeWarning

#: the largest relative change of a diagonal entry, slices doubled, that passes as resolved
RESOLVED_CHANGE = 0.01


class StiffnessResolutionWarning(BearingdaeWarning):
    """The scene's slices do not resolve the stiffness matrix to :data:`RESOLVED_CHANGE`."""


#: the degrees of freedom of the ring, in the static problem's order (§5)
DOFS = ("radial", "tangential", "tilt_radial", "tilt_tangential")
#: the entries a rotor model takes from the matrix: the lateral ones (ROSS's BearingElement:
#: kxx, kxy, kyx, kyy; studies/coefficients.ross_coefficients), and kzz with flanges. The tilt
#: entries converge more slowly on the slices (the moment is the load's first moment along
#: the roller): their resolution is judged apart.
ROTOR_DOFS = ("radial", "tangential", "axial")
#: with flanges (§16) the axial displacement joins them
DOFS_FLANGE = ("radial", "tangential", "axial", "tilt_radial", "tilt_tangential")
#: the DAE's unknown of each (system/layout.py)
DOF_UNKNOWN = {"radial": "ring_dr", "tangential": "ring_dt", "axial": "ring_axial",
               "tilt_radial": "ring_gr", "tilt_tangential": "ring_gt"}
#: what each row (reaction) and column (motion) is, with its unit
DOF_MEANING = {
    "radial": ("force F_r along the load line (azimuth 0)", "N",
               "displacement δ_r along the load line", "m"),
    "tangential": ("force F_t at azimuth 90° (direction of rotation)", "N",
                   "displacement δ_t at azimuth 90°", "m"),
    "axial": ("axial force F_a along +X (bearing axis)", "N",
              "axial displacement along +X", "m"),
    "tilt_radial": ("moment M conjugate to γ_r (loads the +x roller ends at azimuth 0)", "N m",
                    "tilt γ_r (ring radial motion x γ_r at azimuth 0)", "rad"),
    "tilt_tangential": ("moment M_t conjugate to γ_t", "N m",
                        "tilt γ_t (ring radial motion x γ_t at azimuth 90°)", "rad"),
}


def entry_units(dofs=DOFS) -> np.ndarray:
    """(n, n) units of K[i, j] = d(reaction i)/d(motion j): N/m, N/rad, N·m/m, N·m/rad."""
    return np.array([[f"{DOF_MEANING[i][1]}/{DOF_MEANING[j][3]}" for j in dofs] for i in dofs],
                    dtype=object)


def static_stiffness(sol) -> np.ndarray:
    """K (4, 4) [SI, :func:`entry_units`] of a converged static solution (solvers/static.py)
    without flanges: the Schur complement of the rollers' block of the analytic Jacobian."""
    from ..solvers import static

    prob = replace(sol.problem, support_N_m=0.0, ring_free=True)  # the bearing alone
    _, J, _ = static.evaluate(prob, sol.z)
    n = 2 * prob.geometry.rollers
    # scaled, so that the solve is well conditioned (unknowns and rows of very different size)
    xs, fs = prob.unknown_scale, prob.equation_scale
    Js = J * xs[None, :] / fs[:, None]
    Gq, Gr = Js[:n, :n], Js[:n, n:]
    Eq, Er = Js[n:, :n], Js[n:, n:]
    Ks = -(Er - Eq @ _rollers_solve(Gq, Gr, prob.geometry.slices))
    return Ks * fs[n:, None] / xs[None, n:]


def _rollers_solve(G: np.ndarray, R: np.ndarray, slices: int) -> np.ndarray:
    """G⁻¹ R for the rollers' block G of the Schur complement; a singular block is a
    SceneError naming its cause and the key: with one slice a roller's tilt has no lever arm
    (no contact moment resists it), so the rollers cannot re-find their equilibrium."""
    from ..scene.errors import SceneError

    try:
        return np.linalg.solve(G, R)
    except np.linalg.LinAlgError:
        if slices < 2:
            raise SceneError(f"stiffness: 'numerics.slices' = {slices}: one slice gives a "
                             "roller's tilt no lever arm, so the rollers' block of the "
                             "stiffness is singular; set numerics.slices >= 2") from None
        raise SceneError(f"stiffness: the rollers' block of the stiffness is singular at "
                         f"this operating point ('numerics.slices' = {slices}): a roller has "
                         "no stiffness against one of its motions (no contact); load the "
                         "bearing (operating.radial_load_N) or reduce the clearance") from None


def dae_stiffness(scene, dofs=DOFS_FLANGE) -> np.ndarray:
    """K [SI] on ``dofs`` (default :data:`DOFS_FLANGE`) of a scene with flanges: the same
    Schur complement on the algebraic block of the compiled DAE's analytic Jacobian at the quasi-static state
    with flanges (solvers/flange_static.py), whose rows are the rollers' radial, tilt and
    axial balances with the flange contacts and the ring's balances. A dynamic ring's rows are
    its momentum rows at rest (the opposite sign, and its support in parallel, removed)."""
    from ..solvers.algebraic import static_state, support_stiffness
    from ..solvers.common import jacobian_filler
    from ..solvers.flange_static import _unknowns
    from ..system.model import build_model

    model = build_model(scene)
    lay = model.layout
    y = static_state(model)[0]
    jd, fill, _ = jacobian_filler(model, "analytic")
    fill(0.0, y, np.zeros(model.size), 0.0, model.data, jd)
    J = np.asarray(jd[0])
    rows, cols = _unknowns(model, ring_balance=True)  # ring rows paired with ring unknowns
    row_of = dict(zip(cols, rows))
    rc = [lay.index(DOF_UNKNOWN[d]) for d in dofs]
    rr = [row_of[c] for c in rc]
    qc = [c for c in cols if c not in rc]
    qr = [r for r in rows if r not in rr]
    Ks = -(J[np.ix_(rr, rc)] - J[np.ix_(rr, qc)] @ _rollers_solve(
        J[np.ix_(qr, qc)], J[np.ix_(qr, rc)], scene.numerics.slices))
    K = Ks * model.row_scale[rr][:, None] / model.scale[rc][None, :]
    if lay.ring_dynamic:  # momentum rows m v' = F - k δ - shares: the opposite sign
        K = -K
        k = support_stiffness(scene)
        for i, d in enumerate(dofs):
            if d in ("radial", "tangential"):
                K[i, i] -= k
    return K


def scene_stiffness(scene, warn: bool = True):
    """The Dataset of :func:`stiffness_dataset` for a scene without flanges, with its
    discretisation error: the matrix again with ``numerics.slices`` doubled, the difference
    ``stiffness_slice_error`` (dof, dof_2); a :class:`StiffnessResolutionWarning` (one line
    naming the setting) when a diagonal entry a rotor model uses (:data:`ROTOR_DOFS`) changes
    by more than :data:`RESOLVED_CHANGE`; the tilt entries' change is said in the same line,
    and kept as the attribute ``stiffness_slice_error_relative_tilt_max``."""
    from ..physics.geometry import make_geometry
    from .static_state import scene_static, with_slices

    K = []
    for s in (scene, with_slices(scene, 2 * scene.numerics.slices)):
        if scene.bearing.flanges is not None:
            K.append(dae_stiffness(s))
        else:
            sol, _ = scene_static(s, make_geometry(s))
            K.append(static_stiffness(sol))
    dofs = DOFS_FLANGE if scene.bearing.flanges is not None else DOFS
    ds = stiffness_dataset(K[0], scene, dofs)
    error = np.abs(K[1] - K[0])
    ds["stiffness_slice_error"] = (("dof", "dof_2"), error, {
        "long_name": "discretisation error of stiffness: |K(2 x numerics.slices) - K|",
        "units": ds.stiffness.attrs["units"]})
    rel = np.diag(error) / np.abs(np.diag(K[0]))
    rotor, tilt = rotor_and_tilt(rel)
    ds.attrs["stiffness_slice_error_relative_max"] = float(rel.max())
    ds.attrs["stiffness_slice_error_relative_rotor_max"] = float(rotor.max())
    ds.attrs["stiffness_slice_error_relative_tilt_max"] = float(tilt.max())
    if warn and rotor.max() > RESOLVED_CHANGE:
        warnings.warn(resolution_message(scene.numerics.slices, rel), StiffnessResolutionWarning,
                      stacklevel=3)
    return ds


def rotor_and_tilt(rel) -> tuple[np.ndarray, np.ndarray]:
    """The relative changes of the diagonal split: the entries a rotor model uses
    (:data:`ROTOR_DOFS`), the tilt entries."""
    dofs = DOFS if len(rel) == len(DOFS) else DOFS_FLANGE
    rel = np.asarray(rel, float)
    rotor = np.array([r for d, r in zip(dofs, rel) if d in ROTOR_DOFS])
    return rotor, np.array([r for d, r in zip(dofs, rel) if d not in ROTOR_DOFS])


def resolution_message(slices: int, rel) -> str:
    """One line: how far the entries a rotor model uses change with the slices doubled (and
    the tilt entries, apart), and the setting."""
    dofs = [d for d in (DOFS if len(rel) == len(DOFS) else DOFS_FLANGE) if d in ROTOR_DOFS]
    rotor, tilt = rotor_and_tilt(rel)
    worst = dofs[int(np.argmax(rotor))]
    return (f"stiffness: {slices} slices resolve the entries a rotor model uses "
            f"({', '.join(dofs)}) to {100 * rotor.max():.1f} % ({worst}, the change with "
            f"numerics.slices doubled; the tilt entries {100 * tilt.max():.1f} %); raise "
            f"numerics.slices to {2 * slices} or more for converged lateral coefficients")


def stiffness_dataset(K: np.ndarray, scene, dofs=DOFS):
    """The matrix as a Dataset: ``stiffness`` (dof, dof_2) with ``entry_units`` and the
    meaning of each row and column."""
    import xarray as xr

    dofs = list(dofs)
    rows = [f"{d}: {DOF_MEANING[d][0]} [{DOF_MEANING[d][1]}]" for d in dofs]
    cols = [f"{d}: {DOF_MEANING[d][2]} [{DOF_MEANING[d][3]}]" for d in dofs]
    o = scene.operating
    ds = xr.Dataset(
        {"stiffness": (("dof", "dof_2"), np.asarray(K, float), {
            "long_name": "quasi-static stiffness of the bearing: d(reaction of the rollers on "
                         "the inner ring, row dof)/d(ring displacement or tilt, column dof_2), "
                         "rollers re-equilibrated (docs/theory.md §18)",
            "units": "mixed by entry: see entry_units (N m-1, N rad-1, N m m-1, N m rad-1)"}),
         "entry_units": (("dof", "dof_2"), entry_units(dofs).astype(str),
                         {"long_name": "unit of each stiffness entry"})},
        coords={"dof": ("dof", dofs, {"long_name": "row: reaction force or moment; "
                                      + "; ".join(rows)}),
                "dof_2": ("dof_2", dofs, {"long_name": "column: ring displacement or tilt; "
                                          + "; ".join(cols)})},
        attrs={"title": scene.title, "speed_rpm": o.speed_at(0.0),
               "radial_load_N": float(o.radial_load_N), "scene_toml": scene.to_toml(True)},
    )
    return ds
