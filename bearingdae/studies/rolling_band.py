"""The band of the published rolling laws: each law's rolling moment at one operating point.

Pipeline place: a scene -> its quasi-static load distribution (:func:`bearingdae.solve_static`,
centrifugal force included) -> the rollers at pure rolling (the epicyclic cage speed, the spin
that rolls on both races) -> per law of physics/rolling_resistance.py (:data:`LAWS`), fully
flooded and at given inlet films, the rolling resistance's power Σ H Σ over every slice of
every roller (physics/power.rolling_resistance_power, the dynamic runs' own function) -> the
rolling moment referred to the inner ring, M_rr = P / ω_i (docs/theory.md §19).

Why quasi-static: the three laws differ by up to 5x (Biboulet & Houpert 2010), more than the
load distribution and the slip of a dynamic run move them, and a dynamic run per law and film
costs minutes; this costs one static solve per point. What it leaves out: the slip (a roller
that skids has a smaller rolling sum on one race and a larger one on the other) and the
dynamic loads, so at a point where the cage slips by more than a few per cent the dynamic
run's rolling moment differs from these (docs/user-guide.md, "Friction against the
catalogue, term by term").
"""

from __future__ import annotations

import warnings

import numpy as np

from ..system.rolling_resistance import INLET_FILM_KEY as FILM_KEY

#: the published laws the band spans (physics/rolling_resistance.LAW_CODES)
LAWS = ("biboulet_houpert", "goksem_hargreaves", "zhou_hoeprich")
LAW_KEY = "physics.rolling_resistance"


def rolling_moments_N_m(case: str, overrides: dict | None = None,
                        inlet_films_um=(None,)) -> dict[tuple[str, float | None], float]:
    """{(law, film µm or None for flooded): M_rr [N m]} at the operating point of ``case``
    with ``overrides`` (module docstring); every law of :data:`LAWS` at every film."""
    from ..api import solve_static
    from ..scene import load_scene
    from ..physics.geometry import make_geometry
    from ..physics.power import rolling_resistance_power
    from ..system.rolling_resistance import (RR_LAW_ARGS, RR_PARAM_NAMES,
                                             rolling_resistance_parameters)

    base = dict(overrides or {})
    scene = load_scene(case, {**base, LAW_KEY: LAWS[0]})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        static = solve_static(scene)
    q = static.contact_force.transpose("roller", "slice", "race").values
    g = make_geometry(scene)
    w = scene.operating.speed_rpm * np.pi / 30.0
    orbit = g.epicyclic_orbit_speed(w)
    spin = g.pure_rolling_spin(w)
    Z = q.shape[0]
    out = {}
    for name in LAWS:
        for film in inlet_films_um:
            over = {**base, LAW_KEY: name}
            if film is not None:
                over[FILM_KEY] = float(film)
            sc = load_scene(case, over)
            values = rolling_resistance_parameters(sc, g)
            PR = [values[n] for n in RR_PARAM_NAMES]
            P, _, _ = rolling_resistance_power(
                q, w, np.full(Z, orbit), np.full(Z, spin), np.zeros(Z), g.x_m,
                (g.inner_race_radius_m, g.outer_race_radius_m, g.roller_radius_m),
                sc.physics.slip == "paper", g.slice_width_m,
                (g.reduced_radius_inner_m, g.reduced_radius_outer_m),
                tuple(PR[i] for i in RR_LAW_ARGS))
            out[(name, film)] = float(P) / w
    return out
