"""List import cycles and upward imports between bearingdae's modules; the layers are the folders.

Every ``import`` statement of the package is read from the source (``ast``), at module level
*and* inside functions: a lazy import is still a dependency. Two exceptions, both printed
apart and not counted: imports under ``if __name__ == "__main__":`` (the module then runs as
``__main__``, another module object) and imports under ``if TYPE_CHECKING:`` (never executed).

A module's layer is its folder under ``bearingdae/``; the package root holds only the flat public
API (``__init__``, the lowest layer, with ``util/``) and ``api.py`` (its own layer). Lowest first
(a module may import its own layer and the layers below it):

    0  root, util   bearingdae/__init__ (version, lazy flat API); util/ (atomic file writes)
    1  scene        the input: TOML -> validated SI scene; the cited bearing sets it names
    2  physics      pure laws
    3  system       the DAE model: layout, residual, Jacobian
    4  solvers      time integrators, static Newton, the compiled IDA core
    5  run          what surrounds one dynamic run: checkpoint, progress, until-steady
    6  analysis     what reads a result: summaries, statistics, life/film/power, static state,
                    stiffness, flange, whirl, vibration, spectrum, trends, plausibility guards
    7  results      the record: solver output -> Dataset -> NetCDF (and back: readers)
    8  plots        figures from a result Dataset
    9  api          simulate, solve_static, save (bearingdae/api.py)
   10  studies      many runs: sweep, work-precision, paper set, skid map
   11  cli          the ``bearingdae`` program

``analysis`` sits *below* ``results`` although it reads results: the record of every run
computes the engineering, whirl, flange and vibration variables, the statistics and the
plausibility findings into the Dataset it builds (results/dataset.py,
results/streamed_record.py), so the record imports the analysis and the analysis imports no record module (a function of the
analysis takes arrays or an ``xarray.Dataset``, never a ``bearingdae.results`` object).

``from bearingdae import name`` of a flat-API name counts as an import of the root (whose
``__getattr__`` loads the module on first use). Any other module at the package root, or a
folder missing from ``LAYERS``, is reported as an error: new code goes into the folder of the
stage it serves.

Usage: ``python tools/check_imports.py [--quiet]``; exit status 1 when a cycle, an upward import
or a misplaced module exists. tests/tools/test_layering.py runs it.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

PACKAGE = "bearingdae"
ROOT = Path(__file__).resolve().parents[1] / PACKAGE

#: the layers, lowest first: (name, folders under bearingdae/ that form it)
LAYERS = [
    ("root/util", ["", "util"]),
    ("scene", ["scene"]),
    ("physics", ["physics"]),
    ("system", ["system"]),
    ("solvers", ["solvers"]),
    ("run", ["run"]),
    ("analysis", ["analysis"]),
    ("results", ["results"]),
    ("plots", ["plots"]),
    ("api", ["api"]),
    ("studies", ["studies"]),
    ("cli", ["cli"]),
]
#: the only modules allowed at the package root (besides folders)
ROOT_MODULES = {"": "", "api": "api", "__main__": "cli"}


def module_name(path: Path) -> str:
    rel = path.relative_to(ROOT.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def modules() -> dict[str, Path]:
    return {module_name(p): p for p in sorted(ROOT.rglob("*.py"))}


def folder(mod: str) -> str:
    """The folder (layer key) of a module: ``bearingdae.run.steady`` -> ``run``; root modules
    map through ``ROOT_MODULES``."""
    parts = mod.split(".")[1:]
    if len(parts) <= 1 and not (parts and (ROOT / parts[0]).is_dir()):
        name = parts[0] if parts else ""
        if name not in ROOT_MODULES:
            raise SystemExit(f"check_imports: module {mod} sits at the package root; move it "
                             "to the folder of the stage it serves")
        return ROOT_MODULES[name]
    return parts[0]


def layer(mod: str) -> int:
    key = folder(mod)
    for i, (_, folders) in enumerate(LAYERS):
        if key in folders:
            return i
    raise SystemExit(f"check_imports: folder bearingdae/{key} has no layer; add it to LAYERS")


def misplaced() -> list[str]:
    """Modules at the package root that are not the public API."""
    out = []
    for mod in modules():
        parts = mod.split(".")[1:]
        if len(parts) == 1 and parts[0] not in ROOT_MODULES and not (ROOT / parts[0]).is_dir():
            out.append(mod)
    return out


def _is_main_guard(node: ast.If) -> bool:
    t = node.test
    return (isinstance(t, ast.Compare) and isinstance(t.left, ast.Name)
            and t.left.id == "__name__" and any(isinstance(c, ast.Constant)
                                                and c.value == "__main__"
                                                for c in t.comparators))


def _is_type_checking(node: ast.If) -> bool:
    t = node.test
    return (isinstance(t, ast.Name) and t.id == "TYPE_CHECKING") or (
        isinstance(t, ast.Attribute) and t.attr == "TYPE_CHECKING")


def imports_of(mod: str, path: Path, known: set[str]):
    """[(imported module, line, counted)] of one module; ``counted`` False for the exceptions."""
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    is_pkg = path.name == "__init__.py"
    base = mod.split(".") if is_pkg else mod.split(".")[:-1]
    out = []

    def resolve(node: ast.ImportFrom) -> str:
        if node.level == 0:
            return node.module or ""
        parent = base[: len(base) - (node.level - 1)]
        return ".".join(parent + ([node.module] if node.module else []))

    def visit(node, counted: bool):
        for child in ast.iter_child_nodes(node):
            c = counted
            if isinstance(child, ast.If) and (_is_main_guard(child) or _is_type_checking(child)):
                for sub in child.body:
                    visit_one(sub, False)
                for sub in child.orelse:
                    visit_one(sub, counted)
                continue
            visit_one(child, c)

    def visit_one(child, counted):
        if isinstance(child, ast.Import):
            for a in child.names:
                if a.name.split(".")[0] == PACKAGE:
                    out.append((_known(a.name, known), child.lineno, counted))
        elif isinstance(child, ast.ImportFrom):
            target = resolve(child)
            if target.split(".")[0] != PACKAGE:
                return
            for a in child.names:
                sub = f"{target}.{a.name}"
                out.append((sub if sub in known else _known(target, known), child.lineno,
                            counted))
        visit(child, counted)

    visit(tree, True)
    return out


def _known(name: str, known: set[str]) -> str:
    while name and name not in known:
        name = name.rpartition(".")[0]
    return name or PACKAGE


def graph():
    mods = modules()
    known = set(mods)
    edges: dict[str, set[str]] = {m: set() for m in mods}
    lines: dict[tuple[str, str], int] = {}
    skipped = []
    for m, p in mods.items():
        for target, line, counted in imports_of(m, p, known):
            if target == m:
                continue
            if not counted:
                skipped.append((m, target, line))
                continue
            edges[m].add(target)
            lines.setdefault((m, target), line)
    return edges, lines, skipped


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def strong(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v), on.add(v)
        for w in sorted(edges[v]):
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(edges):
        if v not in index:
            strong(v)
    return out


def upward(edges, lines) -> list[tuple[str, str, int]]:
    out = []
    for m in sorted(edges):
        for t in sorted(edges[m]):
            if layer(t) > layer(m):
                out.append((m, t, lines[(m, t)]))
    return out


def report() -> tuple[list, list, list]:
    bad = misplaced()
    if bad:
        raise SystemExit("check_imports: modules at the package root that are not the public "
                         f"API: {', '.join(bad)}")
    edges, lines, skipped = graph()
    return cycles(edges), upward(edges, lines), skipped


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    cyc, up, skipped = report()
    print(f"import cycles: {len(cyc)}")
    for c in cyc:
        print("  " + " <-> ".join(c))
    print(f"upward imports: {len(up)}")
    for m, t, line in up:
        print(f"  {m}:{line} ({LAYERS[layer(m)][0]}) imports {t} ({LAYERS[layer(t)][0]})")
    if "--quiet" not in argv and skipped:
        print(f"not counted ({len(skipped)}: __main__ blocks, TYPE_CHECKING):")
        for m, t, line in skipped:
            print(f"  {m}:{line} -> {t}")
    return 1 if (cyc or up) else 0


if __name__ == "__main__":
    sys.exit(main())
