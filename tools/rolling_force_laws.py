"""Regenerate docs/data/rolling_force_laws.csv: ``PYTHONPATH=. python tools/rolling_force_laws.py``.

The published line-contact rolling-force laws of bearingdae/physics/rolling_force_laws.py
(Biboulet & Houpert, Goksem & Hargreaves, Zhou & Hoeprich) on B&H's dimensionless interface,
one row per law per point of a grid over B&H's range of validity: L = 4-16, M_l = 0.2-200
(at their steel value G = 4520), fully flooded (S empty) and at S = H_a/H_m* = 0.5, 1, 2.
Columns ``law, U, W, G, S, F_tilde``: U, W, G of B&H's eq. (14) (U = 2 η₀ u_m / (E'R)),
F_tilde = rolling force per unit length / (E'R). tests/physics/test_rolling_force_laws.py
regenerates the rows and compares them with the file.
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "data" / "rolling_force_laws.csv"
COLUMNS = ("law", "U", "W", "G", "S", "F_tilde")
#: the grid: B&H's L and M_l range (their section 3.3), and the starvation ratios
L_VALUES = (4.0, 8.0, 12.0, 16.0)
M_VALUES = tuple(float(m) for m in np.logspace(np.log10(0.2), np.log10(200.0), 7))
S_VALUES = (None, 0.5, 1.0, 2.0)  # None: fully flooded


def rows() -> list[dict]:
    """The table: every law at every (L, M_l, S) of the grid."""
    from bearingdae.physics.rolling_force_laws import (BH_STEEL_G, LAWS,
                                                       dimensionless_from_moes, rolling_force)

    out = []
    for law in LAWS:
        for L in L_VALUES:
            for M in M_VALUES:
                U, W, G = (float(x) for x in dimensionless_from_moes(M, L, BH_STEEL_G))
                for S in S_VALUES:
                    F = float(rolling_force(law, U, W, G, np.nan if S is None else S))
                    out.append({"law": law, "U": U, "W": W, "G": G, "S": S, "F_tilde": F})
    return out


def write(path: Path = OUT) -> int:
    """Write the CSV (10 significant digits; S empty when flooded); the number of rows."""
    table = rows()
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(COLUMNS)
        for r in table:
            w.writerow([r["law"], f"{r['U']:.10g}", f"{r['W']:.10g}", f"{r['G']:.10g}",
                        "" if r["S"] is None else f"{r['S']:g}", f"{r['F_tilde']:.10g}"])
    return len(table)


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))
    print(f"wrote {write()} rows to {OUT.relative_to(ROOT)}")
