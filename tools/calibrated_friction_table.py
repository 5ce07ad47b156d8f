"""Regenerate docs/data/calibrated_friction.csv and .md:
``PYTHONPATH=. python tools/calibrated_friction_table.py``.

What one measured torque buys (docs/user-guide.md, "Calibrating on one torque"): for each
bundled bearing, the model with the friction switches on (Biboulet & Houpert's rolling
resistance and mixed lubrication; tools/catalogue_friction.MODELS["switches"]) is calibrated
at :data:`CAL_POINT` to the SKF model's torque there (studies/calibrate.py, as ``bearingdae
calibrate`` does), then run with that inlet film at the other points of :data:`GRID`. Each
row: the film, the model's friction torque without the drag, SKF's, and whether the model
lies within the band from 0.5x to 2x the catalogue model. Only SKF's model is typed in this
repository (tools/skf_friction.py); no Schaeffler model is, so the band is SKF's alone.
Every run starts from the torque-balance estimate of the steady speeds and records
:data:`WINDOW` cage revolutions (as tools/inlet_film_table.py; shorter than the friction maps'
runs until steady). tests/docs/test_calibrated_friction_table.py checks one row against a
fresh run.
"""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
OUT = ROOT / "docs" / "data" / "calibrated_friction"
COLUMNS = ("bearing", "speed_rpm", "radial_load_N", "inlet_film_um", "calibration_point",
           "model_N_mm", "skf_N_mm", "ratio", "within_band")
#: the point at which each bearing is calibrated (r/min, N)
CAL_POINT = (2000.0, 2000.0)
#: the other points (a subset of the catalogue grid, tools/catalogue_friction.py)
GRID = ((500.0, 400.0), (2000.0, 8000.0), (6000.0, 2000.0), (10000.0, 400.0),
        (10000.0, 8000.0))
#: the band around the catalogue model (the issue's 0.5x the smaller, 2x the larger)
BAND = (0.5, 2.0)


#: recorded cage revolutions per run
WINDOW = 0.5


def _overrides(speed, load, film=None):
    from catalogue_friction import MODELS

    over = {**MODELS["switches"], "operating.speed_rpm": speed, "operating.radial_load_N": load,
            "operating.moment_Nm": 0.0, "numerics.initial_speeds": "torque_balance",
            "numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": WINDOW}
    if film is not None:
        over["lubricant.inlet_film_um"] = float(film)
    return over


def torque_N_mm(case: str, speed, load, film) -> float:
    """The friction torque without the drag [N mm] of one run (studies/calibrate's measure)."""
    from bearingdae.studies.calibrate import _run_torque
    from bearingdae import load_scene

    return _run_torque(load_scene(case, _overrides(speed, load, film)))


def rows(bearings) -> list[dict]:
    import skf_friction as skf
    from catalogue_friction import CASES

    from bearingdae.studies.calibrate import calibrate_inlet_film
    from bearingdae import load_scene

    out = []
    for bearing in bearings:
        case = CASES[bearing]
        n, F = CAL_POINT
        target = skf.friction_torque_N_m(bearing, n, F) * 1e3
        fit = calibrate_inlet_film(lambda film: load_scene(case, _overrides(n, F, film)), target,
                                   progress=lambda s: print(f"{bearing}: {s}", flush=True))
        out.append({"bearing": bearing, "speed_rpm": n, "radial_load_N": F,
                    "inlet_film_um": fit.film_um, "calibration_point": 1,
                    "model_N_mm": fit.torque_N_mm, "skf_N_mm": target})
        for n, F in GRID:
            T = torque_N_mm(case, n, F, fit.film_um)
            print(f"{bearing}: {n:.0f} r/min, {F:.0f} N: {T:.4g} N mm", flush=True)
            out.append({"bearing": bearing, "speed_rpm": n, "radial_load_N": F,
                        "inlet_film_um": fit.film_um, "calibration_point": 0,
                        "model_N_mm": T, "skf_N_mm": skf.friction_torque_N_m(bearing, n, F) * 1e3})
    for r in out:
        r["ratio"] = r["model_N_mm"] / r["skf_N_mm"]
        r["within_band"] = int(BAND[0] <= r["ratio"] <= BAND[1])
    return out


def markdown(table: list[dict]) -> str:
    lines = ["| bearing | speed [r/min] | radial load [N] | inlet film [µm] | model, drag "
             "excluded [N mm] | SKF [N mm] | model / SKF | within 0.5–2x |",
             "|---|---|---|---|---|---|---|---|"]
    for r in table:
        mark = " (calibrated here)" if r["calibration_point"] else ""
        lines.append(f"| {r['bearing']} | {r['speed_rpm']:.0f} | {r['radial_load_N']:.0f}"
                     f"{mark} | {r['inlet_film_um']:.3g} | {r['model_N_mm']:.3g} | "
                     f"{r['skf_N_mm']:.3g} | {r['ratio']:.2f} | "
                     f"{'yes' if r['within_band'] else 'no'} |")
    return "\n".join(lines) + "\n"


def write(table: list[dict]) -> None:
    with open(OUT.with_suffix(".csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS, lineterminator="\n")
        w.writeheader()
        for r in table:
            w.writerow({k: (f"{r[k]:.6g}" if isinstance(r[k], float) else r[k])
                        for k in COLUMNS})
    OUT.with_suffix(".md").write_text(markdown(read()), encoding="utf-8")


def read() -> list[dict]:
    with open(OUT.with_suffix(".csv"), newline="") as f:
        return [{k: (v if k == "bearing" else float(v)) for k, v in r.items()}
                for r in csv.DictReader(f)]


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--bearings", nargs="+", default=None, help="default: both bundled")
    args = p.parse_args(argv)
    from catalogue_friction import CASES

    bearings = args.bearings or list(CASES)
    new = rows(bearings)
    kept = [r for r in read() if r["bearing"] not in bearings] if OUT.with_suffix(
        ".csv").exists() else []  # the other bearings' rows, as last written
    write(sorted(kept + new, key=lambda r: list(CASES).index(r["bearing"])))
    print(f"wrote {OUT}.csv, .md")
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))
    sys.exit(main())
