"""LICENSE, CITATION.cff and the one place of the version."""

from __future__ import annotations

import tomllib

import yaml

import bearingdae
from bearingdae.cli import main
from doc_blocks import ROOT


def test_license_is_the_declared_bsd_3_clause():
    text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert text.startswith("BSD 3-Clause License")
    assert "Copyright (c) 2026, bearingdae developers" in text
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    assert project["license"] == {"text": "BSD-3-Clause"}


def test_citation_names_the_software_and_the_seed_paper():
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text(encoding="utf-8"))
    assert cff["cff-version"] == "1.2.0" and cff["type"] == "software"
    assert cff["license"] == "BSD-3-Clause"
    paper = cff["preferred-citation"]
    assert paper == cff["references"][0]
    assert paper["doi"] == "10.3390/lubricants12090317"
    assert (paper["journal"], paper["year"], paper["volume"], paper["issue"], paper["start"]) == (
        "Lubricants", 2024, 12, 9, 317)
    assert [a["family-names"] for a in paper["authors"]] == ["Yang", "Wang", "Wang", "Wen"]
    assert "version" not in cff  # one place: bearingdae.__version__


def test_the_version_has_one_place(capsys):
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert "version" not in project["project"] and "version" in project["project"]["dynamic"]
    assert project["tool"]["setuptools"]["dynamic"]["version"] == {
        "attr": "bearingdae.__version__"}
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"bearingdae {bearingdae.__version__}"
    conf = (ROOT / "docs" / "conf.py").read_text(encoding="utf-8")
    assert "version = release = bearingdae.__version__" in conf


def test_output_files_carry_the_version():
    from bearingdae import load_scene, solve_static

    ds = solve_static(load_scene("yang20_baseline"))
    assert ds.attrs["bearingdae_version"] == bearingdae.__version__
    assert ds.attrs["source"] == f"bearingdae {bearingdae.__version__}"
    assert "docs/theory.md" in ds.attrs["references"] and "MODEL" not in ds.attrs["references"]


def test_the_site_includes_the_changelog_when_there_is_one(tmp_path):
    """docs/_ext/generated_pages.py: CHANGELOG.md of the repository root is included (MyST
    include) if it exists; without it the page says so and the build does not fail."""
    from test_key_reference import _generated_pages_module

    docs = tmp_path / "docs"
    docs.mkdir()
    write_pages = _generated_pages_module().write_pages
    _keys, changelog = write_pages(docs)
    assert "has no `CHANGELOG.md`" in changelog.read_text(encoding="utf-8")
    (tmp_path / "CHANGELOG.md").write_text("# Changelog\n\n## 0.1.0\n", encoding="utf-8")
    _keys, changelog = write_pages(docs)
    text = changelog.read_text(encoding="utf-8")
    assert text.startswith("```{include} ../../CHANGELOG.md")
    assert (changelog.parent / "../../CHANGELOG.md").resolve() == tmp_path / "CHANGELOG.md"


def test_the_performance_page_stays_a_page_to_read():
    """docs/performance.md holds the current figures a user needs, each with its command; the
    history of the measurements lives in CHANGELOG.md. Past 300 lines it has become a log."""
    lines = (ROOT / "docs" / "performance.md").read_text(encoding="utf-8").splitlines()
    assert len(lines) <= 300, f"docs/performance.md has {len(lines)} lines (at most 300)"


def test_the_benchmark_suite_stays_at_twelve_files():
    """benchmarks/: at most 12 scripts (run.py included) and its README; every benchmark name
    of ``run.py --list`` has its module and a row in the README's table."""
    import importlib.util

    bench = ROOT / "benchmarks"
    scripts = sorted(p.name for p in bench.glob("*.py"))
    assert len(scripts) <= 12, scripts
    spec = importlib.util.spec_from_file_location("benchmarks_run", bench / "run.py")
    run = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(run)
    readme = (bench / "README.md").read_text(encoding="utf-8")
    for name, (module, _question) in run.BENCHMARKS.items():
        assert f"{module}.py" in scripts, (name, module)
        assert f"| `{name}` |" in readme, name


def test_the_readme_links_the_cfchecks_recipe():
    """`cfchecks FILE` fails offline; the README points at the recipe that works, and the
    section it links holds it (the cfchecks command with its local tables)."""
    import re

    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    link = re.search(r"\]\(docs/robustness\.md#([\w-]+)\)", readme[readme.index("cfchecks"):])
    assert link, "README: no link to the cfchecks recipe in docs/robustness.md"
    page = (ROOT / "docs" / "robustness.md").read_text(encoding="utf-8")
    heading = next(h for h in re.findall(r"^## (.+)$", page, re.M)
                   if re.sub(r"[^\w\- ]", "", h.lower()).replace(" ", "-") == link.group(1))
    section = page.split(f"## {heading}", 1)[1].split("\n## ", 1)[0]
    assert "cfchecks -v auto -s" in section
