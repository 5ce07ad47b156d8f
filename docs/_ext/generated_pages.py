"""Pages of the documentation written at build time (called by docs/conf.py).

* ``_generated/scene-keys.md``: every scene key, from the scene schema
  (:func:`bearingdae.scene.keydoc.key_reference`), so that a key added to the schema appears
  without editing a document.
* ``_generated/changelog.md``: the repository's ``CHANGELOG.md`` (a MyST include) if it
  exists, else a line saying this checkout has none.

``docs/_generated/`` is kept out of git.
"""

from __future__ import annotations

from pathlib import Path

GENERATED = "_generated"


def write_pages(docs: Path) -> list[Path]:
    """Write the generated pages under ``docs/_generated/``; return their paths.

    A page is rewritten only when its text changed, so that an incremental build does not
    re-read unchanged pages.
    """
    from bearingdae.scene.keydoc import key_reference

    out = Path(docs) / GENERATED
    out.mkdir(exist_ok=True)
    changelog = Path(docs).resolve().parent / "CHANGELOG.md"
    if changelog.is_file():
        changes = f"```{{include}} ../../CHANGELOG.md\n```\n"
    else:
        changes = "# Changelog\n\nThis checkout has no `CHANGELOG.md`.\n"
    pages = {"scene-keys.md": key_reference(), "changelog.md": changes}
    written = []
    for name, text in pages.items():
        path = out / name
        if not path.is_file() or path.read_text(encoding="utf-8") != text:
            path.write_text(text, encoding="utf-8")
        written.append(path)
    return written
