"""Sharp against smoothed defect edges at equal error: the work-precision of a defect scene's
headline outputs over the edge ramp length and IDA's rtol (``python benchmarks/run.py
workprecision --edges``; the tables on docs/user-guide.md, "Sharp edges").

A sharp edge (``edge_mm = 0``) is a jump of the residual; the model smooths it over the least
ramp, physics/defects.EDGE_MIN_M (0.0025 mm), and a longer ``edge_mm`` smooths it further. A
longer ramp is cheaper for IDA but changes the answer. This study measures both effects on the
outputs an analyst reads, against a dense reference (the least ramp at the tightest rtol):

- **ring acceleration RMS** [m s-2] over the recorded window (both directions);
- **contact-force drop impulse** [N s]: the time integral of the largest loss, over rollers
  and races, of a roller's contact force on a race (summed over its slices) against the same
  scene without its defects at the reference rtol (:func:`force_drop_impulse`): the depth and
  the duration of the drop together. (Its peak, :func:`force_drop_peak`, is the covered slices'
  whole load for a spall deeper than the deflection, whatever the ramp: it is recorded, not
  compared.)
- the **ring acceleration signal**: the relative RMS of its difference from the reference's
  (workprecision.errors.relative_errors), the strictest of the three.

Beside the ramps, ``locate`` runs the sharp edge itself (``numerics.defect_edges = "locate"``:
IDA's root finding and a restart at each crossing, system/defect_sides.py) at each rtol; its
rows have ``edge_mm`` 0 and ``edges`` "locate" (the ramps' "smooth"), and the reference's
``located`` entry holds the located sharp edge at the reference rtol, its errors against the
reference (the least ramp's own distance from the sharp edge, which it converges to).

Each run's cost is the process CPU time of ``simulate`` (the median over ``repeat`` runs). At a
target error, the cheapest run of each ramp length (and of the located edge) that reaches it
(:func:`cheapest`) answers "which is faster at equal error".
"""

from __future__ import annotations

import math
import statistics
import time
import tomllib

import numpy as np
import xarray as xr

from .errors import interp_time, relative_errors
from .ladders import tolerance_overrides

#: the outputs compared, in the table's order: name -> (label, units)
HEADLINES = {"ring_acceleration_rms": ("ring acceleration RMS", "m s-2"),
             "force_drop_impulse": ("contact-force drop impulse", "N s"),
             "ring_acceleration_signal": ("ring acceleration signal (relative RMS)", "1")}


def ring_acceleration_rms(ds: xr.Dataset) -> float:
    """RMS [m s-2] over the record of the ring acceleration's magnitude (both directions)."""
    a = np.asarray(ds["ring_acceleration"].values, float)
    return math.sqrt(float(np.mean(np.sum(a * a, axis=-1))))


def race_forces(ds: xr.Dataset) -> np.ndarray:
    """(time, roller, race) contact force of each roller on each race [N] (summed over slices)."""
    return np.asarray(ds["contact_force"].transpose("time", "roller", "race", "slice")
                      .values, float).sum(axis=-1)


def force_drop(ds: xr.Dataset, healthy: xr.Dataset) -> np.ndarray:
    """(time,) the largest loss [N] over rollers and races of a roller's contact force on a
    race against the ``healthy`` run (the scene without defects; interpolated to ``ds``'s
    times), 0 where none loses."""
    f = race_forces(ds)
    h = interp_time(healthy.time.values, race_forces(healthy), ds.time.values)
    return np.maximum((h - f).reshape(f.shape[0], -1).max(axis=1), 0.0)


def force_drop_peak(ds: xr.Dataset, healthy: xr.Dataset) -> float:
    """The largest :func:`force_drop` over the record [N]."""
    return float(np.max(force_drop(ds, healthy)))


def force_drop_impulse(ds: xr.Dataset, healthy: xr.Dataset) -> float:
    """The time integral [N s] of :func:`force_drop` over the record (trapezoidal rule)."""
    d, t = force_drop(ds, healthy), np.asarray(ds.time.values, float)
    return float(np.sum(0.5 * (d[1:] + d[:-1]) * np.diff(t)))


def headline_values(ds: xr.Dataset, healthy: xr.Dataset) -> dict:
    """The scalar headlines of one run (and the recorded peak drop)."""
    return {"ring_acceleration_rms": ring_acceleration_rms(ds),
            "force_drop_impulse": force_drop_impulse(ds, healthy),
            "force_drop_peak": force_drop_peak(ds, healthy)}


def headline_errors(ds: xr.Dataset, ref: xr.Dataset, values: dict, ref_values: dict) -> dict:
    """Relative errors of a run's headlines against the reference's."""
    out = {k: abs(values[k] - ref_values[k]) / abs(ref_values[k]) for k in ref_values}
    a = interp_time(ref.time.values, np.asarray(ref["ring_acceleration"].values, float),
                    ds.time.values)
    out["ring_acceleration_signal"] = relative_errors(ds["ring_acceleration"].values, a)[0]
    return out


#: the overrides of a located sharp edge (its rows: ``edge_mm`` 0)
LOCATE = {"numerics.defect_edges": "locate"}


def label(edge_mm: float) -> str:
    """A column's head: the ramp, or the located sharp edge (``edge_mm`` 0)."""
    return "located" if edge_mm == 0.0 else f"ramp {edge_mm:g} mm"


def _solver_steps(ds) -> tuple[int, int, float]:
    """(IDA steps, edge crossings, CPU [s] of their restarts) of a run."""
    import json

    st = json.loads(ds.attrs["solver_statistics"])
    return (int(st.get("steps", -1)), int(st.get("edge_crossings", 0)),
            float(st.get("edge_restart_cpu_s", 0.0)))


def with_edges(scene, edge_mm: float | None, overrides: dict):
    """``scene`` with every defect's ``edge_mm`` set to ``edge_mm`` (None: as given, or no
    defects at all when ``edge_mm`` is the string "none") and the dotted ``overrides``."""
    from ...scene import scene_from_dict

    data = tomllib.loads(scene.to_toml())
    if edge_mm == "none":
        data["defects"], data["waviness"] = [], []
    elif edge_mm is not None:
        data["defects"] = [{**d, "edge_mm": float(edge_mm)} for d in data.get("defects", [])]
    return scene_from_dict(data, overrides, origin=f"edge study ({scene.title})")


def _timed(scene, repeat: int) -> tuple[xr.Dataset, float, int]:
    """(Dataset, median process CPU [s], IDA steps) of ``repeat`` runs of ``scene``."""
    from ...api import simulate

    cpus, ds = [], None
    for _ in range(repeat):
        c0 = time.process_time()
        ds = simulate(scene, progress=False)
        cpus.append(time.process_time() - c0)
    return ds, float(statistics.median(cpus)), _solver_steps(ds)[0]


def sharper(scene, least_ramp_mm: float, rtol: float) -> tuple[xr.Dataset, float, int]:
    """A run of ``scene`` with sharp edges smoothed over ``least_ramp_mm`` instead of
    physics/defects.EDGE_MIN_M: how far the least ramp itself is from a sharper edge (each
    defect's ``least_ramp_m``, scene/defects.Defect, which the defect table reads)."""
    import dataclasses

    sharp = with_edges(scene, 0.0, tolerance_overrides(rtol))
    finer = tuple(dataclasses.replace(d, least_ramp_m=least_ramp_mm * 1e-3)
                  for d in sharp.defects)
    return _timed(dataclasses.replace(sharp, defects=finer), 1)


def edge_study(scene, edges_mm, rtols, reference_rtol: float = 1e-8, repeat: int = 1,
               sharper_mm: float | None = None, log=print, locate: bool = False) -> dict:
    """Every (ramp length, rtol) run of ``scene``, its CPU, steps, headlines and their errors
    against the reference: the least ramp (``edges_mm[0]``) at ``reference_rtol``; with
    ``sharper_mm``, the reference's own errors against a ramp of that length (:func:`sharper`);
    with ``locate``, the located sharp edge at every rtol (module docstring). Returns a
    JSON-ready dict."""
    ref_scene = with_edges(scene, edges_mm[0], tolerance_overrides(reference_rtol))
    _timed(with_edges(scene, edges_mm[0], {"numerics.cage_revolutions": 0.01,
                                           "numerics.warmup_cage_revolutions": 0.0}), 1)
    healthy, _, _ = _timed(with_edges(scene, "none", tolerance_overrides(reference_rtol)), 1)
    ref, ref_cpu, ref_steps = _timed(ref_scene, 1)
    ref_values = headline_values(ref, healthy)
    log(f"reference: ramp {edges_mm[0]} mm, rtol {reference_rtol:g}: CPU {ref_cpu:.2f} s, "
        f"{ref_steps} steps, {ref_values}")
    sharp = None  # the located sharp edge at the reference rtol: the second reference
    if locate:  # (its run also compiles the located edge's kernels before any timed run)
        sharp_ds, cpu, steps = _timed(with_edges(
            scene, 0.0, {**tolerance_overrides(reference_rtol), **LOCATE}), 1)
        values = headline_values(sharp_ds, healthy)
        sharp = (sharp_ds, values)
        located = {"cpu_s": cpu, "steps": steps, "values": values,
                   "crossings": _solver_steps(sharp_ds)[1],
                   "errors": headline_errors(sharp_ds, ref, values, ref_values)}
        log(f"located at rtol {reference_rtol:g}: {located}")
    runs = []
    # interleaved: each rtol's ramps and located edge one after another (the load drifts)
    for rt in rtols:
        for e in list(edges_mm) + ([0.0] if locate else []):
            over = {**tolerance_overrides(rt), **(LOCATE if e == 0.0 else {})}
            row = {"edge_mm": float(e), "rtol": float(rt),
                   "edges": "locate" if e == 0.0 else "smooth"}
            try:
                ds, cpu, steps = _timed(with_edges(scene, e, over), repeat)
            except Exception as exc:  # noqa: BLE001 - a failed rung is a result
                runs.append({**row, "status": "failed",
                             "message": f"{type(exc).__name__}: {exc}"})
                log(f"{label(e)} rtol {rt:g}: failed: {exc}")
                continue
            values = headline_values(ds, healthy)
            row.update(cpu_s=cpu, steps=steps, values=values, crossings=_solver_steps(ds)[1],
                       restart_cpu_s=_solver_steps(ds)[2],
                       errors=headline_errors(ds, ref, values, ref_values))
            if sharp is not None:  # against the located sharp edge
                row["errors_sharp"] = headline_errors(ds, sharp[0], values, sharp[1])
            runs.append(row)
            log(f"{label(e)} rtol {rt:g}: CPU {cpu:.2f} s, {steps} steps, errors "
                + ", ".join(f"{k} {v:.2e}" for k, v in row["errors"].items())
                + ("" if sharp is None else "; against the sharp edge " + ", ".join(
                    f"{k} {v:.2e}" for k, v in row["errors_sharp"].items())))
    runs.sort(key=lambda r: (r["edge_mm"] == 0.0, r["edge_mm"], -r["rtol"]))
    reference = {"edge_mm": float(edges_mm[0]), "rtol": float(reference_rtol),
                 "cpu_s": ref_cpu, "steps": ref_steps, "values": ref_values}
    if locate:
        reference["located"] = located
    if sharper_mm is not None:
        ds, cpu, steps = sharper(scene, sharper_mm, reference_rtol)
        values = headline_values(ds, healthy)
        reference["sharper"] = {"edge_mm": float(sharper_mm), "cpu_s": cpu, "steps": steps,
                                "values": values,
                                "errors_of_reference": headline_errors(ref, ds, ref_values,
                                                                       values)}
        log(f"sharper ramp {sharper_mm} mm: {reference['sharper']}")
    return {"title": scene.title, "reference": reference, "runs": runs}


def cheapest(runs: list[dict], headline: str, target: float, errors: str = "errors") -> dict:
    """{ramp length: the cheapest run (least CPU) of that ramp whose ``headline`` error (of
    ``errors``: against the least ramp, or "errors_sharp", against the located sharp edge) is
    at most ``target``, or None when none reaches it}."""
    out: dict = {}
    for r in runs:
        e = r["edge_mm"]
        out.setdefault(e, None)
        if (r.get("status", "ok") == "ok" and r[errors][headline] <= target
                and (out[e] is None or r["cpu_s"] < out[e]["cpu_s"])):
            out[e] = r
    return out


def markdown(name: str, study: dict, targets=(0.1, 0.01, 0.003, 0.001)) -> str:
    """The study's tables: every run, then the CPU at equal error for each headline."""
    ref = study["reference"]
    edges = sorted({r["edge_mm"] for r in study["runs"]})
    lines = [f"**{name}** ({study['title']}). Reference: ramp {ref['edge_mm']:g} mm at rtol "
             f"{ref['rtol']:.0e} (CPU {ref['cpu_s']:.1f} s, {ref['steps']} steps): "
             + ", ".join(f"{HEADLINES[k][0]} {ref['values'][k]:.4g} {HEADLINES[k][1]}"
                         for k in HEADLINES if k in ref["values"])
             + f", peak contact-force drop {ref['values']['force_drop_peak']:.4g} N.", ""]
    if "sharper" in ref:
        sh = ref["sharper"]
        lines += [f"The reference against a sharper edge (ramp {sh['edge_mm']:g} mm, same "
                  "rtol): " + ", ".join(f"{HEADLINES[k][0]} {v:.1e}" for k, v in
                                        sh["errors_of_reference"].items() if k in HEADLINES)
                  + " (relative).", ""]
    if "located" in ref:
        lo = ref["located"]
        lines += [f"The located sharp edge at the same rtol ({lo['steps']} steps, "
                  f"{lo['crossings']} crossings) against the reference: "
                  + ", ".join(f"{HEADLINES[k][0]} {v:.1e}" for k, v in lo["errors"].items()
                              if k in HEADLINES) + " (relative).", ""]
    lines += ["| ramp [mm] (0: located) | rtol | CPU [s] | steps | "
              + " | ".join(f"{HEADLINES[k][0]} error" for k in HEADLINES) + " |",
              "|---|---|---|---|" + "---|" * len(HEADLINES)]
    for r in study["runs"]:
        if r.get("status", "ok") != "ok":
            lines.append(f"| {r['edge_mm']:g} | {r['rtol']:.0e} | failed: {r['message'][:80]} "
                         "| | " + " | ".join("–" for _ in HEADLINES) + " |")
            continue
        lines.append(f"| {r['edge_mm']:g} | {r['rtol']:.0e} | {r['cpu_s']:.2f} | {r['steps']} | "
                     + " | ".join(f"{r['errors'][k]:.1e}" for k in HEADLINES) + " |")
    for errors, against in (("errors", "the least ramp at the reference rtol"),
                            ("errors_sharp", "the located sharp edge at the reference rtol")):
        if not all(errors in r for r in study["runs"] if r.get("status", "ok") == "ok"):
            continue
        lines += ["", f"CPU [s] of the cheapest run reaching each error against {against} "
                  "(its rtol; – : no rtol of the ladder reaches it):", "",
                  "| output | error ≤ | " + " | ".join(label(e) for e in edges) + " |",
                  "|---|---|" + "---|" * len(edges)]
        for k in HEADLINES:
            for tgt in targets:
                best = cheapest(study["runs"], k, tgt, errors)
                cells = [("–" if best[e] is None else
                          f"{best[e]['cpu_s']:.2f} ({best[e]['rtol']:.0e})") for e in edges]
                lines.append(f"| {HEADLINES[k][0]} | {tgt:g} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def docs_tables(data: dict, errors: str = "errors_sharp", rtol: float = 1e-6,
                targets=(0.1, 0.01, 0.003, 0.001)) -> str:
    """The tables docs/user-guide.md ("Sharp edges") shows of a written study
    (``benchmarks/results/defect-edges.json``), the errors ``errors`` ("errors_sharp": against
    the located sharp edge at the reference rtol; "errors": against the least ramp there):
    each edge at the scenes' default ``rtol`` (steps, CPU, errors), then :func:`cheapest_table`."""
    names = list(data["scenes"])
    lines = [f"| scene | edge | steps at rtol {rtol:.0e} | CPU [s] | "
             + " | ".join(f"{HEADLINES[k][0]} error" for k in HEADLINES) + " |",
             "|---|---|---|---|" + "---|" * len(HEADLINES)]
    for name in names:
        for r in data["scenes"][name]["runs"]:
            if r.get("status", "ok") == "ok" and math.isclose(r["rtol"], rtol):
                lines.append(f"| {name} | {label(r['edge_mm'])} | {r['steps']} | "
                             f"{r['cpu_s']:.2f} | "
                             + " | ".join(f"{r[errors][k]:.1e}" for k in HEADLINES) + " |")
    return "\n".join(lines) + "\n\n" + cheapest_table(data, errors, targets)


def cheapest_table(data: dict, errors: str = "errors_sharp",
                   targets=(0.1, 0.01, 0.003, 0.001)) -> str:
    """Per scene, output and target error: the CPU (and rtol) of each edge's cheapest run
    reaching it (:func:`cheapest`; – : none does)."""
    names = list(data["scenes"])
    edges = sorted({r["edge_mm"] for st in data["scenes"].values() for r in st["runs"]})
    lines = ["| scene | output | error ≤ | " + " | ".join(label(e) for e in edges) + " |",
             "|---|---|---|" + "---|" * len(edges)]
    for name in names:
        for k in HEADLINES:
            for tgt in targets:
                best = cheapest(data["scenes"][name]["runs"], k, tgt, errors)
                cells = [("–" if best.get(e) is None else
                          f"{best[e]['cpu_s']:.2f} s ({best[e]['rtol']:.0e})") for e in edges]
                lines.append(f"| {name} | {HEADLINES[k][0]} | {tgt:g} | " + " | ".join(cells)
                             + " |")
    return "\n".join(lines) + "\n"
