"""The envelope panel marks the defect frequencies (plots/defect_markers.py): the measured
ones where the file has them, each with its harmonics, and the sidebands BPFI ± fs and
2×BSF ± FTF, every group named once in the legend."""

from __future__ import annotations

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
