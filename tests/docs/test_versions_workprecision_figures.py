"""docs/performance.md, "At equal error": the ratios it quotes are those of the benchmark's
output (benchmarks/results/versions-workprecision-926583b.json, written by ``python
benchmarks/run.py versions --old 926583b --workprecision --json ...``), and that output says
what the paragraph claims of it: at each rtol the two trees' errors lie within the factor it
states, the new tree is cheaper at equal error, and it makes the residual calls it quotes."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
RESULT = ROOT / "benchmarks" / "results" / "versions-workprecision-926583b.json"


def paragraph() -> str:
    text = (ROOT / "docs" / "performance.md").read_text()
    start = text.index("**At equal error** (`versions --old 926583b")
    return " ".join(text[start:text.index("![work-precision of this tree", start)].split())


def test_the_page_quotes_the_benchmark():
    got = json.loads(RESULT.read_text())
    p = paragraph()
    old, new = got["table"]["old"], got["table"]["new"]
    i6 = got["rtols"].index(1e-6)
    quoted = [float(v) for v in re.findall(r"(\d\.\d+)×", p)]
    expected = [got["new_over_old_at_default_rtol"]] + [
        got["at_equal_error"][q]["new_over_old"]
        for q in ("cage_speed", "skew_angle", "contact_force")] + [
        new[i6]["residual_calls"] / old[i6]["residual_calls"]]
    assert quoted == [round(v, 3) for v in expected], (quoted, expected)
    calls = re.search(r"\(([\d ]+) against ([\d ]+):", p).groups()
    assert [int(c.replace(" ", "")) for c in calls] == [new[i6]["residual_calls"],
                                                         old[i6]["residual_calls"]]
    loosest, tightest = (f"1e-{round(-math.log10(r))}"
                         for r in (max(got["rtols"]), min(got["rtols"])))
    assert f"rtol {loosest} … {tightest}" in p
    assert f"rtol 1e-{round(-math.log10(got['reference_rtol']))}" in p


def test_the_benchmark_says_what_the_page_claims():
    got = json.loads(RESULT.read_text())
    old, new = got["table"]["old"], got["table"]["new"]
    i6 = got["rtols"].index(1e-6)
    # "at each rtol both reach errors within 7x of each other"
    (within,) = re.search(r"both reach errors within (\d+)× of each other", paragraph()).groups()
    for o, n in zip(old, new):
        for q in o["errors"]:
            assert max(o["errors"][q], n["errors"][q]) <= int(within) * min(o["errors"][q],
                                                                               n["errors"][q])
    for q in ("cage_speed", "skew_angle", "contact_force"):
        assert got["at_equal_error"][q]["kind"] == "interpolated"
        assert got["at_equal_error"][q]["new_over_old"] < 1
    # "parallel from 1e-4 on": the CPU ratio per rung stays within a factor 1.5 of the
    # ratio at 1e-6
    r6 = new[i6]["cpu_s"] / old[i6]["cpu_s"]
    for o, n in zip(old, new):
        if o["rtol"] <= 1e-4:
            assert 1 / 1.5 < (n["cpu_s"] / o["cpu_s"]) / r6 < 1.5
