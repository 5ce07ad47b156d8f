"""``bearingdae sweep``, ``skidmap`` and ``paper``: the studies that run many scenes (dask).

Pipeline: the cli layer over the studies (sweep, skid map, paper set).
"""

from __future__ import annotations

import sys
from pathlib import Path

from .common import _check_workers, _overrides, _set_origin

def _print_sweep(ds) -> None:
    from ..plots.figure_common import SKEW_SCALE, SKEW_UNIT  # one unit in every command
    from ..studies.sweep import axis_units

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
                  f"skew {r.skew_amplitude_rad.item() * SKEW_SCALE:7.3f} {SKEW_UNIT}  "
                  f"max slip {r.max_abs_slip_m_s.item():7.4f} m/s  "
                  f"peak cage {r.peak_cage_force_N.item():7.3f} N"
                  + (f"  [check: {flags}]" if flags else ""))
        else:
            print(f"  {label:28s} {r.status.item()}: {r.error.item()}")


def _sweep(args) -> int:
    from ..util.atomic import check_writable, refuse_aliases
    from ..studies.sweep import SchedulerUnreachable, SweepIncomplete, load_sweep, run_sweep

    _check_workers(args)
    sw = load_sweep(args.sweep, _overrides(args.set), _set_origin(args.set))
    out = check_writable(args.output or Path(f"{sw.name}.nc"))
    runs = out.with_name(out.stem + "_runs")
    check_writable(runs / "run.nc")
    refuse_aliases([("output", out)], [("sweep file", sw.origin), ("base scene", sw.base_path)])
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
        from ..util.atomic import write_failure

        print(f"bearingdae: {write_failure(exc, getattr(exc, 'filename', None) or out)}; "
              f"the runs completed so far are kept in {runs}/: the same command computes only "
              "the others", file=sys.stderr)
        return 1
    _print_sweep(ds)
    print(f"wrote {out}")
    return 0 if ds.attrs["runs_failed"] == 0 and ds.attrs["runs_completed"] == len(sw.points) \
        else 1


def _skidmap(args) -> int:
    from ..util.atomic import check_writable, refuse_aliases
    from ..scene import resolve_case
    from ..studies.skidmap import run_skidmap
    from ..studies.sweep import SchedulerUnreachable, SweepIncomplete

    _check_workers(args)
    source = resolve_case(args.case)
    out = check_writable(args.output or Path(f"{source.stem}_skidmap.nc"))
    check_writable(out.with_name(out.stem + "_sweep_runs") / "run.nc")
    refuse_aliases([("output", out), ("figure", out.with_suffix(".png"))],
                   [("scene file", source)])
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
    from ..util.atomic import check_writable
    from ..studies.paper import run_paper
    from ..studies.sweep import SchedulerUnreachable, SweepIncomplete

    _check_workers(args)
    check_writable(args.output / "runs" / "run.nc")
    if args.trends:
        return _paper_trends(args)
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
        return _write_failed(exc, args)
    bad = 0
    for name, ds in res.items():
        _print_sweep(ds)
        bad += ds.attrs["runs_failed"]
    first = next(iter(res.values()))
    figs = __import__("json").loads(first.attrs["paper_set_figures"])
    print(f"paper set: {first.attrs['paper_set_wall_time_s']:.1f} s wall; wrote "
          f"{len(res)} sweep files and {len(figs)} figures to {args.output}/")
    return 0 if bad == 0 else 1


def _write_failed(exc, args) -> int:
    """A write of ``paper`` failed: say which, and that the completed runs are kept; status 1."""
    from ..util.atomic import write_failure

    print(f"bearingdae: {write_failure(exc, getattr(exc, 'filename', None) or args.output)}"
          f"; the runs completed so far are kept in {args.output / 'runs'}/: the same "
          "command computes only the others", file=sys.stderr)
    return 1


def _paper_trends(args) -> int:
    """``bearingdae paper --trends``: the trends table, its verdicts and figures."""
    from ..studies.sweep import SchedulerUnreachable, SweepIncomplete
    from ..scene import SceneError
    from ..studies.trends import TREND_WINDOW
    from ..studies.trends_report import run_paper_trends

    window = (TREND_WINDOW["numerics.warmup_cage_revolutions"],
              TREND_WINDOW["numerics.cage_revolutions"])
    print(f"paper trends: the speed, moment and radial-load sweeps, {window[0]:g} warm-up + "
          f"{window[1]:g} recorded cage revolutions per run (before --set); runs in "
          f"{args.output / 'runs'}/ (resumable)", flush=True)
    try:
        table, verdicts, paths = run_paper_trends(
            args.output, scheduler=args.scheduler, workers=args.workers,
            progress=not args.no_progress, retry_failed=args.retry_failed,
            figures=not args.no_figures, overrides=_overrides(args.set),
            override_origin=_set_origin(args.set), scheduler_timeout_s=args.scheduler_timeout)
    except SceneError:
        raise  # bad --set: status 2 with the field named, as every command
    except (SweepIncomplete, SchedulerUnreachable, ValueError) as exc:  # ValueError: failed runs
        print(f"bearingdae: {exc}", file=sys.stderr)
        return 1
    except (OSError, RuntimeError) as exc:
        return _write_failed(exc, args)
    for _, v in verdicts.iterrows():
        print(f"  {v['claim']:45s} {v['reading']:16s} z {v['z_first_last']:+6.1f}  "
              f"{v['verdict']}")
    counts = verdicts["verdict"].value_counts().to_dict()
    print("verdicts: " + ", ".join(f"{n} {k}" for k, n in counts.items()))
    print(f"wrote {len(paths)} files to {args.output}/ (trends.csv, trends_verdicts.csv, "
          "trends.nc, trends.md, figures)")
    return 0
