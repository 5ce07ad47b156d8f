"""The inner ring's vibration spectrum from a run's Dataset, with the bearing's characteristic
frequencies (``bearingdae plot RUN.nc --spectrum``; theory.md §15).

Pipeline place: analysis (reads a Dataset only). The recorded window (time >= record_start_s)
of ``ring_acceleration`` (a dynamic ring), else of ``ring_displacement``, is taken with the
mean removed, a Hann window and the single-sided amplitude scaling (a sine of amplitude A gives
a peak of A at its bin; Harris 1978, Proc. IEEE 66(1), 51-83). Samples not equally spaced (a
dense output) are first interpolated linearly onto equal steps of their median spacing. The bin
width is 1 / (record length). A ``ring_acceleration`` low-passed over the samples (its
``filter_transfer_function``, analysis/vibration.py) is divided by that transfer function up to
0.8 of the Nyquist frequency (its pass band), so a line there reads its true amplitude.

The figure (plots/plot_spectrum.py) draws a frequency range (default up to 4× the inner-race
roller pass, :func:`default_fmax`) on a linear or logarithmic amplitude axis, marks the
characteristic frequencies with labels set in rows so that none overlaps another
(``marker_rows``), writes the window, the bin width and the sampling on the figure, and
optionally the **envelope spectrum** (:func:`envelope_spectrum`): the signal band-passed
around a resonance of the ring (ideal band-pass of its FFT), its Hilbert envelope (the
magnitude of the analytic signal), and that envelope's amplitude spectrum, in which the
impacts' repetition frequencies (roller pass, cage) stand out (Randall & Antoni 2011, Mech.
Syst. Signal Process. 25(2), 485-520, §2).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from .result_variables import value as result_value

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


def variable_note(ds: xr.Dataset, name: str) -> str:
    """Why the spectrum is of ``name`` when that is not ring_acceleration (the first choice of
    :func:`spectrum_variable`), in one line; "" for ring_acceleration. A quasi-static ring
    (the default ``physics.ring``) has no acceleration; a dynamic one records it unless
    ``output.variables`` left it out."""
    if name == "ring_acceleration":
        return ""
    import tomllib

    try:
        scene = tomllib.loads(str(ds.attrs.get("scene_toml", "")))
    except tomllib.TOMLDecodeError:
        scene = {}
    ring = scene.get("physics", {}).get("ring", "quasi-static") if scene else None
    if ring is None:
        why = "the file has no ring_acceleration"
    elif ring == "dynamic":
        why = "the file does not record ring_acceleration (output.variables)"
    else:
        why = (f'the ring is {ring} (physics.ring = "{ring}"), without an acceleration; '
               'physics.ring = "dynamic" records ring_acceleration')
    return f"spectrum of {name}, not ring_acceleration: {why}"


def recorded_window(ds: xr.Dataset, var: xr.DataArray) -> xr.DataArray:
    """``var`` over the run's recorded window (time >= record_start_s; the whole of it without
    that value)."""
    start = float(result_value(ds, "record_start_s", float(ds.time[0])))
    return var.sel(time=var.time >= start - 1e-12 * max(abs(start), 1.0))


def amplitude_spectrum(ds: xr.Dataset, name: str | None = None) -> xr.DataArray:
    """Single-sided amplitude spectrum (frequency, direction) of ``name`` over the recorded
    window (module docstring), in the variable's units."""
    name = name or spectrum_variable(ds)
    var = recorded_window(ds, ds[name])
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
    compensated = "sample_interval_s" in var.attrs and "filter_transfer_function" in var.attrs
    if compensated:  # the filter the record went through (analysis/vibration.py), in its band
        from .vibration import PASSBAND_OF_NYQUIST, transfer

        T = float(var.attrs["sample_interval_s"])
        fir = var.attrs.get("filter_fir_coefficients")
        band = f <= PASSBAND_OF_NYQUIST * 0.5 / T
        amp[band] = amp[band] / transfer(f[band], T, None if fir is None
                                         else np.atleast_1d(fir))[:, None]
    dims = ("frequency",) + tuple(d for d in var.dims if d != "time")
    return xr.DataArray(amp.reshape((f.size,) + var.shape[1:]), dims=dims,
                        coords={"frequency": f, **{d: var[d] for d in dims[1:]}},
                        attrs={"units": var.attrs.get("units", ""),
                               "long_name": f"amplitude spectrum of {name}",
                               "bin_width_Hz": 1.0 / (dt * t.size),
                               "window": "Hann", "samples": int(t.size),
                               "sample_interval_s": dt,
                               "filter_compensated": int(compensated)})


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
    """The characteristic frequencies the run recorded (Hz; the variable
    ``characteristic_frequencies_Hz`` over ``frequency_name``), {} for files without them; a
    ValueError of one line when they are not finite numbers (a damaged file)."""
    from .result_variables import upgrade

    ds = upgrade(ds)  # (a file of the older format: a JSON attribute)
    if "characteristic_frequencies_Hz" not in ds:
        return {}
    da = ds["characteristic_frequencies_Hz"]
    values = np.asarray(da.values)
    if da.dims != ("frequency_name",) or values.dtype.kind not in "fiu" or not np.all(
            np.isfinite(values)):
        raise ValueError("the file's variable 'characteristic_frequencies_Hz' is not finite "
                         "numbers over 'frequency_name' (Hz); a damaged file?")
    return {str(k): float(v) for k, v in zip(da["frequency_name"].values, values)}


def default_fmax(ds: xr.Dataset, nyquist_Hz: float) -> float:
    """The figure's default upper frequency [Hz]: 4× the inner-race roller pass (its lines and
    first harmonics, and the cage and shaft lines below), at most the Nyquist frequency."""
    f = characteristic(ds).get("roller_pass_inner", 0.0)
    return float(min(4.0 * f, nyquist_Hz)) if f > 0 else float(nyquist_Hz)


def default_band(ds: xr.Dataset, nyquist_Hz: float) -> tuple[float, float, str]:
    """The envelope's band [Hz] and why: ±20 % around the highest natural frequency of the ring
    (``ring_natural_frequencies_Hz``, analysis/vibration.py) the record resolves (below 0.8 of
    Nyquist), else 0.4-0.8 of Nyquist (the record's top band: the resonances lie above it)."""
    from .result_variables import upgrade

    ds = upgrade(ds)
    fn = [float(f) for f in np.ravel(ds["ring_natural_frequencies_Hz"].values)
          if 0.0 < f <= 0.8 * nyquist_Hz] if "ring_natural_frequencies_Hz" in ds else []
    if fn:
        f0 = max(fn)
        return 0.8 * f0, min(1.2 * f0, 0.95 * nyquist_Hz), f"ring mode {f0:.4g} Hz ± 20 %"
    return 0.4 * nyquist_Hz, 0.8 * nyquist_Hz, "no ring mode below 0.8 f_Nyquist: top band"


def envelope_spectrum(ds: xr.Dataset, name: str | None = None,
                      band_Hz: tuple[float, float] | None = None) -> xr.DataArray:
    """Amplitude spectrum of the Hilbert envelope of ``name`` band-passed to ``band_Hz``
    (default :func:`default_band`) over the recorded window (module docstring); in the
    variable's units, attributes as :func:`amplitude_spectrum`'s plus ``band_Hz``."""
    from scipy.signal import detrend, hilbert

    name = name or spectrum_variable(ds)
    spec = amplitude_spectrum(ds, name)  # checks the record, gives its sampling
    dt, n = spec.attrs["sample_interval_s"], spec.attrs["samples"]
    nyquist = 0.5 / dt
    lo, hi = band_Hz if band_Hz is not None else default_band(ds, nyquist)[:2]
    if not (0.0 <= lo < hi <= nyquist):
        raise ValueError(f"envelope band {lo:.6g}-{hi:.6g} Hz: expected 0 <= low < high <= "
                         f"the record's Nyquist frequency {nyquist:.6g} Hz")
    var = recorded_window(ds, ds[name])
    t = var.time.values
    x = var.transpose("time", ...).values.reshape(t.size, -1)
    grid = t[0] + dt * np.arange(n)
    x = np.column_stack([np.interp(grid, t, x[:, c]) for c in range(x.shape[1])])
    X = np.fft.rfft(x - x.mean(axis=0), axis=0)
    f = np.fft.rfftfreq(n, dt)
    X[(f < lo) | (f > hi)] = 0.0
    env = np.abs(hilbert(np.fft.irfft(X, n, axis=0), axis=0))
    # the envelope's mean and slow drift would be the panel's largest feature (0-5 Hz at the
    # default sampling, the window's main lobe around 0): a straight line off, and the mean
    # the Hann window weights, so that the windowed envelope has no 0 Hz content left
    w = np.hanning(n)
    env = detrend(env, axis=0, type="linear")
    env = env - (w @ env) / w.sum()
    amp = 2.0 * np.abs(np.fft.rfft(env * w[:, None], axis=0)) / w.sum()
    out = spec.copy(data=amp.reshape(spec.shape))
    out.attrs.update({"long_name": f"envelope spectrum of {name} ({lo:.4g}-{hi:.4g} Hz)",
                      "band_Hz": [float(lo), float(hi)], "filter_compensated": 0})
    return out

