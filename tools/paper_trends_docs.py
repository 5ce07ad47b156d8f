"""Copy the output of two ``bearingdae paper --trends`` runs into docs/data/ and regenerate the
parts of docs/validation.md made from them (tests/docs/test_trends_page.py checks they agree).

    python tools/paper_trends_docs.py RUN_DIR REPEAT_DIR [--figures]

RUN_DIR: the reference (``bearingdae paper --trends -o RUN_DIR``); REPEAT_DIR: the same from
another start state, recorded after the reference's window (``--set
numerics.warmup_cage_revolutions=34``: the runs are deterministic, so a shorter extra warm-up
would record mostly the same revolutions). ``--figures`` also copies
RUN_DIR's figures to docs/figures/trends/.
"""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main(argv: list[str]) -> int:
    from bearingdae.studies.trends_report import DOCS_STEMS, docs_pages

    run, repeat = Path(argv[0]), Path(argv[1])
    data = ROOT / "docs" / "data"
    data.mkdir(exist_ok=True)
    for stem, folder in zip(DOCS_STEMS, (run, repeat)):
        for suffix in ("", "_verdicts", "_levels"):
            shutil.copyfile(folder / f"trends{suffix}.csv", data / f"{stem}{suffix}.csv")
    for name, text in docs_pages(data).items():
        (data / name).write_text(text, encoding="utf-8")
        print(f"wrote docs/data/{name}")
    if "--figures" in argv:
        figures = ROOT / "docs" / "figures" / "trends"
        figures.mkdir(parents=True, exist_ok=True)
        for png in sorted(run.glob("trends_*.png")):
            shutil.copyfile(png, figures / png.name)
        print(f"copied the figures to {figures.relative_to(ROOT)}/")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
