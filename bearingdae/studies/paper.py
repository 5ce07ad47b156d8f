"""The paper set: every sweep of Yang et al. (2024) and their figures, with one call.

``run_paper(out_dir)`` runs the bundled sweeps of ``cases/paper/`` on one dask cluster (runs
shared between sweeps are computed once, see :mod:`bearingdae.studies.sweep`), writes one NetCDF file
per sweep and the PNGs of Figs 11-24 plus a trends figure per one-axis sweep. It resumes from
``out_dir/runs`` like any sweep.
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import xarray as xr

#: Bundled sweeps of the paper set (cases/paper/), in the order of the paper.
PAPER_SWEEPS = (
    "harris36_cage_speed",        # Fig 11
    "yang20_baseline_figs12_17",  # Figs 12-17
    "yang20_speed_sweep",         # Figs 18-20, conclusion (1)
    "yang20_moment_sweep",        # Figs 21-24, conclusion (3)
    "yang20_radial_load_sweep",   # conclusion (2)
)


def run_paper(out_dir: str | Path = "paper", scheduler: str | None = None,
              workers: int | None = None, progress: bool = True, retry_failed: bool = False,
              figures: bool = True, overrides: dict | None = None,
              scheduler_timeout_s: float | None = None,
              override_origin: str = "--set") -> dict[str, xr.Dataset]:
    """Run the paper set into ``out_dir`` (``<sweep>.nc``, ``runs/``, ``figNN.png``,
    ``trends_<sweep>.png``); returns the sweep Datasets by name. The wall time is stored in
    each Dataset's ``paper_set_wall_time_s`` attribute (whole set, including figures).
    ``overrides`` (dotted scene keys, ``bearingdae paper --set``) apply to every run."""
    from ..plots.plotting import available_figures, figure
    from .sweep import load_sweep, run_sweeps

    t0 = time.perf_counter()
    out = Path(out_dir)
    sweeps = [load_sweep(f"paper/{name}", overrides, override_origin) for name in PAPER_SWEEPS]
    outputs = [out / f"{sw.name}.nc" for sw in sweeps]
    timeout = {} if scheduler_timeout_s is None else {"scheduler_timeout_s": scheduler_timeout_s}
    results = run_sweeps(sweeps, outputs, run_dir=out / "runs", scheduler=scheduler,
                         workers=workers, progress=progress, retry_failed=retry_failed,
                         **timeout)
    by_name = {sw.name: ds for sw, ds in zip(sweeps, results)}
    drawn = []
    if figures:
        for name, ds in by_name.items():
            for number in available_figures(ds):
                target = out / (f"trends_{name}.png" if number == "trends"
                                else f"fig{number:02d}.png")
                try:
                    drawn.append(str(figure(ds, number, target)))
                except ValueError as exc:  # e.g. every run of the sweep failed
                    print(f"bearingdae: figure {number} of {name} not drawn: {exc}")
    wall = time.perf_counter() - t0
    for ds in by_name.values():
        ds.attrs["paper_set_wall_time_s"] = wall
        ds.attrs["paper_set_figures"] = json.dumps(drawn)
    return by_name
