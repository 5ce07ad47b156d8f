"""Trend figures with error bars: one figure per claim, one panel per reading.

Stage: plots (reads the trends table of bearingdae.studies.trends, writes PNGs).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .figure_common import _plt, save_figure, wrap_title

#: CF units of a trend quantity -> (factor, display units)
DISPLAY_UNITS = {"rad": (1e3, "mrad"), "1": (100.0, "%"), "m s-1": (1.0, "m/s"),
                 "N": (1.0, "N")}
#: sweep dimension -> axis label
AXIS_LABELS = {"speed_rpm": "inner-ring speed [r/min]", "radial_load_N": "radial load [N]",
               "moment_Nm": "moment [N·m]"}


def display(units: str) -> tuple[float, str]:
    """(factor, display units) of CF ``units`` (1, units if not listed)."""
    return DISPLAY_UNITS.get(units, (1.0, units))


def claim_figure(table, verdicts, claim: str, path: str | Path) -> Path:
    """The claim's readings against the sweep value, ± 2 standard errors (bars) and ± 1
    (caps-free thick bars), each panel titled with its verdict."""
    plt = _plt()
    rows = table[table["claim"] == claim]
    readings = list(dict.fromkeys(rows["reading"]))
    fig, axes = plt.subplots(1, len(readings), figsize=(3.3 * len(readings), 3.4),
                             layout="constrained", squeeze=False)
    for ax, reading in zip(axes[0], readings):
        r = rows[rows["reading"] == reading].sort_values("sweep_value")
        factor, shown = display(str(r["units"].iloc[0]))
        x = r["sweep_value"].to_numpy(float)
        y = r["value"].to_numpy(float) * factor
        se = r["stderr"].to_numpy(float) * factor
        ax.errorbar(x, y, yerr=2 * se, fmt="o-", color="C0", capsize=3, lw=1, ms=4,
                    label="mean ± 2 SE")
        ax.errorbar(x, y, yerr=se, fmt="none", color="C3", lw=3, label="± 1 SE")
        v = verdicts[(verdicts["claim"] == claim) & (verdicts["reading"] == reading)]
        word = v["verdict"].iloc[0] if len(v) else "?"
        ax.set_title(f"{reading}: {word}", fontsize=9)
        ax.set_xlabel(AXIS_LABELS.get(str(r["sweep_variable"].iloc[0]),
                                      str(r["sweep_variable"].iloc[0])), fontsize=8)
        ax.set_ylabel(shown, fontsize=8)
        ax.tick_params(labelsize=7)
        lo = np.nanmin(y - 2 * se)
        ax.set_ylim(bottom=min(0.0, lo) if lo > 0 else None)
    axes[0][0].legend(fontsize=7, loc="best")
    fig.suptitle(wrap_title(f"claim: {claim}", fig), fontsize=10)
    out = save_figure(fig, path)
    plt.close(fig)
    return out
