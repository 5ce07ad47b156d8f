"""The work-precision study's verdict, table, figure and files."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import xarray as xr

from .errors import time_at_error
from .ladders import ATOL_PER_RTOL, IDA_TARGET_RTOL, QUANTITIES
from .runs import Study
from ...plots.figure_common import closed_on_failure

#: time_at_error kind -> what the peer's true time at the target error is, relative to the
#: reported one (assuming error falls as the tolerance tightens)
BOUNDS = {"interpolated": "=", "not reached": ">=", "below ladder": "<=", "no runs": "?"}
SPEEDUP_CLAIM = 10.0
#: IDA-1e-6's error must exceed the reference's own error floor by this factor to be resolved
RESOLVED_FACTOR = 10.0
#: a relative error of IDA-1e-6 below this is round-off (rtol 1e-6 leaves ~1e-7 once the
#: window holds dynamics): the window is too short to compare the solvers
ROUNDOFF_ERROR = 1e-11


def comparison(st: Study, quantity: str = "cage_speed") -> dict:
    """The Must-show number: each scipy peer's time at IDA-1e-6's error in ``quantity`` (rel.
    RMS), as a multiple of IDA-1e-6's time, with whether it is exact or a bound (the same for
    the other ladders, e.g. Newmark-β, under ``others``), and the verdict on
    "IDA is at least 10x faster than the best peer": "met" when every peer's ratio is >= 10
    (exactly or as a lower bound), "not met" when some peer's ratio is < 10 (exactly or as an
    upper bound), otherwise "undetermined". ``note`` says why a verdict is undetermined and
    what to change for one (:func:`_advice`)."""
    key = f"{quantity}_rel_rms"
    ida = [r for r in st.runs if r.solver == "ida" and r.status == "ok"
           and math.isclose(r.value, IDA_TARGET_RTOL) and not r.is_reference]
    if not ida:
        return {"quantity": quantity, "ida_wall_s": math.nan, "ida_error": math.nan,
                "peers": {}, "verdict": "undetermined",
                "note": f"IDA at rtol {IDA_TARGET_RTOL:g} did not complete (or is the "
                        "reference): its row's message says why; the comparison needs it"}
    e_star, t_ida = ida[0].errors[key], ida[0].wall_s
    floor = st.floor.get(key, math.nan)
    peers, others = {}, {}
    for s in sorted({r.solver for r in st.runs if r.solver != "ida"}):
        rows = [r for r in st.runs if r.solver == s]
        ok = [r for r in rows if r.status == "ok"]
        t, kind = time_at_error([r.errors.get(key, math.nan) for r in ok],
                                [r.wall_s for r in ok], e_star)
        bound = BOUNDS[kind]
        if kind in ("not reached", "no runs") and any("time limit" in r.message for r in rows):
            t, kind, bound = st.time_limit_s, f"{kind} within the time limit", ">="
        entry = {"wall_s": t, "kind": kind, "bound": bound, "ratio": t / t_ida,
                 "rungs": len(rows)}
        (peers if s.startswith("scipy-") else others)[s] = entry
    lower = [p["ratio"] for p in peers.values() if p["bound"] in ("=", ">=")]
    upper = [p["ratio"] for p in peers.values() if p["bound"] in ("=", "<=")]
    if any(r < SPEEDUP_CLAIM for r in upper):
        verdict = "not met"
    elif peers and len(lower) == len(peers) and all(r >= SPEEDUP_CLAIM for r in lower):
        verdict = "met"
    else:
        verdict = "undetermined"
    resolved = e_star > RESOLVED_FACTOR * floor  # False also when there is no floor (NaN)
    if not resolved:
        verdict = "undetermined"
    note = "" if verdict != "undetermined" else "; ".join(
        _advice(st, peers, e_star, floor, resolved))
    known = {s: p for s, p in peers.items() if np.isfinite(p["ratio"])}
    best = min(known, key=lambda s: known[s]["ratio"]) if known else None
    return {"quantity": quantity, "ida_wall_s": t_ida, "ida_error": e_star, "peers": peers,
            "others": others, "best_peer": best,
            "best_ratio": known[best]["ratio"] if best else math.nan, "verdict": verdict,
            "reference_floor": floor, "note": note}


def _advice(st: Study, peers: dict, e_star: float, floor: float, resolved: bool) -> list[str]:
    """Why the verdict is undetermined, each reason with what to change (reasons with the
    same change share one line)."""
    found = _floor_advice(st, e_star, floor) if not resolved else []
    for name, p in peers.items():
        if p["bound"] == ">=" and p["ratio"] < SPEEDUP_CLAIM:
            if "time limit" in p["kind"]:
                found.append((f"{name} was stopped at the time limit before reaching IDA-1e-6's "
                              f"error (only >= {p['ratio']:.1f}x known)",
                              f"raise --time-limit-factor to at least {SPEEDUP_CLAIM:g}"))
            else:
                found.append((f"{name}'s tightest rung is still less accurate than IDA-1e-6 "
                              f"(only >= {p['ratio']:.1f}x known)", _more_rungs(p, "tighter")))
        elif p["bound"] == "<=" and p["ratio"] >= SPEEDUP_CLAIM:
            found.append((f"{name}'s loosest rung is already more accurate than IDA-1e-6 (only "
                          f"<= {p['ratio']:.1f}x known)", _more_rungs(p, "looser")))
        elif p["bound"] == "?":
            found.append((f"every rung of {name} failed", "their rows say why"))
    changes = list(dict.fromkeys(change for _, change in found))
    return [f"{'; '.join(why for why, c in found if c == change)}: {change}"
            for change in changes]


def _floor_advice(st: Study, e_star: float, floor: float) -> list[tuple[str, str]]:
    """(why, what to change) when IDA-1e-6's error is not resolved against the reference."""
    if not np.isfinite(floor):
        return [("the reference is unconfirmed: fewer than two IDA rungs completed, so the "
                 "errors' floor is unknown", "their rows say why")]
    rev = st.overrides.get("numerics.cage_revolutions")
    known = isinstance(rev, (int, float))
    floor_run = str(st.floor.get("run", "the next-tightest IDA run"))
    what = (f"errors not resolved: IDA-1e-6's error {e_star:.2e} is not {RESOLVED_FACTOR:g}x "
            f"above the reference's own error floor {floor:.2e} ({floor_run} against the "
            "reference)")
    out = []
    if floor_run.startswith("ida rtol=") and math.isclose(
            float(floor_run.rpartition("=")[2]), IDA_TARGET_RTOL):
        out.append((f"{what}, and that run is IDA-1e-6 itself (the --quick ladder has no IDA "
                    "rung between it and the reference)", QUICK_FIX))
    if e_star < ROUNDOFF_ERROR:
        out.append(("the runs agree to round-off: the window is too short for the tolerances "
                    "to matter" if out else f"{what}: the runs agree to round-off, the window "
                    "is too short for the tolerances to matter",
                    "lengthen it" + (f", e.g. --revolutions {2 * rev:g} (now {rev:g})" if known
                                     else " (--revolutions)")))
    elif not out:
        out.append((f"{what}: runs at different tolerances diverge exponentially over a long "
                    "window", "shorten it" + (f", e.g. --revolutions {rev / 2:g} (now {rev:g})"
                                              if known else " (--revolutions)")))
    return out


#: what settles a verdict that --quick's short ladders leave open
QUICK_FIX = "run without --quick (its ladders are too short for a verdict)"


def _more_rungs(peer: dict, which: str) -> str:
    if peer["rungs"] == 1:
        return QUICK_FIX
    return (f"its ladder needs {which} rungs (PEER_RTOLS in "
            "bearingdae/studies/workprecision/ladders.py)")


# ---------------------------------------------------------------------------------------------
# Output
# ---------------------------------------------------------------------------------------------
COLUMNS = ("solver", "parameter", "value", "rtol", "atol", "status", "is_reference", "wall_s",
           "walls_s", "time_limit_s", "kernel_evaluations", "steps", "message")


def table(st: Study) -> xr.Dataset:
    """The study as a Dataset with one row per run (dimension ``run``)."""
    err_cols = [f"{q}_{m}" for q in QUANTITIES for m in ("rel_rms", "rel_max")] + ["mescd"]
    rows = []
    for r in st.runs:
        row = {c: getattr(r, c) for c in COLUMNS}
        row["walls_s"] = " ".join(f"{w:.4g}" for w in r.walls_s)
        row["time_limit_s"] = r.time_limit_s
        row.update({c: r.errors.get(c, math.nan) for c in err_cols})
        rows.append(row)
    units = {"value": "1 (rtol) or s (step_s)", "rtol": "1", "atol": "1 (unknown scales)",
             "wall_s": "s", "time_limit_s": "s", "mescd": "1"}
    data = {}
    for c in list(COLUMNS) + err_cols:
        vals = [row[c] for row in rows]
        arr = np.array(vals, dtype=str if isinstance(vals[0], str) else None) if vals else []
        if c == "is_reference":
            arr = np.array(vals, dtype=np.int8)
        attrs = {"units": units.get(c, "1")} if c not in ("solver", "parameter", "status",
                                                            "message", "walls_s") else {}
        data[c] = xr.Variable("run", arr, attrs)
    cmp = comparison(st)
    ds = xr.Dataset(data)
    ds.attrs.update({
        "title": f"bearingdae work-precision study: {st.scene_title}",
        "reference": st.reference.label if st.reference else "none",
        "reference_error_floor": json.dumps(st.floor),
        "reference_confirmations": json.dumps(st.confirmations),
        "time_limit_s": st.time_limit_s,
        "repeat": st.repeat,
        "scene_overrides": json.dumps(st.overrides),
        "error_definitions": "rel_rms = rms(x - x_ref)/rms(x_ref), rel_max = max|x - x_ref|/"
                             "max|x_ref| over the recorded window; mescd = -log10 max|x - x_ref|"
                             f"/({ATOL_PER_RTOL:g} + |x_ref|) in unknown-scale units",
        "time_definition": "integrator wall time (solver_statistics wall_time_s), median of "
                           "repeats after a JIT warm-up",
        "comparison_cage_speed": json.dumps(cmp, default=float),
    })
    return ds


@closed_on_failure
def plot(st: Study, path: Path) -> Path:
    """Log-log error (x) against wall time (y): one panel per quantity and one for mescd."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, NullFormatter

    panels = [(f"{q}_rel_rms", f"{q.replace('_', ' ')}: relative RMS error") for q in QUANTITIES]
    panels.append(("mescd", "10^-mescd (mixed error)"))
    fig, axes = plt.subplots(2, 3, figsize=(14, 8))
    # fixed margins: constrained layout doubled the (already seconds-long) log-axis rendering;
    # the key below the panels (inside one it hid points)
    fig.subplots_adjust(left=0.055, right=0.99, bottom=0.12, top=0.93, wspace=0.22, hspace=0.25)
    solvers = list(dict.fromkeys(r.solver for r in st.runs))
    markers = dict(zip(solvers, "os^vDP*X"))
    for ax, (key, title) in zip(axes.ravel(), panels):
        for s in solvers:
            rows = [r for r in st.runs if r.solver == s and r.status == "ok"
                    and not r.is_reference and key in r.errors]
            e = np.array([10.0 ** -r.errors[key] if key == "mescd" else r.errors[key]
                          for r in rows])
            t = np.array([r.wall_s for r in rows])
            good = np.isfinite(e) & (e > 0)
            if good.any():
                ax.loglog(e[good], t[good], marker=markers[s], label=s)
                for r, ee, tt in zip([r for r, g in zip(rows, good) if g], e[good], t[good]):
                    ax.annotate(f"{r.value:.0e}", (ee, tt), fontsize=6, alpha=0.7)
        fl = st.floor.get(key)
        if fl is not None and np.isfinite(fl) and fl > 0:
            fl = 10.0 ** -fl if key == "mescd" else fl
            ax.axvline(fl, color="grey", ls=":", lw=1, label="reference floor")
        if np.isfinite(st.time_limit_s):
            ax.axhline(st.time_limit_s, color="r", ls="--", lw=0.8, label="peer time limit")
        ax.set(xlabel=title, ylabel="wall time [s]")
        ax.xaxis.set_minor_formatter(NullFormatter())
        # wall times as plain numbers (0.2, 0.5, 1, 2; "4 x 10^0" ran into the next panel),
        # the minor ticks labelled too where the axis spans less than two decades
        ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        low, high = ax.get_ylim()
        ax.yaxis.set_minor_formatter(FuncFormatter(_two_and_five) if high < 100 * low
                                     else NullFormatter())
        ax.grid(True, which="both", alpha=0.3)
    from ...plots.figure_common import save_figure, wrap_title  # the one figure recipe

    key = {}
    for ax in axes.ravel():  # every solver and line of any panel, once
        for handle, label in zip(*ax.get_legend_handles_labels()):
            key.setdefault(label, handle)
    fig.legend(list(key.values()), list(key), loc="lower center", ncol=len(key), fontsize=8,
               title="labels at the points: each run's rtol (IDA, scipy) or step [s] (Newmark)",
               title_fontsize=8)
    ref = st.reference.label if st.reference else "none"
    fig.suptitle(wrap_title(f"work-precision: {st.scene_title} (reference {ref})", fig, 10),
                 fontsize=10)

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    return save_figure(fig, path)


def _two_and_five(value: float, _pos=None) -> str:
    """Minor tick label of a log axis: 0.2, 0.5, 2, 5, ... (the others stay unlabelled)."""
    if not value > 0:
        return ""
    lead = value / 10.0 ** math.floor(math.log10(value) + 1e-9)
    return f"{value:g}" if round(lead) in (2, 5) and abs(lead - round(lead)) < 1e-6 else ""


def write(st: Study, out_dir: Path, stem: str) -> dict[str, Path]:
    """NetCDF table, CSV table and PNG of a study into ``out_dir``."""
    from ...results import save

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    ds = table(st)
    nc = save(ds, out_dir / f"{stem}_workprecision.nc")
    csv = out_dir / f"{stem}_workprecision.csv"
    df = ds.to_dataframe()
    df.to_csv(csv, index=False)
    png = plot(st, out_dir / f"{stem}_workprecision.png")
    return {"netcdf": nc, "csv": csv, "png": png}
