"""The trends Yang et al. (2024) claim, checked against our sweep summaries (slow).

Reference for every test: the paper's text (section 2.5 for Fig 11, sections 4.1-4.2 for
Figs 18-24, conclusions (1)-(3)), quoted in the test id/docstring. Summaries are those of
bearingdae.results.analysis over each run's recorded window (windows: cases/paper/*.toml).

Runs the whole paper set once per session (about 5 min on two idle cores); set
BEARINGDAE_PAPER_DIR to the output folder of an earlier `bearingdae paper -o DIR` to reuse its
runs (they are resumed by hash, so only missing runs are computed).

Trend criterion, fixed before looking at the results: over the sweep axis the quantity moves
in the claimed direction by at least 10 % of its largest magnitude from the first to the last
point, and at most one step between neighbouring points goes against the claim.
Where our model does not reproduce a claim, the test is an xfail(strict=True) whose reason
says what we see (docs/validation.md discusses each); if a model change makes the claim hold,
the strict xfail fails and the docs must be updated. Two weak effects are inconclusive (their
verdict changed with solver details); their tests assert only that no strong trend appears.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

pytestmark = pytest.mark.slow

#: min relative change first -> last (of max |value|) for a trend to count
MIN_CHANGE = 0.10


@pytest.fixture(scope="session")
def paper(tmp_path_factory):
    from bearingdae.studies.paper import run_paper

    out = Path(os.environ.get("BEARINGDAE_PAPER_DIR") or tmp_path_factory.mktemp("paper"))
    res = run_paper(out, progress=False, figures=False)
    for name, ds in res.items():
        assert (ds.status == "completed").all(), (name, ds.error.values)
    return res


def trend(values, direction: int) -> tuple[bool, str]:
    """(holds, description) of the claimed trend (+1 rises, -1 falls) over the axis."""
    v = np.asarray(values, float)
    scale = np.abs(v).max()
    change = (v[-1] - v[0]) / scale if scale > 0 else 0.0
    against = int((direction * np.diff(v) < 0).sum())
    ok = direction * change >= MIN_CHANGE and against <= 1
    claim = "rises" if direction > 0 else "falls"
    return ok, (f"claimed: {claim}; values {np.array2string(v, precision=4)}; first -> last "
                f"{change:+.1%} of max, {against} step(s) against the claim")


def check(ds, name: str, direction: int) -> None:
    ok, text = trend(ds[name].values, direction)
    assert ok, f"{name}: {text}"


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
# Conclusions (1)-(3) and Figs 18-24
# ------------------------------------------------------------------------------------------
#: (test id naming the paper's claim, sweep, summary, claimed direction)
CLAIMS = [
    # Conclusion (1), section 4.1, Figs 18-20: speed 2000 -> 14 000 r/min
    ("conclusion1-fig20-sliding-speed-rises-with-speed(max)",
     "yang20_speed_sweep", "max_abs_slip_m_s", +1),
    ("conclusion1-sliding-speed-rises-with-speed(load-weighted)",
     "yang20_speed_sweep", "load_weighted_slip_m_s", +1),
    ("conclusion1-fig18-skew-rises-with-speed",
     "yang20_speed_sweep", "skew_amplitude_rad", +1),
    ("conclusion1-fig19-cage-force-rises-with-speed(peak)",
     "yang20_speed_sweep", "peak_cage_force_N", +1),
    ("conclusion1-fig19-cage-force-rises-with-speed(rms)",
     "yang20_speed_sweep", "rms_cage_force_N", +1),
    ("conclusion1-fig20-slice-slip-difference-rises-with-speed",
     "yang20_speed_sweep", "slice_slip_spread_m_s", +1),
    ("conclusion1-slice-traction-difference-rises-with-speed",
     "yang20_speed_sweep", "slice_traction_spread_N", +1),
    # Conclusion (2): radial load 200 -> 1600 N
    ("conclusion2-sliding-speed-falls-with-load(max)",
     "yang20_radial_load_sweep", "max_abs_slip_m_s", -1),
    ("conclusion2-sliding-speed-falls-with-load(load-weighted)",
     "yang20_radial_load_sweep", "load_weighted_slip_m_s", -1),
    ("conclusion2-skew-falls-with-load",
     "yang20_radial_load_sweep", "skew_amplitude_rad", -1),
    ("conclusion2-cage-force-falls-with-load(peak)",
     "yang20_radial_load_sweep", "peak_cage_force_N", -1),
    ("conclusion2-cage-force-falls-with-load(rms)",
     "yang20_radial_load_sweep", "rms_cage_force_N", -1),
    ("conclusion2-slice-slip-difference-falls-with-load",
     "yang20_radial_load_sweep", "slice_slip_spread_m_s", -1),
    ("conclusion2-slice-traction-difference-falls-with-load",
     "yang20_radial_load_sweep", "slice_traction_spread_N", -1),
    # Conclusion (3), section 4.2, Figs 21-24: moment 0 -> 10 N·m
    ("fig21-roller-speeds-rise-with-moment(cage-slip-falls)",
     "yang20_moment_sweep", "cage_slip_ratio", -1),
    ("conclusion3-fig24-sliding-speed-falls-with-moment(max)",
     "yang20_moment_sweep", "max_abs_slip_m_s", -1),
    ("conclusion3-fig24-sliding-speed-falls-with-moment(load-weighted)",
     "yang20_moment_sweep", "load_weighted_slip_m_s", -1),
    ("conclusion3-fig22-skew-rises-with-moment",
     "yang20_moment_sweep", "skew_amplitude_rad", +1),
    ("conclusion3-fig24-slice-slip-difference-rises-with-moment",
     "yang20_moment_sweep", "slice_slip_spread_m_s", +1),
    ("conclusion3-slice-traction-difference-rises-with-moment",
     "yang20_moment_sweep", "slice_traction_spread_N", +1),
    # The paper contradicts itself on the cage force against moment: Fig 23's text says it
    # grows, conclusion (3) says it falls. Both claims are tested; our runs decide.
    ("fig23-text-cage-force-rises-with-moment(peak)",
     "yang20_moment_sweep", "peak_cage_force_N", +1),
    ("conclusion3-cage-force-falls-with-moment(peak)",
     "yang20_moment_sweep", "peak_cage_force_N", -1),
    ("fig23-text-cage-force-rises-with-moment(rms)",
     "yang20_moment_sweep", "rms_cage_force_N", +1),
    ("conclusion3-cage-force-falls-with-moment(rms)",
     "yang20_moment_sweep", "rms_cage_force_N", -1),
]

#: Claims our model does not reproduce (docs/validation.md): id -> what we see instead.
#: Each verdict was the same with the finite-difference and the analytic Jacobian and with a
#: longer window (2 warm-up + 3 recorded revolutions).
DISAGREEMENTS = {
    "conclusion1-fig18-skew-rises-with-speed":
        "skew amplitude about 2.3, 1.6, 1.2, 1.6 mrad at 2000-14 000 r/min: the free skew "
        "oscillation in the unloaded zone is largest at 2000 r/min",
    "conclusion2-sliding-speed-falls-with-load(max)":
        "max slip rises about 0.14 -> 0.20 m/s from 200 to 1600 N (it is set in the "
        "unloaded zone; the load-weighted slip falls)",
    "conclusion2-cage-force-falls-with-load(peak)":
        "peak pocket force rises about 4.7 -> 9 N from 200 to 1600 N",
    "conclusion2-cage-force-falls-with-load(rms)":
        "rms pocket force rises about 0.23 -> 0.28 N from 200 to 1600 N",
    "conclusion2-slice-slip-difference-falls-with-load":
        "slice slip spread rises about 0.09 -> 0.18 m/s from 200 to 1600 N",
    "conclusion2-slice-traction-difference-falls-with-load":
        "slice traction spread is lowest at 400-800 N and rises again towards 1600 N",
    "fig23-text-cage-force-rises-with-moment(peak)":
        "peak pocket force about 6, 7, 5, 6 N at 0-10 N·m: no trend either way",
    "conclusion3-cage-force-falls-with-moment(peak)":
        "peak pocket force about 6, 7, 5, 6 N at 0-10 N·m: no trend either way",
    "fig23-text-cage-force-rises-with-moment(rms)":
        "rms pocket force falls about 0.30 -> 0.23 N from 0 to 10 N·m: conclusion (3) "
        "holds, Fig 23's text does not",
}

#: (The slice slip difference against moment was listed here with +33 %, +39 %, +8 % at the
#: former pocket smoothing 0.1 µm; at the corrected 0.01 µm it rises +53 %, 0.042 -> 0.107 m/s
#: from 0 to 3 N·m and flat beyond, and is tested as a claim again: docs/validation.md.)
#: Claims whose verdict flipped between those three variants (weak effects within the
#: numerical sensitivity of the pocket impacts): the test asserts what is robust -- no strong
#: trend either way (|first -> last| < WEAK of max) -- and the docs report them inconclusive.
INCONCLUSIVE = {
    "conclusion3-fig24-sliding-speed-falls-with-moment(max)":
        "max slip changes by -9 %, +3 %, -15 % (FD, long window, analytic Jacobian)",
}
WEAK = 0.40


def _params():
    for tid, sweep, name, direction in CLAIMS:
        marks = ()
        if tid in DISAGREEMENTS:
            marks = pytest.mark.xfail(strict=True, reason="documented disagreement: "
                                      + DISAGREEMENTS[tid])
        yield pytest.param(sweep, name, direction, tid, id=tid, marks=marks)


@pytest.mark.parametrize("sweep, name, direction, tid", list(_params()))
def test_paper_trend(paper, sweep, name, direction, tid):
    """The claim in the test id, from the paper's conclusions (1)-(3) / Figs 18-24; for an
    inconclusive claim, that our model shows no strong trend either way."""
    if tid in INCONCLUSIVE:
        v = paper[sweep][name].values
        change = (v[-1] - v[0]) / np.abs(v).max()
        assert abs(change) < WEAK, f"{name}: {v}: a strong trend now ({change:+.0%}); " \
            "decide the claim and update docs/validation.md"
        return
    check(paper[sweep], name, direction)
