"""Layering of the package: no import cycle, no upward import, layers = folders.

tools/check_imports.py reads every import statement of bearingdae (module level and inside
functions) and checks it against the pipeline's layers, which are the package's folders:
root/util -> scene -> physics -> system -> solvers -> run -> analysis -> results -> plots -> api
-> studies -> cli.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

TOOL = Path(__file__).resolve().parents[2] / "tools" / "check_imports.py"
PACKAGE = Path(__file__).resolve().parents[2] / "bearingdae"


def load_tool():
    spec = importlib.util.spec_from_file_location("check_imports", TOOL)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_no_import_cycle_and_no_upward_import():
    cycles, upward, _ = load_tool().report()
    assert cycles == [], f"import cycles: {cycles}"
    assert upward == [], "upward imports: " + "; ".join(f"{m}:{line} -> {t}"
                                                        for m, t, line in upward)


def test_package_root_holds_only_the_public_api():
    """Every other module lives in the folder of the stage it serves."""
    root_modules = sorted(p.name for p in PACKAGE.glob("*.py"))
    assert set(root_modules) <= {"__init__.py", "api.py", "__main__.py"}, root_modules
    tool = load_tool()
    folders = {p.name for p in PACKAGE.iterdir() if (p / "__init__.py").exists()}
    known = {f for _, fs in tool.LAYERS for f in fs}
    assert folders <= known, f"folders without a layer: {sorted(folders - known)}"


def _planted(tmp_path: Path) -> Path:
    pkg = tmp_path / "bearingdae"
    for folder in ("physics", "cli"):
        (pkg / folder).mkdir(parents=True)
        (pkg / folder / "__init__.py").write_text("")
    (pkg / "__init__.py").write_text("")
    (pkg / "physics" / "law.py").write_text("def f():\n    from ..api import simulate\n")
    (pkg / "api.py").write_text("from .physics import law\n")
    (pkg / "cli" / "__init__.py").write_text("from . import program\n")
    (pkg / "cli" / "program.py").write_text("def main():\n    from . import execute\n")
    return pkg


def test_the_check_sees_a_planted_violation(tmp_path, monkeypatch):
    """The checker is not blind: a lazy upward import and a cycle in a copy are reported."""
    tool = load_tool()
    monkeypatch.setattr(tool, "ROOT", _planted(tmp_path))
    cycles, upward, _ = tool.report()
    assert ["bearingdae.cli", "bearingdae.cli.program"] in cycles
    assert ["bearingdae.api", "bearingdae.physics.law"] in cycles
    assert ("bearingdae.physics.law", "bearingdae.api", 2) in upward


def test_the_check_refuses_a_module_at_the_root(tmp_path, monkeypatch):
    tool = load_tool()
    pkg = _planted(tmp_path)
    (pkg / "helpers.py").write_text("")
    monkeypatch.setattr(tool, "ROOT", pkg)
    with pytest.raises(SystemExit, match="bearingdae.helpers"):
        tool.report()


def test_every_package_folder_is_shipped():
    """pyproject.toml lists the packages by name: a new folder missing there would be left out
    of the wheel (and only fail after `pip install .`, not in an editable checkout)."""
    import tomllib

    cfg = tomllib.loads((PACKAGE.parent / "pyproject.toml").read_text())["tool"]["setuptools"]
    folders = {".".join(p.parent.relative_to(PACKAGE.parent).parts)
               for p in PACKAGE.rglob("__init__.py")}
    assert folders <= set(cfg["packages"]), sorted(folders - set(cfg["packages"]))
