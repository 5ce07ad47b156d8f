"""The inner ring's vibration spectrum from a run's Dataset, with the bearing's characteristic
frequencies (``bearingdae plot RUN.nc --spectrum``; theory.md §15).

Pipeline place: results (reads a Dataset only). The recorded window (time >= record_start_s)
of ``ring_acceleration`` (a dynamic ring), else of ``ring_displacement``, is taken with the
mean removed, a Hann window and the single-sided amplitude scaling (a sine of amplitude A gives
a peak of A at its bin; Harris 1978, Proc. IEEE 66(1), 51-83). Samples not equally spaced (a
dense output) are first interpolated linearly onto equal steps of their median spacing. The bin
width is 1 / (record length).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr

from .figure_common import closed_on_failure, _plt, outside_legend, save_figure

#: how the figure labels each characteristic frequency (physics/frequencies.py names)
LABELS = {"shaft": "shaft $f_s$", "cage": "cage (FTF)", "roller_pass_outer": "roller pass, outer",
          "roller_pass_inner": "roller pass, inner", "roller_spin": "roller spin"}


def spectrum_variable(ds: xr.Dataset) -> str:
    """The variable the spectrum is taken of: ring_acceleration, else ring_displacement."""
    for name in ("ring_acceleration", "ring_displacement"):
        if name in ds:
            return name
    raise ValueError("the file has neither ring_acceleration nor ring_displacement; a spectrum "
                     "needs a dynamic run file (bearingdae run)")


def amplitude_spectrum(ds: xr.Dataset, name: str | None = None) -> xr.DataArray:
    """Single-sided amplitude spectrum (frequency, direction) of ``name`` over the recorded
    window (module docstring), in the variable's units."""
    name = name or spectrum_variable(ds)
    var = ds[name]
    start = float(ds.attrs.get("record_start_s", float(ds.time[0])))
    var = var.sel(time=var.time >= start - 1e-12 * max(abs(start), 1.0))
    t = var.time.values
    if t.size < 8:
        raise ValueError(f"'{name}': {t.size} samples in the recorded window; a spectrum needs "
                         "at least 8")
    x = var.transpose("time", ...).values.reshape(t.size, -1)
    dt = _checked_window(name, t, x)
    if not np.allclose(np.diff(t), dt, rtol=1e-6, atol=0.0):  # a dense output: equal steps
        grid = t[0] + dt * np.arange(int(np.floor((t[-1] - t[0]) / dt)) + 1)
        x = np.column_stack([np.interp(grid, t, x[:, c]) for c in range(x.shape[1])])
        t = grid
    x = x - x.mean(axis=0)
    w = np.hanning(t.size)
    amp = 2.0 * np.abs(np.fft.rfft(x * w[:, None], axis=0)) / w.sum()
    f = np.fft.rfftfreq(t.size, dt)
    dims = ("frequency",) + tuple(d for d in var.dims if d != "time")
    return xr.DataArray(amp.reshape((f.size,) + var.shape[1:]), dims=dims,
                        coords={"frequency": f, **{d: var[d] for d in dims[1:]}},
                        attrs={"units": var.attrs.get("units", ""),
                               "long_name": f"amplitude spectrum of {name}",
                               "bin_width_Hz": 1.0 / (dt * t.size)})


#: most samples the resampling onto equal steps may make per recorded sample: a dense output's
#: steps vary by a few times; far more means a damaged time axis (one sample far away)
RESAMPLE_FACTOR_MAX = 16


def _checked_window(name: str, t: np.ndarray, x: np.ndarray) -> float:
    """The median time step [s] of the recorded window, after checking what a spectrum reads
    from a file: finite, strictly increasing times whose equal-step grid stays within
    :data:`RESAMPLE_FACTOR_MAX` times the samples (bounded memory), and finite values; a
    ValueError of one line otherwise."""
    steps = np.diff(t)
    if not (np.all(np.isfinite(t)) and np.all(steps > 0)):
        i = int(np.flatnonzero(~(np.isfinite(steps) & (steps > 0)))[0])
        raise ValueError(f"'{name}': time {float(t[i + 1])!r} s at sample {i + 1} does not "
                         f"follow {float(t[i])!r} s; a spectrum needs finite, increasing times "
                         "(a damaged file?)")
    dt = float(np.median(steps))
    needed = (t[-1] - t[0]) / dt + 1
    if needed > RESAMPLE_FACTOR_MAX * t.size:
        raise ValueError(f"'{name}': {t.size} samples over {t[-1] - t[0]:.6g} s with a median "
                         f"step of {dt:.6g} s would be resampled onto {needed:.3g} equal steps "
                         f"(at most {RESAMPLE_FACTOR_MAX} per sample); the time axis has a gap "
                         "or a stray sample (a damaged file?)")
    bad = ~np.isfinite(x)
    if bad.any():
        i = int(np.flatnonzero(bad.any(axis=1))[0])
        raise ValueError(f"'{name}': {float(x[i][bad[i]][0])!r} at t = {t[i]:.9g} s (sample "
                         f"{i}); a spectrum needs finite values")
    return dt


def characteristic(ds: xr.Dataset) -> dict[str, float]:
    """The characteristic frequencies the run recorded (Hz), {} for older files; a ValueError
    of one line when the attribute is not a JSON object of numbers (a damaged file)."""
    text = ds.attrs.get("characteristic_frequencies_Hz", "{}")
    try:
        value = json.loads(text) if isinstance(text, str) else None
    except (ValueError, RecursionError):  # not JSON, or nested too deeply
        value = None
    if not (isinstance(value, dict) and all(
            isinstance(k, str) and isinstance(v, (int, float)) and not isinstance(v, bool)
            and np.isfinite(v) for k, v in value.items())):
        raise ValueError("the file's attribute 'characteristic_frequencies_Hz' is not a JSON "
                         "object of finite numbers (frequency name: Hz); a damaged file?")
    return {k: float(v) for k, v in value.items()}


def draw_spectrum(ax, ds: xr.Dataset, name: str | None = None) -> None:
    """The spectrum of ``name`` (default :func:`spectrum_variable`) on ``ax`` (log amplitude)
    with the characteristic frequencies marked."""
    name = name or spectrum_variable(ds)
    spec = amplitude_spectrum(ds, name)
    f = spec.frequency.values
    for d in spec.direction.values if "direction" in spec.dims else [None]:
        y = spec.sel(direction=d) if d is not None else spec
        ax.semilogy(f[1:], np.maximum(y.values[1:], 1e-30), lw=0.8, label=str(d))
    top = float(spec.max())
    for (key, fk), colour in zip(characteristic(ds).items(),
                                 ("k", "tab:green", "tab:red", "tab:purple", "tab:brown")):
        if 0.0 < fk <= f[-1]:
            ax.axvline(fk, color=colour, ls="--", lw=0.8)
            ax.text(fk, top, " " + LABELS.get(key, key), rotation=90, va="top", fontsize=7,
                    color=colour)
    label = name.replace("_", " ")
    ax.set(xlabel="frequency [Hz]", ylabel=f"amplitude [{spec.attrs['units']}]",
           title=f"{label} spectrum (bin {spec.attrs['bin_width_Hz']:.3g} Hz)")
    outside_legend(ax)


@closed_on_failure
def spectrum_figure(ds: xr.Dataset, path: str | Path) -> Path:
    """PNG of the ring's spectra (``bearingdae plot RUN.nc --spectrum``): acceleration (a
    dynamic ring) above displacement. The acceleration of a ring without damping also shows its
    contact resonance (aliased when the samples are sparser than twice its frequency; the
    user guide's recipe), the displacement the roller-pass and shaft lines most clearly."""
    names = [n for n in ("ring_acceleration", "ring_displacement") if n in ds]
    if not names:
        spectrum_variable(ds)  # the error naming what is missing
    plt = _plt()
    fig, axes = plt.subplots(len(names), 1, figsize=(10, 4.5 * len(names)),
                             layout="constrained", squeeze=False)
    for ax, name in zip(axes[:, 0], names):
        draw_spectrum(ax, ds, name)
    return save_figure(fig, path)
