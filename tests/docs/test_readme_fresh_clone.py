"""README.md's commands, in order, on a fresh clone of the repository, as a new user types
them (each a process of its own, in one working folder), with the reduced windows of the
README's ``<!-- docs-test`` comments (tests/docs/doc_blocks.py), the ``--resume`` example
included. The ``pip install`` lines are checked, not run (the extras they name exist); the
test suite line is the suite itself, and the documentation build is .ci/run's site build. Slow tier: ~10 processes, each starting bearingdae.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from doc_blocks import ROOT, blocks, commands


@pytest.mark.slow
def test_readme_commands_in_order_on_a_fresh_clone(tmp_path):
    if shutil.which("git") is None:
        pytest.skip("needs git")
    clone, work = tmp_path / "clone", tmp_path / "work"
    subprocess.run(["git", "clone", "--quiet", str(ROOT), str(clone)], check=True)
    work.mkdir()
    env = {**os.environ, "PYTHONPATH": str(clone), "MPLBACKEND": "Agg", "OMP_NUM_THREADS": "1"}
    extras = set(tomllib.loads((clone / "pyproject.toml").read_text())["project"]
                 ["optional-dependencies"])
    ran, said = [], {}
    for block in blocks(clone / "README.md"):
        if block.lang != "bash" or block.slow:
            continue
        for argv, text in commands(block):
            if argv[:2] == ["pip", "install"]:
                for spec in argv[2:]:
                    wanted = set(filter(None, spec.partition("[")[2].rstrip("]").split(",")))
                    assert wanted <= extras, (text, wanted - extras)
                continue
            if argv[:3] in (["python", "-m", "pytest"], ["python", "-m", "sphinx"]):
                continue  # the suite itself; the documentation build (.ci/run's site build)
            assert argv[0] == "bearingdae", f"README runs {text!r}: add it to this test"
            command = argv[1] if len(argv) > 1 else ""
            full = [sys.executable, "-m", "bearingdae.cli", *argv[1:],
                    *block.append.get(command, [])]
            r = subprocess.run(full, cwd=work, env=env, capture_output=True, text=True)
            assert r.returncode == 0, (text, r.stdout[-2000:], r.stderr[-2000:])
            assert "Traceback" not in r.stderr, r.stderr[-3000:]
            ran.append(text)
            said[text] = r.stdout + r.stderr
    resumed = [t for t in ran if "--resume" in t]
    assert resumed and "nothing to resume" in said[resumed[0]], said.get(
        resumed[0] if resumed else "", ran)
    assert (work / "my_case.nc").exists() and (work / "out.nc").exists()
    assert any(t.startswith("bearingdae cases --copy") for t in ran)
