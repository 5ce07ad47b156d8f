"""The ring's spectrum figure (``bearingdae plot RUN.nc --spectrum``; analysis/spectrum.py
computes what it draws).

Pipeline place: plots (figures). Each panel draws one spectrum over [fmin, fmax] on a linear
(default) or logarithmic amplitude axis, marks the characteristic frequencies in that range
with dashed lines, and sets their labels in rows above the traces: a label goes into the
lowest row where it keeps clear of every label already there (:func:`marker_rows`), so no two
labels overlap however close the frequencies. The envelope panel instead marks the defect
frequencies with their harmonics and sidebands, named in the legend (plots/defect_markers.py).
Every panel marks the same frequencies: the run's measured ones (mean cage and roller spin
speeds) where it has them (analysis/defect_frequencies.run_characteristic), and its title
says which. The panel's title says the window, the bin width, the number of samples, the
sampling rate and, for a filtered record, the filter compensated.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from .figure_common import _plt, closed_on_failure, outside_legend, save_figure, wrap_title
from ..analysis.defect_frequencies import run_characteristic
from ..analysis.spectrum import (LABELS, amplitude_spectrum, default_band, default_fmax,
                                 envelope_spectrum, spectrum_variable)

#: marker colours, in the order of physics/frequencies.NAMES
COLOURS = ("k", "tab:green", "tab:red", "tab:purple", "tab:brown")
#: label font size [pt], the gap kept between two labels of one row [fraction of the axis]
#: and the height of a row of labels [pt]
LABEL_PT, LABEL_GAP, ROW_PT = 7.0, 0.01, 9.5


def marker_rows(x_frac: list[float], widths_frac: list[float]) -> list[int]:
    """The row of each label (0 = top), labels given by their left edge ``x_frac`` and width
    ``widths_frac`` in fractions of the axis width: in order of position, each takes the first
    row whose labels all end (plus :data:`LABEL_GAP`) before it starts."""
    order = np.argsort(x_frac, kind="stable")
    ends: list[float] = []  # right end of the last label of each row
    rows = [0] * len(x_frac)
    for i in order:
        for r, end in enumerate(ends):
            if x_frac[i] >= end + LABEL_GAP:
                break
        else:
            r = len(ends)
            ends.append(-np.inf)
        ends[r] = x_frac[i] + widths_frac[i]
        rows[i] = r
    return rows


def _label_widths_frac(ax, texts: list[str]) -> list[float]:
    """Widths of ``texts`` at :data:`LABEL_PT` as fractions of ``ax``'s width (measured by the
    renderer, the figure's layout done first: a constrained layout narrows the axes for the
    legend and labels beside them). One layout for all of them: each probe is removed before
    the next, so the figure is the same for each (a layout per label cost ~1 s each)."""
    fig = ax.figure.figure  # the root figure (a subfigure's parent)
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    axes_width = max(ax.get_window_extent(renderer).width, 1.0)
    widths = []
    for text in texts:
        probe = ax.text(0, 0, text, fontsize=LABEL_PT, transform=ax.transAxes)
        widths.append(probe.get_window_extent(renderer).width / axes_width)
        probe.remove()
    return widths


#: the label ending of a harmonic of the outer-race roller pass (BPFO): "2× BPFO", ...
HARMONIC = "× BPFO"
#: the most harmonics of the BPFO marked (an outer-race defect's impacts repeat at the BPFO:
#: their envelope and their spectrum carry its harmonics)
MAX_HARMONICS = 8


def bpfo_harmonics(ds: xr.Dataset, fmin: float, fmax: float) -> list:
    """(label, frequency, colour) of the harmonics 2, 3, ... of the outer-race roller pass
    within [fmin, fmax], in its colour."""
    freqs = run_characteristic(ds)[0]
    if "roller_pass_outer" not in freqs or freqs["roller_pass_outer"] <= 0:
        return []
    colour = COLOURS[list(freqs).index("roller_pass_outer") % len(COLOURS)]
    f1 = freqs["roller_pass_outer"]
    return [(f"{k}{HARMONIC}", k * f1, colour) for k in range(2, MAX_HARMONICS + 1)
            if fmin <= k * f1 <= fmax]


def draw_markers(ax, ds: xr.Dataset, fmin: float, fmax: float) -> list:
    """Dashed lines at the characteristic frequencies in [fmin, fmax] and their labels in rows
    above the axes' top (:func:`marker_rows`); returns the label Text objects."""
    freqs, source = run_characteristic(ds)
    marks = [(key, f, c) for (key, f), c in zip(freqs.items(), COLOURS)
             if fmin <= f <= fmax and f > 0]
    marks += bpfo_harmonics(ds, fmin, fmax)
    if not marks:
        return []
    ax._bearingdae_defect_source = source
    span = fmax - fmin
    texts = [f"{LABELS.get(k, k)} {f:.4g} Hz" for k, f, _ in marks]
    x = [(f - fmin) / span for _, f, _ in marks]
    widths = _label_widths_frac(ax, texts)
    left = [min(max(xi - 0.5 * w, 0.0), max(1.0 - w, 0.0)) for xi, w in zip(x, widths)]
    rows = marker_rows(left, widths)
    out = []
    for (key, f, colour), s, lx, r in zip(marks, texts, left, rows):
        ax.axvline(f, color=colour, ls=":" if key.endswith(HARMONIC) else "--", lw=0.8)
        out.append(ax.annotate(s, xy=(lx, 1.0), xycoords="axes fraction",
                               xytext=(0.0, 2.0 + ROW_PT * r), textcoords="offset points",
                               fontsize=LABEL_PT, color=colour, ha="left", va="bottom"))
    ax._bearingdae_above_pt = ROW_PT * (max(rows) + 1)  # their height above the axes [pt]
    return out


def draw_spectrum(ax, ds: xr.Dataset, name: str | None = None, fmin: float = 0.0,
                  fmax: float | None = None, log: bool = False, envelope: bool = False,
                  band_Hz: tuple[float, float] | None = None) -> xr.DataArray:
    """The spectrum of ``name`` (default: analysis/spectrum.spectrum_variable), or its
    envelope spectrum, on ``ax`` over [fmin, fmax] (default fmax: spectrum.default_fmax), with
    the characteristic frequencies marked (module docstring); returns the spectrum."""
    name = name or spectrum_variable(ds)
    spec = amplitude_spectrum(ds, name)
    nyquist = 0.5 / spec.attrs["sample_interval_s"]
    band_note = ""
    if envelope:
        if band_Hz is None:
            lo, hi, why = default_band(ds, nyquist)
            band_Hz, band_note = (lo, hi), f" ({why})"
        spec = envelope_spectrum(ds, name, band_Hz)
    fmax = default_fmax(ds, nyquist) if fmax is None else float(fmax)
    check_range(fmin, fmax, nyquist)
    f = spec.frequency.values
    keep = (f >= fmin) & (f <= fmax) & (f > 0)
    # a linear axis in a unit with a prefix (nm, mm s-2): no offset text among the labels
    factor, units = (1.0, spec.attrs["units"]) if log else _prefixed(
        float(np.nanmax(spec.values[keep])) if keep.any() else 1.0, spec.attrs["units"])
    for d in spec.direction.values if "direction" in spec.dims else [None]:
        y = (spec.sel(direction=d) if d is not None else spec).values[keep] / factor
        trace = str(d) if d is not None else "_nolegend_"
        if log:
            ax.semilogy(f[keep], np.maximum(y, 1e-30), lw=0.8, label=trace)
        else:
            ax.plot(f[keep], y, lw=0.8, label=trace)
    ax.set_xlim(fmin, fmax)
    if envelope:  # the defect frequencies, harmonics and sidebands, named in the legend
        from .defect_markers import draw_defect_orders

        draw_defect_orders(ax, ds, fmin, fmax)
    # before the marker labels: the legend narrows the axes
    if "direction" in spec.dims or ax.get_legend_handles_labels()[0]:
        outside_legend(ax)
    if not envelope:
        draw_markers(ax, ds, fmin, fmax)
    label = name.replace("_", " ")
    source = getattr(ax, "_bearingdae_defect_source", None)
    what = (f"envelope spectrum of {label}, band {band_Hz[0]:.4g}-{band_Hz[1]:.4g} Hz"
            f"{band_note}" if envelope else f"{label} spectrum") + (
        f";\n{'defect' if envelope else 'characteristic'} frequencies {source}"
        if source else "")
    a = spec.attrs
    # on a line of its own: appended to the sampling line it is wider than the figure
    filt = (";\nthe recording's low-pass divided out to 0.8 f_Nyquist"
            if a.get("filter_compensated") else
            ";\nsamples at the instants: ring modes above Nyquist fold back"
            if "ring_vibration_note" in ds.attrs and not envelope else "")
    ax.set(xlabel="frequency [Hz]", ylabel=f"amplitude [{units}]")
    ax.set_title(f"{what}\n{a.get('window', 'Hann')} window, bin {a['bin_width_Hz']:.3g} Hz "
                 f"({a['samples']} samples at {1.0 / a['sample_interval_s']:.4g} Hz, Nyquist "
                 f"{nyquist:.4g} Hz){filt}", fontsize=9, pad=4 + _height_above(ax))
    return spec


#: SI prefixes of a linear amplitude axis, by the power of ten of its largest value
PREFIXES = {-12: "p", -9: "n", -6: "µ", -3: "m", 0: "", 3: "k"}


def _prefixed(top: float, units: str) -> tuple[float, str]:
    """(factor, units): the amplitude divided by ``factor`` reads in ``units`` with the SI
    prefix that puts ``top`` in [1, 1000) (``units`` starting with "m": metres)."""
    if not (np.isfinite(top) and top > 0) or not units.startswith("m"):
        return 1.0, units
    power = int(min(max(3 * np.floor(np.log10(top) / 3), -12), 3))
    return 10.0 ** power, PREFIXES[power] + units


def _height_above(ax) -> float:
    """Height [pt] of the rows of marker labels above ``ax`` (the title goes above them)."""
    return float(getattr(ax, "_bearingdae_above_pt", 0.0))


def check_range(fmin: float, fmax: float, nyquist: float) -> None:
    """ValueError unless 0 <= fmin < fmax <= the Nyquist frequency (the spectrum's range)."""
    if not (np.isfinite(fmin) and np.isfinite(fmax) and 0.0 <= fmin < fmax):
        raise ValueError(f"--fmin {fmin:.6g} / --fmax {fmax:.6g} Hz: expected finite "
                         f"0 <= fmin < fmax <= {nyquist:.6g} Hz (the record's Nyquist "
                         "frequency)")
    if fmax > nyquist * (1.0 + 1e-9):
        raise ValueError(f"--fmax {fmax:.6g} Hz: expected at most the record's Nyquist "
                         f"frequency {nyquist:.6g} Hz (sample denser to see higher: "
                         "numerics.samples_per_cage_revolution)")


@closed_on_failure
def spectrum_figure(ds: xr.Dataset, path: str | Path, fmin: float = 0.0,
                    fmax: float | None = None, log: bool = False, envelope: bool = False,
                    band_Hz: tuple[float, float] | None = None) -> Path:
    """PNG of the ring's spectra (``bearingdae plot RUN.nc --spectrum``): acceleration (a
    dynamic ring) above displacement, and with ``envelope`` the envelope spectrum of the
    first below them. ``fmax`` above the Nyquist frequency is cut to it."""
    names = [n for n in ("ring_acceleration", "ring_displacement") if n in ds]
    if not names:
        spectrum_variable(ds)  # the error naming what is missing
    panels = [(n, False) for n in names] + ([(names[0], True)] if envelope else [])
    plt = _plt()
    fig, axes = plt.subplots(len(panels), 1, figsize=(10, 4.8 * len(panels)),
                             layout="constrained", squeeze=False)
    try:
        fig.suptitle(wrap_title(str(ds.attrs.get("title", "bearingdae")), fig, 10),
                     fontsize=10)  # which run: the scene's title, as on the overview
        for ax, (name, env) in zip(axes[:, 0], panels):
            draw_spectrum(ax, ds, name, fmin, fmax, log, env, band_Hz)
    except Exception:
        plt.close(fig)
        raise
    return save_figure(fig, path)
