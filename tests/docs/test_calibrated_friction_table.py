"""docs/data/calibrated_friction.* (tools/calibrated_friction_table.py): the table is the
tool's output of its CSV, the calibration point's run is within 2 % of SKF's torque there
(calibrate's promise), the band flags follow from the ratios, and one row is a fresh run."""

from __future__ import annotations

from pathlib import Path

import pytest

from tool_module import load_tool

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "docs" / "data"


@pytest.fixture(scope="module")
def tool():
    return load_tool("calibrated_friction_table")


def test_table_is_the_tools_output(tool):
    rows = tool.read()
    assert list(rows[0]) == list(tool.COLUMNS)
    assert (DATA / "calibrated_friction.md").read_text() == tool.markdown(rows)


def test_each_calibration_point_is_within_2_percent_of_skf(tool):
    import skf_friction as skf

    cal = [r for r in tool.read() if r["calibration_point"] == 1]
    assert cal
    for r in cal:
        assert (r["speed_rpm"], r["radial_load_N"]) == tool.CAL_POINT
        ref = skf.friction_torque_N_m(r["bearing"], r["speed_rpm"], r["radial_load_N"]) * 1e3
        assert r["skf_N_mm"] == pytest.approx(ref, rel=1e-5)
        assert abs(r["model_N_mm"] / ref - 1) <= 0.02


def test_band_flags_follow_from_the_ratios(tool):
    for r in tool.read():
        assert r["ratio"] == pytest.approx(r["model_N_mm"] / r["skf_N_mm"], rel=1e-5)
        assert r["within_band"] == float(tool.BAND[0] <= r["ratio"] <= tool.BAND[1])


@pytest.mark.slow
def test_one_row_is_a_fresh_run(tool):
    """The last yang20 row: a run at the table's film gives its torque (another CPU: 1e-5;
    the window mean of half a cage revolution from the same start, so 1 % is ample)."""
    row = [r for r in tool.read() if r["bearing"] == "yang20"][-1]
    T = tool.torque_N_mm("yang20_baseline", row["speed_rpm"], row["radial_load_N"],
                         row["inlet_film_um"])
    assert T == pytest.approx(row["model_N_mm"], rel=0.01)


def test_the_pages_claims_follow_from_the_table(tool):
    """"On yang20 every point lands within the band (0.66–0.99x SKF)"; harris36's film
    "13.6 µm" and its two points outside "at 2.4x and 4.4x SKF"."""
    page = " ".join((ROOT / "docs" / "user-guide.md").read_text().split())
    rows = tool.read()
    yang = [r for r in rows if r["bearing"] == "yang20" and not r["calibration_point"]]
    assert all(r["within_band"] for r in yang)
    assert f"({min(r['ratio'] for r in yang):.2f}–{max(r['ratio'] for r in yang):.2f}x SKF)" \
        in page
    harris = [r for r in rows if r["bearing"] == "harris36"]
    assert f"({harris[0]['inlet_film_um']:.1f} µm:" in page
    out = sorted(r["ratio"] for r in harris if not r["within_band"])
    assert f"at {out[0]:.1f}x and {out[1]:.1f}x SKF" in page and len(out) == 2
