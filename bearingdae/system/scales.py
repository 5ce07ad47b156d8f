"""Reference scales of the unknowns and equations (theory.md §5, §11), shared by the DAE model
(system/model.py) and the static Newton (solvers/static.py).

Stage: physics -> **system** -> solvers. Forces are measured in units of a reference roller
load Q_ref, lengths in units of the Palmgren approach δ_ref of one roller under Q_ref.
"""

from __future__ import annotations

import numpy as np

from ..physics.contact import palmgren_approach
from ..physics.geometry import Geometry

#: smallest reference load [N]: an unloaded scene still gets a finite scale
MIN_FORCE_SCALE_N = 1e-3


def reference_scales(geometry: Geometry, loads, centrifugal_N,
                     axial_N: float = 0.0) -> tuple[float, float]:
    """(Q_ref [N], δ_ref [m]): Stribeck's 5 F/Z for the forces, the moment over the half length,
    the axial load ``axial_N`` of a bearing with flanges (its share pinches every roller between
    the raceways by the flange couple, theory.md §16: with no radial load it alone sets the slice
    loads, and a scale from the radial load alone, or the floor, left the flange Newton without
    a usable step), the largest centrifugal force, floored at :data:`MIN_FORCE_SCALE_N`; δ_ref
    the Palmgren approach of one roller under Q_ref."""
    loads = np.asarray(loads, dtype=float)
    half = 0.5 * geometry.roller_length_m
    Z = geometry.rollers
    q_ref = max(
        5.0 * np.hypot(loads[0], loads[1]) / Z,
        5.0 * np.hypot(loads[2], loads[3]) / (half * Z),
        5.0 * abs(float(axial_N)) / Z,
        float(np.max(centrifugal_N, initial=0.0)),
        MIN_FORCE_SCALE_N,
    )
    return q_ref, palmgren_approach(q_ref, geometry.roller_length_m, geometry.compliance_m2_N)
