"""Long runs of the Harris bearing at light load: how long the cage takes to settle.

    python benchmarks/harris_spin_down.py [--revolutions 12] [--loads 250 500] [--out DIR]

The paper set records Fig 11 after 2 warm-up cage revolutions; at light load the cage is
then still slowing down from its epicyclic start. This script runs the base scene of
cases/paper/harris36_cage_speed from t = 0 for many revolutions (cage and roller speeds only),
fits the per-revolution mean cage speed with c_k = c_inf + A r^k (exponential approach) and
draws docs/figures/harris_light_load_spin_down.png. c_inf is an extrapolation, labelled so.
Runs are kept in OUT/longh_<load>.nc and reused.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402


def per_revolution(ds: xr.Dataset, samples: int) -> np.ndarray:
    c = ds.cage_speed.values / ds.attrs["epicyclic_cage_speed_rad_s"]
    n = len(c) // samples
    return c[: n * samples].reshape(n, samples).mean(1)


def fit(c: np.ndarray) -> tuple[float, float]:
    """(c_inf, r) of c_k = c_inf + A r^k from the decrements d_k = c_{k+1} - c_k = d_0 r^k."""
    d = np.diff(c)
    k = np.arange(d.size)
    slope, _ = np.polyfit(k[2:], np.log(-d[2:]), 1)  # skip the start-up transient
    r = float(np.exp(slope))
    return float(c[-1] + d[-1] * r / (1.0 - r)), r


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--revolutions", type=float, default=12.0)
    ap.add_argument("--loads", type=float, nargs="+", default=[250.0, 500.0])
    ap.add_argument("--out", type=Path, default=Path("."))
    ap.add_argument("--figure", type=Path,
                    default=Path(__file__).resolve().parents[1] / "docs" / "figures"
                    / "harris_light_load_spin_down.png")
    args = ap.parse_args()
    from bearingdae import load_scene, save, simulate
    from bearingdae.results.plotting import _plt

    samples = 20
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.5, 4.2), constrained_layout=True)
    for load in args.loads:
        path = args.out / f"longh_{int(load)}.nc"
        if not path.exists():
            sc = load_scene("paper/harris36_5000rpm", {
                "operating.radial_load_N": load, "numerics.warmup_cage_revolutions": 0.0,
                "numerics.cage_revolutions": args.revolutions,
                "numerics.samples_per_cage_revolution": samples,
                "output.variables": ["cage_speed", "orbit_speed", "spin_speed", "skew_angle"]})
            save(simulate(sc), path)
        ds = xr.open_dataset(path).load()
        c = per_revolution(ds, samples)
        c_inf, r = fit(c)
        rev = np.arange(1, c.size + 1)
        print(f"{load:g} N: per-revolution mean cage/epicyclic {np.round(c, 4)}; "
              f"fit c_inf = {c_inf:.3f}, r = {r:.3f}/rev (time constant {-1 / np.log(r):.1f} rev)")
        line, = ax.plot(rev, c, "o-", ms=3, label=f"{load:g} N")
        ax.axhline(c_inf, color=line.get_color(), ls=":", lw=1,
                   label=f"{load:g} N: extrapolated {c_inf:.2f}")
    ax.axvspan(2, 3, color="0.9", label="window of the paper set (Fig 11)")
    ax.set(xlabel="cage revolution since start", ylabel="mean cage speed / epicyclic",
           title="harris36, 5000 r/min: light-load spin-down from the epicyclic start")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    args.figure.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.figure, dpi=100)
    print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
