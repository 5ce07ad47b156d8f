"""The paper set (bearingdae/studies/paper.py, ``bearingdae paper``): every run of its sweeps
completes at the defaults (slow).

The Fig 11 sweep (harris36, each point run until steady) is run and checked for completion by
tests/validation/test_paper_trends.py, whose claims read it; here run_paper runs the other four
(Figs 12-24 and conclusions (1)-(3), yang20) as ``bearingdae paper`` does. Two modules, so
that the two test workers compute the two halves of the set at once; each run once per
session, as before.
"""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.slow

#: the sweep tests/validation/test_paper_trends.py runs and checks (its FIG11)
FIG11 = "harris36_cage_speed"


def test_every_run_of_the_paper_set_completes_at_the_defaults(tmp_path, monkeypatch):
    from bearingdae.studies import paper

    assert FIG11 in paper.PAPER_SWEEPS  # run and checked in test_paper_trends.py
    rest = tuple(name for name in paper.PAPER_SWEEPS if name != FIG11)
    assert len(rest) == len(paper.PAPER_SWEEPS) - 1 >= 4
    monkeypatch.setattr(paper, "PAPER_SWEEPS", rest)
    # in this process: the test runner's workers already keep the cores busy
    res = paper.run_paper(tmp_path, scheduler="synchronous", progress=False, figures=False)
    assert list(res) == list(rest)
    for name, ds in res.items():
        assert (ds.status == "completed").all(), (name, ds.error.values)
        assert (tmp_path / f"{name}.nc").is_file()
