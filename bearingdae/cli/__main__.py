"""``python -m bearingdae.cli``: the ``bearingdae`` program (bearingdae/cli/program.py)."""

import sys

if __name__ == "__main__":  # pragma: no cover
    from bearingdae.cli.program import main as program

    sys.exit(program())
