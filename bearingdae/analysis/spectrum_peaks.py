"""The strongest peaks of a run's (envelope) spectrum, each matched to a characteristic order
(``bearingdae spectrum RUN.nc --envelope --peaks N``).

Pipeline place: analysis (reads a Dataset). The spectrum is analysis/spectrum.py's: the
envelope spectrum of the ring's vibration (band-pass around a ring resonance, Hilbert
envelope) or, without ``envelope``, its amplitude spectrum. Where the record has several
directions a peak is read on their root sum of squares (a line in either counts), and the
table gives each direction's amplitude too. A peak is a bin larger than both its neighbours in
(0, fmax]; its frequency is refined by the parabola through the bin and its neighbours (the
Hann window's main lobe). When fewer such local maxima exist than asked for, the table prints
those and says so. It is matched to the characteristic orders (analysis/
defect_frequencies.py: BPFO, BPFI, BSF, 2×BSF, FTF, the shaft, their harmonics, BPFI ± f_s,
2×BSF ± FTF around each harmonic, and their second sidebands) within one resolution bin: the
bin centred on the refined peak, |frequency − order| <= half the bin width
(:data:`MATCH_HALF_WIDTH_BINS`); a peak with none is "unmatched". Where the run's scene names
its defects, only the orders their kinds can produce are kept if one of them is in the bin (an
inner spall's BPFI − 2 f_s is not called BPFO); when several orders that can occur share the
bin, the table prints them all, nearest first, each with its offset ("BPFO or BPFI−2×fs").
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import xarray as xr

from .defect_frequencies import defect_kinds, matches, orders, run_defect_frequencies
from .spectrum import (amplitude_spectrum, default_band, default_fmax, envelope_spectrum,
                       spectrum_variable, variable_note)

#: an order matches a peak within this many bin widths either side of the refined peak: half
#: a bin, the peak's own bin; an order further off lies in a neighbouring bin, where the
#: spectrum would have shown it as a line of its own
MATCH_HALF_WIDTH_BINS = 0.5


class Peak(NamedTuple):
    """One peak: ``frequency_Hz`` (refined), ``amplitude`` (root sum of squares over the
    directions), the amplitude in each direction, and the order it matches (None: none) with
    the offset ``frequency_Hz − order`` [Hz]; ``others``: (label, offset [Hz]) of every other
    order within the same bin that can occur too, nearest first (empty: none)."""

    frequency_Hz: float
    amplitude: float
    by_direction: dict
    order: str | None
    offset_Hz: float
    others: tuple = ()


class PeakTable(NamedTuple):
    """The peaks, strongest first, and what they were read from: ``asked`` the number asked
    for, ``maxima`` the local maxima in (0, ``fmax_Hz``] (fewer than asked: all are printed),
    ``bins`` the bins there, ``tolerance_Hz`` the matching half-width, ``variable_note`` why
    the spectrum is not of ring_acceleration ("" when it is)."""

    peaks: list
    spectrum: xr.DataArray
    band: tuple | None
    band_note: str
    defect_frequencies: dict
    shaft_Hz: float
    source: str
    asked: int = 0
    maxima: int = 0
    fmax_Hz: float = np.nan
    bins: int = 0
    tolerance_Hz: float = np.nan
    variable_note: str = ""


def spectrum_peaks(ds: xr.Dataset, count: int, envelope: bool = True,
                   band_Hz: tuple[float, float] | None = None,
                   fmax_Hz: float | None = None) -> PeakTable:
    """The ``count`` strongest peaks (module docstring) of the envelope spectrum (``envelope``)
    or the amplitude spectrum of a run's ring vibration up to ``fmax_Hz`` (default:
    analysis/spectrum.default_fmax)."""
    if count < 1:
        raise ValueError(f"--peaks {count}: expected a whole number >= 1")
    spec = amplitude_spectrum(ds)
    nyquist = 0.5 / spec.attrs["sample_interval_s"]
    note = ""
    if envelope:
        if band_Hz is None:
            lo, hi, note = default_band(ds, nyquist)
            band_Hz = (lo, hi)
        spec = envelope_spectrum(ds, band_Hz=band_Hz)
    fmax = default_fmax(ds, nyquist) if fmax_Hz is None else float(fmax_Hz)
    if not (np.isfinite(fmax) and 0.0 < fmax <= nyquist * (1.0 + 1e-9)):
        raise ValueError(f"--fmax {fmax!r}: expected 0 < fmax <= the record's Nyquist "
                         f"frequency {nyquist:.6g} Hz")
    f = spec.frequency.values
    other = [d for d in spec.dims if d != "frequency"]
    a = spec.transpose("frequency", *other).values.reshape(f.size, -1)
    total = np.sqrt((a * a).sum(axis=1))
    width = float(spec.attrs["bin_width_Hz"])
    i = np.arange(1, f.size - 1)
    is_peak = (total[i] > total[i - 1]) & (total[i] >= total[i + 1]) & (f[i] <= fmax)
    found = i[is_peak]
    found = found[np.argsort(total[found], kind="stable")[::-1]][:count]
    tolerance = MATCH_HALF_WIDTH_BINS * width
    freqs, shaft, source = run_defect_frequencies(ds)
    candidates = orders(freqs, shaft, fmax + tolerance, sidebands=2) if freqs else []
    kinds = defect_kinds(ds)
    labels = ([str(v) for v in spec[other[0]].values] if other and a.shape[1] > 1
              else [spec.name or "amplitude"])
    peaks = []
    for k in found:
        y0, y1, y2 = total[k - 1], total[k], total[k + 1]
        den = y0 - 2.0 * y1 + y2
        shift = 0.5 * (y0 - y2) / den if den < 0 else 0.0
        fk = float(f[k] + np.clip(shift, -0.5, 0.5) * width)
        near = matches(fk, candidates, tolerance, kinds)
        o = near[0] if near else None
        peaks.append(Peak(fk, float(y1), dict(zip(labels, map(float, a[k]))),
                          None if o is None else o.label,
                          np.nan if o is None else fk - o.frequency_Hz,
                          tuple((n.label, fk - n.frequency_Hz) for n in near[1:])))
    bins = int(((f > 0) & (f <= fmax)).sum())
    return PeakTable(peaks, spec, band_Hz, note, freqs, shaft, source, count,
                     int(is_peak.sum()), fmax, bins, tolerance,
                     variable_note(ds, spectrum_variable(ds)))


def format_table(table: PeakTable, path_text: str) -> str:
    """The table as printed: a head naming the spectrum, its resolution and the defect
    frequencies, then one row per peak."""
    spec = table.spectrum
    a = spec.attrs
    units = a.get("units", "")
    head = [f"{path_text}: {a['long_name']} [{units}]"
            + (f" ({table.band_note})" if table.band_note else "")]
    head += [table.variable_note] if table.variable_note else []
    head.append(f"resolution (bin width) {a['bin_width_Hz']:.4g} Hz, {a['samples']} samples at "
                f"{1.0 / a['sample_interval_s']:.5g} Hz; an order matches a peak within its "
                f"resolution bin, |offset| <= {table.tolerance_Hz:.4g} Hz (half the bin "
                f"width); \"A or B\": every order in the bin that can occur, nearest first")
    if table.defect_frequencies:
        fr = table.defect_frequencies
        head.append(f"defect frequencies, {table.source}: "
                    + ", ".join(f"{n} {fr[k]:.5g} Hz" for k, n in (
                        ("bpfo", "BPFO"), ("bpfi", "BPFI"), ("bsf", "BSF"),
                        ("2bsf", "2×BSF"), ("ftf", "FTF")))
                    + f"; shaft fs {table.shaft_Hz:.5g} Hz")
    else:
        head.append("the file has no characteristic frequencies: every peak unmatched")
    dirs = list(table.peaks[0].by_direction) if table.peaks else []
    cols = ["#", "frequency [Hz]", f"amplitude [{units}]"] + [f"{d} [{units}]" for d in dirs
                                                              if len(dirs) > 1]
    cols += ["order", "offset [Hz]"]
    rows = []
    for n, p in enumerate(table.peaks, 1):
        row = [str(n), f"{p.frequency_Hz:.4f}", f"{p.amplitude:.4g}"]
        row += [f"{v:.4g}" for v in p.by_direction.values()] if len(dirs) > 1 else []
        named = [] if p.order is None else [(p.order, p.offset_Hz), *p.others]
        row += [" or ".join(n for n, _ in named) or "unmatched",
                " / ".join(f"{d:+.3f}" for _, d in named)]
        rows.append(row)
    if not rows:
        return "\n".join(head + ["no peak below fmax"])
    widths = [max(len(c), *(len(r[i]) for r in rows)) for i, c in enumerate(cols)]
    line = "  ".join(c.rjust(w) for c, w in zip(cols, widths))
    body = ["  ".join(v.rjust(w) for v, w in zip(r, widths)) for r in rows]
    return "\n".join(head + [line] + body + _fewer(table))


def _fewer(table: PeakTable) -> list[str]:
    """The line saying why fewer peaks than asked are printed ([] when all are)."""
    if len(table.peaks) >= table.asked:
        return []
    width = float(table.spectrum.attrs["bin_width_Hz"])
    return [f"{len(table.peaks)} of the {table.asked} peaks asked for: the spectrum has only "
            f"{table.maxima} local maxima (bins above both neighbours) in 0-"
            f"{table.fmax_Hz:.5g} Hz, {table.bins} bins of {width:.4g} Hz; "
            "a longer record (numerics.cage_revolutions) or a higher --fmax holds more"]
