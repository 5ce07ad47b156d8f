"""The convergence study (studies/converge.py) as text, a Markdown table and a figure.

Pipeline: studies; reads the Dataset :func:`bearingdae.studies.converge.converge` returns.
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from ..plots.figure_common import SKEW_SCALE, SKEW_UNIT
from .converge import CONVERGED_SE, REFINEMENTS

#: display scale and units of outputs whose SI value reads badly in a table
DISPLAY = {"cage_slip": (100.0, "%"), "max_skew_per_pass": (SKEW_SCALE, SKEW_UNIT),
           "min_film_per_pass": (1e6, "µm")}


def _shown(ds, output):
    scale, units = DISPLAY.get(output, (1.0, str(ds.output_units.sel(output=output).item())))
    return scale, units


def _cell(ds, setting, output, signed=False) -> str:
    from ..analysis.statistics import with_error

    row = ds.sel(setting=setting, output=output)
    scale, _ = _shown(ds, output)
    base = setting == ds.setting.values[0]
    v, e = ((row.value, row.stderr) if base else (row.delta, row.delta_stderr))
    v, e = float(v) * scale, float(e) * scale
    if 0 < max(abs(v), e) < 1e-4:  # zero to integration noise (the skew of a moment-free load)
        text = f"{v:.1e} ± {e:.1e}" if np.isfinite(e) else f"{v:.2e}"
    else:
        text = with_error(v, e)
    text = ("+" if signed and not text.startswith(("-", "nan")) else "") + text
    x = float(ds.value.sel(setting=ds.setting.values[0], output=output)) * scale
    if base or not (np.isfinite(v) and x != 0 and np.isfinite(x)):
        return text
    return f"{text} ({v / abs(x):+.1e} rel.)"


def summary_lines(ds: xr.Dataset) -> list[str]:
    """The study as text: per setting its CPU time, then each output's value (base) or change
    with the verdict; last, one line naming what is not converged and the setting to raise."""
    lines = []
    if "kernels_wall_s" in ds.attrs:
        lines.append(f"kernels loaded or compiled before the runs: "
                     f"{ds.attrs['kernels_wall_s']:.1f} s wall, {ds.attrs['kernels_cpu_s']:.1f} s "
                     f"CPU; the study: {ds.attrs['study_wall_s']:.1f} s wall")
    for text in json.loads(ds.attrs.get("base_run_warnings", "[]")):
        lines.append(f"base run: {text}")
    for s, label in zip(ds.setting.values, ds.setting_label.values):
        row = ds.sel(setting=s)
        head = f"{s}: {label}, {_times(row)}"
        lines.append(head if row.status.item() in ("ok", "") else f"{head} {row.status.item()}")
        for o in ds.output.values:
            _, units = _shown(ds, o)
            name = f"{o} [{units}]"
            if s == ds.setting.values[0]:
                lines.append(f"  {name:34s} {_cell(ds, s, o)}")
            else:
                lines.append(f"  {name:34s} Δ {_cell(ds, s, o, True):28s} "
                             f"{row.verdict.sel(output=o).item()}")
    bad = []
    for o in ds.output.values:
        advice = [REFINEMENTS[str(s)][1] + " " + REFINEMENTS[str(s)][0]
                  for s in ds.setting.values[1:]
                  if ds.verdict.sel(setting=s, output=o).item().startswith("not converged")]
        if advice:
            bad.append(f"{o} ({', '.join(advice)})")
    tol = float(ds.attrs.get("practical_tolerance_rel", 0.0))
    lines.append("not converged at the base settings: " + "; ".join(bad) if bad else
                 "every output converged under every refinement (|Δ| <= "
                 f"{CONVERGED_SE:g} combined standard errors or {tol:g} of the base value)")
    return lines


def _times(row) -> str:
    """A setting's run time: wall and CPU (older studies: CPU only)."""
    cpu = f"{float(row.run_time_s):.1f} s CPU"
    return f"{float(row.wall_time_s):.1f} s wall, {cpu}" if "wall_time_s" in row else cpu


def markdown(ds: xr.Dataset, caption: str = "") -> str:
    """The study as a Markdown table (outputs x settings, the CPU times in the last row), with
    ``caption`` as an italic line above it: the docs include it (docs/validation.md)."""
    settings_ = list(ds.setting.values)
    head = ["output", f"base: {ds.setting_label.values[0]}"] + [
        f"{lab} (Δ)" for lab in ds.setting_label.values[1:]]
    rows = []
    for o in ds.output.values:
        _, units = _shown(ds, o)
        meaning = ds.output_long_name.sel(output=o).item().replace("|", "\\|")
        cells = [f"{meaning} [{units}]",
                 _cell(ds, settings_[0], o)]
        for s in settings_[1:]:
            v = ds.verdict.sel(setting=s, output=o).item()
            v = "converged" if v == "converged" else f"**{v}**"
            cells.append(f"{_cell(ds, s, o, True)}: {v}")
        rows.append(cells)
    if "wall_time_s" in ds:
        rows.append(["run time [s wall]"] + [f"{float(t):.1f}" for t in ds.wall_time_s.values])
    rows.append(["run time [s CPU]"] + [f"{float(t):.1f}" for t in ds.run_time_s.values])
    text = (f"*{caption}*\n\n" if caption else "") + "| " + " | ".join(head) + " |\n"
    text += "|" + "---|" * len(head) + "\n"
    return text + "".join("| " + " | ".join(r) + " |\n" for r in rows)


def plot(ds: xr.Dataset, path):
    """One panel per output: the change under each refinement (± CONVERGED_SE combined
    standard errors) against the CPU time of the run; green where converged, red where not."""
    from ..plots.figure_common import panel_grid, save_figure

    outputs = list(ds.output.values)
    fig, axes = panel_grid(len(outputs), 4, 3.8, 3.2)
    base = ds.setting.values[0]
    for ax, o in zip(axes, outputs):
        scale, units = _shown(ds, o)
        ax.axhline(0.0, color="k", lw=0.6)
        ax.plot(float(ds.run_time_s.sel(setting=base)), 0.0, "ks")
        for s in ds.setting.values[1:]:
            d = ds.sel(setting=s, output=o)
            ok = d.verdict.item() == "converged"
            ax.errorbar(float(d.run_time_s), float(d.delta) * scale,
                        yerr=CONVERGED_SE * float(d.delta_stderr) * scale, fmt="o", capsize=3,
                        color="tab:green" if ok else "tab:red")
            ax.annotate(str(s), (float(d.run_time_s), float(d.delta) * scale),
                        textcoords="offset points", xytext=(4, 4), fontsize=7)
        ax.set(xlabel="run time [s CPU]", ylabel=f"Δ [{units}]", title=str(o))
        ax.title.set_fontsize(9)
    fig.suptitle(f"{ds.attrs['title']}: change under refinement ± {CONVERGED_SE:g} SE "
                 "(green: converged)", fontsize=9)
    return save_figure(fig, path)
