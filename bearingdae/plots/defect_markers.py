"""The defect frequencies marked on an envelope spectrum (``bearingdae plot RUN.nc --spectrum
--envelope``; analysis/defect_frequencies.py computes them).

Pipeline place: plots. Every characteristic order up to the panel's top frequency gets a thin
vertical line in its defect's colour: the fundamental dashed, its harmonics dotted, the
sidebands that apply (BPFI ± f_s, 2×BSF ± FTF) dash-dotted. A legend beside the panel names each
group once with its fundamental's value ("BPFO 75.64 Hz and harmonics"), so that a reader tells
the lines apart without labels crowding the traces; the frequencies are the run's measured ones
(mean cage and roller spin speeds, slip included) where the file has them.
"""

from __future__ import annotations

import xarray as xr

from ..analysis.defect_frequencies import LABELS, orders, run_defect_frequencies

#: line colour of each family of orders
COLOURS = {"bpfo": "tab:red", "bpfi": "tab:purple", "bsf": "tab:orange", "2bsf": "tab:brown",
           "ftf": "tab:green", "shaft": "k"}
#: the legend's order of the families
LEGEND_ORDER = ("bpfo", "bpfi", "bsf", "2bsf", "ftf", "shaft")
#: what the legend calls each family, given its fundamental
NAMES = {"shaft": "shaft fs", **LABELS}


def _legend_text(family: str, kind: str, f1: float, freqs: dict, shaft_Hz: float) -> str:
    if kind == "sideband":
        mod = ("fs", shaft_Hz) if family == "bpfi" else ("FTF", freqs["ftf"])
        return f"{NAMES[family]} ± {mod[0]} ({mod[1]:.4g} Hz) sidebands"
    return f"{NAMES[family]} {f1:.4g} Hz" + (" and harmonics" if kind == "harmonic" else "")


def draw_defect_orders(ax, ds: xr.Dataset, fmin: float, fmax: float) -> list:
    """Lines at the run's characteristic orders in [fmin, fmax] (module docstring), each group
    labelled once for the legend; returns the orders drawn."""
    freqs, shaft, source = run_defect_frequencies(ds)
    if not freqs:
        return []
    # grouped by defect (the legend's order), the fundamental first
    drawn = sorted((o for o in orders(freqs, shaft, fmax) if o.frequency_Hz >= fmin),
                   key=lambda o: (LEGEND_ORDER.index(o.family), abs(o.sideband), o.harmonic))
    seen: set = set()
    for o in drawn:
        kind = "sideband" if o.sideband else "harmonic"
        family = o.family  # (the even harmonics of BSF are 2×BSF's)
        key = (family, kind)
        label = "_nolegend_"
        if key not in seen:
            seen.add(key)
            f1 = shaft if family == "shaft" else freqs[family]
            label = _legend_text(family, kind, f1, freqs, shaft)
        fundamental = o.harmonic == (2 if family == "2bsf" and not o.sideband else 1)
        style = "-." if o.sideband else "--" if fundamental else ":"
        ax.axvline(o.frequency_Hz, color=COLOURS[family], ls=style, lw=0.8,
                   alpha=0.6 if o.sideband else 0.9, label=label)
    if drawn:
        ax._bearingdae_defect_source = source
    return drawn
