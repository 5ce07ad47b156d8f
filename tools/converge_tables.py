"""Regenerate the convergence tables of docs/validation.md: ``python tools/converge_tables.py``.

Runs ``bearingdae converge`` on each scene of :data:`SCENES` (the scene's own window; each
table's caption says the window and the command) and writes, per scene,
``docs/data/converge_<name>.md`` (the table the page includes), ``.csv`` beside it and the
figure ``docs/figures/converge_<name>.png``; the NetCDF files go to a temporary folder (or to
``--keep DIR``). Prints the wall and CPU time of each scene. Run it from a checkout whose
package is the one on the path (``PYTHONPATH=. python tools/converge_tables.py``).
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: table name -> (bundled case, extra command-line options)
SCENES = {"yang20_baseline": ("yang20_baseline", []),
          "harris36_5000rpm": ("paper/harris36_5000rpm", [])}


def main(argv=None) -> int:
    from bearingdae.cli import main as bearingdae

    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--keep", type=Path, help="folder for the NetCDF files (default: temporary)")
    p.add_argument("--only", choices=sorted(SCENES), help="one scene only")
    args = p.parse_args(argv)
    data, figures = ROOT / "docs" / "data", ROOT / "docs" / "figures"
    with tempfile.TemporaryDirectory() as scratch:
        folder = args.keep or Path(scratch)
        for name, (case, options) in SCENES.items():
            if args.only and name != args.only:
                continue
            nc = folder / f"converge_{name}.nc"
            wall, cpu = time.perf_counter(), time.process_time()
            rc = bearingdae(["converge", case, *options, "--no-progress", "-o", str(nc),
                             "--table", str(data / f"converge_{name}.md")])
            wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
            if rc != 0:
                print(f"converge_tables: {name} failed (status {rc})", file=sys.stderr)
                return rc
            shutil.copyfile(nc.with_suffix(".png"), figures / f"converge_{name}.png")
            print(f"converge_tables: {name}: {wall:.0f} s wall, {cpu:.0f} s CPU")
    return 0


if __name__ == "__main__":
    sys.exit(main())
