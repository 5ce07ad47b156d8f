"""The flat public entry points: each takes a :class:`~bearingdae.scene.Scene`, returns a Dataset."""

from __future__ import annotations

import xarray as xr

from .physics.geometry import make_geometry
from .results import static_dataset
from .scene import Scene
from .solvers import static


def solve_static(scene: Scene, z0=None) -> xr.Dataset:
    """Quasi-static equilibrium of inner ring and rollers (MODEL §5) as a Dataset.

    Rollers at their initial azimuths (roller 1 on the load line, equally spaced), orbiting at
    the epicyclic speed of ``operating.speed_rpm`` (at t = 0 for a ramp), so the centrifugal
    force is included; ``speed_rpm = 0`` is the plain static case.
    """
    geometry = make_geometry(scene)
    o = scene.operating
    prob = static.make_problem(
        geometry,
        (o.radial_load_N, o.tangential_load_N, o.moment_Nm, o.tangential_moment_Nm),
        o.speed_at(0.0),
        scene.numerics.contact_smoothing_m,
    )
    sol = static.solve(prob, z0, tol=scene.numerics.static_tolerance,
                       max_iter=scene.numerics.static_max_iterations)
    return static_dataset(scene, geometry, sol)
