"""Regenerate the term-by-term catalogue comparison of docs/user-guide.md:
``PYTHONPATH=. python tools/catalogue_terms.py --keep DIR`` (DIR: tools/catalogue_friction.py's
``--keep`` folder, whose friction maps it reads; run that first).

Two tables:

* ``terms`` (``docs/data/catalogue_terms.csv`` and ``.md``): at every point of the catalogue
  grid, the model's rolling, sliding and drag moments (the friction map of the model with the
  switches on, tools/catalogue_friction.MODELS["switches"]: Biboulet & Houpert's law, mixed
  lubrication; each source's mean power over the inner ring's speed) beside SKF's M_rr, M_sl
  and M_drag (tools/skf_friction.py; no drag for oil-air lubrication), and the band of the
  three published rolling laws at that point (bearingdae/studies/rolling_band.py: each law's
  rolling moment at the quasi-static loads and pure rolling), fully flooded and at the inlet
  film :data:`BAND_FILM_UM`.
* ``skid`` (``docs/data/catalogue_skid_band.csv`` and ``.md``): Fig 11's setting (harris36,
  5000 r/min) over its loads, the torque balance's cage speed over the epicyclic one for the
  paper's model and for each law with mixed lubrication (bearingdae/studies/skid_band.py), and
  each one's skid boundary beside the SKF minimum load of a cylindrical roller bearing,
  F_rm = k_r (6 + 4 n/n_r) (d_m/100)² kN, written as the minimum load factor k_r at which it
  equals the boundary (k_r and the reference speed n_r are product-table values; this bearing
  is no catalogue bearing).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
from catalogue_friction import read_csv, write_csv  # noqa: E402 (the same CSV format)

DATA = ROOT / "docs" / "data"
#: the stated inlet film of the band's starved columns [µm] (oil-air's rule of thumb, 0.1-1 µm,
#: docs/user-guide.md "How much oil reaches the contact")
BAND_FILM_UM = 1.0
LAW_SHORT = {"biboulet_houpert": "bh", "goksem_hargreaves": "gh", "zhou_hoeprich": "zh"}
TERMS_COLUMNS = (["bearing", "speed_rpm", "radial_load_N", "skf_rolling_N_mm",
                  "skf_sliding_N_mm", "skf_drag_N_mm", "model_rolling_N_mm",
                  "model_sliding_N_mm", "model_drag_N_mm", "model_cage_slip"]
                 + [f"{s}_{f}_N_mm" for f in ("flooded", "starved") for s in LAW_SHORT.values()])
#: Fig 11's setting and loads (cases/paper/harris36_cage_speed.toml)
SKID_CASE, SKID_BEARING, SKID_SPEED_RPM = "paper/harris36_5000rpm", "harris36", 5000.0
SKID_LOADS_N = (0.0, 250.0, 500.0, 1000.0, 1500.0, 2000.0, 3000.0, 4000.0, 5000.0, 6000.0,
                8000.0, 10000.0, 12000.0)
#: the skid table's models: the paper's, and each law with mixed lubrication
SKID_MODELS = {"paper": {},
               **{s: {"physics.rolling_resistance": law, "physics.lubrication": "mixed"}
                  for law, s in LAW_SHORT.items()}}
SKID_COLUMNS = ["radial_load_N"] + [f"{m}_cage_speed_ratio" for m in SKID_MODELS]


def minimum_load_kN_per_kr(n_over_nr: float, dm_mm: float) -> float:
    """SKF's minimum radial load of a cylindrical roller bearing over its minimum load factor,
    F_rm / k_r = (6 + 4 n/n_r) (d_m/100)² [kN]."""
    return (6.0 + 4.0 * n_over_nr) * (dm_mm / 100.0) ** 2


def terms_rows(folder: Path) -> list[dict]:
    import skf_friction as skf
    from catalogue_friction import CASES, LOADS_N, MODELS, SPEEDS_RPM, _stored

    from bearingdae.studies.friction import DRAG_SOURCES, make_sweep, map_dataset
    from bearingdae.studies.rolling_band import rolling_moments_N_m

    rows = []
    for bearing, case in CASES.items():
        name = f"friction_{bearing}_switches"
        ds = map_dataset(_stored(make_sweep(case, SPEEDS_RPM, LOADS_N, MODELS["switches"],
                                            name=name), folder, name), folder)
        d, D = skf.BEARINGS_MM[bearing]
        for n in SPEEDS_RPM:
            w = n * math.pi / 30.0
            for F in LOADS_N:
                m = skf.frictional_moment_Nmm(n, F, d, D, skf.kinematic_viscosity_mm2_s())
                pt = ds.sel(speed_rpm=n, radial_load_N=F)
                P = {str(s): float(p) for s, p in zip(ds.loss_source.values,
                                                      pt.power_loss_by_source_W.values)}
                drag = sum(P.get(s, 0.0) for s in DRAG_SOURCES)
                roll = P.get("rolling_resistance", float("nan"))
                total = sum(P.values()) if P else float("nan")
                row = {"bearing": bearing, "speed_rpm": n, "radial_load_N": F,
                       "skf_rolling_N_mm": m["rolling"], "skf_sliding_N_mm": m["sliding"],
                       "skf_drag_N_mm": 0.0,
                       "model_rolling_N_mm": roll / w * 1e3,
                       "model_sliding_N_mm": (total - roll - drag) / w * 1e3,
                       "model_drag_N_mm": drag / w * 1e3,
                       "model_cage_slip": float(pt.cage_slip_ratio)}
                band = rolling_moments_N_m(case, {**MODELS["switches"],
                                                  "operating.speed_rpm": n,
                                                  "operating.radial_load_N": F},
                                           (None, BAND_FILM_UM))
                for (law, film), M in band.items():
                    key = "flooded" if film is None else "starved"
                    row[f"{LAW_SHORT[law]}_{key}_N_mm"] = M * 1e3
                rows.append(row)
    return rows


def skid_rows() -> list[dict]:
    from bearingdae.studies.skid_band import cage_speed_fractions

    cols = {m: cage_speed_fractions(SKID_CASE, SKID_LOADS_N,
                                    {**over, "operating.speed_rpm": SKID_SPEED_RPM})
            for m, over in SKID_MODELS.items()}
    return [{"radial_load_N": F, **{f"{m}_cage_speed_ratio": cols[m][i] for m in SKID_MODELS}}
            for i, F in enumerate(SKID_LOADS_N)]


def _g(x: float) -> str:
    return "–" if x != x else (f"{x:.0f}" if abs(x) >= 100 else f"{x:.3g}")


def terms_markdown(rows: list[dict]) -> str:
    """The user guide's term-by-term table from docs/data/catalogue_terms.csv."""
    def band(r, key):
        v = [r[f"{s}_{key}_N_mm"] for s in LAW_SHORT.values()]
        return f"{_g(min(v))}–{_g(max(v))}"

    lines = ["| bearing | speed [r/min] | load [N] | SKF M_rr | model rolling (B&H) | "
             "laws flooded | laws at "
             f"{BAND_FILM_UM:g} µm | SKF M_sl | model sliding | model drag (SKF: none) | "
             "cage slip |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(
            f"| {r['bearing']} | {r['speed_rpm']:.0f} | {r['radial_load_N']:.0f} "
            f"| {_g(r['skf_rolling_N_mm'])} | {_g(r['model_rolling_N_mm'])} "
            f"| {band(r, 'flooded')} | {band(r, 'starved')} "
            f"| {_g(r['skf_sliding_N_mm'])} | {_g(r['model_sliding_N_mm'])} "
            f"| {_g(r['model_drag_N_mm'])} | {100 * r['model_cage_slip']:.1f} % |")
    return "\n".join(lines) + "\n"


def skid_boundaries(rows: list[dict]) -> dict[str, float]:
    from bearingdae.studies.skid_band import skid_boundary_N

    loads = [r["radial_load_N"] for r in rows]
    return {m: skid_boundary_N(loads, [r[f"{m}_cage_speed_ratio"] for r in rows])
            for m in SKID_MODELS}


def skid_markdown(rows: list[dict]) -> str:
    """The skid-boundary table from docs/data/catalogue_skid_band.csv: the cage speed per
    model, then each boundary and the k_r at which SKF's minimum load equals it."""
    import skf_friction as skf

    names = {"paper": "paper model", "bh": "B&H + mixed", "gh": "Goksem + mixed",
             "zh": "Zhou + mixed"}
    lines = ["| radial load [N] | " + " | ".join(names[m] for m in SKID_MODELS) + " |",
             "|---|" + "---|" * len(SKID_MODELS)]
    for r in rows:
        lines.append(f"| {r['radial_load_N']:.0f} | " + " | ".join(
            f"{r[f'{m}_cage_speed_ratio']:.4f}" for m in SKID_MODELS) + " |")
    d, D = skf.BEARINGS_MM[SKID_BEARING]
    per_kr = minimum_load_kN_per_kr(1.0, 0.5 * (d + D))
    bound = skid_boundaries(rows)
    lines.append("| **skid boundary [N]** | " + " | ".join(
        f"**{bound[m]:.0f}**" for m in SKID_MODELS) + " |")
    lines.append("| k_r at which F_rm (n = n_r) equals it | " + " | ".join(
        f"{bound[m] / 1e3 / per_kr:.3f}" for m in SKID_MODELS) + " |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--keep", type=Path, help="tools/catalogue_friction.py's --keep folder")
    p.add_argument("--only", choices=("terms", "skid"))
    args = p.parse_args(argv)
    if args.only != "skid":
        if args.keep is None:
            p.error("--keep: the folder of tools/catalogue_friction.py's runs")
        write_csv(terms_rows(args.keep), TERMS_COLUMNS, DATA / "catalogue_terms.csv")
        rows = read_csv(DATA / "catalogue_terms.csv")
        (DATA / "catalogue_terms.md").write_text(terms_markdown(rows), encoding="utf-8")
    if args.only != "terms":
        write_csv(skid_rows(), SKID_COLUMNS, DATA / "catalogue_skid_band.csv")
        rows = read_csv(DATA / "catalogue_skid_band.csv")
        (DATA / "catalogue_skid_band.md").write_text(skid_markdown(rows), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))
    sys.exit(main())
