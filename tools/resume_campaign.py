"""Kill/resume campaign: `bearingdae run` interrupted by Ctrl-C (SIGINT) at a random sample,
then `bearingdae run --resume`, against the same run uninterrupted, over switch combinations.

Each trial checks what a user relies on (docs/user-guide.md, "Resuming"):

* the interrupted run ends with status 130 and its summary does not say it was resumed;
* the resumed run ends with status 0, its samples up to the resume point are the uninterrupted
  run's bit for bit (the mean series: cage speed, contact forces, pocket forces, peak traces);
* every per-pass peak statistic and every mean statistic agrees with the uninterrupted one
  within 3 combined standard errors (or, without error bars, 1e-3 relative);
* no extreme says its values before the resume point come from the samples only.

Run from the repository root (PYTHONPATH set to it)::

    python tools/resume_campaign.py --trials 24 --out /tmp/campaign

It prints one line per trial and a count of trials passed; status 1 if any failed.
tests/robustness/test_resume_campaign.py runs two trials (slow).
"""

from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

COMBINATIONS = {
    "default": [],
    "mixed": ["physics.lubrication=mixed"],
    "rolling resistance": ["physics.rolling_resistance=true"],
    "dynamic ring": ["physics.ring=dynamic"],
    "cage whirl": ["physics.cage_whirl=true", 'cage.guidance="outer-land"',
                   "cage.land_clearance_mm=0.09"],
    "thermal": ["physics.thermal=steady"],
}
WINDOW = ["numerics.cage_revolutions=0.5", "numerics.warmup_cage_revolutions=0.05",
          "numerics.samples_per_cage_revolution=200"]
SERIES = ("cage_speed", "contact_force", "cage_force", "cage_force_peak",
          "contact_pressure_peak", "slip_velocity_peak")


def _args(target: Path, sets: list[str], *extra: str) -> list[str]:
    out = [sys.executable, "-m", "bearingdae.cli", "run", "yang20_baseline", "-o", str(target),
           "--no-plot", "--no-progress", *extra]
    for s in sets + WINDOW:
        out += ["--set", s]
    return out


def _samples_held(checkpoint: Path) -> int:
    try:
        with np.load(checkpoint) as z:
            return int(z["t"].size)
    except Exception:  # noqa: BLE001 -- absent or being replaced: not yet
        return 0


def interrupted(target: Path, sets: list[str], after: int, timeout_s: float = 1800):
    """Run, SIGINT once the checkpoint holds ``after`` samples; (status, stdout + stderr)."""
    checkpoint = target.with_name(target.name + ".checkpoint.npz")
    # an until-steady run (the thermal coupling) keeps its warm-up in blocks instead: it is
    # interrupted once the first block is saved, and resumes from its blocks
    warmup = target.with_name(target.name + ".warmup.npz")
    # SIGINT back to its default in the child: a campaign started in the background (where
    # the shell ignores SIGINT, and a child inherits that) still interrupts its runs
    p = subprocess.Popen(_args(target, sets, "--checkpoint-every=5"), stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True,
                         preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    end = time.monotonic() + timeout_s
    while p.poll() is None and time.monotonic() < end and _samples_held(checkpoint) < after \
            and not warmup.exists():
        time.sleep(0.05)
    if p.poll() is None:
        p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=timeout_s)
    return p.returncode, out + err


def compare(resumed, ref, t_resume: float) -> list[str]:
    """What differs between a resumed and an uninterrupted result ([] if nothing)."""
    from bearingdae.analysis.result_variables import RESULT_VARIABLES

    bad = []
    if not np.array_equal(resumed.time.values, ref.time.values):
        return ["the sample times differ"]
    before = resumed.time.values <= t_resume
    for name in SERIES:
        if name in ref and not np.array_equal(resumed[name].values[before],
                                              ref[name].values[before], equal_nan=True):
            bad.append(f"{name} differs before the resume point")
    for name, q in RESULT_VARIABLES.items():
        if not q.error or name not in ref or name not in resumed:
            continue
        a, b = float(resumed[name]), float(ref[name])
        se = np.hypot(float(resumed[q.error]), float(ref[q.error])) if q.error in ref else np.nan
        allowed = 3 * se if np.isfinite(se) and se > 0 else 1e-3 * abs(b)
        if not (abs(a - b) <= allowed or (np.isnan(a) and np.isnan(b))):
            bad.append(f"{name} {a:.6g} vs {b:.6g} (allowed {allowed:.3g})")
    for name in resumed.data_vars:
        if "resumed there" in str(resumed[name].attrs.get("comment", "")):
            bad.append(f"{name} says its values before the resume come from samples")
    return bad


def main(argv=None) -> int:
    import xarray as xr

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--trials", type=int, default=24)
    ap.add_argument("--out", type=Path, default=Path("resume_campaign"))
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--start", type=int, default=0, help="skip the first trials (their kill "
                    "points are drawn all the same: a campaign continues where it stopped)")
    a = ap.parse_args(argv)
    a.out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(a.seed)
    names = list(COMBINATIONS)
    refs, passed = {}, 0
    for trial in range(a.trials):
        name = names[trial % len(names)]
        sets = COMBINATIONS[name]
        slug = name.replace(" ", "_")
        if name not in refs:
            target = a.out / f"{slug}_ref.nc"
            if not target.exists():
                done = subprocess.run(_args(target, sets), capture_output=True, text=True)
                if done.returncode != 0:
                    print(f"{name}: the uninterrupted run failed: {done.stderr[-300:]}")
                    return 1
            with xr.open_dataset(target) as ds:
                refs[name] = ds.load()
        ref = refs[name]
        after = int(rng.integers(5, ref.sizes["time"] - 5))
        if trial < a.start:
            continue
        target = a.out / f"{slug}_{trial}.nc"
        for p in a.out.glob(f"{target.name}*"):
            p.unlink()
        status, text = interrupted(target, sets, after)
        problems = [] if status == 130 else [f"the interrupted run ended with {status}"]
        if "resumed there" in text or "was resumed" in text:
            problems.append("the interrupted run's summary speaks of a resume")
        done = subprocess.run(_args(target, sets, "--resume"), capture_output=True, text=True)
        if done.returncode != 0:
            problems.append(f"the resumed run ended with {done.returncode}: "
                            f"{done.stderr[-300:]}")
        else:
            import json

            with xr.open_dataset(target) as ds:
                resumed = ds.load()
            stats = json.loads(resumed.attrs["solver_statistics"])
            t_resume = stats.get("resumed_from_s")
            if t_resume is None and "thermal" in name:  # resumed from its warm-up blocks:
                t_resume = np.inf  # the record is the uninterrupted one's, bit for bit
            if t_resume is None:
                problems.append("the run was not resumed (it had ended before the SIGINT?)")
            else:
                problems += compare(resumed, ref, t_resume)
        passed += not problems
        print(f"trial {trial + 1:2d} {name:20s} SIGINT after {after:3d} samples: "
              + ("ok" if not problems else "; ".join(problems)), flush=True)
    ran = a.trials - a.start
    print(f"{passed}/{ran} trials: the resumed run equals the uninterrupted one")
    return 0 if passed == ran else 1


if __name__ == "__main__":
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    sys.exit(main())
