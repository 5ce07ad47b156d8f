"""The first-run time has one source: the cold-start benchmark's output,
benchmarks/results/cold-start.json (``python benchmarks/run.py cold-start --write``). The
compile notice's constant (bearingdae/run/progress.py ``COLD_START_RATIO``) is its
cold/warm ratio, and every page that speaks of the first run quotes that ratio and no other
first-run figure than the file's, so the pages cannot drift apart again (they once said
"about 10 s", "14-20 s", "~15 s" and "33-41 s of CPU" at the same time)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from bearingdae.run import progress

ROOT = Path(__file__).resolve().parents[2]
FIGURE = ROOT / "benchmarks" / "results" / "cold-start.json"
#: the pages that tell a user about the first run
PAGES = ("README.md", "docs/index.md", "docs/user-guide.md", "docs/performance.md")
#: a paragraph about the first run (its compile)
FIRST_RUN = re.compile(r"first (?:`bearingdae run`|run\b)|cold start", re.I)
RATIO = re.compile(r"(\d+(?:\.\d+)?)\s*[×x](?![\w])")
PAIR = re.compile(r"(\d+(?:\.\d+)?) → (\d+(?:\.\d+)?)")  # before → now, compile CPU [s]
SECONDS = re.compile(r"(\d+(?:\.\d+)?)(?:\s*[–-]\s*(\d+(?:\.\d+)?))?\s*(?:s|seconds?|min)\b")


def figure() -> dict:
    return json.loads(FIGURE.read_text())


def paragraphs(page: str):
    """The paragraphs of ``page`` about the first run; a table's rows count one by one."""
    units = []
    for p in re.split(r"\n\s*\n", (ROOT / page).read_text()):
        table = all(line.startswith("|") for line in p.strip().splitlines())
        units += p.strip().splitlines() if table else [p]
    return [u for u in units if FIRST_RUN.search(u)]


def test_the_notice_quotes_the_benchmark(monkeypatch):
    fig = figure()
    assert progress.COLD_START_RATIO == fig["cold_over_warm"]
    monkeypatch.setattr(progress, "kernels_cold", lambda: True)
    assert f"~{fig['cold_over_warm']:g}x the time of a later run" in progress.compile_notice()


@pytest.mark.parametrize("page", PAGES)
def test_each_page_quotes_the_one_figure(page):
    fig = figure()
    ratio = f"{fig['cold_over_warm']:g}×"
    paras = paragraphs(page)
    assert any(ratio in p for p in paras), f"{page}: no paragraph on the first run quotes {ratio}"
    allowed_s = {float(v) for k, v in fig.items() if k.endswith("_s") and not isinstance(v, dict)}
    allowed_s |= {float(v) for c in fig.get("compared", {}).values() for v in c.values()}
    allowed_s |= {float(cpu) for steps in fig.get("compile_cpu_s", {}).values()
                  for cpu, _ in steps.values()}
    allowed_s |= {round(sum(cpu for cpu, _ in steps.values()), 1)
                  for steps in fig.get("compile_cpu_s", {}).values()}
    allowed_x = {fig["cold_over_warm"]} | {c["cold_over_warm"]
                                           for c in fig.get("compared", {}).values()}
    for p in paras:
        for m in RATIO.finditer(p):
            assert float(m.group(1)) in allowed_x, (page, m.group(0), p[:300])
        for m in PAIR.finditer(p):
            assert {float(m.group(1)), float(m.group(2))} <= allowed_s, (page, m.group(0))
        for m in SECONDS.finditer(p):
            for v in filter(None, m.groups()):
                assert float(v) in allowed_s, (page, m.group(0), p[:300])
