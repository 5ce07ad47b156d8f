"""Work-precision study: error against wall time for IDA, Newmark-β and the scipy peers.

Conventions (SOLVER-NOTES.md, after SciMLBenchmarks and the IVP Test Set):

- **Reference**: IDA at the tightest rtol of its ladder that completes (atol = rtol ·
  ``ATOL_PER_RTOL``, the ratio of the scene defaults), *confirmed* by its agreement with the
  next-tightest completed IDA run (and with the finest run of any ladder marked
  ``confirms_reference``, e.g. Newmark-β at its smallest step). That agreement is recorded as the
  error floor: errors below it are not resolved by the reference.
- **Errors** over the recorded window, the reference interpolated to each run's output times,
  for cage speed, orbit speed, spin speed, skew angle and slice contact force:
  relative RMS ``rms(x - x_ref) / rms(x_ref)`` and relative max ``max|x - x_ref| / max|x_ref|``
  (both over every time and every roller / slice / race), plus
  ``mescd = -log10 max |x - x_ref| / (atol/rtol + |x_ref|)`` over the five quantities in units of
  their unknown scale (contact force in units of the model's force scale), with the fixed
  ratio atol/rtol = ``ATOL_PER_RTOL``.
- **Time**: the integrator's wall time (consistent initialisation and stepping, what
  ``solver_statistics['wall_time_s']`` records; the shared output post-processing is excluded),
  median over ``repeat`` runs after a JIT warm-up of every solver. A scipy peer is stopped after
  ``time_limit_factor`` × the median wall time of IDA at rtol 1e-6 and recorded as failed;
  tighter rungs of that peer are then recorded as skipped.

Adding a ladder (e.g. Newmark-β's step sizes) is one :class:`Ladder` entry in :func:`ladders`.
Failed runs are rows with ``status`` "failed" or "skipped" and their message, never dropped.
"""

from __future__ import annotations

import json
import math
import statistics
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np
import xarray as xr

QUANTITIES = ("cage_speed", "orbit_speed", "spin_speed", "skew_angle", "contact_force")
#: atol / rtol along the ladders: the ratio of the scene defaults (1e-8 / 1e-6)
ATOL_PER_RTOL = 1e-2
ATOL_MAX = 1e-4  # the scene's upper bound on atol
IDA_RTOLS = tuple(10.0 ** -e for e in range(3, 11))  # 1e-3 ... 1e-10
PEER_RTOLS = IDA_RTOLS  # tighter rungs are skipped once a peer exceeds the time limit
QUICK_IDA_RTOLS = (1e-4, 1e-6, 1e-8)
QUICK_PEER_RTOLS = (1e-4,)
#: Newmark-β fixed steps [s] (average acceleration); the finest also confirms the reference
NEWMARK_STEPS_S = (4e-6, 2e-6, 1e-6, 5e-7)
QUICK_NEWMARK_STEPS_S = (2e-6,)
PEERS = ("scipy-BDF", "scipy-Radau", "scipy-LSODA")
#: IDA rung whose wall time sets the peers' time limit, and whose error is compared (Must show)
IDA_TARGET_RTOL = 1e-6
TIME_LIMIT_FACTOR = 20.0
#: tiny window for the JIT warm-up of each solver
WARMUP_OVERRIDES = {"numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 0.01}


def tolerance_overrides(rtol: float) -> dict:
    """Scene overrides of one rtol rung (atol scaled alongside)."""
    return {"numerics.rtol": rtol, "numerics.atol": min(ATOL_PER_RTOL * rtol, ATOL_MAX)}


@dataclass(frozen=True)
class Ladder:
    """One solver's ladder: ``configure(value) -> (scene overrides, solver_options)``."""

    solver: str
    parameter: str  #: "rtol" or "step_s"
    values: tuple
    configure: Callable[[float], tuple[dict, dict]]
    timed_limit: bool = False  #: stop runs after the time limit (the scipy peers)
    confirms_reference: bool = False  #: its finest run is compared with the reference
    label: str = ""  #: name in the table (default: ``solver``)

    @property
    def name(self) -> str:
        return self.label or self.solver


def ladders(quick: bool = False, solvers: tuple[str, ...] | None = None) -> list[Ladder]:
    """The ladders of the study (IDA first: it provides the reference and the time limit)."""
    ida_r, peer_r, nm_h = ((QUICK_IDA_RTOLS, QUICK_PEER_RTOLS, QUICK_NEWMARK_STEPS_S) if quick
                           else (IDA_RTOLS, PEER_RTOLS, NEWMARK_STEPS_S))
    out = [Ladder("ida", "rtol", ida_r, lambda r: (tolerance_overrides(r), {}))]
    out.append(Ladder("newmark", "step_s", nm_h,
                      lambda h: ({"numerics.newmark_step_s": h}, {}), confirms_reference=True))
    out += [Ladder(p, "rtol", peer_r, lambda r: (tolerance_overrides(r), {}), timed_limit=True)
            for p in PEERS]
    if solvers is not None:
        unknown = set(solvers) - {ld.solver for ld in out}
        if unknown:
            raise ValueError(f"solvers {sorted(unknown)}: allowed are "
                             f"{', '.join(ld.solver for ld in out)}")
        out = [ld for ld in out if ld.solver in solvers or ld.solver == "ida"]
    return out


def naive_ladders(rtols=(IDA_TARGET_RTOL,)) -> list[Ladder]:
    """The straightforward nested implementation, for scale: the static solver's numpy Newton
    per right-hand side and scipy's own finite-difference Jacobian (BDF and LSODA). Named
    ``naive-*`` so they are not counted among the peers of the verdict."""
    return [Ladder(f"scipy-{m}", "rtol", tuple(rtols),
                   lambda r: (tolerance_overrides(r), {"inner": "static", "jac": "fd"}),
                   timed_limit=True, label=f"naive-{m}") for m in ("BDF", "LSODA")]


# ---------------------------------------------------------------------------------------------
# Error metrics (pure functions of arrays)
# ---------------------------------------------------------------------------------------------
def relative_errors(sol: np.ndarray, ref: np.ndarray) -> tuple[float, float]:
    """(relative RMS, relative max) of ``sol`` against ``ref`` over all elements:
    rms(sol - ref) / rms(ref) and max|sol - ref| / max|ref| (NaN for a zero reference)."""
    sol, ref = np.asarray(sol, float), np.asarray(ref, float)
    d = sol - ref
    ref_ms, ref_max = float(np.mean(ref * ref)), float(np.max(np.abs(ref)))
    if ref_max == 0.0:  # a relative error of an identically zero reference is undefined
        return math.nan, math.nan
    return math.sqrt(float(np.mean(d * d)) / ref_ms), float(np.max(np.abs(d))) / ref_max


def mescd(sol: np.ndarray, ref: np.ndarray, floor: float) -> float:
    """Mixed-error significant correct digits, -log10 max |sol - ref| / (floor + |ref|)
    (IVP Test Set; ``floor`` = atol / rtol). +inf for identical arrays."""
    sol, ref = np.asarray(sol, float), np.asarray(ref, float)
    e = float(np.max(np.abs(sol - ref) / (floor + np.abs(ref))))
    return math.inf if e == 0.0 else -math.log10(e)


def interp_time(t_ref: np.ndarray, values: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Linear interpolation along axis 0 of ``values`` (given at ``t_ref``) to times ``t``."""
    t_ref, t = np.asarray(t_ref, float), np.asarray(t, float)
    if t_ref.shape == t.shape and np.array_equal(t_ref, t):
        return np.asarray(values)
    i = np.clip(np.searchsorted(t_ref, t) - 1, 0, t_ref.size - 2)
    w = ((t - t_ref[i]) / (t_ref[i + 1] - t_ref[i])).reshape((-1,) + (1,) * (values.ndim - 1))
    return values[i] * (1.0 - w) + values[i + 1] * w


def quantity_errors(ds: xr.Dataset, ref: xr.Dataset, scales: dict[str, float]) -> dict:
    """Errors of a run against the reference, per quantity, over the run's times that lie
    inside the reference window; plus ``mescd`` over all five quantities (scaled)."""
    t = ds.time.values
    t_ref = ref.time.values
    keep = (t >= t_ref[0] - 1e-12) & (t <= t_ref[-1] + 1e-12)
    out, worst = {}, []
    for q in QUANTITIES:
        if q not in ds or q not in ref or not keep.any():
            out[f"{q}_rel_rms"] = out[f"{q}_rel_max"] = math.nan
            continue
        x = ds[q].values[keep]
        x_ref = interp_time(t_ref, ref[q].values, t[keep])
        out[f"{q}_rel_rms"], out[f"{q}_rel_max"] = relative_errors(x, x_ref)
        s = scales[q]
        worst.append(10.0 ** -mescd(x / s, x_ref / s, ATOL_PER_RTOL))
    out["mescd"] = -math.log10(max(worst)) if worst and max(worst) > 0 else math.nan
    return out


def time_at_error(errors, times, target: float) -> tuple[float, str]:
    """Wall time of a solver at error ``target``, log-log interpolated along its Pareto front
    (runs not beaten in both error and time by another run).

    Returns (time, kind): kind "interpolated"; "not reached" (every run less accurate than
    ``target``: time = the most accurate run's time, a lower bound only if that ladder was
    stopped by the time limit); "below ladder" (even the loosest run is more accurate: time =
    that run's, an upper bound); "no runs".
    """
    pts = sorted((e, t) for e, t in zip(errors, times)
                 if np.isfinite(e) and np.isfinite(t) and e > 0)
    if not pts:
        return math.nan, "no runs"
    front = []
    for e, t in pts:  # ascending error: keep a run only if faster than every more accurate one
        if not front or t < front[-1][1]:
            front.append((e, t))
    if target < front[0][0]:
        return front[0][1], "not reached"
    if target >= front[-1][0]:
        return front[-1][1], "below ladder"
    for (e0, t0), (e1, t1) in zip(front, front[1:]):
        if e0 <= target <= e1:
            a = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + a * (math.log(t1) - math.log(t0))), "interpolated"
    return math.nan, "no runs"  # unreachable


# ---------------------------------------------------------------------------------------------
# Running the study
# ---------------------------------------------------------------------------------------------
@dataclass
class Run:
    solver: str
    parameter: str
    value: float
    rtol: float = math.nan
    atol: float = math.nan
    status: str = "ok"  #: ok | failed | skipped
    message: str = ""
    wall_s: float = math.nan  #: median integrator wall time
    walls_s: list = field(default_factory=list)
    time_limit_s: float = math.nan
    kernel_evaluations: int = -1  #: residual-kernel calls, including those in Jacobians
    steps: int = -1
    errors: dict = field(default_factory=dict)
    is_reference: bool = False
    dataset: xr.Dataset | None = field(default=None, repr=False)

    @property
    def label(self) -> str:
        return f"{self.solver} {self.parameter}={self.value:g}"


def derive(scene, overrides: dict):
    """A copy of ``scene`` with dotted-key ``overrides`` applied (through its TOML text)."""
    from .scene import scene_from_dict

    return scene_from_dict(tomllib.loads(scene.to_toml()), overrides)


def _execute(scene, solver: str, options: dict):
    """One run -> (Dataset or None, status, message, integrator wall [s], statistics)."""
    from .api import SimulationError, simulate
    from .solvers import from_name

    try:
        ds = simulate(scene, solver=from_name(solver, **(options or {})))
        status, msg = "ok", "completed"
    except SimulationError as exc:
        ds, status, msg = exc.dataset, "failed", str(exc)
    except Exception as exc:  # noqa: BLE001 - a failed rung is a result, not a crash
        return None, "failed", f"{type(exc).__name__}: {exc}", math.nan, {}
    stats = json.loads(ds.attrs["solver_statistics"]) if ds is not None else {}
    return ds, status, msg, float(stats.get("wall_time_s", math.nan)), stats


def warm_up(scene, solvers) -> None:
    """Compile every solver's kernels (numba) outside the timings."""
    tiny = derive(scene, WARMUP_OVERRIDES)
    for s in solvers:
        _execute(tiny, s, {})


def run_ladder(scene, ladder: Ladder, repeat: int, time_limit_s: float | None,
               bar=None) -> list[Run]:
    """Every rung of one ladder; after a time-out the tighter rungs are recorded as skipped."""
    runs, stopped = [], None
    for v in ladder.values:
        overrides, options = ladder.configure(v)
        sc = derive(scene, overrides)
        tol = ladder.parameter == "rtol"
        run = Run(ladder.name, ladder.parameter, v, rtol=sc.dynamics.rtol if tol else math.nan,
                  atol=sc.dynamics.atol if tol else math.nan)
        if ladder.timed_limit and time_limit_s is not None:
            options = {**options, "time_limit_s": time_limit_s}
            run.time_limit_s = time_limit_s
        if stopped is not None:
            run.status, run.message = "skipped", stopped
            runs.append(run)
            if bar is not None:
                bar.update(repeat)
            continue
        for k in range(repeat):
            if bar is not None:
                bar.set_description(f"{run.label} ({k + 1}/{repeat})")
            ds, status, msg, wall, stats = _execute(sc, ladder.solver, options)
            if k == 0:
                # keep only what the errors need (a long window's slice fields are large)
                run.dataset = ds[[q for q in QUANTITIES if q in ds]] if ds is not None else None
                run.status, run.message = status, msg
                run.kernel_evaluations = int(stats.get("residual_calls", -1)
                                             + stats.get("residual_calls_in_jacobian", 0))
                run.steps = int(stats.get("steps", -1))  # IDA's step count is not exposed
            run.walls_s.append(wall)
            if bar is not None:
                bar.update(1)
            if status != "ok":
                if bar is not None:
                    bar.update(repeat - k - 1)
                break
        run.wall_s = float(statistics.median(run.walls_s)) if run.walls_s else math.nan
        if run.status != "ok" and "time limit" in run.message:
            stopped = f"not run: {run.label} already exceeded the time limit"
        runs.append(run)
    return runs


def error_scales(scene) -> dict[str, float]:
    """Unit of each quantity in the mescd: its unknown scale; the model's force scale."""
    from .system.model import build_model

    m = build_model(scene)
    lay = m.layout
    out = {"contact_force": m.force_scale_N}
    for q in ("cage_speed", "orbit_speed", "spin_speed", "skew_angle"):
        try:
            out[q] = float(m.scale[lay.index(q, 0 if q in lay.local_names else None)])
        except KeyError:  # physics switched off: the quantity is not in the output either
            out[q] = 1.0
    return out


@dataclass
class Study:
    scene_title: str
    runs: list[Run]
    reference: Run | None
    floor: dict  #: errors of the next-tightest IDA run against the reference
    confirmations: dict  #: solver -> errors of its finest run against the reference
    time_limit_s: float
    repeat: int
    overrides: dict


def study(scene, repeat: int = 3, quick: bool = False, solvers=None,
          time_limit_factor: float = TIME_LIMIT_FACTOR, progress: bool = True,
          base_overrides: dict | None = None, extra: list[Ladder] = ()) -> Study:
    """Run every ladder (and the ``extra`` ones) on ``scene``, choose and confirm the
    reference, compute the errors."""
    lads = ladders(quick, solvers) + list(extra)
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=sum(len(ld.values) for ld in lads) * repeat, unit="run")
    warm_up(scene, list(dict.fromkeys(ld.solver for ld in lads)))
    runs = run_ladder(scene, lads[0], repeat, None, bar)
    ida_ok = [r for r in runs if r.status == "ok"]
    target = [r for r in ida_ok if math.isclose(r.value, IDA_TARGET_RTOL)]
    basis = target[0].wall_s if target else (
        statistics.median(r.wall_s for r in ida_ok) if ida_ok else math.nan)
    limit = time_limit_factor * basis if np.isfinite(basis) else None
    for ld in lads[1:]:
        runs += run_ladder(scene, ld, repeat, limit, bar)
    if bar is not None:
        bar.close()

    ref = min(ida_ok, key=lambda r: r.rtol) if ida_ok else None
    floor, confirmations = {}, {}
    if ref is not None:
        ref.is_reference = True
        scales = error_scales(scene)
        for r in runs:
            if r.status == "ok" and r.dataset is not None:
                r.errors = quantity_errors(r.dataset, ref.dataset, scales)
        nxt = [r for r in ida_ok if r is not ref]
        if nxt:
            second = min(nxt, key=lambda r: r.rtol)
            floor = {"run": second.label, **second.errors}
        for ld in lads:
            if ld.confirms_reference:
                ok = [r for r in runs if r.solver == ld.name and r.status == "ok"]
                if ok:
                    finest = min(ok, key=lambda r: r.value)
                    confirmations[ld.name] = {"run": finest.label, **finest.errors}
    return Study(scene.title, runs, ref, floor, confirmations,
                 limit if limit is not None else math.nan, repeat, base_overrides or {})


#: time_at_error kind -> what the peer's true time at the target error is, relative to the
#: reported one (assuming error falls as the tolerance tightens)
BOUNDS = {"interpolated": "=", "not reached": ">=", "below ladder": "<=", "no runs": "?"}
SPEEDUP_CLAIM = 10.0
#: IDA-1e-6's error must exceed the reference's own error floor by this factor to be resolved
RESOLVED_FACTOR = 10.0


def comparison(st: Study, quantity: str = "cage_speed") -> dict:
    """The Must-show number: each scipy peer's time at IDA-1e-6's error in ``quantity`` (rel.
    RMS), as a multiple of IDA-1e-6's time, with whether it is exact or a bound (the same for
    the other ladders, e.g. Newmark-β, under ``others``), and the verdict on
    "IDA is at least 10x faster than the best peer": "met" when every peer's ratio is >= 10
    (exactly or as a lower bound), "not met" when some peer's ratio is < 10 (exactly or as an
    upper bound), otherwise "undetermined"."""
    key = f"{quantity}_rel_rms"
    ida = [r for r in st.runs if r.solver == "ida" and r.status == "ok"
           and math.isclose(r.value, IDA_TARGET_RTOL) and not r.is_reference]
    if not ida:
        return {"quantity": quantity, "ida_wall_s": math.nan, "ida_error": math.nan,
                "peers": {}, "verdict": "undetermined",
                "note": f"IDA at rtol {IDA_TARGET_RTOL:g} did not complete (or is the reference)"}
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
        entry = {"wall_s": t, "kind": kind, "bound": bound, "ratio": t / t_ida}
        (peers if s.startswith("scipy-") else others)[s] = entry
    lower = [p["ratio"] for p in peers.values() if p["bound"] in ("=", ">=")]
    upper = [p["ratio"] for p in peers.values() if p["bound"] in ("=", "<=")]
    if any(r < SPEEDUP_CLAIM for r in upper):
        verdict = "not met"
    elif peers and len(lower) == len(peers) and all(r >= SPEEDUP_CLAIM for r in lower):
        verdict = "met"
    else:
        verdict = "undetermined"
    note = ""
    if not e_star > RESOLVED_FACTOR * floor:  # also when there is no floor (NaN)
        verdict = "undetermined"
        note = (f"IDA-1e-6's error {e_star:.2e} is not {RESOLVED_FACTOR:g}x above the "
                f"reference's own error floor {floor:.2e} (agreement with the next-tightest "
                "IDA run): the errors are not resolved, e.g. trajectories of different "
                "tolerances diverge over a long window (shorten it)")
    known = {s: p for s, p in peers.items() if np.isfinite(p["ratio"])}
    best = min(known, key=lambda s: known[s]["ratio"]) if known else None
    return {"quantity": quantity, "ida_wall_s": t_ida, "ida_error": e_star, "peers": peers,
            "others": others, "best_peer": best,
            "best_ratio": known[best]["ratio"] if best else math.nan, "verdict": verdict,
            "reference_floor": floor, "note": note}


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


def plot(st: Study, path: Path) -> Path:
    """Log-log error (x) against wall time (y): one panel per quantity and one for mescd."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter

    panels = [(f"{q}_rel_rms", f"{q.replace('_', ' ')}: relative RMS error") for q in QUANTITIES]
    panels.append(("mescd", "10^-mescd (mixed error)"))
    fig, axes = plt.subplots(2, 3, figsize=(14, 8))
    # fixed margins: constrained layout doubled the (already seconds-long) log-axis rendering
    fig.subplots_adjust(left=0.05, right=0.99, bottom=0.07, top=0.94, wspace=0.22, hspace=0.25)
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
        ax.yaxis.set_minor_formatter(NullFormatter())
        ax.grid(True, which="both", alpha=0.3)
    axes.ravel()[0].legend(fontsize=8)
    ref = st.reference.label if st.reference else "none"
    fig.suptitle(f"work-precision: {st.scene_title} (reference {ref})", fontsize=10)
    from .plotting import save_figure  # the one atomic figure recipe

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    return save_figure(fig, path)


def write(st: Study, out_dir: Path, stem: str) -> dict[str, Path]:
    """NetCDF table, CSV table and PNG of a study into ``out_dir``."""
    from .results import save

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    ds = table(st)
    nc = save(ds, out_dir / f"{stem}_workprecision.nc")
    csv = out_dir / f"{stem}_workprecision.csv"
    df = ds.to_dataframe()
    df.to_csv(csv, index=False)
    png = plot(st, out_dir / f"{stem}_workprecision.png")
    return {"netcdf": nc, "csv": csv, "png": png}
