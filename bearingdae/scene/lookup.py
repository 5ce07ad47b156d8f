"""Where scene files are found: a path as given, or a bundled case by name (pipeline stage 1).

The bundled cases are the top-level ``cases/`` folder, shipped in the wheel as
``bearingdae/cases`` (pyproject.toml).
"""

from __future__ import annotations

from pathlib import Path

from ..util.atomic import shown_path
from .errors import SceneError, close_matches

def resolve_case(path: str | Path) -> Path:
    """A path as given, or the bundled case of that name (``yang20_baseline``)."""
    p = Path(path)
    if _exists(p):
        return p
    name = p.name if p.suffix == ".toml" else p.name + ".toml"
    rel = p if p.suffix == ".toml" else Path(f"{p}.toml")  # "extreme/zero_speed" as written
    for folder in bundled_case_dirs():
        for cand in (folder / rel, folder / name, folder / "extreme" / name,
                     folder / "paper" / name):
            if _exists(cand):
                return cand
    # Bundled names as `bearingdae cases` lists them (extreme/... included); a typo is matched
    # against each name's last part.
    names = sorted({q.relative_to(d).with_suffix("").as_posix()
                    for d in bundled_case_dirs() for q in d.rglob("*.toml")})
    leaf = {n.rsplit("/", 1)[-1]: n for n in names}
    close = close_matches(p.stem, list(leaf), n=1)
    hint = f" Did you mean the bundled case '{leaf[close[0]]}'?" if close else ""
    raise SceneError(
        f"scene file '{shown_path(path)}' does not exist and is not a bundled case "
        f"(bundled: {', '.join(names)}).{hint}"
    )


def _exists(p: Path) -> bool:
    """``p.exists()``, but False for names the OS rejects (too long, NUL bytes)."""
    try:
        return p.exists()
    except (OSError, ValueError):
        return False


def bundled_case_dirs() -> list[Path]:
    """Folders holding the bundled cases: the installed package data, then a source checkout."""
    # Installed wheels carry the top-level cases/ folder as bearingdae/cases (pyproject.toml);
    # it is a data folder, not an importable module, so it is found beside the package folder
    # holding this file (bearingdae/scene/ -> bearingdae/).
    here = Path(__file__).resolve().parents[1]
    return [d for d in (here / "cases", here.parent / "cases") if d.is_dir()]
