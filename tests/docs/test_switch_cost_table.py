"""The friction and thermal switches' cost rows of docs/performance.md are what
benchmarks/results/switches-friction.json measured: the median CPU ratio, its range over the
repeats, the steps and the residual calls (a number in the docs is generated or tested)."""

from __future__ import annotations

import json
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "performance.md"
RESULTS = ROOT / "benchmarks" / "results" / "switches-friction.json"

#: the table's row label -> the benchmark's switch (its --try)
ROWS = {
    "rolling resistance, Biboulet & Houpert ¹": "physics.rolling_resistance=biboulet_houpert",
    "mixed lubrication ¹": "physics.lubrication=mixed",
    "rolling resistance (B&H) + mixed ¹":
        "physics.rolling_resistance=biboulet_houpert,physics.lubrication=mixed",
    "steady thermal model ¹": "physics.thermal=steady",
    "full friction model ¹": "physics.friction_model=full",
}


def _number(text: str) -> float:
    return float(text.replace(" ", "").replace("\u202f", ""))


def test_each_switch_row_is_the_benchmark_result():
    data = json.loads(RESULTS.read_text())
    rows, default = data["rows"], data["rows"]["default"]
    table = {}
    for line in PAGE.read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells and cells[0] in ROWS:
            table[cells[0]] = cells
    assert set(table) == set(ROWS), set(ROWS) - set(table)
    for label, key in ROWS.items():
        cells = table[label]
        m = re.fullmatch(r"([\d.]+) \(([\d.]+)–([\d.]+)\)", cells[2])
        assert m, cells[2]
        per_repeat = [a["cpu_s"] / b["cpu_s"] for a, b in zip(rows[key], default)]
        # two printed decimals: within half a unit of the last digit
        assert abs(float(m.group(1)) - data["cpu_ratio_to_default"][key]) <= 0.005 + 1e-9
        assert abs(float(m.group(2)) - min(per_repeat)) <= 0.005 + 1e-9
        assert abs(float(m.group(3)) - max(per_repeat)) <= 0.005 + 1e-9
        assert _number(cells[3]) == rows[key][0]["steps"]
        assert _number(cells[4]) == rows[key][0]["residual_calls"]
