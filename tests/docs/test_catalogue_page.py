"""docs/user-guide.md's catalogue section is generated: its tables are what
tools/catalogue_friction.py makes of the committed CSVs, the page includes them and their
figures, and the numbers its text quotes are the CSVs'."""

from __future__ import annotations

from pathlib import Path

import pytest

from tool_module import load_tool

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"


@pytest.fixture(scope="module")
def tool():
    return load_tool("catalogue_friction")


def test_friction_table_is_the_tools_output(tool):
    rows = tool.read_csv(DOCS / "data" / "catalogue_friction.csv")
    assert list(rows[0]) == tool.FRICTION_COLUMNS
    assert len(rows) == len(tool.CASES) * len(tool.SPEEDS_RPM) * len(tool.LOADS_N)
    assert (DOCS / "data" / "catalogue_friction.md").read_text() == tool.friction_markdown(rows)


def test_skf_column_is_the_reference_model(tool):
    """The CSV's catalogue column is tools/skf_friction.py at each point (to the CSV's
    nine digits): a change of the reference shows here until the tool is run again."""
    import skf_friction as skf  # on the path the tool puts it

    for r in tool.read_csv(DOCS / "data" / "catalogue_friction.csv"):
        ref = skf.friction_torque_N_m(r["bearing"], r["speed_rpm"], r["radial_load_N"]) * 1e3
        assert r["skf_N_mm"] == pytest.approx(ref, rel=1e-5)
        for model in ("paper", "switches"):
            friction = r[f"{model}_N_mm"] - r[f"{model}_drag_N_mm"]
            assert r[f"{model}_ratio"] == pytest.approx(friction / ref, rel=1e-4, nan_ok=True)
            assert r[f"{model}_total_ratio"] == pytest.approx(r[f"{model}_N_mm"] / ref,
                                                             rel=1e-4, nan_ok=True)


def test_skid_table_is_the_tools_output(tool):
    rows = tool.read_csv(DOCS / "data" / "catalogue_skid.csv")
    assert list(rows[0]) == tool.SKID_COLUMNS
    assert (DOCS / "data" / "catalogue_skid.md").read_text() == tool.skid_markdown(rows)


def test_user_guide_includes_the_tables_and_figures():
    page = (DOCS / "user-guide.md").read_text()
    assert "## Friction, power loss and temperature against the catalogue" in page
    for name in ("catalogue_friction.md", "catalogue_skid.md", "catalogue_terms.md",
                 "catalogue_skid_band.md", "calibrated_friction.md"):
        assert f"```{{include}} data/{name}" in page, name
    for name in ("catalogue_friction.png", "catalogue_skid.png"):
        assert f"figures/{name}" in page and (DOCS / "figures" / name).exists(), name
    import skf_friction as skf  # on the path the tool puts it

    assert "(ν n)" in page and f"ν = η/ρ of the scene ({skf.kinematic_viscosity_mm2_s():.1f} mm²/s" \
        in " ".join(page.split())


def test_the_pages_claims_follow_from_the_table(tool):
    """What the section's list says of the table, checked on the committed CSV."""
    rows = [r for r in tool.read_csv(DOCS / "data" / "catalogue_friction.csv")
            if r["switches_N_mm"] == r["switches_N_mm"]]  # the runs that completed
    page = " ".join((DOCS / "user-guide.md").read_text().split())
    # "between 10⁻⁶ and 3·10⁻² of the catalogue's wherever the cage rolls" (slip below 2 %)
    assert "between 10⁻⁶ and 3·10⁻² of the catalogue's wherever the cage rolls" in page
    rolling = [r["paper_ratio"] for r in rows if r["paper_cage_slip"] < 0.02]
    assert rolling and 1e-6 <= min(rolling) and max(rolling) <= 3e-2
    # "puts the model at 0.6–4.5× the catalogue; 3 of the 24 points are within a factor 1.5"
    ratios = [r["switches_ratio"] for r in rows]
    stated = f"puts the model at {min(ratios):.1f}–{max(ratios):.1f}× the catalogue"
    assert stated in page, stated
    inside = sum(1 / 1.5 <= x <= 1.5 for x in ratios)
    assert f"{inside} of the {len(rows)} points are within a factor 1.5" in page
    # "At 500 r/min the catalogue's sliding term ... weighs most under 8000 N (69 % of its
    # moment on yang20)"
    import skf_friction as skf  # on the path the tool puts it

    d, D = skf.BEARINGS_MM["yang20"]
    m = skf.frictional_moment_Nmm(500.0, 8000.0, d, D, skf.kinematic_viscosity_mm2_s())
    share = f"({m['sliding'] / m['total']:.0%} of its moment on yang20)"
    assert share.replace("%", " %") in page, share
    # "Goksem & Hargreaves's law (the column beside) is lower than B&H's at every point that ran"
    gk = [r for r in rows if r["goksem_N_mm"] == r["goksem_N_mm"]]
    assert all(r["goksem_ratio"] < r["switches_ratio"] for r in gk)
    # "on harris36 at 6000 and 10 000 r/min, wherever the cage rolls, [the drag exceeds]
    # the catalogue's whole moment; on yang20 [it is] at most about a tenth of the friction"
    drag = [r for r in tool.read_csv(DOCS / "data" / "catalogue_friction.csv")
            if r["bearing"] == "harris36" and r["speed_rpm"] >= 6000.0
            and r["paper_cage_slip"] < 0.02]
    assert drag and all(r["paper_drag_N_mm"] > r["skf_N_mm"] for r in drag)
    assert all(r["switches_drag_N_mm"] <= 0.12 * (r["switches_N_mm"] - r["switches_drag_N_mm"])
               for r in rows if r["bearing"] == "yang20")


def test_the_skid_boundary_the_page_states(tool):
    """"the lightest load at which the cage slips less than 1 %, moves from 2000 N to
    4000 N", from the committed skid CSV; "above it ... within a few tenths of a per cent"."""
    rows = tool.read_csv(DOCS / "data" / "catalogue_skid.csv")

    def boundary(model):
        return min(r["radial_load_N"] for r in rows if r[f"{model}_cage_speed_ratio"] > 0.99)

    page = " ".join((DOCS / "user-guide.md").read_text().split())
    stated = f"moves from {boundary('paper'):.0f} N to {boundary('goksem'):.0f} N"
    assert stated in page, stated
    above = [r for r in rows if r["radial_load_N"] >= boundary("goksem")]
    assert all(abs(r["paper_cage_speed_ratio"] - r["goksem_cage_speed_ratio"]) < 0.005
               for r in above)
    assert all(r["goksem_cage_speed_ratio"] < r["paper_cage_speed_ratio"] for r in rows
               if r["radial_load_N"] > 0 and r["goksem_cage_speed_ratio"] > 0)


def test_geometry_table_is_the_tools_output(tool):
    """The table of the rollers the catalogue does not see: the tool's output of its CSV, the
    catalogue column the reference model's, the full-length points the friction table's (the
    same runs' settings), and the page's claim that shorter rollers lower the model's friction
    at an unchanged catalogue."""
    import skf_friction as skf  # on the path the tool puts it

    rows = tool.read_csv(DOCS / "data" / "catalogue_geometry.csv")
    assert list(rows[0]) == tool.GEOMETRY_COLUMNS
    assert len(rows) == len(tool.GEOMETRY_SPEEDS_RPM) * len(tool.GEOMETRY_LOADS_N)
    assert (DOCS / "data" / "catalogue_geometry.md").read_text() == tool.geometry_markdown(rows)
    friction = {(r["bearing"], r["speed_rpm"], r["radial_load_N"]): r
                for r in tool.read_csv(DOCS / "data" / "catalogue_friction.csv")}
    for r in rows:
        key = (r["bearing"], r["speed_rpm"], r["radial_load_N"])
        ref = skf.friction_torque_N_m(*key) * 1e3
        assert r["skf_N_mm"] == pytest.approx(ref, rel=1e-5)
        full = friction[key]
        assert r["full_N_mm"] == pytest.approx(full["switches_N_mm"] - full["switches_drag_N_mm"],
                                               rel=1e-6)
        assert r["half_N_mm"] < 0.8 * r["full_N_mm"]
        assert r["half_ratio"] == pytest.approx(r["half_N_mm"] / ref, rel=1e-6)
    page = (DOCS / "user-guide.md").read_text()
    assert "```{include} data/catalogue_geometry.md" in page
