"""Regenerate the catalogue comparison of docs/user-guide.md: ``python tools/catalogue_friction.py``.

Three studies, each run for the paper's model (every switch at its default), for the model
with the friction switches on (Biboulet & Houpert's rolling law, the default) and for the same
with Goksem & Hargreaves's law (:data:`MODELS`):

* ``friction``: the steady total friction torque of yang20 and harris36 over speed x radial
  load (bearingdae/studies/friction.py), beside the SKF catalogue model typed independently
  in tools/skf_friction.py. Writes ``docs/data/catalogue_friction.csv`` and ``.md``
  (the table the user guide includes) and ``docs/figures/catalogue_friction.png``.
* ``geometry``: yang20 with the switches at two speeds, with its rollers and with rollers half
  as long (the catalogue has no input for them). Writes ``docs/data/catalogue_geometry.csv``
  and ``.md``.
* ``skid``: Fig 11's sweep (cases/paper/harris36_cage_speed.toml: harris36 at 5000 r/min,
  cage speed against radial load, every point until steady), for :data:`SKID_MODELS` (the
  quasi-static boundary of every law: tools/catalogue_terms.py). Writes
  ``docs/data/catalogue_skid.csv``, ``.md`` and ``docs/figures/catalogue_skid.png``.

The runs are kept in ``--keep DIR`` (default: a temporary folder), so a second call with the
same folder computes only what is missing. Prints the CPU time of each model's runs. Run it
from a checkout whose package is the one on the path (``PYTHONPATH=. python tools/...``).
"""

from __future__ import annotations

import argparse
import csv
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))  # skf_friction.py: the SKF model, typed apart

#: bearing -> bundled base case of the friction maps
CASES = {"yang20": "yang20_baseline", "harris36": "paper/harris36_5000rpm"}
SPEEDS_RPM = (500.0, 2000.0, 6000.0, 10000.0)
LOADS_N = (400.0, 2000.0, 8000.0)
#: model -> scene overrides; "paper": today's defaults, "switches": the friction switches on
#: (thermal off: the same oil, at the same fixed viscosity, as the catalogue's ν) with the
#: default rolling law (Biboulet & Houpert's), "goksem": the same with Goksem & Hargreaves's
MODELS = {"paper": {},
          "switches": {"physics.rolling_resistance": "biboulet_houpert",
                       "physics.lubrication": "mixed"},
          "goksem": {"physics.rolling_resistance": "goksem_hargreaves",
                     "physics.lubrication": "mixed"}}
SKID_SWEEP = "paper/harris36_cage_speed"
#: the geometry the catalogue does not see: yang20 with the switches and its rollers half as
#: long (total and effective lengths halved, same load and speed); the full-length points
#: are the friction study's runs
GEOMETRY_BEARING = "yang20"
GEOMETRY_SPEEDS_RPM = (2000.0, 10000.0)
GEOMETRY_LOADS_N = (2000.0,)
GEOMETRY_ROLLER_MM = {"full": (25.5, 22.95), "half": (12.75, 11.475)}
#: the skid sweep's extra overrides per model: with the switches the warm-up is capped at 20
#: cage revolutions (the paper's sweep allows 200; its points settle in 4); a point that hits
#: the cap is marked not steady in the table
SKID_OVERRIDES = {"paper": {}, "goksem": {"numerics.max_warmup_cage_revolutions": 20.0}}
#: a model point within this factor of the catalogue (either way) agrees with it
FACTOR = 1.5
DATA, FIGURES = ROOT / "docs" / "data", ROOT / "docs" / "figures"
FRICTION_COLUMNS = ["bearing", "speed_rpm", "radial_load_N", "skf_N_mm",
                    "paper_N_mm", "paper_drag_N_mm", "paper_ratio", "paper_total_ratio",
                    "paper_cage_slip", "paper_cpu_s",
                    "switches_N_mm", "switches_drag_N_mm", "switches_ratio",
                    "switches_total_ratio", "switches_cage_slip", "switches_cpu_s",
                    "goksem_N_mm", "goksem_drag_N_mm", "goksem_ratio",
                    "goksem_total_ratio", "goksem_cage_slip", "goksem_cpu_s"]
GEOMETRY_COLUMNS = ["bearing", "speed_rpm", "radial_load_N", "skf_N_mm",
                    "full_roller_length_mm", "full_N_mm", "full_ratio",
                    "half_roller_length_mm", "half_N_mm", "half_ratio"]
#: the models of the dynamic skid sweep (each point until steady: minutes with the switches);
#: the quasi-static boundary of every law is tools/catalogue_terms.py's
SKID_MODELS = ("paper", "goksem")
SKID_COLUMNS = ["radial_load_N", "paper_cage_speed_ratio", "goksem_cage_speed_ratio",
                "paper_steady", "goksem_steady"]


def friction_rows(maps: dict) -> list[dict]:
    """Table rows from ``maps[(bearing, model)]`` (friction map Datasets) and the SKF model."""
    import skf_friction as skf

    rows = []
    for bearing in CASES:
        for n in SPEEDS_RPM:
            for F in LOADS_N:
                ref = skf.friction_torque_N_m(bearing, n, F) * 1e3
                row = {"bearing": bearing, "speed_rpm": n, "radial_load_N": F, "skf_N_mm": ref}
                for model in MODELS:
                    ds = maps.get((bearing, model))
                    pt = ds.sel(speed_rpm=n, radial_load_N=F) if ds is not None else None

                    def value(name, scale=1.0):
                        return float(pt[name]) * scale if pt is not None else float("nan")

                    total, drag = value("friction_torque_N_m", 1e3), value("drag_torque_N_m", 1e3)
                    row[f"{model}_N_mm"], row[f"{model}_drag_N_mm"] = total, drag
                    row[f"{model}_ratio"] = (total - drag) / ref
                    row[f"{model}_total_ratio"] = total / ref
                    row[f"{model}_cage_slip"] = value("cage_slip_ratio")
                    row[f"{model}_cpu_s"] = value("run_cpu_time_s")
                rows.append(row)
    return rows


def geometry_rows(full_map, half_map) -> list[dict]:
    """Rows of the geometry table: the friction without the drag [N·mm] of the switched model
    with the scene's rollers (``full_map``) and with rollers half as long (``half_map``),
    beside the catalogue, which has no input for the rollers."""
    import skf_friction as skf

    rows = []
    for n in GEOMETRY_SPEEDS_RPM:
        for F in GEOMETRY_LOADS_N:
            ref = skf.friction_torque_N_m(GEOMETRY_BEARING, n, F) * 1e3
            row = {"bearing": GEOMETRY_BEARING, "speed_rpm": n, "radial_load_N": F,
                   "skf_N_mm": ref}
            for key, ds in (("full", full_map), ("half", half_map)):
                pt = ds.sel(speed_rpm=n, radial_load_N=F)
                T = float(pt.friction_torque_N_m - pt.drag_torque_N_m) * 1e3
                row[f"{key}_roller_length_mm"] = GEOMETRY_ROLLER_MM[key][0]
                row[f"{key}_N_mm"], row[f"{key}_ratio"] = T, T / ref
            rows.append(row)
    return rows


def write_csv(rows: list[dict], columns: list[str], path: Path) -> None:
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns, lineterminator="\n")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{r[k]:.9g}" if isinstance(r[k], float) else r[k])
                        for k in columns})


def read_csv(path: Path) -> list[dict]:
    with open(path, newline="") as f:
        return [{k: (v if k == "bearing" else float(v)) for k, v in r.items()}
                for r in csv.DictReader(f)]


def _g(x: float) -> str:
    """A torque [N·mm]: whole from 100 on, else three significant digits; "–" for nan."""
    return "–" if x != x else (f"{x:.0f}" if abs(x) >= 100 else f"{x:.3g}")


def _ratio(x: float) -> str:
    """A ratio: two decimals, or two digits in powers of ten below 0.1; "–" for nan."""
    return "–" if x != x else (f"{x:.2f}" if x >= 0.1 else f"{x:.1e}")


def friction_markdown(rows: list[dict]) -> str:
    """The user guide's table, from the CSV rows (tests/docs check it is this function's
    output of docs/data/catalogue_friction.csv). Torques as friction + drag: the contacts'
    friction (everything but the lubricant's drag) and the oil-air drag the catalogue
    leaves out; the ratios compare the friction alone, the last one the total."""
    def torque(r, m):
        total, drag = r[f"{m}_N_mm"], r[f"{m}_drag_N_mm"]
        return "–" if total != total else f"{_g(total - drag)} + {_g(drag)}"

    def slip(x):
        return "–" if x != x else f"{100 * x:.1f} %"

    lines = ["| bearing | speed [r/min] | radial load [N] | SKF [N·mm] | paper model: friction "
             "+ drag [N·mm] | paper / SKF | switches on (B&H): friction + drag [N·mm] | on / SKF "
             "| on / SKF, with drag | Goksem instead of B&H: / SKF | cage slip, paper → on |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(
            f"| {r['bearing']} | {r['speed_rpm']:.0f} | {r['radial_load_N']:.0f} "
            f"| {_g(r['skf_N_mm'])} | {torque(r, 'paper')} | {_ratio(r['paper_ratio'])} "
            f"| {torque(r, 'switches')} | {_ratio(r['switches_ratio'])} "
            f"| {_ratio(r['switches_total_ratio'])} | {_ratio(r['goksem_ratio'])} "
            f"| {slip(r['paper_cage_slip'])} → {slip(r['switches_cage_slip'])} |")
    return "\n".join(lines) + "\n"


def geometry_markdown(rows: list[dict]) -> str:
    """The geometry table of the user guide, from docs/data/catalogue_geometry.csv."""
    lines = ["| bearing | speed [r/min] | radial load [N] | SKF [N·mm] | switches on, rollers "
             "25.5 mm [N·mm] | / SKF | rollers 12.75 mm [N·mm] | / SKF |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(
            f"| {r['bearing']} | {r['speed_rpm']:.0f} | {r['radial_load_N']:.0f} "
            f"| {_g(r['skf_N_mm'])} | {_g(r['full_N_mm'])} | {_ratio(r['full_ratio'])} "
            f"| {_g(r['half_N_mm'])} | {_ratio(r['half_ratio'])} |")
    return "\n".join(lines) + "\n"


def skid_markdown(rows: list[dict]) -> str:
    """The skid table of the user guide, from docs/data/catalogue_skid.csv."""
    def cell(r, m):
        x = r[f"{m}_cage_speed_ratio"]
        if x != x:
            return "–"
        return f"{x:.4f}" + ("" if r[f"{m}_steady"] == 1 else " (not steady)")

    lines = ["| radial load [N] | cage speed / epicyclic, paper model | Goksem & Hargreaves's "
             "law + mixed lubrication |", "|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['radial_load_N']:.0f} | {cell(r, 'paper')} | {cell(r, 'goksem')} |")
    return "\n".join(lines) + "\n"


def friction_figure(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    import skf_friction as skf

    fig, axes = plt.subplots(1, 2, figsize=(11, 5.2), layout="constrained")
    n = np.linspace(300.0, 11000.0, 200)
    colours = dict(zip(LOADS_N, ("tab:blue", "tab:orange", "tab:green")))
    for ax, bearing in zip(axes, CASES):
        for F, c in colours.items():
            ax.plot(n, [skf.friction_torque_N_m(bearing, x, F) * 1e3 for x in n], color=c,
                    label=f"SKF, {F:.0f} N")
            pts = [r for r in rows if r["bearing"] == bearing and r["radial_load_N"] == F]
            x = [r["speed_rpm"] for r in pts]
            for model, marker, fill, name in (("paper", "o", "none", "paper model"),
                                              ("switches", "s", c, "switches on")):
                ax.plot(x, [r[f"{model}_N_mm"] - r[f"{model}_drag_N_mm"] for r in pts], marker,
                        mfc=fill, color=c, label=f"{name}, {F:.0f} N")
            ax.plot(x, [r["switches_N_mm"] for r in pts], "x", color=c, ms=5,
                    label=f"switches on + oil-air drag, {F:.0f} N")
        ax.set(yscale="log", xlabel="inner ring speed [r/min]",
               ylabel="friction torque without the oil-air drag [N·mm]", title=bearing)
    fig.legend(*axes[0].get_legend_handles_labels(), loc="outside lower center", ncol=3,
               fontsize=7)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def skid_figure(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4), layout="constrained")
    F = [r["radial_load_N"] for r in rows]
    ax.plot(F, [r["paper_cage_speed_ratio"] for r in rows], "o-", mfc="none",
            label="paper model")
    ax.plot(F, [r["goksem_cage_speed_ratio"] for r in rows], "s-",
            label="rolling resistance (Goksem & Hargreaves) + mixed lubrication")
    ax.axhline(0.99, color="k", ls=":", lw=1, label="1 % cage slip")
    ax.set(xlabel="radial load [N]", ylabel="cage speed / epicyclic speed",
           title="harris36, 5000 r/min (Fig 11)", ylim=(0, 1.02))
    ax.legend()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _stored(sweep, folder: Path, name: str):
    """The sweep Dataset of the runs already in ``folder/<name>_runs`` (others "missing")."""
    from bearingdae.studies.sweep import RunStore, assemble

    return assemble(sweep, RunStore(folder / f"{name}_runs"), relative_to=folder)


def run_friction(folder: Path, models, workers, stored_only=False) -> None:
    from bearingdae.studies.friction import make_sweep, map_dataset, run_friction_map

    maps = {}
    for model in models:
        cpu = 0.0
        for bearing, case in CASES.items():
            name = f"friction_{bearing}_{model}"
            if stored_only:
                sweep = make_sweep(case, SPEEDS_RPM, LOADS_N, MODELS[model], name=name)
                ds = map_dataset(_stored(sweep, folder, name), folder)
            else:
                ds = run_friction_map(case, SPEEDS_RPM, LOADS_N, folder / f"{name}.nc",
                                      overrides=MODELS[model], workers=workers, progress=False)
            maps[(bearing, model)] = ds
            cpu += float(ds.run_cpu_time_s.sum())
        print(f"catalogue_friction: friction, {model}: {cpu:.0f} s CPU in the runs")
    if set(models) == set(MODELS):
        rows = friction_rows(maps)
        write_csv(rows, FRICTION_COLUMNS, DATA / "catalogue_friction.csv")
        rows = read_csv(DATA / "catalogue_friction.csv")  # the page is what the CSV gives
        (DATA / "catalogue_friction.md").write_text(friction_markdown(rows))
        friction_figure(rows, FIGURES / "catalogue_friction.png")


def run_geometry(folder: Path, models, workers, stored_only=False) -> None:
    """The switched model of yang20 with rollers half as long, beside the friction study's
    runs of the same points (read from ``folder``: run the friction study first)."""
    from bearingdae.studies.friction import make_sweep, map_dataset, run_friction_map

    if "switches" not in models:
        return
    case = CASES[GEOMETRY_BEARING]
    name = f"friction_{GEOMETRY_BEARING}_switches"
    full = map_dataset(_stored(make_sweep(case, SPEEDS_RPM, LOADS_N, MODELS["switches"],
                                          name=name), folder, name), folder)
    L, L_eff = GEOMETRY_ROLLER_MM["half"]
    over = {**MODELS["switches"], "bearing.roller_length_mm": L,
            "bearing.effective_length_mm": L_eff}
    if stored_only:
        sweep = make_sweep(case, GEOMETRY_SPEEDS_RPM, GEOMETRY_LOADS_N, over,
                           name="geometry_half")
        half = map_dataset(_stored(sweep, folder, "geometry_half"), folder)
    else:
        half = run_friction_map(case, GEOMETRY_SPEEDS_RPM, GEOMETRY_LOADS_N,
                                folder / "geometry_half.nc", overrides=over, workers=workers,
                                progress=False)
    print(f"catalogue_friction: geometry: {float(half.run_cpu_time_s.sum()):.0f} s CPU")
    write_csv(geometry_rows(full, half), GEOMETRY_COLUMNS, DATA / "catalogue_geometry.csv")
    rows = read_csv(DATA / "catalogue_geometry.csv")
    (DATA / "catalogue_geometry.md").write_text(geometry_markdown(rows))


def run_skid(folder: Path, models, workers, stored_only=False) -> None:
    import numpy as np

    from bearingdae.studies.sweep import load_sweep, run_sweep

    sweeps = {}
    for model in (m for m in models if m in SKID_MODELS):
        sw = load_sweep(SKID_SWEEP, overrides={**MODELS[model], **SKID_OVERRIDES[model]} or None)
        ds = (_stored(sw, folder, f"skid_{model}") if stored_only else
              run_sweep(sw, folder / f"skid_{model}.nc", workers=workers, progress=False))
        sweeps[model] = ds
        print(f"catalogue_friction: skid, {model}: {float(ds.run_cpu_time_s.sum()):.0f} s CPU")
    if set(models) >= set(SKID_MODELS):
        rows = []
        for i, F in enumerate(sweeps["paper"].radial_load_N.values):
            row = {"radial_load_N": float(F)}
            for model, ds in sweeps.items():
                pt = ds.isel(radial_load_N=i)
                row[f"{model}_cage_speed_ratio"] = float(pt.mean_cage_speed_rad_s
                                                         / pt.epicyclic_cage_speed_rad_s)
                steady = float(pt.steady_state_reached) if "steady_state_reached" in pt \
                    else np.nan
                row[f"{model}_steady"] = steady
            rows.append(row)
        write_csv(rows, SKID_COLUMNS, DATA / "catalogue_skid.csv")
        rows = read_csv(DATA / "catalogue_skid.csv")
        (DATA / "catalogue_skid.md").write_text(skid_markdown(rows))
        skid_figure(rows, FIGURES / "catalogue_skid.png")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--keep", type=Path, help="folder for the sweeps and runs (default: "
                   "temporary); a second call with it computes only the missing runs")
    p.add_argument("--only", choices=("friction", "geometry", "skid"), help="one study only")
    p.add_argument("--models", nargs="+", choices=sorted(MODELS), default=list(MODELS),
                   help="models to run (the docs files are written when all are run)")
    p.add_argument("--workers", type=int, default=None, help="local worker processes")
    p.add_argument("--stored-only", action="store_true", help="compute nothing: the tables "
                   "from the runs already in --keep (the others shown as missing)")
    args = p.parse_args(argv)
    with tempfile.TemporaryDirectory() as scratch:
        folder = args.keep or Path(scratch)
        folder.mkdir(parents=True, exist_ok=True)
        for study, fn in (("friction", run_friction), ("geometry", run_geometry),
                          ("skid", run_skid)):
            if args.only and study != args.only:
                continue
            wall, cpu = time.perf_counter(), time.process_time()
            fn(folder, args.models, args.workers, args.stored_only)
            print(f"catalogue_friction: {study}: {time.perf_counter() - wall:.0f} s wall")
    return 0


if __name__ == "__main__":
    sys.exit(main())
