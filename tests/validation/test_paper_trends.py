"""The trends Yang et al. (2024) claim, checked with error bars (slow).

Reference for every test: the paper's text (section 2.5 for Fig 11, sections 4.1-4.2 for
Figs 18-24, conclusions (1)-(3)), named in the claim.

**Fig 11** runs the paper set's Fig 11 sweep once per session, as `bearingdae paper` does; set
BEARINGDAE_PAPER_DIR to the output folder of an earlier `bearingdae paper -o DIR` to reuse its
runs.

**Conclusions (1)-(3), Figs 18-24**: every claim under several readings (orbit-wide, per roller
pass, loaded zone, load-weighted: bearingdae/analysis/trends.py), each value the mean over 64
half-revolution blocks with its blocking standard error. The table is the committed
docs/data/paper_trends.csv (`bearingdae paper --trends`, 2 + 32 cage revolutions per run,
about 40 min of one shared core); set BEARINGDAE_TRENDS_DIR to the output folder of a fresh
`bearingdae paper --trends -o DIR` to check that instead. Criterion, fixed before the long
runs: a claim **holds** if no two sweep points move against it by more than 2 standard errors
of their difference and the first-to-last change goes with it by more than 2; it is
**contradicted** if some pair moves against it by more than 2; else **not resolved**. The
expected verdict of each claim x reading is below with what it means (docs/validation.md);
a test fails when the data no longer support it at that significance.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

pytestmark = pytest.mark.slow

DATA = Path(__file__).resolve().parents[2] / "docs" / "data"


#: the sweep of the paper set these tests read; the other four sweeps' runs are checked in
#: tests/studies/test_paper.py (every run of the set completes at the defaults), a module of its
#: own so that another test worker computes them while this one computes Fig 11's
FIG11 = "harris36_cage_speed"


@pytest.fixture(scope="session")
def paper(tmp_path_factory):
    """{sweep name: Dataset} of the paper set's Fig 11 sweep, as ``bearingdae paper`` runs it
    (its bundled sweep, at the defaults; BEARINGDAE_PAPER_DIR: the runs of an earlier
    ``bearingdae paper -o DIR``, resumed)."""
    from bearingdae.studies.sweep import load_sweep, run_sweeps

    out = Path(os.environ.get("BEARINGDAE_PAPER_DIR") or tmp_path_factory.mktemp("paper"))
    sweep = load_sweep(f"paper/{FIG11}")
    # in this process: the test runner's workers already keep the cores busy, and a cluster's
    # processes would each load (or, on a cold cache, compile) the kernels again; each run's
    # numbers do not depend on the process that computes it
    (ds,) = run_sweeps([sweep], [out / f"{sweep.name}.nc"], run_dir=out / "runs",
                       scheduler="synchronous", progress=False)
    assert (ds.status == "completed").all(), (sweep.name, ds.error.values)
    return {sweep.name: ds}


# ------------------------------------------------------------------------------------------
# Fig 11 (section 2.5): Harris bearing, 5000 r/min
# ------------------------------------------------------------------------------------------
def test_fig11_cage_speed_rises_with_radial_load(paper):
    """Fig 11: 'with an increase in radial load, there is a corresponding increase in cage
    speed until it reaches its maximum value' -- monotone within 0.05 % of epicyclic."""
    h = paper["harris36_cage_speed"]
    cage, epi = h.mean_cage_speed_rad_s.values, h.epicyclic_cage_speed_rad_s.values
    assert np.all(np.diff(cage) >= -5e-4 * epi[0]), cage
    assert cage[-1] - cage[0] > 0.02 * epi[0]


def test_fig11_cage_speed_saturates_at_or_just_below_epicyclic(paper):
    """Fig 11 / theory.md §13: the steady cage speed saturates at or below n/2 (1 - D_w/d_m):
    from 6000 N on, steady (drift < 0.2 %), 0 <= slip <= 1 %, and flat within 0.3 %."""
    h = paper["harris36_cage_speed"].sel(radial_load_N=slice(6000, None))
    assert np.all(np.abs(h.cage_speed_drift) < 2e-3)
    assert np.all((h.cage_slip_ratio >= 0) & (h.cage_slip_ratio <= 0.01)), h.cage_slip_ratio
    span = float(h.cage_slip_ratio.max() - h.cage_slip_ratio.min())
    assert span < 3e-3


def test_fig11_cage_skids_at_light_load(paper):
    """Fig 11: at light load the cage skids: up to 1000 N its slip exceeds
    2 % and five times the slip at 12 000 N; every point was recorded after the until_steady
    criterion held (bearingdae/run/steady.py), so these are the steady skids, not upper bounds."""
    h = paper["harris36_cage_speed"]
    light = h.sel(radial_load_N=slice(None, 1000))
    heavy = float(h.cage_slip_ratio.sel(radial_load_N=12000))
    assert np.all(light.cage_slip_ratio > 0.02), light.cage_slip_ratio.values
    assert np.all(light.cage_slip_ratio > 5 * heavy)
    assert np.all(h.steady_state_reached == 1), h.steady_state_reached.values


# ------------------------------------------------------------------------------------------
# Conclusions (1)-(3) and Figs 18-24, with error bars
# ------------------------------------------------------------------------------------------
@pytest.fixture(scope="session")
def trends():
    from bearingdae.studies.trends_report import read_trends

    folder = os.environ.get("BEARINGDAE_TRENDS_DIR")
    return read_trends(folder, "trends")[0] if folder else read_trends(DATA, "paper_trends")[0]


def significance(values, stderr, direction: int) -> tuple[float, float]:
    """(z of the first-to-last change along the claim, the most negative z along the claim of
    any pair i < j), typed afresh from the criterion in the module docstring."""
    v, s = np.asarray(values, float), np.asarray(stderr, float)
    z = [[direction * (v[j] - v[i]) / np.sqrt(s[i] ** 2 + s[j] ** 2)
          for j in range(i + 1, len(v))] for i in range(len(v))]
    return z[0][-1], min(min(row) for row in z if row)


#: claim -> (claimed direction, {reading: expected verdict}); what each means for a bearing
#: engineer: docs/validation.md, "Trend claims with error bars"
EXPECTED = {
    "speed: sliding speed rises": (+1, {
        "orbit_max": "holds",
        "pass_peak": "holds",
        "loaded_zone": "holds",
        "load_weighted": "holds",
    }),
    "speed: skew rises": (+1, {
        "orbit_amplitude": "contradicted",
        "pass_peak": "contradicted",
        "loaded_zone": "contradicted",
        "load_weighted": "contradicted",
    }),
    "speed: pocket force rises": (+1, {
        "orbit_peak": "holds",
        "orbit_rms": "holds",
        "pass_peak": "holds",
        "loaded_zone": "holds",
    }),
    "speed: slice slip difference rises": (+1, {
        "orbit_max": "holds",
        "pass_peak": "holds",
        "loaded_zone": "holds",
        "load_weighted": "holds",
    }),
    "speed: slice traction difference rises": (+1, {
        "orbit_max": "holds",
        "pass_peak": "holds",
        "loaded_zone": "holds",
        "load_weighted": "holds",
    }),
    "load: sliding speed falls": (-1, {
        "orbit_max": "contradicted",
        "pass_peak": "contradicted",
        "loaded_zone": "contradicted",
        "load_weighted": "holds",
    }),
    "load: skew falls": (-1, {
        "orbit_amplitude": "contradicted",
        "pass_peak": "contradicted",
        "loaded_zone": "holds",
        "load_weighted": "holds",
    }),
    "load: pocket force falls": (-1, {
        "orbit_peak": "contradicted",
        "orbit_rms": "contradicted",
        "pass_peak": "contradicted",
        "loaded_zone": "contradicted",
    }),
    "load: slice slip difference falls": (-1, {
        "orbit_max": "contradicted",
        "pass_peak": "contradicted",
        "loaded_zone": "contradicted",
        "load_weighted": "contradicted",
    }),
    "load: slice traction difference falls": (-1, {
        "orbit_max": "contradicted",
        "pass_peak": "holds",
        "loaded_zone": "contradicted",
        "load_weighted": "holds",
    }),
    "moment: roller speeds rise (cage slip falls)": (-1, {
        "orbit_mean": "holds",
        "loaded_zone": "contradicted",
        "load_weighted": "contradicted",
    }),
    "moment: sliding speed falls": (-1, {
        "orbit_max": "contradicted",
        "pass_peak": "holds",
        "loaded_zone": "holds",
        "load_weighted": "holds",
    }),
    "moment: skew rises": (+1, {
        "orbit_amplitude": "holds",
        "pass_peak": "contradicted",
        "loaded_zone": "contradicted",
        "load_weighted": "contradicted",
    }),
    "moment: slice slip difference rises": (+1, {
        "orbit_max": "contradicted",
        "pass_peak": "contradicted",
        "loaded_zone": "contradicted",
        "load_weighted": "contradicted",
    }),
    "moment: slice traction difference rises": (+1, {
        "orbit_max": "holds",
        "pass_peak": "contradicted",
        "loaded_zone": "holds",
        "load_weighted": "contradicted",
    }),
    "moment: pocket force rises (Fig 23 text)": (+1, {
        "orbit_peak": "contradicted",
        "orbit_rms": "contradicted",
        "pass_peak": "contradicted",
        "loaded_zone": "contradicted",
    }),
    "moment: pocket force falls (conclusion 3)": (-1, {
        "orbit_peak": "contradicted",
        "orbit_rms": "holds",
        "pass_peak": "contradicted",
        "loaded_zone": "holds",
    }),
}


def _params():
    for claim, (direction, readings) in EXPECTED.items():
        for reading, expected in readings.items():
            yield pytest.param(claim, reading, direction, expected, id=f"{claim}|{reading}")


@pytest.mark.parametrize("claim, reading, direction, expected", list(_params()))
def test_claim_with_error_bars(trends, claim, reading, direction, expected):
    """The verdict of the claim under the reading, at 2 standard errors."""
    rows = trends[(trends.claim == claim) & (trends.reading == reading)]
    rows = rows.sort_values("sweep_value")
    assert len(rows) >= 4 and (rows.stderr > 0).all() and (rows.n_blocks >= 20).all()
    z, worst = significance(rows.value, rows.stderr, direction)
    shown = ", ".join(f"{v:.4g} ± {e:.2g}" for v, e in zip(rows.value, rows.stderr))
    what = f"{claim} / {reading}: {shown} {rows.units.iloc[0]}; z first->last {z:+.1f}, " \
        f"most against {worst:+.1f}"
    if expected == "holds":
        assert worst >= -2 and z > 2, what
    elif expected == "contradicted":
        assert worst < -2, what
    else:
        assert worst >= -2 and z <= 2, what


def test_every_claim_has_three_readings():
    assert all(len(readings) >= 3 for _, readings in EXPECTED.values())


def test_the_repeat_from_another_start_state_gives_the_same_verdicts():
    """docs/data/paper_trends_repeat.csv: the same runs warmed up 34 instead of 2 cage
    revolutions, so that the recorded window follows the reference's without overlap (another
    start state of the chaotic motion, independent of the reference window)."""
    from bearingdae.studies.trends import CLAIMS
    from bearingdae.studies.trends_report import read_trends

    repeat = read_trends(DATA, "paper_trends_repeat")[0]
    differ = []
    for claim, (direction, readings) in EXPECTED.items():
        assert CLAIMS[claim][2] == direction
        for reading, expected in readings.items():
            rows = repeat[(repeat.claim == claim) & (repeat.reading == reading)]
            rows = rows.sort_values("sweep_value")
            z, worst = significance(rows.value, rows.stderr, direction)
            got = ("contradicted" if worst < -2 else "holds" if z > 2 else "not resolved")
            if got != expected:
                differ.append(f"{claim} / {reading}: {got}")
    assert not differ, differ
