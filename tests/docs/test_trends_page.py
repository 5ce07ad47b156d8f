"""docs/validation.md's trend tables and error-bar checks are generated from the committed
trends (docs/data/paper_trends*.csv, written by ``bearingdae paper --trends`` and copied by
tools/paper_trends_docs.py): the page includes the generated files, and they are what the CSVs
give today. Also the table's contract: columns, a positive error and >= 20 blocks on every row,
every claim under at least three readings, verdicts that follow from the table."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

from bearingdae.studies.trends import CLAIMS, verdict
from bearingdae.studies.trends_report import DOCS_STEMS, docs_pages

DOCS = Path(__file__).resolve().parents[2] / "docs"
DATA = DOCS / "data"


@pytest.mark.parametrize("stem", DOCS_STEMS)
def test_committed_table_contract(stem):
    table = pd.read_csv(DATA / f"{stem}.csv")
    assert list(table.columns) == ["claim", "reading", "sweep_variable", "sweep_value", "value",
                                   "stderr", "n_blocks", "units"]
    assert (table.stderr > 0).all(), table[~(table.stderr > 0)]
    assert (table.n_blocks >= 20).all(), table[table.n_blocks < 20]
    verdicts = pd.read_csv(DATA / f"{stem}_verdicts.csv")
    assert set(verdicts.claim) == set(CLAIMS)
    assert (verdicts.groupby("claim").reading.nunique() >= 3).all()
    for v in verdicts.itertuples():
        rows = table[(table.claim == v.claim) & (table.reading == v.reading)]
        rows = rows.sort_values("sweep_value")
        assert verdict(rows.value, rows.stderr, v.direction)[0] == v.verdict, v


def test_page_is_generated_from_the_csv():
    for name, text in docs_pages(DATA).items():
        committed = (DATA / name).read_text(encoding="utf-8")
        assert committed == text, (f"docs/data/{name} is not what the committed CSVs give: "
                                   "run tools/paper_trends_docs.py")
    page = (DOCS / "validation.md").read_text(encoding="utf-8")
    for name in docs_pages(DATA):
        assert f"```{{include}} data/{name}" in page, name


def test_page_states_the_window_and_blocks_the_code_uses():
    """The numbers of the method paragraph are the code's constants."""
    from bearingdae.analysis.trends import BLOCK_CAGE_REVOLUTIONS, LOADED_ZONE_DEG
    from bearingdae.studies.trends import TREND_WINDOW

    page = " ".join((DOCS / "validation.md").read_text(encoding="utf-8").split())
    warmup = TREND_WINDOW["numerics.warmup_cage_revolutions"]
    recorded = TREND_WINDOW["numerics.cage_revolutions"]
    assert f"{warmup:g} warm-up + {recorded:g} recorded cage revolutions" in page
    assert f"{recorded / BLOCK_CAGE_REVOLUTIONS:.0f} blocks of half a cage revolution" in page
    assert BLOCK_CAGE_REVOLUTIONS == 0.5
    assert f"sampled {TREND_WINDOW['numerics.samples_per_cage_revolution']} times" in page
    assert f"±{LOADED_ZONE_DEG:g}° of the radial-load line" in page
