"""docs/user-guide.md, "Sharp edges": the tables are the ones studies/workprecision/edges.py
generates from benchmarks/results/defect-edges.json, and each number the paragraph states is
the JSON's (``python benchmarks/run.py workprecision --edges`` regenerates both)."""

from __future__ import annotations

import json
from pathlib import Path

from bearingdae.studies.workprecision.edges import HEADLINES, docs_tables

ROOT = Path(__file__).resolve().parents[2]
DATA = json.loads((ROOT / "benchmarks" / "results" / "defect-edges.json").read_text())
PAGE = (ROOT / "docs" / "user-guide.md").read_text()
LEAST = 0.0025


def _runs():
    return [r for st in DATA["scenes"].values() for r in st["runs"]
            if r.get("status", "ok") == "ok"]


def test_the_tables_are_generated_from_the_results():
    assert docs_tables(DATA) in PAGE


def test_the_stated_numbers_are_the_results():
    text = " ".join(PAGE.split())
    assert f"at least **{LEAST:g} mm**" in text
    spread = 0.0
    for st in DATA["scenes"].values():
        by_rtol: dict = {}
        for r in st["runs"]:
            by_rtol.setdefault(r["rtol"], []).append(r["steps"])
        spread = max(spread, *(max(v) / min(v) - 1.0 for v in by_rtol.values()))
    assert f"by at most {round(100 * spread)} %" in text
    shifts = [r["errors"][k] for r in _runs() if r["edge_mm"] > LEAST for k in HEADLINES]
    assert f"by {100 * min(shifts):.1f} % to {round(100 * max(shifts))} %" in text
    # the least ramp reaches 1 % on every output from rtol 1e-5 on; no longer ramp at any rtol
    for r in _runs():
        within = all(r["errors"][k] <= 0.01 for k in HEADLINES)
        if r["edge_mm"] == LEAST and r["rtol"] <= 1e-5:
            assert within, r
        if r["edge_mm"] > LEAST:
            assert not within, r
    for st in DATA["scenes"].values():
        ref = st["reference"]
        assert f"{ref['sharper']['steps']} steps against {ref['steps']}" in text or (
            f"{ref['sharper']['steps']} against {ref['steps']}" in text)
        for k in HEADLINES:  # halving the least ramp moves every output by < 1 %
            change = ref["sharper"]["errors_of_reference"][k]
            assert change < 0.01 and f"{100 * change:.2f} %" in text



def test_the_outputs_converge_at_first_order_in_the_ramp():
    """The ring acceleration RMS and signal of the 0.05 mm ramp (rtol 1e-7) against the least
    ramp's, over the least ramp's against half of it: the ratio of the ramp differences at
    first order, (0.05 - 0.0025) / (0.0025 - 0.00125) = 38, within 25 %."""
    text = " ".join(PAGE.split())
    ratios = []
    for st in DATA["scenes"].values():
        sharper = st["reference"]["sharper"]
        first_order = (0.05 - LEAST) / (LEAST - sharper["edge_mm"])
        for r in st["runs"]:
            if r["edge_mm"] == 0.05 and r["rtol"] == 1e-7:
                for k in ("ring_acceleration_rms", "ring_acceleration_signal"):
                    ratios.append(r["errors"][k] / sharper["errors_of_reference"][k])
                    assert abs(ratios[-1] / first_order - 1.0) < 0.25, (k, ratios[-1])
    assert len(ratios) == 4
    assert f"are {round(min(ratios))} to {round(max(ratios))} times as far" in text
    assert f"differences ({round(first_order)})" in text


def test_the_defect_costs_on_the_performance_page_are_the_results():
    """docs/performance.md, "A defect": the ratios of benchmarks/results/switches-defects.json,
    switches-roller-spall.json and switches-defects-baseline.json (medians of the per-repeat
    ratios, their ranges, and the medians' ratios)."""
    from statistics import median

    page = " ".join((ROOT / "docs" / "performance.md").read_text().split())
    res = ROOT / "benchmarks" / "results"
    outer, roller, base = (json.loads((res / f"{n}.json").read_text())["rows"] for n in (
        "switches-defects", "switches-roller-spall", "switches-defects-baseline"))
    for rows, bold in ((outer, "1.40×"), (roller, "2.76×")):
        each = [d["cpu_s"] / h["cpu_s"] for d, h in zip(rows["default"],
                                                          rows["no defects or waviness"])]
        assert f"{median(each):.2f}×" == bold
        assert f"**{bold} ({min(each):.2f}–{max(each):.2f}×)" in page
    cpu = {k: median(r["cpu_s"] for r in rows["default"])
           for k, rows in (("outer", outer), ("roller", roller), ("base", base))}
    assert f"**{cpu['roller'] / cpu['outer']:.2f}× the outer spall** ({cpu['roller']:.2f} s "\
           f"against {cpu['outer']:.2f} s)" in page
    assert f"**{cpu['roller'] / cpu['base']:.2f}× the default scene**" in page
    assert f"({roller['no defects or waviness'][-1]['steps']} steps against" in page
    # the other bundled defects against their own (preloaded, nearly steady) scenes, and the
    # roller spall on the baseline's clearance, whose healthy run is dynamic
    for name, bold in (("switches-inner-spall", "3.33×"), ("switches-outer-waviness", "2.31×"),
                       ("switches-roller-spall-clearance", "1.12×")):
        rows = json.loads((res / f"{name}.json").read_text())["rows"]
        each = [d["cpu_s"] / h["cpu_s"] for d, h in zip(rows["default"],
                                                          rows["no defects or waviness"])]
        assert f"{median(each):.2f}×" == bold, name
        assert f"**{bold} ({min(each):.2f}–{max(each):.2f}×)" in page, name
        assert f"{name}.json" in page
    clear = json.loads((res / "switches-roller-spall-clearance.json").read_text())
    assert clear["window"]["bearing.radial_clearance_mm"] == 0.01
    steps = clear["rows"]["default"][-1]["steps"] / clear["rows"]["no defects or waviness"][-1][
        "steps"]
    assert f"and {steps:.2f}× the steps (switches-roller-spall-clearance.json)" in page
