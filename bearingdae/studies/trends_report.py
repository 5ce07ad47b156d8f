"""``bearingdae paper --trends`` (:func:`run_paper_trends`) and its outputs: CSV, NetCDF, the
Markdown tables of docs/validation.md, one figure per claim, and the check of the error bars
against a repeat.

Pipeline place: studies (formats the tables of :mod:`.trends`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from .trends import CLAIMS, LEVEL_COLUMNS, SIGNIFICANCE_SE, TABLE_COLUMNS, VERDICT_COLUMNS


# ---------------------------------------------------------------------------------------------
# Outputs: CSV, NetCDF, the Markdown tables of docs/validation.md, figures
# ---------------------------------------------------------------------------------------------
#: sweep dimension -> (heading, display units of its values)
SWEEP_HEADINGS = {"speed_rpm": ("speed", "r/min"), "radial_load_N": ("radial load", "N"),
                  "moment_Nm": ("moment", "N·m")}


#: verdict -> its mark in the summary
MARKS = {"holds": "✓ holds", "contradicted": "✗ contradicted", "not resolved": "? not resolved"}


def verdict_summary_markdown(verdicts) -> str:
    """One row per claim: its verdict under each reading (orbit-wide readings together)."""
    groups = {"orbit-wide": lambda r: r.startswith("orbit_"), "per roller pass":
              lambda r: r == "pass_peak", "loaded zone": lambda r: r == "loaded_zone",
              "load-weighted": lambda r: r == "load_weighted"}
    out = ["| claim | paper | " + " | ".join(groups) + " |", "|---|---|" + "---|" * len(groups)]
    for claim in dict.fromkeys(verdicts["claim"]):
        rows = verdicts[verdicts["claim"] == claim]
        cells = []
        for test in groups.values():
            hit = rows[[test(r) for r in rows["reading"]]]
            many = len(hit) > 1
            cells.append("; ".join((f"{r.reading.removeprefix('orbit_')}: " if many else "")
                                   + MARKS[r.verdict] for r in hit.itertuples()) or "—")
        out.append(f"| {claim} | {rows['source'].iloc[0]} | " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"


def trends_markdown(table, verdicts, summary: bool = True) -> str:
    """The trend tables of docs/validation.md from the trends table: one table per sweep, one
    row per claim x reading, mean ± standard error at each sweep point (display units), the
    z of the first-to-last change along the claim, the largest change against the claim as a
    fraction of the range (``against_of_range``) and the verdict."""
    from ..plots.plot_trends import display
    from ..analysis.statistics import with_error

    out = [verdict_summary_markdown(verdicts)] if summary else []
    for dim in dict.fromkeys(table["sweep_variable"]):
        part = table[table["sweep_variable"] == dim]
        points = sorted(set(part["sweep_value"]))
        heading, unit = SWEEP_HEADINGS.get(dim, (dim, ""))
        blocks = sorted(set(part["n_blocks"]))
        out.append(f"**{heading.capitalize()}** (mean ± standard error over "
                   f"{', '.join(str(b) for b in blocks)} blocks per point)\n")
        out.append("| claim | reading | units | " + " | ".join(f"{p:g} {unit}" for p in points)
                   + " | z first→last | most against | verdict |")
        out.append("|---|---|---|" + "---|" * len(points) + "---|---|---|")
        for claim in dict.fromkeys(part["claim"]):
            rows = part[part["claim"] == claim]
            for reading in dict.fromkeys(rows["reading"]):
                r = rows[rows["reading"] == reading].sort_values("sweep_value")
                factor, shown = display(str(r["units"].iloc[0]))
                cells = [with_error(v * factor, s * factor)
                         for v, s in zip(r["value"], r["stderr"])]
                v = verdicts[(verdicts["claim"] == claim) & (verdicts["reading"] == reading)]
                z = float(v["z_first_last"].iloc[0])
                against = float(v["against_of_range"].iloc[0])
                out.append(f"| {claim} | {reading} | {shown} | " + " | ".join(cells)
                           + f" | {z:+.1f} | {against:.0%} | {v['verdict'].iloc[0]} |")
        out.append("")
    return "\n".join(out)


def trends_dataset(table, verdicts) -> xr.Dataset:
    """The trends table (dimension ``row``) and the verdicts (dimension ``test``) as one
    Dataset for NetCDF, with the units and meaning of each column."""
    ds = xr.Dataset({c: ("row", table[c].to_numpy()) for c in TABLE_COLUMNS})
    for c in VERDICT_COLUMNS:
        ds[f"verdict_{c}" if c != "verdict" else "verdict"] = ("test", verdicts[c].to_numpy())
    levels = table.attrs.get("level_stderr")
    if levels is not None:
        ds["stderr_by_block_length"] = (("row", "block_length"), levels.to_numpy(float))
        ds = ds.assign_coords(block_length=("block_length", [0.5, 1.0, 2.0, 4.0],
                                            {"units": "1", "long_name": "block length in "
                                             "epicyclic cage revolutions"}))
    ds["value"].attrs["long_name"] = "mean over the blocks (units in column units)"
    ds["stderr"].attrs["long_name"] = ("standard error: largest blocking SE over levels with "
                                       "at least 16 blocks (bearingdae.analysis.trends)")
    ds.attrs["title"] = "bearingdae: the paper's trend claims with error bars"
    return ds


def _write_csv(frame, path: Path) -> Path:
    from ..util.atomic import atomic_write

    with atomic_write(path) as tmp:
        frame.to_csv(tmp, index=False, float_format="%.6g")
    return path


def _write_text(path: Path, text: str) -> Path:
    from ..util.atomic import atomic_write

    with atomic_write(path) as tmp:
        Path(tmp).write_text(text, encoding="utf-8")
    return path


def read_trends(folder: str | Path, stem: str = "trends"):
    """(table, verdicts) as written by :func:`write_trends` (``STEM.csv``,
    ``STEM_verdicts.csv``), with the standard errors by block length in
    ``table.attrs["level_stderr"]`` when ``STEM_levels.csv`` is there. Pages are made from
    these, so that a page and its CSV agree to the digit."""
    import pandas as pd

    folder = Path(folder)
    table = pd.read_csv(folder / f"{stem}.csv")
    levels = folder / f"{stem}_levels.csv"
    if levels.is_file():
        table.attrs["level_stderr"] = pd.read_csv(levels)[LEVEL_COLUMNS]
    return table, pd.read_csv(folder / f"{stem}_verdicts.csv")


#: the committed trends of docs/validation.md (docs/data/): the run and its repeat
DOCS_STEMS = ("paper_trends", "paper_trends_repeat")


def docs_pages(data_dir: str | Path) -> dict[str, str]:
    """The generated parts of docs/validation.md from the committed CSVs in ``data_dir``:
    ``paper_trends_summary.md`` (the verdicts), ``paper_trends.md`` (the tables) and
    ``paper_trends_check.md`` (the error-bar checks
    against the repeat)."""
    table, verdicts = read_trends(data_dir, DOCS_STEMS[0])
    repeat, repeat_verdicts = read_trends(data_dir, DOCS_STEMS[1])
    check = error_bar_check(table, verdicts, level_table(table), repeat, repeat_verdicts)
    return {f"{DOCS_STEMS[0]}_summary.md": verdict_summary_markdown(verdicts),
            f"{DOCS_STEMS[0]}.md": trends_markdown(table, verdicts, summary=False),
            f"{DOCS_STEMS[0]}_check.md": error_bar_check_markdown(check)}


def write_trends(table, verdicts, out_dir: str | Path, figures: bool = True) -> list[Path]:
    """Write ``trends.csv``, ``trends_verdicts.csv``, ``trends_levels.csv``, ``trends.nc``, ``trends.md`` and (with
    ``figures``) one ``trends_<claim>.png`` per claim into ``out_dir``; returns the paths."""
    import re

    from ..results import save

    out = Path(out_dir)
    paths = [_write_csv(table, out / "trends.csv"),
             _write_csv(verdicts, out / "trends_verdicts.csv"),
             _write_csv(level_table(table), out / "trends_levels.csv"),
             save(trends_dataset(table, verdicts), out / "trends.nc")]
    paths.append(_write_text(out / "trends.md", trends_markdown(*read_trends(out, "trends"))))
    if figures:
        from ..plots.plot_trends import claim_figure

        for claim in CLAIMS:
            slug = re.sub(r"[^a-z0-9]+", "_", claim.lower()).strip("_")
            paths.append(claim_figure(table, verdicts, claim, out / f"trends_{slug}.png"))
    return paths




def level_table(table):
    """claim, reading, sweep_value and the standard errors at block lengths of 0.5 ... 4
    revolutions of every row (the plateau check)."""
    import pandas as pd

    levels = table.attrs.get("level_stderr")
    if levels is None:
        levels = pd.DataFrame(np.nan, index=table.index, columns=LEVEL_COLUMNS)
    return pd.concat([table[["claim", "reading", "sweep_value"]].reset_index(drop=True),
                      levels.reset_index(drop=True)], axis=1)


def error_bar_check(table, verdicts, levels, repeat, repeat_verdicts) -> dict:
    """The checks of the error bars (docs/validation.md), from a trends table with its verdicts
    and standard errors by block length (:func:`level_table`) and a repeat of the whole table
    from another start state (its own table and verdicts):

    - ``neighbour_significant`` of ``neighbour_pairs``: differences between neighbouring sweep
      points larger than 2 SE; ``neighbour_by_chance``: how many 2-SE exceedances pure noise
      would give (4.55 % of them, if nothing changed along any axis);
    - ``repeat_outside`` of ``rows``: distinct values (a run shared by two sweeps, or two claims
      on one quantity, counted once) that differ from their repeat by more than 2 SE of the
      difference (``repeat_expected``: 4.55 % of them for honest error bars);
    - ``verdicts_same`` of ``verdicts`` and the claims x readings whose verdicts differ;
    - ``plateau_median`` / ``plateau_p90``: median and 90th percentile over the rows of the
      standard error at 4-revolution blocks (8 blocks) over the reported one (about 1 or below
      on the plateau; above 1 if longer blocks still see more correlation).
    """
    from math import erf, sqrt

    chance = 1.0 - erf(SIGNIFICANCE_SE / sqrt(2.0))
    key = ["claim", "reading", "sweep_value"]
    a = table.sort_values(key).reset_index(drop=True)
    b = repeat.sort_values(key).reset_index(drop=True)
    if not (a[key].equals(b[key])):
        raise ValueError("the repeat's table has other rows than the table")
    # one value per run and reading: a run shared by two sweeps, or two claims on the same
    # quantity (opposite directions), give identical rows, counted once
    distinct = ~a.duplicated(subset=["reading", "units", "value", "stderr"])
    a, b = a[distinct], b[distinct]
    z_ab = (a.value - b.value) / np.hypot(a.stderr, b.stderr)
    pairs = sig = 0
    for (claim, reading), g in table.groupby(["claim", "reading"], sort=False):
        if claim != next(c for c in CLAIMS if CLAIMS[c][:2] == CLAIMS[claim][:2]):
            continue  # two claims on the same data (opposite directions): count once
        g = g.sort_values("sweep_value")
        d = np.diff(g.value.to_numpy(float))
        s = np.hypot(g.stderr.to_numpy(float)[1:], g.stderr.to_numpy(float)[:-1])
        pairs += d.size
        sig += int((np.abs(d) > SIGNIFICANCE_SE * s).sum())
    merged = verdicts.merge(repeat_verdicts, on=["claim", "reading"], suffixes=("", "_repeat"))
    differ = merged[merged.verdict != merged.verdict_repeat]
    ratio = (levels["stderr_4rev"] / table["stderr"]).to_numpy(float)
    return {
        "neighbour_pairs": pairs, "neighbour_significant": sig,
        "neighbour_by_chance": chance * pairs,
        "rows": int(z_ab.size), "repeat_outside": int((np.abs(z_ab) > SIGNIFICANCE_SE).sum()),
        "repeat_expected": chance * z_ab.size,
        "repeat_z_rms": float(np.sqrt(np.mean(z_ab ** 2))),
        "verdicts": len(merged), "verdicts_same": int((merged.verdict == merged.verdict_repeat)
                                                      .sum()),
        "verdicts_differ": [f"{r.claim} / {r.reading}: {r.verdict} -> {r.verdict_repeat}"
                            for r in differ.itertuples()],
        "plateau_median": float(np.nanmedian(ratio)) if np.isfinite(ratio).any() else np.nan,
        "plateau_p90": (float(np.nanpercentile(ratio, 90)) if np.isfinite(ratio).any()
                        else np.nan),
    }


def error_bar_check_markdown(check: dict) -> str:
    """The paragraph of docs/validation.md that reports :func:`error_bar_check`."""
    differ = "; ".join(check["verdicts_differ"]) or "none"
    return (
        f"- **Repeat from another start state:** {check['verdicts_same']} of {check['verdicts']} verdicts are "
        f"the same (different: {differ}). Of the {check['rows']} distinct values, "
        f"{check['repeat_outside']} differ from their repeat by more than 2 standard errors of "
        f"the difference, where honest error bars give {check['repeat_expected']:.0f} by "
        f"chance; the RMS of (value − repeat) / SE is {check['repeat_z_rms']:.2f} "
        "(1 for honest error bars).\n"
        f"- **Plateau:** the standard error at 4-revolution blocks (8 blocks) over the one "
        f"reported (the largest at 0.5, 1 and 2 revolutions) has the median "
        f"{check['plateau_median']:.2f} and the 90th percentile {check['plateau_p90']:.2f} "
        "over the rows (an 8-block SE scatters by ~27 %).\n"
        f"- **Point-by-point differences:** {check['neighbour_significant']} of the "
        f"{check['neighbour_pairs']} differences between neighbouring sweep points exceed 2 "
        f"SE; {check['neighbour_by_chance']:.1f} would by chance if nothing changed along any "
        "axis.\n")


def run_paper_trends(out_dir: str | Path = "paper_trends", scheduler: str | None = None,
                     workers: int | None = None, progress: bool = True,
                     retry_failed: bool = False, figures: bool = True,
                     overrides: dict | None = None, override_origin: str = "--set",
                     scheduler_timeout_s: float | None = None):
    """``bearingdae paper --trends``: run (or resume, or read) the trend sweeps into
    ``out_dir`` and write the trends table, verdicts and figures there (:func:`write_trends`).
    Returns (table, verdicts, written paths)."""
    from .trends import run_trend_sweeps, trend_table

    sweeps = run_trend_sweeps(out_dir, overrides, scheduler=scheduler, workers=workers,
                              progress=progress, retry_failed=retry_failed,
                              override_origin=override_origin,
                              scheduler_timeout_s=scheduler_timeout_s)
    table, verdicts = trend_table(sweeps, out_dir)
    return table, verdicts, write_trends(table, verdicts, out_dir, figures)
