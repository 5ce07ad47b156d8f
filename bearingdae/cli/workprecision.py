"""``bearingdae workprecision``: the solvers' work-precision study of a scene.

Pipeline: the cli layer over studies/workprecision.
"""

from __future__ import annotations

import sys
from pathlib import Path

from .common import _overrides

def _workprecision(args) -> int:
    from .. import load_scene
    from ..studies import workprecision as wp
    from ..scene import resolve_case

    if args.statistics:
        return _statistical(args)
    if args.revolutions is None:
        args.revolutions = 0.2
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
              f"({p['kind']}); {SPEEDUP_QUESTION}: {VERDICT_WORDS.get(cmp['verdict'], cmp['verdict'])}")
    if cmp.get("note"):  # why the verdict is undetermined, and what to change
        print(f"bearingdae: warning: {SPEEDUP_QUESTION}: "
              f"{VERDICT_WORDS.get(cmp['verdict'], cmp['verdict'])}: {cmp['note']}",
              file=sys.stderr)
    for p in paths.values():
        print(f"wrote {p}")
    return 0 if st.reference is not None else 1


#: what the comparison answers, as the summary asks it (studies/workprecision/report.py)
SPEEDUP_QUESTION = "is IDA at least 10x faster than every scipy solver at the same error"
VERDICT_WORDS = {"met": "yes", "not met": "no",
                 "undetermined": "cannot tell from this study"}


def _statistical(args) -> int:
    from .. import load_scene
    from ..scene import resolve_case
    from ..studies.workprecision import statistical as sw

    default = load_scene(args.case, _overrides(args.set))
    default_revs = default.dynamics.cage_revolutions
    revs = sw.WINDOW_FACTOR * default_revs if args.revolutions is None else args.revolutions
    if not revs >= default_revs:
        raise ValueError(f"--revolutions {revs}: must be at least the scene's record, "
                         f"numerics.cage_revolutions = {default_revs:g}")
    scene = load_scene(args.case, {**_overrides(args.set), "numerics.cage_revolutions": revs})
    print(f"{scene.title}: statistical work-precision, "
          f"{scene.dynamics.warmup_cage_revolutions:g} + {scene.dynamics.cage_revolutions:g} "
          f"cage revolutions per run, rtol {', '.join(f'{r:g}' for r in sw.STATISTICS_RTOLS)}")
    say = None if args.no_progress else (lambda text: print("  " + text, file=sys.stderr))
    ds = sw.statistical_study(scene, default_revs, progress=say)
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    stem = f"{resolve_case(args.case).stem}_statistics"
    from ..results import save

    paths = [save(ds, out / f"{stem}.nc")]
    table = out / f"{stem}.csv"
    ds.drop_vars(["status"]).to_dataframe().to_csv(table)
    paths += [table, sw.plot(ds, out / f"{stem}.png")]
    for line in sw.summary_lines(ds):
        print(line)
    for p in paths:
        print(f"wrote {p}")
    return 0 if all(s == "ok" for s in ds.status.values) else 1
