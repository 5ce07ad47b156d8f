"""``bearingdae calibrate``: the inlet film at which a scene's mean friction torque (drag
excluded) equals a measured or catalogue value, and the calibrated scene as a complete TOML.

Pipeline: the cli layer over studies/calibrate.py.
"""

from __future__ import annotations

import sys
from pathlib import Path

from .common import _overrides, _set_origin


def _calibrate(args) -> int:
    from .. import load_scene
    from ..scene import resolve_case
    from ..studies.calibrate import FILM_KEY, calibrate_inlet_film
    from ..util.atomic import atomic_write, check_writable, refuse_aliases

    source = resolve_case(args.case)
    out = check_writable(args.output or Path(f"{source.stem}_calibrated.toml"))
    refuse_aliases([("output", out)], [("scene file", source)])
    overrides = _overrides(args.set)
    if FILM_KEY in overrides:
        raise ValueError(f"--set {FILM_KEY}=...: calibrate finds that key; drop it")

    def scene_at(film_um):
        more = {} if film_um is None else {FILM_KEY: film_um}
        return load_scene(args.case, {**overrides, **more},
                          override_origin=_set_origin(args.set))

    say = (lambda text: print("  " + text, file=sys.stderr, flush=True))
    fit = calibrate_inlet_film(scene_at, args.friction_torque_Nmm, progress=say)
    text = scene_at(fit.film_um).to_toml(complete=True)
    with atomic_write(out) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        fh.write(text)
    print(f"inlet film {fit.film_um:.4g} µm ({FILM_KEY}): mean friction torque "
          f"{fit.torque_N_mm:.5g} N mm, drag excluded (target {fit.target_N_mm:g}, "
          f"{100 * (fit.torque_N_mm / fit.target_N_mm - 1):+.2f} %), {fit.runs} runs")
    print(f"wrote {out}")
    return 0
