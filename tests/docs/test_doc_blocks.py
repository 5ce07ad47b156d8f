"""Every code block of README.md and docs/*.md runs (docs that cannot drift).

How each kind of block is exercised, and the ``<!-- docs-test ... -->`` comment that gives a
block reduced settings: tests/docs/doc_blocks.py. One test per section of a document (a ``##``
or ``###`` heading) runs its blocks in order in one working folder; blocks marked ``slow`` (they
run many simulations, e.g. the paper set) run only in the slow tier, ``test_document_all_blocks``
(CI runs it in its slow tier), with the other blocks of their section.
"""

from __future__ import annotations

import contextlib
import re
import os
import shlex
import shutil
import subprocess
import sys
import tomllib
import warnings
from pathlib import Path

import pytest

from doc_blocks import DOCUMENTS, ROOT, Block, blocks, commands, layout_paths, sections

pytestmark = pytest.mark.filterwarnings("ignore")


def _doc_id(path):
    return str(path.relative_to(ROOT))


@contextlib.contextmanager
def _reduced_python(block: Block, monkeypatch):
    """Scene overrides of a python block's ``python:`` directive, applied to every scene and sweep
    it loads (the block's own overrides win over them, those of ``python force:`` over the
    block's), and sweeps run in this process if ``synchronous``."""
    import bearingdae
    import bearingdae.scene
    import bearingdae.studies.sweep as studies_sweep

    sweep_modules = [studies_sweep]
    with contextlib.suppress(ImportError):
        import bearingdae.sweep as sweep_shim

        sweep_modules.append(sweep_shim)
    reduced, forced = dict(block.overrides), dict(block.forced)
    if reduced or forced:
        real_load = bearingdae.scene.load_scene

        def load_scene(case, overrides=None, *args, **kwargs):
            return real_load(case, {**reduced, **(overrides or {}), **forced}, *args, **kwargs)

        monkeypatch.setattr(bearingdae, "load_scene", load_scene)
        monkeypatch.setattr(bearingdae.scene, "load_scene", load_scene)
        real_sweep = studies_sweep.load_sweep

        def load_sweep(path, overrides=None, *args, **kwargs):
            sw = real_sweep(path)
            axes = {a.key for a in sw.axes}
            mine = {k: v for k, v in reduced.items() if k not in axes}
            forced_here = {k: v for k, v in forced.items() if k not in axes}
            return real_sweep(path, {**mine, **(overrides or {}), **forced_here}, *args, **kwargs)

        for module in sweep_modules:
            monkeypatch.setattr(module, "load_sweep", load_sweep)
    if block.synchronous:
        for module in sweep_modules:
            for name in ("run_sweep", "run_sweeps"):
                real = getattr(studies_sweep, name)

                def run(*args, _real=real, **kwargs):
                    kwargs.setdefault("scheduler", "synchronous")
                    kwargs.setdefault("progress", False)
                    return _real(*args, **kwargs)

                monkeypatch.setattr(module, name, run)
    yield


def _run_python(block: Block, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with _reduced_python(block, monkeypatch):
        code = compile(block.text, block.where, "exec")
        exec(code, {"__name__": "__docs__"})  # noqa: S102  (the documentation's own code)
    plt.close("all")


def _extras() -> set[str]:
    data = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    return set(data["project"].get("optional-dependencies", {}))


def _bearingdae(block: Block, argv: list[str], capsys) -> None:
    from bearingdae.cli import _parser, main

    argv = list(argv)
    command = argv[0] if argv and not argv[0].startswith("-") else ""
    argv += block.append.get(command, [])
    if any(p in " ".join(argv) for p in block.parse_only):
        _parser().parse_args(argv)  # the syntax is checked; the command cannot run here
        return
    if block.synchronous and command in ("sweep", "paper", "skidmap"):
        argv += ["--scheduler", "synchronous", "--no-progress"]
    status = main(argv)
    out = capsys.readouterr()
    assert status == 0, (f"{block.where}: `bearingdae {' '.join(argv)}` exit status {status}\n"
                         f"{out.out[-2000:]}\n{out.err[-2000:]}")


def _run_bash(block: Block, capsys) -> None:
    for argv, text in [(shlex_split(c), c) for c in block.before] + commands(block):
        program = argv[0]
        if program == "bearingdae":
            _bearingdae(block, argv[1:], capsys)
        elif program == "pip":  # what .ci/run executes; here: the extras named exist
            assert argv[:2] == ["pip", "install"], f"{block.where}: {argv}"
            for spec in argv[2:]:
                if spec.startswith("."):
                    extras = spec.partition("[")[2].rstrip("]")
                    missing = {e for e in extras.split(",") if e} - _extras()
                    assert not missing, f"{block.where}: extras {missing} not in pyproject.toml"
        elif argv[:3] == ["python", "-m", "pytest"]:  # .ci/run runs the suite itself
            assert (ROOT / "tests").is_dir()
        elif any(p in " ".join(argv) for p in block.parse_only):  # run by .ci/run, verbatim
            ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
            assert " ".join(argv) in ci, f"{block.where}: `{' '.join(argv)}` is not in .ci/run"
        else:  # any other program: the shell runs the line in the working folder
            script = next((a for a in argv[1:] if a.endswith(".py")), None)
            if program == "python" and script is not None:
                text += " " + " ".join(shlex.quote(a) for a in block.append.get(script, []))
            result = subprocess.run(["bash", "-c", text], capture_output=True, text=True,
                                    timeout=1800, env=_env())
            if program in block.expect:  # e.g. cfchecks: non-zero status for warnings
                assert block.expect[program] in result.stdout + result.stderr, (
                    f"{block.where}: `{text}` did not say {block.expect[program]!r}\n"
                    f"{result.stdout[-3000:]}\n{result.stderr[-2000:]}")
                continue
            assert result.returncode == 0, (f"{block.where}: `{text}` exit status "
                                            f"{result.returncode}\n{result.stdout[-2000:]}\n"
                                            f"{result.stderr[-2000:]}")


def shlex_split(text: str) -> list[str]:
    return shlex.split(text, comments=True)


def _env() -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH", "")]))
    env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", "")])
    return env


def _run_toml(block: Block) -> None:
    from bearingdae import scene_from_dict
    from bearingdae.studies.sweep import load_sweep

    data = tomllib.loads(block.text)
    first = block.text.lstrip().splitlines()[0]
    target = None
    if first.startswith("#") and first.rstrip().endswith(".toml"):
        target = Path(first.lstrip("# ").split()[0])
        target.write_text(block.text, encoding="utf-8")
    if "base" in data:
        sw = load_sweep(target) if target else None
        assert sw is None or sw.points, f"{block.where}: a sweep without runs"
        if target is None:
            from bearingdae.studies.sweep import sweep_from_dict

            sweep_from_dict(data)
    elif "bearing" in data:
        scene_from_dict(data)
    else:  # a part of a scene: on top of the baseline case
        base = tomllib.loads((ROOT / "cases" / "yang20_baseline.toml").read_text("utf-8"))
        for section, values in data.items():
            if isinstance(values, list):  # an array of tables ([[defects]])
                base[section] = values
            else:
                base.setdefault(section, {}).update(values)
        scene_from_dict(base)


def _run_block(block: Block, monkeypatch, capsys) -> None:
    for program in block.needs:
        if shutil.which(program, path=_env()["PATH"]) is None:
            warnings.warn(f"{block.where}: skipped, needs {program}")
            return
    if block.lang == "python":
        _run_python(block, monkeypatch)
    elif block.lang == "bash":
        _run_bash(block, capsys)
    elif block.lang == "toml":
        _run_toml(block)
    elif block.layout:
        missing = [p for p in layout_paths(block.text) if not (ROOT / p).exists()]
        assert not missing, f"{block.where}: the layout names paths that do not exist: {missing}"


def _run_document(path, tmp_path, monkeypatch, capsys, include_slow: bool,
                  section: str | None = None) -> int:
    """Run the blocks of the document (of its ``section`` only, unless None) in order in
    ``tmp_path``; the count run."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    for name in ("tests", "benchmarks"):  # blocks that name repository files run as from the root
        (tmp_path / name).symlink_to(ROOT / name)
    ran = 0
    for block in blocks(path):
        if (block.slow and not include_slow) or section not in (None, block.section):
            continue
        try:
            _run_block(block, monkeypatch, capsys)
        except AssertionError:
            raise
        except BaseException as exc:  # say which block broke
            raise AssertionError(f"{block.where} ({block.lang}) failed: "
                                 f"{type(exc).__name__}: {exc}") from exc
        ran += 1
    return ran



def _cases(slow: bool) -> list:
    """(document, section) of every section that holds a block of the tier."""
    return [pytest.param(path, name, id=_doc_id(path) + (f"#{name}" if name else ""))
            for path in DOCUMENTS for name in sections(path, slow=slow)]


@pytest.mark.parametrize("path, section", _cases(slow=False))
def test_document_blocks(path, section, tmp_path, monkeypatch, capsys):
    """Every block of the section that is not marked ``slow`` runs (the sections of one
    document are cases of their own: xdist spreads a long page over its workers)."""
    _run_document(path, tmp_path, monkeypatch, capsys, include_slow=False, section=section)


@pytest.mark.slow
@pytest.mark.parametrize("path, section", _cases(slow=True))
def test_document_all_blocks(path, section, tmp_path, monkeypatch, capsys):
    """Every block of a section that holds a slow one (the paper set, skid maps), the slow
    ones included."""
    _run_document(path, tmp_path, monkeypatch, capsys, include_slow=True, section=section)


def test_every_block_is_exercised():
    """Each block is run, parsed or a marked sample: a python/bash/toml block is never only
    shown, an unlabelled block holds no command, and ``text`` samples name no command to run."""
    for path in DOCUMENTS:
        for block in blocks(path):
            if block.lang in ("python", "bash", "toml"):
                assert block.text.strip(), f"{block.where}: empty block"
            else:
                first = block.text.lstrip().split("\n", 1)[0]
                assert block.layout or not first.startswith(("bearingdae ", "python ", "$ ")), (
                    f"{block.where}: a command in a block without a language: mark it ```bash")


def test_ci_runs_the_readme_test_command():
    """README's first bash block is what .ci/run executes (its second line, verbatim)."""
    readme = blocks(ROOT / "README.md")
    first = next(b for b in readme if b.lang == "bash")
    line = first.text.splitlines()[1]
    assert "python -m pytest" in line
    assert "sed -n 2p" in (ROOT / ".ci" / "run").read_text(encoding="utf-8")


@pytest.mark.parametrize("block", [
    "```python\nimport bearingdae\nbearingdae.load_scene('no_such_case')\n```",
    "```bash\nbearingdae run --set numerics.no_such_key=1\n```",
    "```toml\n[numerics]\nslices = -3\n```",
    "<!-- docs-test\nlayout\n-->\n```\nbearingdae/\n  no_such_module.py   gone\n```",
])
def test_a_broken_block_fails(block, tmp_path, monkeypatch, capsys):
    """The test cannot pass a block that breaks: a failing call, exit status, scene or path."""
    doc = tmp_path / "broken.md"
    doc.write_text(f"# A page\n\n{block}\n", encoding="utf-8")
    work = tmp_path / "work"
    work.mkdir()
    with pytest.raises(AssertionError, match="broken.md:"):
        _run_document(doc, work, monkeypatch, capsys, include_slow=True)


def test_each_block_runs_in_one_case_of_its_tier():
    """The sections split every document without losing a block: each block is in the case of
    its section in its tier (fast, or slow for a block marked slow)."""
    cases = {False: {(p, s) for p in DOCUMENTS for s in sections(p)},
             True: {(p, s) for p in DOCUMENTS for s in sections(p, slow=True)}}
    for path in DOCUMENTS:
        for block in blocks(path):
            assert (path, block.section) in cases[block.slow], block.where


TWO_SECTIONS = """# A page

## Writes

```toml
# a.toml
[numerics]
slices = 3
```

### Reads, continuing

<!-- docs-test
continues
-->
```python
assert "slices" in open("a.toml").read()
```

## Reads alone

```python
open("a.toml").read()
```
"""


def test_sections_run_in_folders_of_their_own(tmp_path, monkeypatch, capsys):
    """A section does not see the files of another; a ``continues`` block runs in the section
    above (the reference: a page typed here whose last section reads a file it never writes)."""
    doc = tmp_path / "two.md"
    doc.write_text(TWO_SECTIONS, encoding="utf-8")
    assert sections(doc) == ["writes", "reads-alone"]
    for name in ("w1", "w2"):
        (tmp_path / name).mkdir()
    assert _run_document(doc, tmp_path / "w1", monkeypatch, capsys, include_slow=False,
                         section="writes") == 2
    with pytest.raises(AssertionError, match=r"two.md:\d+ \(python\) failed: FileNotFoundError"):
        _run_document(doc, tmp_path / "w2", monkeypatch, capsys, include_slow=False,
                      section="reads-alone")


PATH_NAMED = re.compile(r"(?<![\w/.])((?:bearingdae|tests|benchmarks|cases|tools|docs)/[\w./-]*\w)")


def _built(path: str) -> bool:
    """A path the docs build writes (the site, the executed gallery): not in a fresh clone."""
    return path.startswith(("docs/_build", "docs/auto_examples"))


def test_named_repository_files_exist():
    """Every repository path the documentation, the gallery, the command-line help and the
    scene-key meanings name (``bearingdae/run/steady.py``, ``tests/...``) exists.
    docs/performance.md is left out: it names benchmark result files by pattern."""
    from bearingdae.scene.keydoc import key_reference

    texts = {str(p.relative_to(ROOT)): p.read_text(encoding="utf-8")
             for p in [*DOCUMENTS, *sorted((ROOT / "docs" / "examples").glob("*.py")),
                       ROOT / "bearingdae" / "cli" / "parser.py"]
             if p.name != "performance.md"}
    texts["scene key reference"] = key_reference()
    missing = [(where, m.group(1)) for where, text in texts.items()
               for m in PATH_NAMED.finditer(text)
               if not (ROOT / m.group(1)).exists() and not _built(m.group(1))]
    assert not missing, missing
