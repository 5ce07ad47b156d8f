"""The test session's own sharing: runs computed once (tests/shared_runs.py) and the slow
tier's longest units first (tests/conftest.py LONG_FIRST)."""

from __future__ import annotations

from pathlib import Path

import kernel_warmup
import shared_runs
from conftest import LONG_FIRST, make_scene

ROOT = Path(__file__).resolve().parents[1]


def test_long_first_names_slow_modules_that_exist():
    """A renamed module would silently fall back to xdist's order: each entry is a file with
    slow tests, listed once."""
    assert len(set(LONG_FIRST)) == len(LONG_FIRST)
    for module in LONG_FIRST:
        text = (ROOT / module).read_text()
        assert "mark.slow" in text, module


def test_a_shared_run_is_computed_once_and_read_back_whole(tmp_path, monkeypatch):
    """The second call with the same scene reads the first one's file: no second run, the
    same Dataset (values and attributes); another scene is a run of its own."""
    calls = []
    real = shared_runs._simulate

    def counted(scene, solver):
        calls.append(scene.title)
        return real(scene, solver)

    monkeypatch.setattr(shared_runs, "_simulate", counted)
    tiny = {"numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 0.01,
            "numerics.samples_per_cage_revolution": 400}
    scene = make_scene(tiny)
    first = shared_runs.shared_simulate(scene, tmp_path)
    again = shared_runs.shared_simulate(make_scene(tiny), tmp_path)
    assert len(calls) == 1
    assert again.identical(first)
    shared_runs.shared_simulate(make_scene({**tiny, "operating.radial_load_N": 900.0}),
                                tmp_path)
    assert len(calls) == 2
    assert len(list(tmp_path.glob("*.pickle"))) == 2


def test_every_warm_up_scene_starts():
    """Each switch pattern's warm-up scene (tests/kernel_warmup.PATTERNS) has a consistent
    start (its quasi-static state converges), so the warm-up compiles its integration's
    kernels; a warm-up that failed there compiled nothing for its tests. The patterns are
    warm by the time this runs in a session (it loads their kernels)."""
    from bearingdae.solvers.algebraic import initial_state
    from bearingdae.system.model import build_model

    for tag in kernel_warmup.PATTERNS:
        y0, _yp0 = initial_state(build_model(kernel_warmup.pattern_scene(tag)))
        assert y0.size and (y0 == y0).all(), tag
