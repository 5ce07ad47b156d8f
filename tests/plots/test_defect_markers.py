"""The envelope panel marks the defect frequencies (plots/defect_markers.py): the measured
ones where the file has them, each with its harmonics, and the sidebands BPFI ± fs and
2×BSF ± FTF, every group named once in the legend."""

from __future__ import annotations

import numpy as np

from bearingdae.analysis.defect_frequencies import variable_name
from bearingdae.plots.plot_spectrum import draw_spectrum
from tests.analysis.test_spectrum_peaks import BAND, BPFO, synthetic

MEASURED = {"bpfo": 75.4, "bpfi": 91.2, "bsf": 46.3, "2bsf": 92.6, "ftf": 3.77}


def test_the_envelope_panel_marks_measured_orders_with_a_legend():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ds = synthetic(BPFO).assign({variable_name(k): v for k, v in MEASURED.items()})
    fig, ax = plt.subplots(layout="constrained")
    try:
        draw_spectrum(ax, ds, "ring_acceleration", fmax=200.0, envelope=True, band_Hz=BAND)
        lines = {round(float(line.get_xdata()[0]), 6) for line in ax.lines
                 if line.get_linestyle() in ("--", ":", "-.")}
        for f in (75.4, 2 * 75.4, 91.2 - 8.3333, 91.2 + 8.3333, 92.6 - 3.77, 92.6 + 3.77,
                  46.3, 3.77, 8.3333):
            assert round(f, 6) in lines, f
        assert round(BPFO, 6) not in lines  # the pure-rolling value is not drawn
        texts = [t.get_text() for t in ax.get_legend().get_texts()]
        assert texts[:2] == ["radial", "tangential"]
        assert "BPFO 75.4 Hz and harmonics" in texts
        assert "BPFI ± fs (8.333 Hz) sidebands" in texts
        assert "2×BSF ± FTF (3.77 Hz) sidebands" in texts
        assert len(texts) == len(set(texts)) == 2 + 8  # each group once
        assert "defect frequencies measured" in ax.get_title()
    finally:
        plt.close(fig)


def test_a_file_without_frequencies_draws_its_envelope_without_markers_or_warnings():
    import warnings

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ds = synthetic(BPFO).drop_vars(["characteristic_frequencies_Hz", "frequency_name"])
    ds = ds.isel(direction=0, drop=True)  # one channel: no direction legend either
    fig, ax = plt.subplots(layout="constrained")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            draw_spectrum(ax, ds, "ring_acceleration", fmax=200.0, envelope=True,
                          band_Hz=BAND)
        assert ax.get_legend() is None and "defect frequencies" not in ax.get_title()
    finally:
        plt.close(fig)


def test_the_spectrum_panels_mark_the_same_measured_frequencies_under_a_title_that_fits(
        monkeypatch, tmp_path):
    """The upper panels' labelled markers are the envelope panel's measured frequencies (BPFO
    75.4 Hz, FTF 3.77 Hz), not pure rolling (75.93 Hz), and say so; the title of a record
    compensated for its low-pass filter, sampled at the default rate (30370 Hz, long numbers
    in the title), stays inside the figure."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from bearingdae.plots import plot_spectrum

    figures = []
    monkeypatch.setattr(plot_spectrum, "save_figure", lambda fig, path: figures.append(fig))
    rate_Hz = 30370.0
    ds = synthetic(BPFO).assign({variable_name(k): v for k, v in MEASURED.items()})
    ds = ds.assign_coords(time=np.arange(ds.sizes["time"]) / rate_Hz)
    ds["ring_acceleration"].attrs.update(sample_interval_s=1 / rate_Hz,
                                         filter_transfer_function="sinc^2(f T)")
    try:
        plot_spectrum.spectrum_figure(ds, tmp_path / "s.png", fmax=200.0, envelope=True,
                                      band_Hz=BAND)
        fig = figures[0]
        upper = fig.axes[0]
        lines = {round(float(line.get_xdata()[0]), 6) for line in upper.lines
                 if line.get_linestyle() in ("--", ":")}
        assert {75.4, 2 * 75.4, 91.2, 46.3, 3.77, 8.3333} <= lines
        assert round(BPFO, 6) not in lines
        labels = [t.get_text() for t in upper.texts]
        assert "roller pass, outer 75.4 Hz" in labels and "cage (FTF) 3.77 Hz" in labels
        assert "characteristic frequencies measured" in upper.get_title()
        fig.canvas.draw()
        width = fig.get_figwidth() * fig.dpi
        for ax in fig.axes:
            box = ax.title.get_window_extent(fig.canvas.get_renderer())
            assert box.x0 >= 0 and box.x1 <= width, ax.get_title()
    finally:
        plt.close("all")
