"""``bearingdae keys`` and ``bearingdae cases``: the scene keys and the bundled cases.

Pipeline: the cli layer over scene (key table, case lookup).
"""

from __future__ import annotations

from pathlib import Path


def _keys(args) -> int:
    from ..scene import key_table

    rows = key_table()
    if args.markdown:  # the documentation's scene-key page, generated from the same schema
        from ..scene.keydoc import key_reference

        print(key_reference())
    else:
        print(f"{'key':34s} {'default':>10s} {'allowed':>18s}  meaning")
        for key, default, rng, desc in rows:
            print(f"{key:34s} {default:>10s} {rng:>18s}  {desc}")
    return 0


def _cases(args) -> int:
    from ..scene import bundled_case_dirs, resolve_case
    from ..studies.sweep import is_sweep_file

    if args.copy:
        from ..util.atomic import atomic_write, check_writable
        from ..scene.files import read_input

        name, dest = args.copy
        source = resolve_case(name)
        dest = check_writable(Path(dest))
        if dest.exists():
            raise ValueError(f"cases --copy: '{dest}' exists already; give a new file name")
        text = read_input(source, "scene file")
        with atomic_write(dest) as tmp:
            Path(tmp).write_bytes(text)
        print(f"wrote {dest} (a copy of {source.name}); edit it, then: bearingdae run {dest}")
        return 0
    seen = set()
    for d in bundled_case_dirs():
        for p in sorted(d.rglob("*.toml")):
            rel = p.relative_to(d).with_suffix("")
            if rel in seen:
                continue
            seen.add(rel)
            tag = "  (sweep: bearingdae sweep NAME)" if is_sweep_file(p) else ""
            name = str(p if args.path else rel)
            print(f"{name:38s} {case_summary(p)}{tag}" if not args.path else f"{name}{tag}")
    return 0


def case_summary(path: Path, width: int = 90) -> str:
    """What a bundled case is: the first sentence of its leading comment, on one line."""
    import re

    lines = []
    try:
        for line in path.read_text(encoding="utf-8").splitlines():
            if not line.startswith("#"):
                break
            lines.append(line.lstrip("#").strip())
    except (OSError, UnicodeDecodeError):
        return ""
    text = re.sub(r"\s*\(issue \d+\)", "", " ".join(lines))  # history is CHANGELOG.md's
    text = re.split(r"(?<=[a-z0-9)])\.\s+(?=[A-Z])", text)[0].rstrip(".")  # not "et al. 2024"
    return text if len(text) <= width else text[:width - 1].rstrip() + "…"
