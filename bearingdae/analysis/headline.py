"""The numbers a user reads off a dynamic run, each with its standard error.

Stage: analysis (reads a Dataset and its scene). ``bearingdae run`` prints cage slip, the peaks
per roller pass, rating life, minimum film, power loss and (a dynamic ring) the ring's motion;
the convergence study (studies/converge.py) compares them between runs at refined settings,
so each needs an error bar from one run. analysis/statistics.py gives the time means and the
peaks per roller pass; this module adds the engineering outputs, each as a statistic that
converges with the record's length (not a window extreme, which grows with it):

* **L10r** (ISO/TS 16281 laminae, analysis/engineering.py): a function of the time means of
  the per-sample lamina power sums m_k (slice k, each ring). Its error is propagated linearly
  (delta method): the per-sample series Σ_k (∂L/∂m_k) x_k(t) has the mean's error of L, and
  gets its blocking error as any series (∂L/∂m_k by central differences). The value is the
  life the run records; its relative error is this one.
* **minimum film and λ**: the smallest film of each roller-pass period (the blocks of
  :func:`~.statistics.roller_pass_blocks`), from the samples, averaged over the periods: the
  sampled counterpart of the peaks per roller pass (film is not kept at every solver step).
* **power loss**: the time mean of the total over sources.
* **ring vibration RMS** (dynamic ring only): sqrt(mean |a|²) of the ring's acceleration.
"""

from __future__ import annotations


import numpy as np
import xarray as xr

from .statistics import MeanEstimate, batch_mean, block_maxima, rms_of, roller_pass_blocks, \
    run_statistics

#: name -> (units, long name) of every headline output, in the order a table shows them
HEADLINE_OUTPUTS = {
    "cage_slip": ("1", "cage slip ratio 1 - mean cage speed / epicyclic speed"),
    "peak_pocket_force_per_pass": ("N", "mean peak pocket force per roller pass"),
    "max_skew_per_pass": ("rad", "mean peak |skew angle| per roller pass"),
    "L10r": ("Mrev", "reference rating life L10r (ISO/TS 16281 laminae)"),
    "min_film_per_pass": ("m", "mean smallest minimum EHL film thickness per roller pass"),
    "min_lambda_per_pass": ("1", "mean smallest film parameter lambda per roller pass"),
    "power_loss": ("W", "mean total power loss"),
    "ring_vibration_rms": ("m s-2", "RMS inner-ring acceleration (dynamic ring)"),
}
#: headline outputs taken from analysis/statistics.run_statistics: name -> its key there
FROM_RUN_STATISTICS = {"cage_slip": "cage_slip_ratio",
                       "peak_pocket_force_per_pass": "roller_pass_peak_cage_force_N",
                       "max_skew_per_pass": "roller_pass_peak_skew_angle_rad"}


def headline_statistics(ds: xr.Dataset, scene) -> dict[str, MeanEstimate]:
    """Every headline output ``ds`` (a dynamic run of ``scene``) provides, with its standard
    error (module docstring); outputs the run does not hold are left out."""
    if ds.sizes.get("time", 0) == 0:
        return {}
    out = {}
    stats = run_statistics(ds)
    for name, key in FROM_RUN_STATISTICS.items():
        if key in stats:
            out[name] = stats[key]
    if "contact_force" in ds:
        out["L10r"] = life_estimate(ds, scene)
    epicyclic = float(ds.attrs.get("epicyclic_cage_speed_rad_s", np.nan))
    blocks = roller_pass_blocks(ds["time"].values, ds.sizes.get("roller", 0), epicyclic)
    for name, var in (("min_film_per_pass", "film_thickness_min"),
                      ("min_lambda_per_pass", "lambda_ratio")):
        if var in ds:
            out[name] = per_pass_minimum(ds[var], blocks)
    if "power_loss_W" in ds:
        out["power_loss"] = batch_mean(ds.power_loss_W.sum("source").values)
    if "ring_acceleration" in ds:
        out["ring_vibration_rms"] = rms_of(batch_mean(
            (ds.ring_acceleration ** 2).sum("direction").values))
    return {k: out[k] for k in HEADLINE_OUTPUTS if k in out}


def per_pass_minimum(da: xr.DataArray, blocks) -> MeanEstimate:
    """Mean over roller-pass blocks of the smallest finite value of ``da`` (time, ...) in each
    block, with its blocking error (a NaN-only sample, e.g. no loaded slice, counts as none)."""
    import warnings

    other = [d for d in da.dims if d != "time"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # "All-NaN slice encountered"
        smallest = da.min(other, skipna=True).values
    return batch_mean(-block_maxima(-np.asarray(smallest, float), blocks))


def life_estimate(ds: xr.Dataset, scene) -> MeanEstimate:
    """L10r [Mrev] with the delta-method error of the module docstring: the value the run
    records (attribute ``reference_rating_life_L10r_Mrev``; from its slice loads when the
    Dataset has none) and the relative error of the power means of analysis/rating_life.py (the
    laminae's correction of a run's life is a constant factor: it keeps the relative error)."""
    from ..physics.geometry import make_geometry
    from .rating_life import lamina_power_sums, ring_exponents, slice_life

    geometry = make_geometry(scene)
    q = np.asarray(ds.contact_force.values, dtype=float)  # (time, roller, slice, race)
    # per-sample sums over rollers: lamina_power_sums sums its first two axes (roller, 1)
    inner, outer = lamina_power_sums(scene, geometry, q.transpose(1, 0, 2, 3)[:, None])
    x = np.concatenate([inner, outer], axis=1)  # (time, 2 slices)
    k = inner.shape[1]
    p_i, p_o = ring_exponents(scene)
    n = geometry.rollers

    def life(m):  # the slice-level life of power means m; its relative error is the life's
        return slice_life(scene, geometry, None, None,
                          equivalent=((m[:k] / n) ** (1.0 / p_i), (m[k:] / n) ** (1.0 / p_o)))

    m = x.mean(axis=0)
    value = life(m)
    grad = np.zeros_like(m)
    for j in np.flatnonzero(m > 0):
        h = 1e-6 * m[j]
        up, down = m.copy(), m.copy()
        up[j] += h
        down[j] -= h
        grad[j] = (life(up) - life(down)) / (2 * h)
    linear = batch_mean(x @ grad)
    recorded = float(ds.attrs.get("reference_rating_life_L10r_Mrev", np.nan))
    if np.isfinite(recorded) and value > 0:  # the life the run reports, its relative error
        return MeanEstimate(recorded, linear.stderr * recorded / value, linear.batches,
                            linear.correlated)
    return MeanEstimate(float(value), linear.stderr, linear.batches, linear.correlated)
