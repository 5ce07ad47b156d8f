"""Figures a report can take: every colour keyed, signs and ends named, units an engineer reads
(r/min, mrad, %), legends beside the traces, titles that fit, the selected sweep point named,
and skip messages with the real reason."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

from bearingdae import load_scene, simulate
from bearingdae.plots import plotting
from bearingdae.plots.figure_common import SKEW_UNIT, wrap_title


@pytest.fixture
def captured(monkeypatch):
    """The figures the plotting functions save (drawn, before they are closed)."""
    import matplotlib.pyplot as plt

    import bearingdae.plots.paper_figures as paper

    figures = []

    def keep(fig, path):  # as save_figure, without closing the figure
        fig.savefig(path, dpi=110)
        figures.append({"fig": fig, "suptitle": fig._suptitle, "axes": list(fig.axes),
                        "legends": list(fig.legends)})
        return path

    monkeypatch.setattr(plotting, "save_figure", keep)
    monkeypatch.setattr(paper, "save_figure", keep)
    yield figures
    plt.close("all")


def _fits(text_artist, fig) -> bool:
    box = text_artist.get_window_extent(fig.canvas.get_renderer())
    width = fig.get_figwidth() * fig.dpi
    return box.x0 >= 0 and box.x1 <= width


def _outside(legend, ax, fig) -> bool:
    """The legend's box does not overlap the axes' box (so it hides no trace)."""
    r = fig.canvas.get_renderer()
    lb, ab = legend.get_window_extent(r), ax.get_window_extent(r)
    return lb.x0 >= ab.x1 or lb.x1 <= ab.x0 or lb.y0 >= ab.y1 or lb.y1 <= ab.y0


def test_wrap_title_fits_and_keeps_each_setting_whole():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(6.5, 4))
    sets = ", ".join(f"numerics.key_{i} = {i}.5" for i in range(12))
    title = f"Fig. 14: roller skew angle\nsweep: a case [set: {sets}]"
    wrapped = wrap_title(title, fig, 9)
    assert wrapped.replace("\n", " ") == title.replace("\n", " ")
    assert all(f"numerics.key_{i} = {i}.5" in wrapped for i in range(12))  # never broken
    text = fig.suptitle(wrapped, fontsize=9)
    fig.canvas.draw()
    assert _fits(text, fig) and len(wrapped.splitlines()) >= 4
    plt.close(fig)


@pytest.fixture(scope="module")
def short_run():
    scene = load_scene("yang20_baseline", {"numerics.warmup_cage_revolutions": 0.1,
                                           "numerics.cage_revolutions": 0.05,
                                           "numerics.samples_per_cage_revolution": 200})
    return simulate(scene, progress=False)


def test_overview_keys_its_colours_names_signs_and_units(short_run, captured, tmp_path):
    plotting.overview(short_run, tmp_path / "o.png")
    (got,) = captured
    fig = got["fig"]
    labels = {ax.get_ylabel() for ax in got["axes"]}
    assert "speed [r/min]" in labels and f"skew angle [{SKEW_UNIT}]" in labels
    assert "slice contact force [N]" in labels
    assert "pocket force [N]\n(+: cage pushes roller forward)" in labels
    (key,) = [lb for lb in labels if lb.startswith("slice (1: end b")]  # the colour bar
    assert key.endswith("10: end a, x = +L/2)")
    for ax in got["axes"]:
        if ax.get_legend() is not None:
            assert _outside(ax.get_legend(), ax, fig), ax.get_title()
            texts = [t.get_text() for t in ax.get_legend().get_texts()]
            assert texts == [ln.get_label() for ln in ax.get_lines()
                             if not ln.get_label().startswith("_")]  # every line keyed
    plotted = [ax for ax in got["axes"] if ax.get_lines()]
    start_ms = short_run["record_start_s"].item() * 1e3
    assert all(f"after {start_ms:.4g} ms of warm-up" in ax.get_xlabel() for ax in plotted)
    ends = [t.get_text() for ax in got["axes"] if ax.get_legend() is not None
            for t in ax.get_legend().get_texts() if t.get_text().startswith("end")]
    assert ends == ["end a (x = +L/2)", "end b (x = -L/2)"]
    assert _fits(got["suptitle"], fig)
    _within_panels(fig)


def _within_panels(fig) -> None:
    """Every panel's texts (tick labels, axis labels, title, legend, colour bar and its label)
    lie inside the panel (a subfigure): the fixed margins cut nothing off and no panel's text
    runs into its neighbour's; the figure title above them all."""
    r = fig.canvas.get_renderer()
    panels = fig.subfigs
    assert panels, "the overview draws a subfigure per panel"
    for panel in panels:
        box = panel.bbox
        for ax in panel.axes:
            tight = ax.get_tightbbox(r)
            assert (tight.x0 >= box.x0 - 0.5 and tight.x1 <= box.x1 + 0.5
                    and tight.y0 >= box.y0 - 0.5 and tight.y1 <= box.y1 + 0.5), \
                (ax.get_title() or ax.get_ylabel(), tight, box)
    top = max(p.bbox.y1 for p in panels)
    assert fig._suptitle.get_window_extent(r).y0 >= top - 0.5


def test_overview_of_a_flanged_bearing_from_the_figure_variables(captured, tmp_path):
    """A run's overview is drawn from the variables the streamed record keeps for it
    (results/streamed_record.FIGURE_VARIABLES): with flanges and a dynamic ring, the same
    figure as from the whole result, the ring's motion and spectrum (its frequency labels
    above the axes) in a third row, the flange forces and their friction power in a fourth."""
    from bearingdae.results.streamed_record import FIGURE_VARIABLES

    scene = load_scene("yang20_baseline", {
        "bearing.type": "NJ", "operating.axial_load_N": 200.0, "physics.ring": "dynamic",
        "numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 0.04,
        "numerics.samples_per_cage_revolution": 1000})
    ds = simulate(scene, progress=False)
    # as results/streamed_record.py keeps them: these series and the values without time
    kept = ds[[n for n, v in ds.data_vars.items()
               if n in FIGURE_VARIABLES or "time" not in v.dims]]
    plotting.overview(ds, tmp_path / "whole.png")
    plotting.overview(kept, tmp_path / "kept.png")
    whole, part = captured
    titles = [[ax.get_title() for ax in got["axes"]] for got in (whole, part)]
    assert titles[0] == titles[1]
    assert "friction power of the end-flange contacts" in titles[1]
    assert any(t.startswith("ring displacement spectrum") for t in titles[1])
    assert any(getattr(ax, "_bearingdae_above_pt", 0.0) > 0 for ax in part["axes"])
    _within_panels(part["fig"])


def _sweep(n_orbit: int = 360, completed: bool = True) -> xr.Dataset:
    """A one-axis sweep file as sweep/assemble.py writes it (two speeds, one-orbit curves)."""
    rng = np.random.default_rng(5)
    az = np.arange(n_orbit) * (360.0 / max(1, n_orbit))
    sp = ("speed_rpm",)
    data = {"status": (sp, np.array(["completed" if completed else "failed"] * 2)),
            "mean_cage_speed_rad_s": (sp, [95.0, 280.0])}
    if n_orbit:
        shapes = {"skew_angle": (), "spin_speed": (), "orbit_speed": (), "cage_force": ("end",),
                  "contact_force": ("slice", "race"), "slip_velocity": ("slice", "race"),
                  "traction_force": ("slice", "race")}
        sizes = {"end": 2, "slice": 3, "race": 2}
        for name, dims in shapes.items():
            shape = (2, n_orbit) + tuple(sizes[d] for d in dims)
            data[name] = (sp + ("azimuth",) + dims, 1e-3 * rng.standard_normal(shape))
    coords = {"speed_rpm": ("speed_rpm", [2000.0, 6000.0],
                            {"units": "min-1", "display_units": "r/min"}),
              "slice": [1, 2, 3], "race": ["inner", "outer"], "end": ["a", "b"]}
    if n_orbit:
        coords["azimuth"] = ("azimuth", az, {"units": "degree"})
    axes = [{"key": "operating.speed_rpm", "dim": "speed_rpm", "values": [2000.0, 6000.0]}]
    return xr.Dataset(data, coords=coords, attrs={
        "title": "bearingdae sweep: synthetic", "sweep_axes": json.dumps(axes),
        "figures": "[18, 19, 20]"})


def test_a_selected_sweep_point_is_named_and_skew_is_in_mrad(captured, tmp_path):
    one = _sweep().sel(speed_rpm=6000.0)
    plotting.figure(one, 14, tmp_path / "f14.png")
    (got,) = captured
    assert "selected: speed_rpm = 6000 r/min" in got["suptitle"].get_text()
    assert got["axes"][0].get_ylabel() == f"skew angle θz [{SKEW_UNIT}]"
    assert _fits(got["suptitle"], got["fig"])


def test_slice_figures_key_the_slices_and_overlays_every_run(captured, tmp_path):
    ds = _sweep()
    plotting.figure(ds.sel(speed_rpm=2000.0), 12, tmp_path / "f12.png")
    plotting.figure(ds, 19, tmp_path / "f19.png")
    f12, f19 = captured
    assert any(ax.get_ylabel().startswith("slice (1: end b") for ax in f12["axes"])
    (legend,) = f19["legends"]  # beside the figure, one entry per run
    assert [t.get_text() for t in legend.get_texts()] == ["2000 r/min", "6000 r/min"]
    labels = [ax.get_ylabel() for ax in f19["axes"]]
    assert labels[0].startswith("(a) pocket force, end a (x = +L/2) [N]")
    assert all("+: cage pushes roller forward" in lb for lb in labels)
    for ax in f19["axes"]:
        assert _outside(legend, ax, f19["fig"])


def test_skip_messages_give_the_real_reason(tmp_path):
    short = _sweep(n_orbit=0)
    with pytest.raises(ValueError, match="runs are shorter than one orbit of a roller"):
        plotting.figure(short, 12, tmp_path / "x.png")
    with pytest.raises(ValueError, match="runs are shorter than one orbit of a roller"):
        plotting.figure(short, 18, tmp_path / "x.png")
    with pytest.raises(ValueError, match="none of its runs completed"):
        plotting.figure(_sweep(n_orbit=0, completed=False), 18, tmp_path / "x.png")
    with pytest.raises(ValueError, match=r"--select speed_rpm = 6000 r/min left one run"):
        plotting.figure(_sweep().sel(speed_rpm=6000.0), 18, tmp_path / "x.png")
    from bearingdae import solve_static

    static = solve_static(load_scene("yang20_baseline"))
    with pytest.raises(ValueError, match="quasi-static solution"):
        plotting.figure(static, 12, tmp_path / "x.png")
    assert not list(tmp_path.iterdir())
