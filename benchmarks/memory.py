"""Peak memory of `bearingdae run` against the recorded length: does RSS grow with the record?

    python benchmarks/run.py memory [--revolutions 3 30] [--old REV] [--set KEY=VALUE ...]
                                    [--json F]

Each point is one ``bearingdae run CASE -o FILE --no-progress --set
numerics.cage_revolutions=N`` (overview PNG included) in a fresh process, after one untimed
short run per tree that loads (or compiles) its kernels. Measured from outside the process
with ``os.wait4``: the peak resident set size (``ru_maxrss``; the child that compiles the
Jacobian on a cold start is not in it: it is compiled before the timed runs), the CPU time
(user + system) and the wall time; and the size of the file written. ``--old REV`` measures
another git revision (or a folder holding ``bearingdae/``) at the same points, interleaved.

Streaming (results/record.py) keeps one block of samples in memory: the peaks at 3 and 30
revolutions must be within 10 % of each other (docs/performance.md, "Memory").
"""

from __future__ import annotations

import argparse
import os
import tempfile

from run import ROOT, header, overrides, run_process, tree, write_json


def one_run(path, case: str, over: dict, out: str) -> dict:
    ru, wall = run_process(path, case, over, out)
    return {"max_rss_MB": ru.ru_maxrss / 1024, "cpu_s": ru.ru_utime + ru.ru_stime,
            "wall_s": wall, "file_MB": os.path.getsize(out) / 2**20}


def main(argv=None, name="memory") -> None:
    ap = argparse.ArgumentParser(prog=f"run.py {name}", description=__doc__.splitlines()[0])
    ap.add_argument("--revolutions", type=float, nargs="+", default=[3.0, 30.0],
                    help="recorded cage revolutions of each point (default 3 30)")
    ap.add_argument("--old", help="also measure this git revision or folder")
    ap.add_argument("--case", default="yang20_baseline")
    ap.add_argument("--set", action="append", metavar="KEY=VALUE",
                    help="further scene overrides, e.g. numerics.samples_per_cage_revolution=400")
    ap.add_argument("--json", help="write the rows here")
    a = ap.parse_args(argv)
    over = overrides(a.set)
    trees = {"new": tree(str(ROOT))}
    if a.old:
        trees["old"] = tree(a.old)
    header(f"{a.case}{f' {over}' if over else ''}: peak RSS of bearingdae run against the "
           f"recorded length; trees {', '.join(f'{k} = {v}' for k, v in trees.items())}")
    scratch = tempfile.mkdtemp(prefix="bearingdae-memory-")
    for label, path in trees.items():  # kernels loaded (or compiled) first, untimed
        one_run(path, a.case, {**over, "numerics.cage_revolutions": 0.05,
                               "numerics.warmup_cage_revolutions": 0},
                os.path.join(scratch, f"warm-{label}.nc"))
    rows = []
    for revs in a.revolutions:
        for label, path in trees.items():
            out = os.path.join(scratch, f"{label}-{revs:g}.nc")
            r = one_run(path, a.case, {**over, "numerics.cage_revolutions": revs}, out)
            os.unlink(out)
            r.update(tree=label, cage_revolutions=revs)
            rows.append(r)
            print(f"{label}: {revs:g} recorded cage revolutions: peak RSS {r['max_rss_MB']:.0f} "
                  f"MB, CPU {r['cpu_s']:.1f} s, wall {r['wall_s']:.1f} s, file "
                  f"{r['file_MB']:.1f} MB", flush=True)
    for label in trees:
        mine = [r for r in rows if r["tree"] == label]
        if len(mine) > 1:
            lo, hi = mine[0]["max_rss_MB"], mine[-1]["max_rss_MB"]
            print(f"{label}: peak RSS at {mine[-1]['cage_revolutions']:g} over "
                  f"{mine[0]['cage_revolutions']:g} revolutions: {hi / lo:.3f}")
    write_json(a.json, {"benchmark": name, "case": a.case, "overrides": over, "rows": rows,
                        "trees": {k: str(v) for k, v in trees.items()}})
