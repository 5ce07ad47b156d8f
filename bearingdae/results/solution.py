"""Solution -> Dataset: projection onto the algebraic equations, error estimates, solver attrs.

Pipeline: solvers -> **results**. :func:`from_solution` is what every solver's output goes
through (solver contract, solvers/base.py); :func:`solver_attrs` records the solver's own name.
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from ..system.layout import GLOBAL, LOCAL
from .dataset import _var, contact_regularisation, dynamic_dataset


# ---------------------------------------------------------------------------------------------
# Solution -> Dataset
# ---------------------------------------------------------------------------------------------
#: Newmark's error-estimate outputs: name -> (state unknown, units, long name)
ERROR_ESTIMATES = {
    "cage_speed_error_estimate": ("cage_speed", "rad s-1", "cage speed"),
    "orbit_speed_error_estimate": ("orbit_speed", "rad s-1", "orbit speed (max over rollers)"),
    "spin_speed_error_estimate": ("spin_speed", "rad s-1", "spin speed (max over rollers)"),
    "skew_angle_error_estimate": ("skew_angle", "rad", "skew angle (max over rollers)"),
}


def error_estimate_variables(model, E: np.ndarray) -> dict:
    """Global-error estimates (n_t, N scaled; Newmark's Richardson estimate) -> Dataset
    variables in SI units, one per kind of unknown (largest magnitude over the rollers)."""
    lay = model.layout
    out = {}
    for name, (unknown, units, long_name) in ERROR_ESTIMATES.items():
        if unknown in lay.local_names:
            idx = [lay.index(unknown, j) for j in range(lay.rollers)]
        elif unknown in lay.global_names:
            idx = [lay.index(unknown)]
        else:
            continue
        val = np.abs(E[:, idx] * model.scale[idx]).max(axis=1)
        out[name] = _var("time", val, units, f"Newmark step-doubling (Richardson) estimate of "
                         f"the global error of the {long_name}",
                         comment="4/3 |y_h - y_h/2| from a second solution at half the step")
    return out


class ProjectionError(RuntimeError):
    """A sample could not be projected onto the algebraic equations; ``.dataset`` holds every
    sample projected before it."""

    def __init__(self, message: str, dataset: xr.Dataset):
        super().__init__(message)
        self.dataset = dataset


def from_solution(model, solution, solver, record_start_s: float = 0.0) -> xr.Dataset:
    """Dataset of a dynamic run: the samples of ``solution`` from ``record_start_s`` on (all of
    them when the run failed), each projected onto the algebraic equations (theory.md §5; the
    static Newton, solvers/algebraic.py) and with the kernel's diagnostics (contact forces,
    pressures, slip, traction, pocket forces); attributes from ``solver.describe()`` and
    ``solver.dataset_attrs(model, solution)``.

    A projection that fails keeps every sample projected before it: :class:`ProjectionError`
    carries that Dataset. A streamed run (results/streamed_record.py) goes through the same
    :func:`project_samples` and :func:`samples_dataset`, a block of samples at a time.
    """
    from ..solvers.algebraic import AlgebraicProjector
    from ..solvers.sundials import precompile

    res = solution
    keep = res.t >= record_start_s - 1e-12 if res.success else np.ones(res.t.size, bool)
    precompile.wait_projection()  # a cold start's second process compiles it (if any)
    project = AlgebraicProjector(model)
    t, Yp, diag, iters, projection_error = project_samples(model, project, res.t[keep],
                                                           res.y[keep])
    info = solver_attrs(model, res, solver, record_start_s, iters, project.fallbacks)
    # the sample before the record (the ring acceleration's filter, analysis/vibration.py)
    early = np.flatnonzero(~keep)
    before = (res.t[early[-1]], res.y[early[-1]]) if early.size else None
    ds, Y = samples_dataset(model, t, Yp, diag, info, before)
    ds = _with_extremes(ds, model, t, Y, diag, res)
    if res.error_estimate is not None:
        ds = ds.assign(error_estimate_variables(model, res.error_estimate[keep][:t.size]))
    if projection_error is not None:
        raise ProjectionError(projection_error, ds)
    return ds


def project_samples(model, project, t, Ys):
    """Samples (times ``t``, scaled states ``Ys``) projected onto the algebraic equations by
    ``project`` (an :class:`~bearingdae.solvers.algebraic.AlgebraicProjector`): ``(t, Yp, diag,
    iterations, error)``, cut before the first sample whose projection fails (``error`` names
    it; None when every sample projected). Each sample is projected from its own state, so a
    block of samples gives what the whole record gives."""
    from ..solvers.static import StaticConvergenceError

    # every sample in one compiled call (solvers/projection_kernel.py); the few it does not
    # settle go through the static Newton one by one, as before
    Yp, its, settled, diag = project.batch(t, Ys)
    n_ok = t.size
    projection_error = None
    for i in np.flatnonzero(~settled):
        try:
            Yp[i], its[i] = project(t[i], Ys[i])
        except StaticConvergenceError as exc:
            projection_error = (f"projection onto the algebraic equations failed at "
                                f"t = {t[i]:.6g} s: {exc}")
            n_ok = i
            break
        for name, value in model.diagnostics(t[i], Yp[i]).items():
            diag[name][i] = value
    diag = {name: value[:n_ok] for name, value in diag.items()}
    return t[:n_ok], Yp[:n_ok], diag, int(its[:n_ok].sum()), projection_error


def samples_dataset(model, t, Yp, diag, info: dict, before=None, after=None):
    """(Dataset, unscaled states) of projected samples (:func:`project_samples`); ``diag``
    gains the ring acceleration of a dynamic ring, low-passed over the samples
    (analysis/vibration.py), with ``before`` / ``after`` the (t, scaled state) of the samples
    just outside these (None: none)."""
    Z = model.geometry.rollers
    full_l, full_g = model.layout.unpack(Yp * model.scale)
    Y = (full_l.reshape(-1, Z, len(LOCAL)), full_g.reshape(-1, len(GLOBAL)))
    if model.layout.ring_dynamic:
        from ..analysis.vibration import filtered_acceleration, ring_state

        g = Y[1]
        x = np.stack([g[:, GLOBAL.index("ring_dr")], g[:, GLOBAL.index("ring_dt")]], axis=-1)
        v = np.stack([g[:, GLOBAL.index("ring_vr")], g[:, GLOBAL.index("ring_vt")]], axis=-1)
        lone = len(t) + (before is not None) + (after is not None) < 2
        point = (np.array([model.ring_acceleration(tk, y) for tk, y in zip(t, Yp)])
                 .reshape(len(t), 2) if lone else np.zeros((len(t), 2)))
        acc = filtered_acceleration(
            t, x, v, point, None if before is None else ring_state(model, *before),
            None if after is None else ring_state(model, *after))
        tapped = False
        if model.ring_taps is not None:  # the solver's taps (system/taps.py)
            from ..analysis.vibration import tap_filtered

            fir, done = tap_filtered(t, model.ring_taps.arrays())
            acc[done] = fir[done]
            tapped = bool(done.any())
        diag["ring_acceleration"] = acc
        ds = dynamic_dataset(model, t, Y, diag, info)
        if "ring_acceleration" in ds:
            from ..analysis.vibration import acceleration_attrs, sample_interval_s

            ds["ring_acceleration"].attrs.update(acceleration_attrs(sample_interval_s(model),
                                                                    tapped))
        return ds, Y
    return dynamic_dataset(model, t, Y, diag, info), Y


def _with_extremes(ds, model, t, Y, diag, res):
    """``ds`` with the extremes the scene asks for (results/extremes.py)."""
    from ..scene import OUTPUT_VARIABLES
    from ..system.layout import LOCAL
    from .extremes import extreme_variables, peak_variables, sampled_peaks

    wanted = model.scene.output_variables or tuple(OUTPUT_VARIABLES)
    skew = Y[0][..., LOCAL.index("skew_angle")]
    variables, attrs = extreme_variables(model, t, skew, diag, res.extremes, wanted)
    variables.update(peak_variables(model, t, res.extremes, wanted,
                                    sampled_peaks(skew, diag)))
    if variables:
        ds = ds.assign(variables)
        ds.attrs.update(attrs)
    return ds


def _unknown_scales(model) -> dict[str, float]:
    """Scale of each kind of unknown (the same for every roller): roller 1's and the globals'."""
    lay = model.layout
    names = list(lay.local_names) + list(lay.global_names)
    idx = list(range(lay.n_local)) + list(range(lay.size - lay.n_global, lay.size))
    return {name: float(model.scale[i]) for name, i in zip(names, idx)}


def solver_attrs(model, solution, solver, record_start_s: float,
                 projection_iterations: int, projection_fallbacks: int = 0) -> dict:
    """The solver's Dataset attributes: ``solver`` (one human line), ``solver_options`` (JSON,
    ``"solver"`` is the solver's own short name, contract item 5), statistics, tolerances,
    unknown scales and regularisation lengths."""
    from ..solvers.common import algebraic_atol
    from ..solvers.sundials.library import versions
    from ..system.residual import PARAM_NAMES

    sc, dyn = model.scene, model.scene.dynamics
    d = solver.describe()
    stats = dict(solution.stats)
    stats["projection_newton_iterations"] = int(projection_iterations)
    # samples the compiled projector handed to the static Newton (solvers/algebraic.py)
    stats["projection_static_fallbacks"] = int(projection_fallbacks)
    P = dict(zip(PARAM_NAMES, model.params))
    sundials_version, scikit_sundae_version = versions()
    options = {"solver": d["solver"], "rtol": dyn.rtol, "atol": dyn.atol,
               "atol_algebraic": algebraic_atol(dyn.atol), **d["options"]}
    attrs = {
        "solver": d["solver_description"],
        "sundials_version": sundials_version,
        "scikit_sundae_version": scikit_sundae_version,
        "solver_status": "completed" if solution.success else "failed",
        "solver_message": solution.message,
        "solver_statistics": json.dumps(stats, default=_json_default),
        "rtol": dyn.rtol,
        "atol": dyn.atol,
        "atol_algebraic": algebraic_atol(dyn.atol),
        "atol_units": "atol is in units of each unknown's scale (unknown_scales)",
        "unknown_scales": json.dumps(_unknown_scales(model)),
        "record_start_s": float(record_start_s),
        "epicyclic_cage_speed_rad_s": float(model.final_cage_speed()),
        "physics": json.dumps(vars(sc.physics)),
        "regularisation": json.dumps({
            **contact_regularisation(sc),
            "traction_sign": "V / sqrt(V^2 + v^2)",
            "traction_velocity_scale_m_s": sc.traction.velocity_scale_m_s,
            "pocket_smoothing_m": sc.cage.smoothing_m,
            "pocket_force_scale_N": float(P["f_p"]),
            "cage_friction_spin_scale_rad_s": float(P["spin_scale"]),
            "algebraic_outputs": "projected onto the algebraic equations (static Newton) at "
                                 "every output time",
        }),
    }
    extra = dict(solver.dataset_attrs(model, solution))
    options.update(extra.pop("options", {}))
    attrs.update(extra)
    options["solver"] = d["solver"]  # the solver's own name, whatever the extras say
    attrs["solver_options"] = json.dumps(options, default=_json_default)
    return attrs


def _json_default(value):
    """numpy scalars and other leftovers in statistics -> JSON."""
    if isinstance(value, np.generic):
        return value.item()
    return str(value)
