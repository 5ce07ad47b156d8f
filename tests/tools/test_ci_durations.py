"""README's "Duration" is generated from the measured `.ci/run` logs
(benchmarks/results/ci-durations.json, tools/ci_durations.py), not typed: the paragraph is the
tool's rendering of that file, and the tool reads a log as `.ci/run` prints it."""

from __future__ import annotations

from pathlib import Path

from conftest import load_tool

ROOT = Path(__file__).resolve().parents[2]


def tool():
    return load_tool("ci_durations")


def test_the_readme_paragraph_is_the_files():
    t = tool()
    readme = (ROOT / "README.md").read_text()
    start, end = t.readme_bullet(readme)
    assert readme[start:end] == t.paragraph(t.load()), \
        "README's Duration differs: python tools/ci_durations.py readme --write"


def test_every_run_kept_adds_up():
    """Each run's steps fit in its total, each tier's pytest in its step, and the test counts
    do not fall from run to run of the same day (tests leave no tier)."""
    runs = tool().load()
    assert len(runs) >= 4
    for r in runs:
        assert None not in r.values(), r
        assert r["fast_tier_s"] + r["docs_install_s"] + r["slow_tier_s"] + r["site_after_s"] \
            <= r["total_s"], r
        assert r["fast_pytest_s"] <= r["fast_tier_s"] and r["slow_pytest_s"] <= r["slow_tier_s"]
        assert r["fast_failed"] == r["slow_failed"] == 0
    for a, b in zip(runs, runs[1:]):
        if a["date"] == b["date"]:
            assert b["fast_tests"] + b["slow_tests"] >= a["fast_tests"] + a["slow_tests"]


LOG = """\
.ci/run: main abc1234 on Some CPU (AVX-512), 2 CPUs, 2026-12-02
.ci/run: libudunits2-0 present
+ pip install ".[test]" && python -m pytest -q -m "not slow" -n auto --dist loadscope
1900 passed, 3 skipped, 160 warnings in 250.50s (0:04:10)
.ci/run: fast tier (install included) took 262 s
.ci/run: docs install took 8 s
320 passed, 2 skipped, 1 xfailed, 43 warnings in 700.26s (0:11:40)
.ci/run: slow tier, physics and documentation (the site build beside it) took 701 s
.ci/run: site build, what it needed after the slow tier took 3 s
.ci/run: all took 1001 s
"""


def test_a_log_as_ci_prints_it():
    run = tool().parse(LOG)
    assert run == {"commit": "abc1234", "cpu": "Some CPU (AVX-512), 2 CPUs",
                   "date": "2026-12-02", "fast_tier_s": 262, "docs_install_s": 8,
                   "slow_tier_s": 701, "site_after_s": 3, "total_s": 1001,
                   "fast_pytest_s": 250, "fast_tests": 1903, "fast_failed": 0,
                   "slow_pytest_s": 700, "slow_tests": 323, "slow_failed": 0}
    failed = tool().parse(LOG.replace("1900 passed, 3 skipped", "1898 passed, 2 failed, 3 skipped"))
    assert failed["fast_failed"] == 2 and failed["fast_tests"] == 1903
