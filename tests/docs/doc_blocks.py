"""The code blocks of README.md and docs/*.md, and how tests/docs/test_doc_blocks.py runs them.

Every fenced block is exercised, by its language:

* ``python``: executed (a fresh namespace per block; the blocks of one document share a working
  folder, so a file one block writes is there for the next).
* ``bash``: each command runs: ``bearingdae ...`` in this process (:func:`bearingdae.cli.main`,
  exit status 0 expected), ``python SCRIPT ...`` as a process; ``pip install`` and
  ``python -m pytest`` lines are what ``.ci/run`` executes, so here their extras are checked to
  exist in pyproject.toml.
* ``toml``: parsed; a sweep file (``base = ...``) is loaded as a sweep, anything else as a scene
  (a partial one on top of ``yang20_baseline``). A first line ``# NAME.toml`` writes the block
  to NAME in the working folder, for the blocks after it.
* ``text`` or no language: an output sample, shown, not run (a layout tree with the
  ``layout`` directive: every path in it must exist).

The blocks of a document run section by section (:func:`sections`: a ``##`` or ``###`` heading
starts one), each section in a folder of its own: the sections are test cases that xdist spreads
over its workers. A block that needs a file an earlier section writes makes it with
``before:``, or runs in that section (``continues``).

An HTML comment right above a block's fence says how the test runs it (the reader sees it in
the Markdown source, beside the block)::

    <!-- docs-test
    run static: --set numerics.cage_revolutions=0.05   (appended to each `bearingdae run` / `static`)
    python: numerics.cage_revolutions=0.05             (overrides of every scene a python block loads)
    python force: numerics.cage_revolutions=0.3        (the same, winning over the block's own overrides)
    synchronous                                        (sweeps run in this process, no dask cluster)
    parse only: tcp://                                 (commands containing this are parsed, not run)
    before: bearingdae run -o run.nc --set ...         (a command run first)
    needs: cfchecks                                    (skipped unless this program is installed)
    expect cfchecks: ERRORS detected: 0                (passes if the output says so, any status)
    slow                                               (run in the slow tier: `-m slow`)
    continues                                          (runs in the section above, in its folder)
    layout                                             (a layout tree: its paths must exist)
    -->
"""

from __future__ import annotations

import re
import shlex
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
FENCE = re.compile(r"^(\s*)```+\s*(\{[\w-]+\}|[\w+-]*)")
HEADING = re.compile(r"^#{2,3} (.+)$")  #: a heading that starts a section (outside a fence)
DIRECTIVE = re.compile(r"<!--\s*docs-test\b(.*?)-->", re.S)
KNOWN = ("python", "bash", "toml", "text", "")
#: bearingdae commands that take --set (a reduction given as "run static: ..." goes only there)
COMMANDS = ("run", "static", "sweep", "paper", "plot", "workprecision", "skidmap", "cases",
            "keys", "converge", "coefficients", "calibrate")


@dataclass
class Block:
    path: Path
    line: int  #: 1-based line of the opening fence
    lang: str
    text: str
    append: dict = field(default_factory=dict)  #: command -> extra argv
    overrides: dict = field(default_factory=dict)  #: python blocks: scene overrides
    forced: dict = field(default_factory=dict)  #: python blocks: overrides over the block's own
    synchronous: bool = False
    parse_only: list = field(default_factory=list)
    before: list = field(default_factory=list)
    needs: list = field(default_factory=list)
    expect: dict = field(default_factory=dict)  #: program -> text its output must contain
    slow: bool = False
    layout: bool = False
    continues: bool = False  #: runs in the section above (it reads what that one writes)
    section: str = ""  #: the anchor of the ``##``/``###`` heading above the block ("" before any)

    @property
    def where(self) -> str:
        path = self.path.relative_to(ROOT) if self.path.is_relative_to(ROOT) else self.path
        return f"{path}:{self.line}"


def _directive(block: Block, body: str) -> None:
    """Read the lines of a ``<!-- docs-test ... -->`` comment into ``block``."""
    for raw in body.strip().lstrip(":").splitlines():
        line = raw.split("  (")[0].strip()  # "  (...)" explains the line to a reader
        if not line:
            continue
        if line == "slow":
            block.slow = True
        elif line == "synchronous":
            block.synchronous = True
        elif line == "layout":
            block.layout = True
        elif line == "continues":
            block.continues = True
        elif ":" not in line:
            raise ValueError(f"{block.where}: unknown docs-test directive {line!r}")
        else:
            head, _, rest = line.partition(":")
            head, rest = head.strip(), rest.strip()
            if head in ("python", "python force"):
                target = block.overrides if head == "python" else block.forced
                for item in shlex.split(rest):
                    key, _, value = item.partition("=")
                    target[key] = _value(value)
            elif head == "parse only":
                block.parse_only.append(rest)
            elif head == "before":
                block.before.append(rest)
            elif head.startswith("expect "):  # judge PROGRAM by its output, not its status
                block.expect[head.split(None, 1)[1]] = rest
            elif head == "needs":
                block.needs += rest.split()
            elif all(c in COMMANDS or c.endswith(".py") for c in head.split()):
                for command in head.split():
                    block.append.setdefault(command, []).extend(shlex.split(rest))
            else:
                raise ValueError(f"{block.where}: unknown docs-test directive {line!r}")


def _value(text: str):
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return {"true": True, "false": False}.get(text, text)


def blocks(path: Path) -> list[Block]:
    """Every fenced block of a Markdown file, with its directive."""
    lines = path.read_text(encoding="utf-8").splitlines()
    out, i, section, anchors = [], 0, "", set()
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            heading = HEADING.match(lines[i])
            if heading:
                section = _anchor(heading.group(1), anchors)
            i += 1
            continue
        indent, lang = m.group(1), m.group(2).lower()
        j = i + 1
        while j < len(lines) and not lines[j].strip().startswith("```"):
            j += 1
        body = "\n".join(ln[len(indent):] if ln.startswith(indent) else ln.lstrip()
                         for ln in lines[i + 1:j])
        block = Block(path, i + 1, lang, body, section=section)
        start, i = i, j + 1
        if lang.startswith("{"):  # a MyST directive (toctree, eval-rst): page markup, not code
            continue
        if lang not in KNOWN:
            raise ValueError(f"{block.where}: code block language {lang!r}: the docs test runs "
                             f"{', '.join(repr(k) for k in KNOWN)}")
        above = "\n".join(lines[max(0, start - 12):start])
        found = list(DIRECTIVE.finditer(above))
        if found and above[found[-1].end():].strip() == "":
            _directive(block, found[-1].group(1))
        if block.continues and out:
            block.section = out[-1].section
        out.append(block)
    return out


def _anchor(title: str, taken: set[str]) -> str:
    """A heading's anchor as GitHub spells it (lower case, words joined by ``-``; ASCII only
    here, for test ids), unique in its document (``-1``, ``-2`` after a repeated title)."""
    base = re.sub(r"[^a-z0-9_\- ]", "", title.strip().lower()).replace(" ", "-")
    anchor, n = base, 0
    while anchor in taken:
        n += 1
        anchor = f"{base}-{n}"
    taken.add(anchor)
    return anchor


def sections(path: Path, slow: bool = False) -> list[str]:
    """The sections of a document that hold a block the fast tier runs (``slow``: a block
    marked slow), in order (``""``: before any heading). A document without such a block is one
    section in the fast tier (its test runs nothing) and none in the slow tier."""
    found = list(dict.fromkeys(b.section for b in blocks(path) if b.slow == slow))
    return found if found or slow else [""]


def commands(block: Block) -> list[tuple[list[str], str]]:
    """The commands of a bash block as (argv, shell text): continuation lines joined, comments
    dropped, ``&&`` chains split."""
    text = block.text.replace("\\\n", " ")
    out = []
    for line in text.splitlines():
        for part in line.split("&&"):
            words = shlex.split(part, comments=True)
            if words:
                out.append((words, part.strip()))
    return out


def layout_paths(text: str) -> list[str]:
    """Paths named by a layout tree: the first word of each line, joined to its parent folder
    by indentation (``bearingdae/`` then ``  scene/`` -> ``bearingdae/scene/``)."""
    stack: list[tuple[int, str]] = []
    out = []
    for line in text.splitlines():
        stripped = line.lstrip()
        if not stripped:
            continue
        indent = len(line) - len(stripped)
        if indent >= 20:  # a continuation of the description column
            continue
        names = re.split(r"\s{2,}", stripped)[0].replace(",", " ").split()
        while stack and stack[-1][0] >= indent:
            stack.pop()
        parent = stack[-1][1] if stack else ""
        out += [parent + name for name in names]
        if len(names) == 1 and names[0].endswith("/"):
            stack.append((indent, parent + names[0]))
    return out
