"""The API reference (docs/api.md) lists every public name the docs use.

Every ``from bearingdae... import name`` in the user guide, the other pages, README and the
gallery's examples must be in an autosummary of docs/api.md under its module (root names
under ``bearingdae``): a user who reads a name in an example finds its reference. Modules
imported as such (``from bearingdae.studies import workprecision``), constants (ALL CAPS) and
the program's entry point (``bearingdae.cli``) are not API entries.
"""

from __future__ import annotations

import importlib
import inspect
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
IMPORT = re.compile(r"from (bearingdae[\w.]*) import \(?([\w\s,]+?)\)?\s*(?:#|$)", re.M)


def entry_of(line: str) -> str:
    """The name an autosummary line lists ('   load_scene'), else ''."""
    s = line.strip()
    return s if line.startswith("   ") and s and not s.startswith(":") else ""


def documented() -> set[str]:
    """Fully qualified names in docs/api.md's autosummaries."""
    names, module, listing = set(), "bearingdae", False
    for line in (DOCS / "api.md").read_text(encoding="utf-8").splitlines():
        m = re.match(r"\.\. currentmodule:: ([\w.]+)", line.strip())
        if m:
            module = m.group(1)
        if line.strip().startswith(".. autosummary::"):
            listing = True
            continue
        if listing:
            if not entry_of(line) and (not line.strip() or line.strip().startswith(":")):
                continue  # a blank line or an option of the directive
            if entry_of(line):
                names.add(f"{module}.{entry_of(line)}")
                continue
            listing = False
    return names


def used() -> dict[str, str]:
    """Fully qualified public names imported in the docs and examples -> where."""
    out = {}
    files = sorted(DOCS.glob("*.md")) + sorted((DOCS / "examples").glob("*.py"))
    for path in files + [ROOT / "README.md"]:
        for m in IMPORT.finditer(path.read_text(encoding="utf-8")):
            module = m.group(1)
            if module.startswith("bearingdae.cli"):
                continue
            for raw in m.group(2).replace("\n", " ").split(","):
                name = raw.split(" as ")[0].strip()
                if not name or name.startswith("_") or name.isupper():
                    continue
                obj = getattr(importlib.import_module(module), name, None)
                if obj is None or inspect.ismodule(obj):
                    continue
                out.setdefault(f"{module}.{name}", path.name)
    return out


def test_every_public_name_the_docs_use_is_in_the_api_reference():
    ref = documented()
    assert "bearingdae.simulate" in ref and "bearingdae.studies.sweep.run_sweep" in ref
    missing = {name: where for name, where in used().items() if name not in ref}
    assert not missing, f"docs/api.md lacks (name: page using it): {missing}"


def test_the_check_finds_a_name_the_reference_lacks(tmp_path, monkeypatch):
    """The check itself: a page importing a name the reference does not list fails it."""
    page = tmp_path / "docs"
    (page / "examples").mkdir(parents=True)
    (page / "api.md").write_text((DOCS / "api.md").read_text(encoding="utf-8"), encoding="utf-8")
    (page / "guide.md").write_text("```python\nfrom bearingdae.run.steady import "
                                   "NotSteadyWarning\n```\n", encoding="utf-8")
    (tmp_path / "README.md").write_text("", encoding="utf-8")
    monkeypatch.setattr(__import__(__name__), "DOCS", page)
    monkeypatch.setattr(__import__(__name__), "ROOT", tmp_path)
    assert "bearingdae.run.steady.NotSteadyWarning" in used()
    assert "bearingdae.run.steady.NotSteadyWarning" not in documented()
