"""Layering of the package (issue 12, item 3): no import cycle and no upward import.

tools/check_imports.py reads every import statement of bearingdae (module level and inside
functions) and checks it against the pipeline's layers scene -> parameters -> physics -> system
-> solvers -> results -> analysis -> api -> studies -> cli.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

TOOL = Path(__file__).resolve().parents[2] / "tools" / "check_imports.py"


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


def test_the_check_sees_a_planted_violation(tmp_path, monkeypatch):
    """The checker is not blind: a lazy upward import and a cycle in a copy are reported."""
    tool = load_tool()
    pkg = tmp_path / "bearingdae"
    (pkg / "physics").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "physics" / "__init__.py").write_text("")
    (pkg / "physics" / "law.py").write_text("def f():\n    from ..api import simulate\n")
    (pkg / "api.py").write_text("from .physics import law\n")
    (pkg / "cli.py").write_text("from . import program\n")
    (pkg / "program.py").write_text("def main():\n    from .cli import execute\n")
    monkeypatch.setattr(tool, "ROOT", pkg)
    cycles, upward, _ = tool.report()
    assert ["bearingdae.cli", "bearingdae.program"] in cycles
    assert ["bearingdae.api", "bearingdae.physics.law"] in cycles
    assert ("bearingdae.physics.law", "bearingdae.api", 2) in upward
