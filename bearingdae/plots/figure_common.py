"""What every figure says the same way: units an engineer reads, the keys of colours, the sign
and ends of the pocket force, the time axis, titles that fit; and how a figure is saved.

Pipeline place: plots (read by :mod:`.plotting`, the study figures and the run summary).
One unit per quantity across commands: speeds in r/min, skew in mrad (small angles: the
baseline's skew is 0.1-4 mrad; the sweep summary and docs/validation.md use mrad as well),
slip ratios in %.
"""

from __future__ import annotations

import textwrap

from pathlib import Path

import numpy as np

from ..analysis.result_variables import value as result_value

RAD_S_TO_RPM = 60.0 / (2.0 * np.pi)
#: skew angles in every figure and printed summary: value [rad] * SKEW_SCALE, in SKEW_UNIT
SKEW_SCALE, SKEW_UNIT = 1e3, "mrad"
#: the pocket force's sign (results/dataset.py: along the direction of rotation)
POCKET_SIGN = "+: cage pushes roller forward"
#: the roller ends as the Dataset's ``end`` labels them
END_LABELS = {"a": "end a (x = +L/2)", "b": "end b (x = -L/2)"}
#: characters per inch of a title at 1 pt (a proportional font averages ~0.55 em per char)
_CHARS_PER_INCH_PT = 72.0 / 0.55


def wrap_title(text: str, fig, fontsize: float = 10.0) -> str:
    """``text`` broken into lines that fit the width of ``fig``; each line of ``text`` is
    wrapped on its own, and ``key = value`` pairs stay on one line (a title with --set
    overrides lists them)."""
    width = max(20, int(0.95 * fig.get_figwidth() * _CHARS_PER_INCH_PT / fontsize))
    keep = "\u00a0"  # textwrap breaks at ASCII whitespace only
    lines = []
    for line in str(text).splitlines() or [""]:
        lines += textwrap.wrap(line.replace(" = ", f"{keep}={keep}"), width,
                               break_on_hyphens=False) or [""]
    return "\n".join(lines).replace(keep, " ")


def slice_colours(k: int) -> list:
    """Colour of slice 1 ... k (viridis, end b dark to end a yellow)."""
    import matplotlib

    cmap = matplotlib.colormaps["viridis"]
    return [cmap(i / max(1, k - 1)) for i in range(k)]


def slice_key(fig, axes, k: int) -> None:
    """A colour bar beside ``axes`` keying the slice colours of :func:`slice_colours`: slice
    numbers 1 ... k, and which end each side is."""
    import matplotlib
    from matplotlib.colors import BoundaryNorm, ListedColormap

    cmap = ListedColormap(slice_colours(k))
    norm = BoundaryNorm(np.arange(0.5, k + 1.5), k)
    mappable = matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap)
    if fig.get_layout_engine() is None:  # fixed margins (fixed_panels): the bar in the right one
        box = axes.get_position()  # in the panel's fraction
        width_in = fig.bbox.width / fig.dpi
        cax = fig.add_axes([box.x1 + 0.1 / width_in, box.y0, 0.12 / width_in, box.height])
        bar = fig.colorbar(mappable, cax=cax)
    else:
        bar = fig.colorbar(mappable, ax=axes, pad=0.02, aspect=30)
    step = max(1, int(np.ceil(k / 10)))
    ticks = sorted(set(list(range(1, k + 1, step)) + [k]))
    bar.set_ticks(ticks)
    bar.set_label(f"slice (1: end b, x = -L/2 ... {k}: end a, x = +L/2)", fontsize=8)
    bar.ax.tick_params(labelsize=7)


def time_axis(ds) -> tuple[np.ndarray, str, float | None]:
    """(time [ms], axis label, start of the record [ms] if the samples include warm-up) of a
    dynamic run: time counts from the start of the simulation (results/dataset.py), the
    record from ``record_start_s`` after the speed ramp and warm-up."""
    t_ms = ds.time.values * 1e3
    start = result_value(ds, "record_start_s", None)
    if start is None or not float(start) > 0:
        return t_ms, "time since the start of the simulation [ms]", None
    start_ms = float(start) * 1e3
    if t_ms.size and t_ms[0] < start_ms - 1e-9:  # a failed run's partial file keeps warm-up
        return t_ms, (f"time since the start [ms] (warm-up until {start_ms:.4g} ms, then "
                      "the record)"), start_ms
    return t_ms, f"time since the start [ms] (the record, after {start_ms:.4g} ms of warm-up)", \
        None


#: Most points a time-series line of a figure draws: a longer series is drawn as the minimum and
#: maximum of each of PLOT_POINTS / 2 equal bins (in time order), which looks the same at any
#: figure width below a few thousand pixels and keeps the figure's memory bounded (a 60 000-
#: sample line costs matplotlib ~2 MB; a 300-revolution overview has 20 of them).
PLOT_POINTS = 8000


def envelope(t, y, points: int = PLOT_POINTS) -> tuple[np.ndarray, np.ndarray]:
    """(t, y) of a line as drawn: as given up to ``points`` samples, else each bin's minimum
    and maximum (every peak and trough kept, in time order)."""
    t, y = np.asarray(t), np.asarray(y)
    n = y.size
    if n <= points:
        return t, y
    size = -(-n // (points // 2))  # samples per bin (the last one shorter)
    bins = -(-n // size)
    pad = bins * size - n
    yy = np.concatenate([y, np.full(pad, np.nan)]).reshape(bins, size)
    if np.isnan(yy).all(axis=1).any():  # a bin of NaN only: keep the line as it is
        return t, y
    lo, hi = np.nanargmin(yy, axis=1), np.nanargmax(yy, axis=1)
    first = np.minimum(lo, hi) + size * np.arange(bins)
    second = np.maximum(lo, hi) + size * np.arange(bins)
    idx = np.stack([first, second], axis=1).ravel()
    return t[idx], y[idx]


def outside_legend(ax, **kwargs) -> None:
    """A legend right of ``ax`` (hides no trace; constrained layout or the margins of
    :func:`fixed_panels` make room for it)."""
    ax.legend(loc="center left", bbox_to_anchor=(1.01, 0.5), borderaxespad=0.0,
              **{"fontsize": 7, **kwargs})


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


#: margins [in] of a panel of :func:`fixed_panels`: left (tick labels and a two-line axis
#: label), right (a legend or colour bar of :func:`outside_legend` / :func:`slice_key`), bottom
#: (tick labels and the axis label), top (the panel's title above an axis offset text)
PANEL_MARGINS_IN = {"left": 0.95, "right": 1.35, "bottom": 0.6, "top": 0.45}
#: height [in] of a line of the figure title of :func:`fixed_panels`
TITLE_LINE_IN = 0.22


def fixed_panels(plt, rows: int, cols: int, width_in: float, height_in: float, title: str):
    """(figure, its subfigures (rows, cols), one axes in each) on fixed margins
    (:data:`PANEL_MARGINS_IN`) with ``title`` wrapped above them. Why not constrained layout:
    it measures every text of the figure before it draws, 40 % of a run's overview figure
    (0.2 of 0.5 s of CPU); the overview's texts are of known size, so room for them is set
    aside instead."""
    fig = plt.figure(figsize=(width_in * cols, height_in * rows))
    title = wrap_title(title, fig, 10)
    head_in = 0.12 + TITLE_LINE_IN * (title.count("\n") + 1)
    fig.set_figheight(height_in * rows + head_in)
    # a first row of the title's height (a subfigure fills its grid cell, margins aside)
    grid = fig.add_gridspec(rows + 1, cols, height_ratios=[head_in] + [height_in] * rows)
    panels = np.array([[fig.add_subfigure(grid[i + 1, j]) for j in range(cols)]
                       for i in range(rows)])
    m = PANEL_MARGINS_IN
    axes = np.empty((rows, cols), dtype=object)
    for i in range(rows):
        for j in range(cols):
            axes[i, j] = panels[i, j].subplots()
            panels[i, j].subplots_adjust(left=m["left"] / width_in,
                                         right=1.0 - m["right"] / width_in,
                                         bottom=m["bottom"] / height_in,
                                         top=1.0 - m["top"] / height_in)
    fig.suptitle(title, fontsize=10, y=1.0 - 0.06 / fig.get_figheight(), va="top")
    return fig, panels, axes


def room_for_titles(panels, axes, height_in: float) -> None:
    """Each panel of :func:`fixed_panels` ``height_in`` high lowers its axes' top by a line
    (:data:`TITLE_LINE_IN` x 1.2, the 12 pt of a title) per line its title has beyond one (a
    spectrum's title states its window and resolution on a second line) and by the rows of
    marker labels a spectrum puts between its axes and its title (plots/plot_spectrum.py)."""
    for panel, ax in zip(np.ravel(panels), np.ravel(axes)):
        extra = ax.get_title().count("\n")
        above_pt = getattr(ax, "_bearingdae_above_pt", 0.0)  # (plot_spectrum.draw_markers)
        if extra or above_pt:
            top_in = (PANEL_MARGINS_IN["top"] + 1.2 * TITLE_LINE_IN * extra
                      + above_pt / 72.0)
            panel.subplots_adjust(top=1.0 - top_in / height_in)


def panel_grid(n: int, cols: int, width_in: float, height_in: float):
    """(figure, the first ``n`` axes) of a grid of at most ``cols`` columns, one panel per
    quantity of a study figure; the unused panels of the last row hidden."""
    plt = _plt()
    cols = min(cols, n)
    rows = -(-n // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(width_in * cols, height_in * rows),
                             squeeze=False, layout="constrained")
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    return fig, list(axes.flat[:n])


def closed_on_failure(draw):
    """``draw`` (a function that makes and saves figures) with the figures it opened closed
    when it fails: an error while drawing (a damaged file, Ctrl-C) would otherwise leave them
    open in pyplot, holding their memory for the rest of the process (a notebook, a sweep)."""
    import functools

    @functools.wraps(draw)
    def drawing(*args, **kwargs):
        plt = _plt()
        before = set(plt.get_fignums())
        try:
            return draw(*args, **kwargs)
        except BaseException:
            for number in set(plt.get_fignums()) - before:
                plt.close(number)
            raise

    return drawing


def save_figure(fig, path: str | Path) -> Path:
    """Write ``fig`` atomically (bearingdae.util.atomic: a temporary beside ``path``, then rename),
    so that an error or a kill while saving never leaves a partial image at ``path``; the
    format follows the suffix as in ``savefig`` (PNG without one); the figure is closed."""
    import matplotlib
    import matplotlib.pyplot as plt

    from ..util.atomic import atomic_write

    path = Path(path)
    fmt = path.suffix.lstrip(".").lower() or matplotlib.rcParams["savefig.format"]
    try:
        with atomic_write(path) as tmp:  # the temporary's name ends in .part: give the format
            fig.savefig(tmp, format=fmt, dpi=110)
    finally:
        plt.close(fig)
    return path
