"""Regenerate docs/data/inlet_film.csv and .md: ``PYTHONPATH=. python tools/inlet_film_table.py``.

How the friction and the cage respond to ``lubricant.inlet_film_um`` (docs/user-guide.md,
"How much oil reaches the contact"): the yang20 baseline scene at one operating point, with
Biboulet & Houpert's rolling resistance (``physics.rolling_resistance = true``), fully flooded
and at a few inlet films; each run starts from the torque-balance estimate of the steady
speeds and records :data:`WINDOW` cage revolutions. Columns: the film (empty: flooded), the
mean friction torque without the drag [N mm] (studies/calibrate.catalogue_torque_N_mm), the
rolling resistance's mean power [W], the mean total power loss [W] and the cage slip ratio.
tests/docs/test_inlet_film_table.py regenerates the rows and compares them with the file.
"""

from __future__ import annotations

import csv
import sys
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "data" / "inlet_film"
COLUMNS = ("inlet_film_um", "friction_torque_N_mm", "rolling_resistance_W", "power_loss_W",
           "cage_slip_ratio")
#: the scene: the bundled baseline at this operating point, rolling resistance on
CASE = "yang20_baseline"
POINT = {"operating.speed_rpm": 10000.0, "operating.radial_load_N": 400.0,
         "operating.moment_Nm": 0.0, "physics.rolling_resistance": True,
         "numerics.initial_speeds": "torque_balance", "numerics.warmup_cage_revolutions": 0.0}
#: recorded cage revolutions per run
WINDOW = 0.5
#: the films [µm] (None: fully flooded)
FILMS_UM = (None, 10.0, 1.0, 0.3, 0.1)


def rows() -> list[dict]:
    """One row per film of :data:`FILMS_UM` (a run each)."""
    from bearingdae import load_scene, simulate
    from bearingdae.analysis.summary import cage_slip_ratio
    from bearingdae.studies.calibrate import catalogue_torque_N_mm

    out = []
    for film in FILMS_UM:
        over = {**POINT, "numerics.cage_revolutions": WINDOW}
        if film is not None:
            over["lubricant.inlet_film_um"] = film
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ds = simulate(load_scene(CASE, over), progress=False)
        P = ds.power_loss_W.mean("time")
        out.append({"inlet_film_um": film, "friction_torque_N_mm": catalogue_torque_N_mm(ds),
                    "rolling_resistance_W": float(P.sel(loss_source="rolling_resistance")),
                    "power_loss_W": float(P.sum()), "cage_slip_ratio": cage_slip_ratio(ds)})
    return out


def write(table: list[dict]) -> None:
    with open(OUT.with_suffix(".csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for r in table:
            w.writerow({k: "" if r[k] is None else f"{r[k]:.6g}" for k in COLUMNS})
    lines = ["| inlet film [µm] | friction torque, drag excluded [N mm] | rolling resistance "
             "[W] | total power loss [W] | cage slip |", "|---|---|---|---|---|"]
    for r in table:
        film = "flooded" if r["inlet_film_um"] is None else f"{r['inlet_film_um']:g}"
        lines.append(f"| {film} | {r['friction_torque_N_mm']:.3g} | "
                     f"{r['rolling_resistance_W']:.3g} | {r['power_loss_W']:.3g} | "
                     f"{100 * r['cage_slip_ratio']:.1f} % |")
    OUT.with_suffix(".md").write_text("\n".join(lines) + "\n", encoding="utf-8")


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))
    write(rows())
    print(f"wrote {OUT}.csv, .md")
