"""Command line: ``bearingdae run|static|sweep|skidmap|paper|plot|workprecision|cases|keys`` (thin
layer over the Python API).

Errors in the user's input are printed as one paragraph and exit with status 2; no traceback
reaches the user for bad input.
"""

from __future__ import annotations

import contextlib
import sys
import warnings
from pathlib import Path

DEFAULT_CASE = "yang20_baseline"


def _case_arguments(p: argparse.ArgumentParser, default_output: str) -> None:
    """CASE, -o/--output and --set, shared by the commands that run one scene."""
    p.add_argument("case", nargs="?", default=DEFAULT_CASE,
                   help=f"scene TOML file or bundled case name (default: {DEFAULT_CASE})")
    p.add_argument("-o", "--output", type=Path,
                   help=f"NetCDF file to write (default: {default_output})")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override a scene key, e.g. --set operating.radial_load_N=400")


def _parser() -> argparse.ArgumentParser:
    import argparse  # here, not at the top: `import bearingdae.cli` stays cheap (see main)

    p = argparse.ArgumentParser(
        prog="bearingdae",
        description="Cylindrical roller bearing dynamics (skid, skew, cage) with SUNDIALS IDA.",
    )
    p.add_argument("--version", action="store_true", help="print the version and exit")
    sub = p.add_subparsers(dest="command")

    r = sub.add_parser("run", help="dynamic simulation (IDA or Newmark) of a scene -> NetCDF + PNG")
    _case_arguments(r, "CASE.nc")
    r.add_argument("--solver", choices=("ida", "newmark"), default="ida",
                   help="integrator: SUNDIALS IDA (default) or fixed-step Newmark-beta "
                        "(numerics.newmark_step_s)")
    r.add_argument("--no-plot", action="store_true", help="do not write the overview PNG")
    r.add_argument("--no-progress", action="store_true", help="no progress bar")
    r.add_argument("--resume", action="store_true",
                   help="continue from OUTPUT.checkpoint.npz, left by an interrupted run")
    r.add_argument("--checkpoint-every", type=int, default=50, metavar="N",
                   help="write the checkpoint every N output samples (and every 10 s)")
    r.add_argument("--until-steady", action="store_true",
                   help="warm up until the cage speed is steady (numerics.until_steady; "
                        "criterion in bearingdae/steady.py), then record the window")

    s = sub.add_parser("static", help="quasi-static equilibrium of a scene -> NetCDF")
    _case_arguments(s, "CASE_static.nc")

    w = sub.add_parser("sweep", help="parameter sweep (dask) -> one NetCDF with the axes as dims")
    w.add_argument("sweep", help="sweep TOML file or bundled sweep (paper/yang20_speed_sweep)")
    w.add_argument("-o", "--output", type=Path, help="NetCDF file to write (default: SWEEP.nc); "
                   "the runs are kept in OUTPUT_runs/ and reused on restart")
    _cluster_arguments(w)

    pp = sub.add_parser("paper", help="the whole paper set: every sweep of cases/paper + Figs "
                        "11-24")
    pp.add_argument("-o", "--output", type=Path, default=Path("paper"),
                    help="output folder (default: paper/)")
    pp.add_argument("--no-figures", action="store_true", help="do not draw the PNGs")
    _cluster_arguments(pp)

    f = sub.add_parser("plot", help="the paper's figures (11-24) from a run or sweep file")
    f.add_argument("file", type=Path, help="NetCDF file from run, sweep or paper")
    f.add_argument("--figure", action="append", default=[], metavar="N",
                   help="figure number 11-24, 'trends' or 'all' (default: the file's figures); "
                   "repeatable")
    f.add_argument("-o", "--output", type=Path, help="PNG to write (with several figures: the "
                   "stem of OUTPUT_figNN.png; default: FILE_figNN.png)")
    f.add_argument("--select", action="append", default=[], metavar="DIM=VALUE",
                   help="pick runs of a sweep, e.g. --select speed_rpm=6000")

    k = sub.add_parser("keys", help="list every scene key with default, range and meaning")
    k.add_argument("--markdown", action="store_true", help="as a Markdown table")

    wp = sub.add_parser("workprecision", help="error against wall time of IDA and the scipy "
                       "peers -> NetCDF + CSV table and PNG in DIR")
    wp.add_argument("case", nargs="?", default=DEFAULT_CASE,
                   help=f"scene TOML file or bundled case name (default: {DEFAULT_CASE})")
    wp.add_argument("-o", "--output", type=Path, default=Path("."), metavar="DIR",
                   help="output directory (default: .)")
    wp.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="override a scene key, e.g. --set operating.speed_rpm=10000")
    wp.add_argument("--revolutions", type=float, default=0.2, metavar="R",
                    help="errors over the first R cage revolutions from t = 0 (default 0.2: "
                         "on the baseline, runs at different tolerances diverge exponentially "
                         "after ~0.3 revolution; see docs/performance.md)")
    wp.add_argument("--repeat", type=int, default=3, help="timed runs per rung (median; >= 1)")
    wp.add_argument("--quick", action="store_true", help="short ladders (a smoke test)")
    wp.add_argument("--solvers", default=None,
                   help="comma-separated subset of the peers (IDA always runs)")
    wp.add_argument("--time-limit-factor", type=float, default=20.0, metavar="F",
                   help="stop a peer after F x the wall time of IDA at rtol 1e-6 (default 20)")
    wp.add_argument("--no-progress", action="store_true", help="no progress bar")

    sm = sub.add_parser("skidmap", help="steady cage slip over speed x radial load (dask, "
                        "until_steady) -> NetCDF + contour PNG with the skid boundary")
    sm.add_argument("case", help="scene TOML file or bundled case name")
    sm.add_argument("--speeds", type=float, nargs="+", required=True, metavar="RPM",
                    help="inner-ring speeds [r/min], at least 2")
    sm.add_argument("--loads", type=float, nargs="+", required=True, metavar="N",
                    help="radial loads [N], at least 2")
    sm.add_argument("-o", "--output", type=Path, help="NetCDF map (default: CASE_skidmap.nc; "
                    "PNG beside it, runs in OUTPUT_sweep_runs/, reused on restart)")
    sm.add_argument("--boundary", type=float, default=0.01, metavar="SLIP",
                    help="cage slip ratio of the skid boundary line (default 0.01 = 1 %%)")
    _cluster_arguments(sm)  # with --set: a scene key of every run

    c = sub.add_parser("cases", help="list the bundled scenes; --copy one to start a case of "
                       "your own")
    c.add_argument("--path", action="store_true", help="print full paths")
    c.add_argument("--copy", nargs=2, metavar=("CASE", "FILE"),
                   help="copy the bundled CASE to FILE (a new file) to edit, e.g. "
                        "--copy yang20_baseline my_case.toml")
    return p


def _cluster_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="dask scheduler address to attach to (default: a local cluster of "
                   "pinned single-thread processes); 'synchronous' runs in this process")
    p.add_argument("--workers", type=int, metavar="N", help="processes of the local cluster "
                   "(default: [sweep] workers, else the CPU count)")
    p.add_argument("--retry-failed", action="store_true", help="run again the runs recorded "
                   "as failed (default: keep their error)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--scheduler-timeout", type=float, default=30.0, metavar="S",
                   help="seconds to wait for the --scheduler address (default 30)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override a scene key in every run, e.g. --set numerics.slices=6")


def _overrides(pairs: list[str]) -> dict:
    import tomllib

    out = {}
    for pair in pairs:
        if "=" not in pair:
            raise ValueError(f"--set {pair!r}: expected KEY=VALUE, e.g. operating.speed_rpm=6000")
        key, value = pair.split("=", 1)
        try:
            parsed = tomllib.loads(f"v = {value}")
        except (ValueError, RecursionError):  # TOMLDecodeError, > 4300 digits, deep nesting
            parsed = {}
        # A bare string such as a profile name (or text that is more than one TOML value) is
        # passed on as a string; the scene validation then names the key.
        out[key.strip()] = parsed["v"] if list(parsed) == ["v"] else value
    return out


def _scene(args, more: dict | None = None):
    """The scene of CASE with the --set overrides (and ``more``, e.g. from --until-steady);
    an error caused by a --set names it."""
    from . import load_scene

    return load_scene(args.case, {**_overrides(args.set), **(more or {})},
                      override_origin=_set_origin(args.set))


def _static(args) -> int:
    from . import solve_static
    from .atomic import check_writable
    from .outputs import save_or_keep
    from .progress import compile_notice
    from .scene import resolve_case
    from .solvers.static import StaticConvergenceError

    scene = _scene(args)
    out = check_writable(args.output or Path(f"{resolve_case(args.case).stem}_static.nc"))
    _notice(compile_notice())
    try:
        ds = solve_static(scene)
    except StaticConvergenceError as exc:
        print(f"bearingdae: static solver failure: {exc}; no file written", file=sys.stderr)
        return 1
    written, problems = save_or_keep(ds, out)
    q = ds.contact_force
    print(f"{scene.title}")
    print(f"  Newton iterations      {ds.attrs['newton_iterations']}")
    print(f"  relative residual      {ds.attrs['residual_max_relative']:.2e}")
    print(f"  ring displacement      {ds.ring_displacement.sel(direction='radial').item() * 1e6:.3f} µm")
    print(f"  ring tilt              {ds.ring_tilt.sel(direction='radial').item() * 1e3:.4f} mrad")
    print(f"  max roller load inner  {q.sel(race='inner').sum('slice').max().item():.2f} N")
    print(f"  max slice pressure     {ds.contact_pressure.max().item() / 1e9:.3f} GPa")
    for line in problems:
        print(f"bearingdae: {line}", file=sys.stderr)
    if problems:
        return 1
    print(f"wrote {written}")
    return 0


def _notice(line: str | None) -> None:
    if line:
        print(line, file=sys.stderr, flush=True)


def _run(args) -> int:
    from . import SimulationError, simulate
    from .analysis import summary
    from .atomic import check_writable
    from .checkpoint import Checkpoint, checkpoint_path
    from .outputs import remove_superseded, save_or_keep
    from .plotting import overview
    from .progress import compile_notice
    from .scene import resolve_case
    from .solvers import from_name

    scene = _scene(args, {"numerics.until_steady": True} if args.until_steady else None)
    out = check_writable(args.output or Path(f"{resolve_case(args.case).stem}.nc"))
    for other in (checkpoint_path(out),) + (() if args.no_plot else (out.with_suffix(".png"),)):
        check_writable(other)
    accuracy = (f"rtol {scene.dynamics.rtol:g}" if args.solver == "ida" else
                f"Newmark step {scene.dynamics.newmark_step_s:g} s")
    print(f"{scene.title}: {scene.bearing.rollers} rollers x {scene.numerics.slices} slices, "
          f"{accuracy}", flush=True)
    status = 0
    ckpt = Checkpoint(checkpoint_path(out), resume=args.resume,
                      every_samples=args.checkpoint_every)
    if args.resume and not ckpt.path.exists():
        print(f"bearingdae: no checkpoint {ckpt.path}; starting from t = 0", file=sys.stderr)
    _notice(compile_notice())
    try:
        ds = simulate(scene, solver=from_name(args.solver), progress=not args.no_progress,
                      checkpoint=ckpt)  # any solver of the contract checkpoints
    except SimulationError as exc:
        ds = exc.dataset
        # Ctrl-C ends every command with status 130; the samples are kept all the same
        status = 130 if str(exc).startswith("interrupted by the user") else 1
        print(f"bearingdae: {'' if status == 130 else 'solver failure: '}{exc}", file=sys.stderr)
        if ckpt.path.exists():
            print(f"bearingdae: checkpoint {ckpt.path} kept; continue with --resume",
                  file=sys.stderr)
        if ds is None or ds.sizes.get("time", 0) == 0:
            print("bearingdae: nothing was computed before the failure; no file written",
                  file=sys.stderr)
            return status
        out = out.with_name(out.stem + "_partial.nc")
        print(f"bearingdae: keeping the {ds.sizes['time']} samples computed before the failure",
              file=sys.stderr)
    if ckpt.write_error is not None:
        print(f"bearingdae: warning: the checkpoint could not be written "
              f"({ckpt.write_error.strerror or ckpt.write_error}): {ckpt.path}", file=sys.stderr)
    written, problems = save_or_keep(ds, out)
    if problems:
        for line in problems:
            print(f"bearingdae: {line}", file=sys.stderr)
        if ckpt.path.exists() and ckpt.write_error is None:
            print(f"bearingdae: checkpoint {ckpt.path} holds the run: once '{out.parent}' has "
                  "room, the same command with --resume writes it without computing again",
                  file=sys.stderr)
        if written is None:
            return 1
        status = status or 1
        out = written
    elif status == 0:
        ckpt.discard()
        for stale in remove_superseded(out):
            print(f"removed {stale} (an earlier incomplete run of {out.name})")
    s = summary(ds)
    st = __import__("json").loads(ds.attrs["solver_statistics"])
    print(f"  wall time                {st['wall_time_s']:.2f} s "
          f"({st['residual_calls']} residual calls, {st['jacobian_calls']} Jacobians)")
    if "mean_cage_speed_rad_s" in s:
        print(f"  mean cage speed          {s['mean_cage_speed_rad_s']:.3f} rad/s "
              f"(epicyclic {s['epicyclic_cage_speed_rad_s']:.3f}, slip "
              f"{100 * s['cage_slip_ratio']:.2f} %)")
    if "steady_state_reached" in ds.attrs:
        print(f"  steady state             {'reached' if ds.attrs['steady_state_reached'] else 'NOT reached'}"
              f" after {ds.attrs['warmup_cage_revolutions_used']:.3g} warm-up cage revolutions "
              f"(last block change {ds.attrs['steady_last_change']:+.2e} of epicyclic)")
    if "max_abs_skew_rad" in s:
        print(f"  max |skew|               {s['max_abs_skew_rad'] * 180 / 3.141592653589793:.4f} deg")
    if "max_abs_slip_m_s" in s:
        print(f"  max |slip velocity|      {s['max_abs_slip_m_s']:.4f} m/s")
    print(f"wrote {out}")
    if not args.no_plot and ds.sizes.get("time", 0) > 1:
        png = out.with_suffix(".png")
        try:
            print(f"wrote {overview(ds, png)}")
        except OSError as exc:
            from .atomic import write_failure

            print(f"bearingdae: {write_failure(exc, png)} (the NetCDF result {out} is "
                  "written)", file=sys.stderr)
            return status or 1
    return status


def _workprecision(args) -> int:
    from . import load_scene
    from .studies import workprecision as wp
    from .scene import resolve_case

    if args.repeat < 1:
        raise ValueError(f"--repeat {args.repeat}: must be >= 1")
    if not args.time_limit_factor > 0:
        raise ValueError(f"--time-limit-factor {args.time_limit_factor}: must be > 0")
    overrides = {"numerics.warmup_cage_revolutions": 0.0,
                 "numerics.cage_revolutions": args.revolutions, **_overrides(args.set)}
    scene = load_scene(args.case, overrides)
    solvers = tuple(s.strip() for s in args.solvers.split(",")) if args.solvers else None
    print(f"{scene.title}: work-precision, {scene.dynamics.warmup_cage_revolutions:g} + "
          f"{scene.dynamics.cage_revolutions:g} cage revolutions, repeat {args.repeat}")
    st = wp.study(scene, repeat=args.repeat, quick=args.quick, solvers=solvers,
                  time_limit_factor=args.time_limit_factor, progress=not args.no_progress,
                  base_overrides=overrides)
    paths = wp.write(st, args.output, resolve_case(args.case).stem)
    for r in st.runs:
        e = r.errors.get("cage_speed_rel_rms", float("nan"))
        note = " (reference)" if r.is_reference else ("" if r.status == "ok" else
                                                      f" {r.status}: {r.message}")
        print(f"  {r.label:28s} {r.wall_s:9.3f} s  cage-speed error {e:9.2e}{note}")
    cmp = wp.comparison(st)
    if cmp.get("best_peer"):
        p = cmp["peers"][cmp["best_peer"]]
        bound = {"=": "", ">=": ">= ", "<=": "<= "}.get(p["bound"], "? ")
        print(f"IDA rtol {wp.IDA_TARGET_RTOL:g}: {cmp['ida_wall_s']:.3f} s at cage-speed error "
              f"{cmp['ida_error']:.2e}; best peer {cmp['best_peer']} at that error: "
              f"{bound}{cmp['best_ratio']:.1f}x "
              f"({p['kind']}); 10x claim: {cmp['verdict']}")
    if cmp.get("note"):
        print(f"bearingdae: warning: {cmp['note']}", file=sys.stderr)
    for p in paths.values():
        print(f"wrote {p}")
    return 0 if st.reference is not None else 1
def _check_workers(args) -> None:
    if args.workers is not None and args.workers < 1:
        raise ValueError(f"--workers {args.workers}: allowed range is [1, 4096]")
    if not args.scheduler_timeout > 0:
        raise ValueError(f"--scheduler-timeout {args.scheduler_timeout}: must be > 0 s")


def _set_origin(pairs: list[str]) -> str:
    return " ".join(f"--set {pair}" for pair in pairs) or "--set"


def _print_sweep(ds) -> None:
    from .sweep import axis_units

    dims = [d for d in ds.status.dims]
    flat = ds.stack(run=dims) if dims else ds.expand_dims("run")
    print(f"{ds.attrs['title']}: {ds.attrs['runs_completed']}/{ds.attrs['runs_total']} "
          f"completed, {ds.attrs['runs_failed']} failed")
    for i in range(flat.sizes["run"]):
        r = flat.isel(run=i)
        label = ", ".join(f"{d} {r[d].item():g}{(' ' + axis_units(ds[d].attrs['scene_key'])[1])}"
                          if isinstance(r[d].item(), (int, float)) else f"{d} {r[d].item()}"
                          for d in dims) or "run"
        if r.status.item() == "completed":
            flags = r.plausibility_warnings.item() if "plausibility_warnings" in r else ""
            print(f"  {label:28s} cage slip {100 * r.cage_slip_ratio.item():6.2f} %  "
                  f"skew {r.skew_amplitude_rad.item() * 1e3:7.3f} mrad  "
                  f"max slip {r.max_abs_slip_m_s.item():7.4f} m/s  "
                  f"peak cage {r.peak_cage_force_N.item():7.3f} N"
                  + (f"  [check: {flags}]" if flags else ""))
        else:
            print(f"  {label:28s} {r.status.item()}: {r.error.item()}")


def _sweep(args) -> int:
    from .atomic import check_writable
    from .sweep import SchedulerUnreachable, SweepIncomplete, load_sweep, run_sweep

    _check_workers(args)
    sw = load_sweep(args.sweep, _overrides(args.set), _set_origin(args.set))
    out = check_writable(args.output or Path(f"{sw.name}.nc"))
    runs = out.with_name(out.stem + "_runs")
    check_writable(runs / "run.nc")
    print(f"{sw.title}: {len(sw.points)} runs; results in {out}, runs in {runs}/", flush=True)
    try:
        ds = run_sweep(sw, out, scheduler=args.scheduler, workers=args.workers,
                       progress=not args.no_progress, retry_failed=args.retry_failed,
                       scheduler_timeout_s=args.scheduler_timeout)
    except SweepIncomplete as exc:
        _print_sweep(exc.datasets[0])
        print(f"bearingdae: {exc}", file=sys.stderr)
        return 1
    except SchedulerUnreachable as exc:
        print(f"bearingdae: {exc}", file=sys.stderr)
        return 1
    except (OSError, RuntimeError) as exc:  # a run or the sweep file could not be written
        from .atomic import write_failure

        print(f"bearingdae: {write_failure(exc, getattr(exc, 'filename', None) or out)}; "
              f"the runs completed so far are kept in {runs}/: the same command computes only "
              "the others", file=sys.stderr)
        return 1
    _print_sweep(ds)
    print(f"wrote {out}")
    return 0 if ds.attrs["runs_failed"] == 0 and ds.attrs["runs_completed"] == len(sw.points) \
        else 1


def _skidmap(args) -> int:
    from .atomic import check_writable
    from .scene import resolve_case
    from .skidmap import run_skidmap
    from .sweep import SchedulerUnreachable, SweepIncomplete

    _check_workers(args)
    out = check_writable(args.output or Path(f"{resolve_case(args.case).stem}_skidmap.nc"))
    check_writable(out.with_name(out.stem + "_sweep_runs") / "run.nc")
    print(f"skid map of {args.case}: {len(args.speeds)} speeds x {len(args.loads)} loads, "
          f"until steady; runs in {out.with_name(out.stem + '_sweep_runs')}/")
    try:
        ds, paths = run_skidmap(args.case, args.speeds, args.loads, out,
                                overrides=_overrides(args.set), boundary=args.boundary,
                                scheduler=args.scheduler, workers=args.workers,
                                progress=not args.no_progress, retry_failed=args.retry_failed,
                                scheduler_timeout_s=args.scheduler_timeout)
    except (SweepIncomplete, SchedulerUnreachable) as exc:
        print(f"bearingdae: {exc}", file=sys.stderr)
        return 1
    slip = ds.cage_slip_ratio.transpose("speed_rpm", "radial_load_N")
    print("cage slip [%]   " + " ".join(f"{f:>8g} N" for f in ds.radial_load_N.values))
    for n, row in zip(ds.speed_rpm.values, slip.values):
        print(f"{n:8g} r/min  " + " ".join(f"{100 * v:10.2f}" for v in row))
    print(f"{ds.attrs['runs_completed']}/{ds.attrs['runs_total']} completed, "
          f"{ds.attrs['runs_not_steady']} not steady")
    for p in paths:
        print(f"wrote {p}")
    return 0 if ds.attrs["runs_completed"] == ds.attrs["runs_total"] else 1


def _paper(args) -> int:
    from .atomic import check_writable, write_failure
    from .paper import run_paper
    from .sweep import SchedulerUnreachable, SweepIncomplete

    _check_workers(args)
    check_writable(args.output / "runs" / "run.nc")
    try:
        res = run_paper(args.output, scheduler=args.scheduler, workers=args.workers,
                        progress=not args.no_progress, retry_failed=args.retry_failed,
                        figures=not args.no_figures, overrides=_overrides(args.set),
                        scheduler_timeout_s=args.scheduler_timeout,
                        override_origin=_set_origin(args.set))
    except (SweepIncomplete, SchedulerUnreachable) as exc:
        print(f"bearingdae: {exc}", file=sys.stderr)
        return 1
    except (OSError, RuntimeError) as exc:
        print(f"bearingdae: {write_failure(exc, getattr(exc, 'filename', None) or args.output)}"
              f"; the runs completed so far are kept in {args.output / 'runs'}/: the same "
              "command computes only the others", file=sys.stderr)
        return 1
    bad = 0
    for name, ds in res.items():
        _print_sweep(ds)
        bad += ds.attrs["runs_failed"]
    first = next(iter(res.values()))
    figs = __import__("json").loads(first.attrs["paper_set_figures"])
    print(f"paper set: {first.attrs['paper_set_wall_time_s']:.1f} s wall; wrote "
          f"{len(res)} sweep files and {len(figs)} figures to {args.output}/")
    return 0 if bad == 0 else 1


def _plot(args) -> int:
    import xarray as xr

    from .atomic import check_writable, write_failure
    from .plotting import PAPER_CAPTIONS, available_figures, figure

    if args.file.is_dir():
        raise ValueError(f"plot: '{args.file}' is a directory; give a NetCDF file from run, "
                         "sweep or paper (e.g. a .nc file inside it)")
    if not args.file.is_file():
        raise ValueError(f"plot: file '{args.file}' does not exist")
    try:
        with xr.open_dataset(args.file) as ds:
            ds = ds.load()
    except (OSError, ValueError) as exc:
        raise ValueError(f"plot: '{args.file}' is not a readable NetCDF file ({exc})") from None
    for pair in args.select:
        dim, sep, value = pair.partition("=")
        if not sep or dim not in ds.dims:
            raise ValueError(f"--select {pair!r}: expected DIM=VALUE with DIM one of "
                             f"{[d for d in ds.dims if d in ds.coords]}")
        coord = ds[dim]
        try:
            kind = type(coord.values[0].item())
            v = value.strip().lower() in ("true", "1") if kind is bool else kind(value)
            ds = ds.sel({dim: v})
        except (KeyError, ValueError):
            raise ValueError(f"--select {pair!r}: {dim} has values "
                             f"{list(coord.values)}") from None
    wanted = []
    for f in args.figure or [None]:
        if f is None or f == "all":
            wanted += available_figures(ds) if f is None else list(PAPER_CAPTIONS) + ["trends"]
        elif f == "trends":
            wanted.append(f)
        elif f.isdigit() and int(f) in PAPER_CAPTIONS:
            wanted.append(int(f))
        else:
            raise ValueError(f"--figure {f!r}: allowed are 11-24, 'trends' and 'all'")
    stem = args.output or args.file
    targets = {}
    for number in wanted:
        tag = "trends" if number == "trends" else f"fig{number:02d}"
        if args.output is not None and len(wanted) == 1:
            targets[number] = args.output
        else:
            targets[number] = stem.with_name(f"{stem.stem}_{tag}.png")
        check_writable(targets[number])  # before drawing anything
    drawn = 0
    for number, target in targets.items():
        try:
            print(f"wrote {figure(ds, number, target)}")
            drawn += 1
        except OSError as exc:  # e.g. the disk filled up while drawing
            print(f"bearingdae: figure {number}: {write_failure(exc, target)}", file=sys.stderr)
            return 1
        except ValueError as exc:
            if len(wanted) == 1 or args.figure not in ([], ["all"]):
                raise ValueError(f"figure {number}: {exc}") from None
            print(f"bearingdae: figure {number} skipped: {exc}", file=sys.stderr)
    if not drawn:
        print(f"bearingdae: no figure drawn from {args.file}", file=sys.stderr)
        return 1
    return 0


def _keys(args) -> int:
    from .scene import key_table

    rows = key_table()
    if args.markdown:
        print("| key | default | allowed | meaning |")
        print("|---|---|---|---|")
        for key, default, rng, desc in rows:
            print(f"| `{key}` | {default} | {rng} | {desc} |")
    else:
        for key, default, rng, desc in rows:
            print(f"{key:34s} {default:>10s} {rng:>18s}  {desc}")
    return 0


def _cases(args) -> int:
    from .scene import bundled_case_dirs, resolve_case
    from .sweep import is_sweep_file

    if args.copy:
        from .atomic import atomic_write, check_writable

        name, dest = args.copy
        source = resolve_case(name)
        dest = check_writable(Path(dest))
        if dest.exists():
            raise ValueError(f"cases --copy: '{dest}' exists already; give a new file name")
        with atomic_write(dest) as tmp:
            Path(tmp).write_bytes(source.read_bytes())
        print(f"wrote {dest} (a copy of {source.name}); edit it, then: bearingdae run {dest}")
        return 0
    seen = set()
    for d in bundled_case_dirs():
        for p in sorted(d.rglob("*.toml")):
            rel = p.relative_to(d).with_suffix("")
            if rel in seen:
                continue
            seen.add(rel)
            tag = "  (sweep: bearingdae sweep NAME)" if is_sweep_file(p) else ""
            print(f"{p if args.path else rel}{tag}")
    return 0


@contextlib.contextmanager
def _plausibility_printed():
    """Print each PlausibilityWarning as one 'bearingdae: warning:' paragraph on stderr, as it
    comes; other warnings go their usual way. (Not catch_warnings(record=True): recording every
    warning of a sweep kept dask objects alive until a garbage collection at exit deadlocked.)"""
    from .guards import PlausibilityWarning

    def show(message, category, filename, lineno, file=None, line=None):
        if issubclass(category, PlausibilityWarning):
            print(f"bearingdae: warning: {message}", file=sys.stderr)
        else:
            shown(message, category, filename, lineno, file, line)

    with warnings.catch_warnings():
        warnings.simplefilter("always", PlausibilityWarning)
        shown, warnings.showwarning = warnings.showwarning, show
        yield


#: modules each command needs, loaded before the command starts (see bearingdae/program.py)
_MODULES = {"run": ("api", "analysis", "checkpoint", "plotting"), "static": ("api",),
            "sweep": ("sweep",), "paper": ("paper",), "plot": ("plotting",),
            "workprecision": ("studies.workprecision",), "cases": ("sweep",), "keys": (),
            "skidmap": ("skidmap", "sweep", "plotting")}


def main(argv: list[str] | None = None) -> int:
    """The command line, in-process; returns the exit status. A KeyboardInterrupt (the heavy
    modules load here, not at ``import bearingdae.cli``) ends with one line and status 130; a
    dynamic run interrupted while integrating keeps its samples (``_partial.nc``) and ends with
    status 130 as well.
    The ``bearingdae`` program (bearingdae/program.py) adds what only a process can do: Ctrl-C
    during start-up and shut-down, and interrupts lost in callbacks."""
    from .interrupts import INTERRUPTED

    try:
        return execute(argv)
    except KeyboardInterrupt:
        print(INTERRUPTED, file=sys.stderr)
        return 130


def execute(argv: list[str] | None) -> int:
    """:func:`main` without its Ctrl-C handling: a KeyboardInterrupt propagates (the program,
    bearingdae/program.py, handles it)."""
    args = _parser().parse_args(argv)
    if args.version:
        from . import __version__

        print(f"bearingdae {__version__}")
        return 0
    import importlib

    from .interrupts import raise_on_ctrl_c
    from .scene import SceneError
    from .solvers.static import StaticConvergenceError
    from .solvers.sundials.library import SundialsUnavailable

    for module in ("guards",) + _MODULES.get(args.command, ()):
        importlib.import_module(f".{module}", __package__)
    raise_on_ctrl_c()  # modules loaded: from here on Ctrl-C is a KeyboardInterrupt
    handlers = {"run": _run, "static": _static, "cases": _cases, "keys": _keys,
                "workprecision": _workprecision,
                "sweep": _sweep, "paper": _paper, "plot": _plot, "skidmap": _skidmap}
    if args.command is None:
        _parser().print_help()
        return 0
    try:
        with _plausibility_printed():
            return handlers[args.command](args)
    except (SceneError, ValueError) as exc:
        print(f"bearingdae: error: {exc}", file=sys.stderr)
        return 2
    except SundialsUnavailable as exc:  # a broken or foreign scikit-sundae installation
        print(f"bearingdae: SUNDIALS unavailable: {exc}", file=sys.stderr)
        return 1
    except StaticConvergenceError as exc:  # e.g. the initial equilibrium of `run`
        print(f"bearingdae: static solver failure: {exc}; no file written", file=sys.stderr)
        return 1
    except OSError as exc:  # a write no command expected to fail (each keeps its results)
        from .atomic import write_failure

        print(f"bearingdae: {write_failure(exc, exc.filename or '?')}", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    from bearingdae.program import main as program

    sys.exit(program())
