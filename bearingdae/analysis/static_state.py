"""The scene's quasi-static state: one builder for every static solve of a scene.

Pipeline: analysis (between the solvers and the Datasets). :func:`scene_static` turns a scene
into the static problem of docs/theory.md §5 — the applied loads at t = 0 with the unbalance
(physics/loads.py), the epicyclic orbit speed, a dynamic ring's support stiffness — solves it,
and adds the flange contacts when the bearing has flanges (§16). ``solve_static`` and the
rating life's extra solves (analysis/rating_life.py: other positions of the roller set, finer
laminae) all call it, so that they see the same loads.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np


def scene_problem(scene, geometry, azimuth_rad=None):
    """The static problem of a scene at t = 0 (solvers/static.py), rollers at ``azimuth_rad``
    (default: the initial azimuths, roller 1 on the load line)."""
    from ..physics.loads import applied_loads
    from ..solvers import static
    from ..solvers.algebraic import support_stiffness
    from ..system.defects import separation_arrays
    from ..system.model import _speed_ramp, load_table

    o = scene.operating
    ramp_t, ramp_w = _speed_ramp(scene)
    return static.make_problem(
        geometry,
        applied_loads(0.0, load_table(o), ramp_t, ramp_w, o.unbalance_N,
                      o.unbalance_phase_rad)[:4],  # the slice contacts' loads (F_a: flanges)
        o.speed_rad_s_at(0.0),
        scene.numerics.contact_smoothing_m,
        azimuth_rad=azimuth_rad,
        support_N_m=support_stiffness(scene),
        separation_m=separation_arrays(scene, geometry, 0.0, geometry.azimuth0_rad
                                       if azimuth_rad is None else azimuth_rad, ramp_t, ramp_w),
    )


def scene_static(scene, geometry, azimuth_rad=None, z0=None, newton_count: bool = True):
    """(static solution, flange variables or None) of the scene at t = 0, rollers at
    ``azimuth_rad`` (default: initial azimuths); ``z0``: a start of the Newton iteration.
    With flanges the flange state solves the slice contacts again (solvers/algebraic.py's
    initial state): ``newton_count=False`` skips the first solve, whose only use then is the
    Newton iteration count of the Dataset (the solution's ``iterations`` are 0)."""
    from ..solvers import static

    prob = scene_problem(scene, geometry, azimuth_rad)
    if scene.bearing.flanges is not None and not newton_count:
        size = 2 * geometry.rollers + 4
        sol = static.StaticSolution(np.zeros(size), np.zeros(size), 0.0, 0, None, prob)
    else:
        sol = static.solve(prob, z0, tol=scene.numerics.static_tolerance,
                           max_iter=scene.numerics.static_max_iterations)
    if scene.bearing.flanges is None:
        return sol, None
    from .flange import static_with_flanges  # the flange contacts and axial unknowns (§16)

    return static_with_flanges(scene, sol, azimuth_rad)


def with_slices(scene, slices: int):
    """The scene with ``numerics.slices`` replaced (everything else as it is)."""
    return replace(scene, numerics=replace(scene.numerics, slices=int(slices)))


def turned_azimuths(geometry, fraction: float) -> np.ndarray:
    """Initial azimuths with the roller set turned by ``fraction`` of a roller pitch."""
    return geometry.azimuth0_rad + 2.0 * np.pi * fraction / geometry.rollers
