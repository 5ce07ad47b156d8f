"""Item 2 of issue 14: revolutions to a steady state from the pure-rolling (epicyclic) start
and from the torque-balance skid start, and whether both reach the same steady state.

    python benchmarks/steady_starts.py [--loads 2000 1500 1000 500] [--cap 200] [--out DIR]

Each load of the Fig 11 scene (harris36, 5000 r/min, the settings of
cases/paper/harris36_cage_speed.toml) is run with ``until_steady`` from both starts. Results
go to OUT/steady_starts.json as each run finishes (re-running skips finished runs): steady or
not, warm-up revolutions used, last block mean (fraction of epicyclic), wall and CPU time.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def run(load: float, start: str, cap: float, out: Path) -> dict:
    import warnings

    from bearingdae import load_scene, simulate
    from bearingdae.run.checkpoint import Checkpoint

    sc = load_scene("paper/harris36_5000rpm", {
        "operating.radial_load_N": load, "numerics.until_steady": True,
        "numerics.initial_speeds": start, "numerics.warmup_cage_revolutions": 0.0,
        "numerics.steady_block_cage_revolutions": 1.0,
        "numerics.max_warmup_cage_revolutions": cap, "numerics.cage_revolutions": 0.1,
        "numerics.samples_per_cage_revolution": 100,
        "output.variables": ["cage_speed"]})
    t0, c0 = time.perf_counter(), time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        # the warm-up file OUT/<load>_<start>.nc.warmup.npz holds the block means so far and
        # lets an interrupted run continue (python benchmarks/steady_starts.py again)
        ds = simulate(sc, checkpoint=Checkpoint(out / f"{load:g}_{start}.nc.checkpoint.npz",
                                                resume=True))
    means = json.loads(ds.attrs["steady_block_means"])
    return {"load_N": load, "start": start, "steady": int(ds.attrs["steady_state_reached"]),
            "revolutions": ds.attrs["warmup_cage_revolutions_used"],
            "last_block_mean": means[-1], "first_block_mean": means[0],
            "remaining_estimate": ds.attrs["steady_remaining_estimate"],
            "last_change": ds.attrs["steady_last_change"],
            "initial_fraction": ds.attrs.get("initial_cage_speed_fraction_of_epicyclic", 1.0),
            "wall_s": time.perf_counter() - t0, "cpu_s": time.process_time() - c0,
            "block_means": means}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--loads", type=float, nargs="+", default=[2000.0, 1500.0, 1000.0, 500.0])
    ap.add_argument("--starts", nargs="+", default=["torque_balance", "epicyclic"])
    ap.add_argument("--cap", type=float, default=200.0)
    ap.add_argument("--out", type=Path, default=Path("."))
    args = ap.parse_args()
    path = args.out / "steady_starts.json"
    done = json.loads(path.read_text()) if path.exists() else []
    for load in args.loads:
        for start in args.starts:
            if any(d["load_N"] == load and d["start"] == start for d in done):
                continue
            r = run(load, start, args.cap, args.out)
            print(f"{load:g} N {start:15s} steady {r['steady']} after {r['revolutions']:.0f} rev,"
                  f" cage/epicyclic {r['last_block_mean']:.5f} ({r['wall_s']:.0f} s wall)",
                  flush=True)
            done.append(r)
            tmp = path.with_suffix(".part")
            tmp.write_text(json.dumps(done, indent=1))
            os.replace(tmp, path)
    for load in args.loads:
        pair = {d["start"]: d for d in done if d["load_N"] == load}
        if len(pair) == 2:
            e, t = pair["epicyclic"], pair["torque_balance"]
            print(f"{load:g} N: revolutions epicyclic {e['revolutions']:.0f} vs torque balance "
                  f"{t['revolutions']:.0f}; steady states differ by "
                  f"{t['last_block_mean'] - e['last_block_mean']:+.2e} of epicyclic")


if __name__ == "__main__":
    main()
