"""``python -m bearingdae.cli``: the ``bearingdae`` program (bearingdae/program.py)."""

import sys

if __name__ == "__main__":  # pragma: no cover
    from bearingdae.program import main as program

    sys.exit(program())
