"""Work-precision: error against cost of IDA, Newmark-β and the nested scipy peers.

    python benchmarks/run.py workprecision [--repeat 3] [--warmup 0] [--revolutions 0.2]
        [--scenes baseline,highspeed] [--solvers scipy-LSODA,scipy-BDF] [--no-naive]
        [--quick] [-o DIR] [--markdown F]
    python benchmarks/run.py workprecision --divergence [--scenes baseline]
    python benchmarks/run.py workprecision --edges [--edge-mm 0.0025,0.05,0.1,0.2,0.4]
        [--rtols 1e-3,1e-4,1e-5,1e-6,1e-7] [--repeat 1] [--no-locate] [--json F] [--markdown F]

For each scene it runs the ladders of ``bearingdae.studies.workprecision`` (IDA rtol 1e-3 ...
1e-10, Newmark-β h = 4, 2, 1, 0.5 µs, scipy BDF / Radau / LSODA rtol 1e-3 ... 1e-10 with a time
limit of 20 x IDA-1e-6's time, atol = rtol / 100; ``--solvers``: only these besides IDA), writes
the NetCDF + CSV table and the PNG into DIR and prints a Markdown section: the table and each
peer's wall time at IDA-1e-6's cage-speed error (log-log interpolated along the peer's Pareto
front) as a multiple of IDA-1e-6's. For scale it also runs the naive nested implementation
(``naive-BDF``/``naive-LSODA``: the static solver's numpy Newton per right-hand side, scipy's
finite-difference Jacobian) at rtol 1e-6 unless ``--no-naive``; those are not peers. Long:
tens of minutes per scene on a 2-core machine with every ladder.

``--divergence`` measures why the window is short: IDA at rtol 1e-6, 1e-8, 1e-9 against 1e-10
over 0.75 cage revolution from t = 0, relative RMS difference per 0.075-revolution window.

``--edges`` measures sharp against smoothed defect edges at equal error
(bearingdae.studies.workprecision.edges): the outer spall and the sharp roller spall (with a
dynamic ring) at each ramp length and rtol, the headline outputs' errors against the least
ramp at rtol 1e-8 (and it against half that ramp), and the CPU of the cheapest run reaching each error;
beside the ramps, the sharp edge located by IDA's root finding (``numerics.defect_edges =
"locate"``) at each rtol, unless ``--no-locate``.
"""

from __future__ import annotations

import argparse
import math
import platform
import time
from pathlib import Path

from bearingdae import load_scene
from bearingdae.studies import workprecision as wp

from run import cpu_model, header, load, summary

SCENES = {
    "baseline": ("yang20_baseline", {}),
    "highspeed": ("yang20_baseline", {"operating.speed_rpm": 10000.0}),
    # a defect scene: the first rollers crossing the outer spall within 0.2 cage revolution
    "spall": ("defects/outer_spall", {}),
}


def _fmt(x, spec=".2e"):
    missing = x is None or (isinstance(x, float) and not math.isfinite(x))
    return "–" if missing else format(x, spec)


def markdown(name: str, overrides: dict, st: wp.Study, paths: dict, wall_total: float) -> str:
    cmp = wp.comparison(st)
    ref = st.reference.label if st.reference else "none"
    lines = [f"### {name}: {st.scene_title}", "",  # (the title names the overrides)
             f"Scene overrides: `{overrides}`. Reference: **{ref}**; its agreement with the "
             f"next-tightest IDA run ({st.floor.get('run', '–')}), i.e. the error floor: "
             f"cage speed {_fmt(st.floor.get('cage_speed_rel_rms'))}, skew "
             f"{_fmt(st.floor.get('skew_angle_rel_rms'))}, contact force "
             f"{_fmt(st.floor.get('contact_force_rel_rms'))} (relative RMS). Peer time limit "
             f"{_fmt(st.time_limit_s, '.1f')} s (= 20 × IDA at rtol 1e-6). Median of "
             f"{st.repeat} timed runs; whole study {wall_total / 60:.0f} min.", "",
             "| solver | rtol or step [s] | status | wall [s] | kernel evals | cage speed | "
             "orbit speed | spin speed | skew angle | contact force | mescd |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in st.runs:
        e = r.errors
        status = "reference" if r.is_reference else r.status
        if r.status != "ok":
            status += f" ({r.message[:90]})"
        lines.append(
            f"| {r.solver} | {r.value:.0e} | {status} | {_fmt(r.wall_s, '.2f')} | "
            f"{r.kernel_evaluations if r.kernel_evaluations >= 0 else '–'} | "
            + " | ".join(_fmt(e.get(f"{q}_rel_rms")) for q in wp.QUANTITIES)
            + f" | {_fmt(e.get('mescd'), '.2f')} |")
    lines += ["", "Errors: relative RMS over the recorded window against the reference "
              "(relative max, the other quantities and all attributes are in the NetCDF/CSV).", ""]
    for s, c in st.confirmations.items():
        lines += [f"Reference confirmed by {c['run']}: cage speed "
                  f"{_fmt(c.get('cage_speed_rel_rms'))}, skew {_fmt(c.get('skew_angle_rel_rms'))}, "
                  f"contact force {_fmt(c.get('contact_force_rel_rms'))} (relative RMS).", ""]
    if cmp.get("peers"):
        lines.append(f"**At equal error** — IDA at rtol 1e-6: {cmp['ida_wall_s']:.2f} s at "
                     f"cage-speed error {cmp['ida_error']:.2e}. The others at that error:")
        lines.append("")
        for s, p in {**cmp["peers"], **cmp["others"]}.items():
            b = {"=": "", ">=": "≥ ", "<=": "≤ "}.get(p["bound"], "? ")
            lines.append(f"- {s}: {b}{_fmt(p['wall_s'], '.2f')} s ({p['kind']}) → "
                         f"**{b}{_fmt(p['ratio'], '.1f')}×** IDA")
        if cmp.get("note"):
            lines += ["", f"Note: {cmp['note']}."]
    else:
        lines.append(f"No comparison at equal error: {cmp.get('note')}")
    lines += ["", f"![work-precision {name}]({paths['png'].name})", ""]
    return "\n".join(lines)


def divergence(name: str, revolutions: float = 0.75, window: float = 0.075) -> str:
    """Relative RMS difference of IDA runs at rtol 1e-6, 1e-8, 1e-9 from rtol 1e-10, per window
    of ``window`` cage revolutions from t = 0 (Markdown table)."""
    import numpy as np

    from bearingdae import simulate

    case, extra = SCENES[name]
    rtols = (1e-6, 1e-8, 1e-9, 1e-10)
    runs = {}
    for rt in rtols:
        scene = load_scene(case, {**extra, "numerics.warmup_cage_revolutions": 0.0,
                                  "numerics.cage_revolutions": revolutions,
                                  **wp.tolerance_overrides(rt)})
        runs[rt] = simulate(scene)
    ref = runs[rtols[-1]]
    spr = load_scene(case, extra).dynamics.samples_per_cage_revolution
    per = max(int(round(window * spr)), 1)
    n = ref.sizes["time"]
    edges = list(range(0, n - 1, per))
    head = " | ".join(f"{i * window:.3g}–{(i + 1) * window:.3g}" for i in range(len(edges)))
    lines = [f"Divergence, {name} {extra}: relative RMS difference from IDA rtol 1e-10 per "
             f"window of {window} cage revolution (from t = 0)", "",
             f"| run | quantity | {head} |", "|---|---|" + "---|" * len(edges)]
    for rt in rtols[:-1]:
        for q in ("cage_speed", "skew_angle"):
            d = (runs[rt][q].values - ref[q].values).reshape(n, -1)
            r = ref[q].values.reshape(n, -1)
            cells = [np.sqrt(np.mean(d[i:i + per] ** 2) / np.mean(r ** 2)) for i in edges]
            lines.append(f"| rtol {rt:.0e} | {q} | " + " | ".join(f"{c:.1e}" for c in cells)
                         + " |")
    return "\n".join(lines) + "\n"


#: the defect scenes of ``--edges``: (case, overrides: a dynamic ring for the acceleration)
EDGE_SCENES = {
    "outer spall": ("defects/outer_spall", {"numerics.warmup_cage_revolutions": 0.0,
                                            "numerics.cage_revolutions": 0.2}),
    "sharp roller spall": ("extreme/sharp_roller_spall",
                           {"physics.ring": "dynamic", "ring.support_damping_N_s_m": 600.0}),
}


def edges(edge_mm, rtols, repeat: int, json_path, markdown_path, locate: bool = True) -> None:
    """The ``--edges`` study on :data:`EDGE_SCENES` (module docstring)."""
    from bearingdae.studies.workprecision import edges as ed

    from run import write_json

    out, sections = {"cpu": cpu_model(), "benchmark": "workprecision --edges",
                     "edges_mm": list(edge_mm), "rtols": list(rtols), "repeat": repeat,
                     "locate": locate, "load_1min": [load()], "scenes": {}}, []
    for name, (case, extra) in EDGE_SCENES.items():
        st = ed.edge_study(load_scene(case, extra), edge_mm, rtols, repeat=repeat,
                           sharper_mm=0.5 * edge_mm[0], log=lambda m: print(m, flush=True),
                           locate=locate)
        st["case"], st["overrides"] = case, extra
        out["scenes"][name] = st
        out["load_1min"].append(load())  # (after each scene)
        sections.append(ed.markdown(name, st))
        print(sections[-1], flush=True)
        write_json(json_path, out)
    if markdown_path:
        markdown_path.write_text("\n".join(sections))


def main(argv=None, name="workprecision") -> None:
    ap = argparse.ArgumentParser(prog=f"run.py {name}", description=summary(__doc__))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--warmup", type=float, default=0.0, help="warm-up cage revolutions")
    ap.add_argument("--revolutions", type=float, default=0.2, help="recorded cage revolutions")
    ap.add_argument("--divergence", action="store_true",
                    help="only the divergence table (IDA tolerances against each other)")
    ap.add_argument("--edges", action="store_true", help="only the sharp-against-smoothed "
                    "defect edges study")
    ap.add_argument("--edge-mm", default=None, help="--edges: ramp lengths [mm], the first the "
                    "reference's (default: the least ramp physics/defects.EDGE_MIN_M, then "
                    "0.05,0.1,0.2,0.4)")
    ap.add_argument("--rtols", default="1e-3,1e-4,1e-5,1e-6,1e-7", help="--edges: IDA's rtols")
    ap.add_argument("--json", type=Path, default=None, help="--edges: write the rows here")
    ap.add_argument("--scenes", default="baseline,highspeed")
    ap.add_argument("-o", "--output", type=Path, default=Path("wp_results"))
    ap.add_argument("--markdown", type=Path, default=None, help="also write the section here")
    ap.add_argument("--solvers", help="comma-separated ladders besides IDA (default: all), "
                    "e.g. scipy-LSODA,scipy-BDF")
    ap.add_argument("--no-naive", action="store_true", help="skip the naive nested runs")
    ap.add_argument("--no-locate", action="store_true", help="--edges: the ramps only, not the "
                    "sharp edge located by IDA's root finding")
    ap.add_argument("--quick", action="store_true", help="short ladders (a smoke test)")
    args = ap.parse_args(argv)
    header(f"{name}: scenes {args.scenes}")
    out = [f"CPU: {cpu_model()}; Python {platform.python_version()}.", ""]
    if args.edges:
        from bearingdae.physics.defects import EDGE_MIN_M

        edge_mm = args.edge_mm or f"{EDGE_MIN_M * 1e3:g},0.05,0.1,0.2,0.4"
        edges([float(v) for v in edge_mm.split(",")],
              [float(v) for v in args.rtols.split(",")], args.repeat, args.json, args.markdown,
              locate=not args.no_locate)
        return
    if args.divergence:
        for name in args.scenes.split(","):
            print(divergence(name), flush=True)
        return
    for name in args.scenes.split(","):
        case, extra = SCENES[name]
        overrides = {**extra, "numerics.warmup_cage_revolutions": args.warmup,
                     "numerics.cage_revolutions": args.revolutions}
        scene = load_scene(case, overrides)
        t0 = time.perf_counter()
        st = wp.study(scene, repeat=args.repeat, quick=args.quick, base_overrides=overrides,
                      solvers=tuple(args.solvers.split(",")) if args.solvers else None,
                      extra=[] if args.no_naive else wp.naive_ladders())
        paths = wp.write(st, args.output, name)
        section = markdown(name, overrides, st, paths, time.perf_counter() - t0)
        print(section, flush=True)
        out.append(section)
        if args.markdown:
            args.markdown.write_text("\n".join(out) + "\n")

