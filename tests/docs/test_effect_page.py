"""docs/adding-an-effect.md names real code: every repository path, every
``bearingdae.module.name`` and every ``tests/FILE.py::name`` it cites exists, so that the page
fails a test, instead of misleading its reader, when a function it cites is renamed or moved."""

from __future__ import annotations

import ast
import importlib
import re

from doc_blocks import ROOT

PAGE = ROOT / "docs" / "adding-an-effect.md"
DOTTED = re.compile(r"`(bearingdae(?:\.\w+)+)`")
NODE = re.compile(r"`(tests/[\w/]+\.py)::(\w+)`")
PATH = re.compile(r"(?<![\w/.])((?:bearingdae|tests|benchmarks|cases|docs)/[\w./-]*\w)")


def resolves(dotted: str) -> bool:
    """Whether ``dotted`` is a module, or a name reached by attributes from the longest
    importable module prefix (``bearingdae.system.flange.flange_pass``)."""
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ModuleNotFoundError:
            continue
        for name in parts[cut:]:
            if not hasattr(obj, name):
                return False
            obj = getattr(obj, name)
        return True
    return False


def defines(path, name: str) -> bool:
    """Whether the Python file ``path`` defines ``name`` at its top level."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return any(getattr(node, "name", None) == name for node in tree.body)


def citations(text: str) -> tuple[set, set, set]:
    return (set(DOTTED.findall(text)), set(NODE.findall(text)), set(PATH.findall(text)))


def missing(text: str) -> list[str]:
    """What ``text`` cites that the repository does not have."""
    dotted, nodes, paths = citations(text)
    out = [d for d in sorted(dotted) if not resolves(d)]
    out += [f"{f}::{n}" for f, n in sorted(nodes)
            if not (ROOT / f).is_file() or not defines(ROOT / f, n)]
    out += [p for p in sorted(paths) if not (ROOT / p).exists()]
    return out


def test_every_code_path_the_page_cites_exists():
    text = PAGE.read_text(encoding="utf-8")
    dotted, nodes, paths = citations(text)
    # the page is a path through the code: it must keep citing it
    assert len(dotted) >= 30 and len(nodes) >= 15 and len(paths) >= 20, (
        len(dotted), len(nodes), len(paths))
    assert missing(text) == []


def test_a_renamed_or_moved_citation_is_caught():
    text = ("`bearingdae.system.flange.flange_pass_v2` `bearingdae.physics.no_such_module.law` "
            "`tests/system/test_jacobian.py::test_that_never_was` "
            "bearingdae/system/no_such_file.py and `bearingdae.system.flange.flange_pass` "
            "`tests/system/test_jacobian.py::test_analytic_jacobian_matches_central_differences`")
    assert missing(text) == [
        "bearingdae.physics.no_such_module.law", "bearingdae.system.flange.flange_pass_v2",
        "tests/system/test_jacobian.py::test_that_never_was",
        "bearingdae/system/no_such_file.py"]


def test_the_page_is_in_the_site():
    index = (ROOT / "docs" / "index.md").read_text(encoding="utf-8")
    toctree = index[index.index("```{toctree}"):]
    assert "\nadding-an-effect\n" in toctree


def test_the_short_paths_example_is_the_test_modules_effect():
    """The page's effect written in one module is tests/system/test_new_effect.py's, line for
    line: from its law to its declaration (the checks that module runs are the page's)."""
    text = PAGE.read_text(encoding="utf-8")
    block = text[text.index("## The short path"):]
    block = block[block.index("```python\n") + 10:]
    block = block[:block.index("```\n")]
    start = block.index("SPIN = LOCAL.index")
    end = block.index("# Registered")
    example = block[start:end].rstrip() + "\n"
    module = (ROOT / "tests" / "system" / "test_new_effect.py").read_text(encoding="utf-8")
    assert example.count("\n") > 60 and example in module
