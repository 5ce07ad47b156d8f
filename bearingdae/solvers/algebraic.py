"""The algebraic unknowns of a dynamic state, solved by the static Newton (MODEL §5, §11).

Stage: system (DAE model) -> **solvers** -> results. The algebraic rows of the DAE are exactly
the quasi-static equations of MODEL §5 at the rollers' current azimuths and orbit speeds, so
the static Newton of solvers/static.py solves them: for the initial state of a run
(:func:`initial_state`) and, after a run, to project every output sample onto them
(:func:`project_algebraic`, results.from_solution). Speeds are SI (rad/s) throughout.
"""

from __future__ import annotations

import numpy as np

from ..system.layout import GLOBAL, LOCAL
from ..system.model import Model
from . import static


def _solve(model: Model, t: float, azimuth_rad, orbit_speed_rad_s, z0=None):
    sc, g = model.scene, model.geometry
    prob = static.make_problem(g, sc.operating.loads, model.ring_speed(t),
                               sc.numerics.contact_smoothing_m,
                               azimuth_rad=azimuth_rad, orbit_speed_rad_s=orbit_speed_rad_s)
    return static.solve(prob, z0, tol=sc.numerics.static_tolerance,
                        max_iter=sc.numerics.static_max_iterations)


def initial_state(model: Model) -> tuple[np.ndarray, np.ndarray]:
    """Scaled (y0, yp0): quasi-static equilibrium at pure-rolling (epicyclic) speeds, zero skew,
    rollers centred in their pockets, cage at the epicyclic speed (MODEL §11); y'0 of the
    differential unknowns from the equations of motion, of the algebraic ones zero (IDA's
    consistent initialisation then corrects both)."""
    g, lay = model.geometry, model.layout
    w0 = model.ring_speed(0.0)
    Om = g.epicyclic_orbit_speed(w0)
    sol = _solve(model, 0.0, g.azimuth0_rad, np.full(g.rollers, Om))
    u, beta, ring = static.split(sol.z, g.rollers)

    full_l = np.zeros((g.rollers, len(LOCAL)))
    full_g = np.zeros(len(GLOBAL))
    full_l[:, LOCAL.index("azimuth")] = g.azimuth0_rad
    full_l[:, LOCAL.index("orbit_speed")] = Om
    full_l[:, LOCAL.index("spin_speed")] = g.pure_rolling_spin(w0)
    full_l[:, LOCAL.index("radial_position")] = u
    full_l[:, LOCAL.index("tilt")] = beta
    full_g[GLOBAL.index("cage_speed")] = Om
    full_g[2:] = ring
    y0 = lay.pack(full_l, full_g) / model.scale
    # y' from F(y, 0) = -f(y): y'_i = f_i / mass_i for the differential rows.
    res0 = model.residual(0.0, y0, np.zeros_like(y0))
    yp0 = np.zeros_like(y0)
    diff = model.mass > 0
    yp0[diff] = -res0[diff] / model.mass[diff]
    return y0, yp0


def project_algebraic(model: Model, t: float, y: np.ndarray) -> tuple[np.ndarray, int]:
    """Solve the algebraic equations (MODEL §5) for the algebraic unknowns of the scaled state
    ``y``, its differential unknowns held fixed; returns (y, Newton iterations).

    The static Newton (solvers/static.py) warm-started from the integrator's value: outputs
    then satisfy the algebraic equations to round-off, independently of its tolerance.
    """
    lay, g = model.layout, model.geometry
    full_l, full_g = lay.unpack(y * model.scale)
    z0 = np.concatenate([full_l[:, LOCAL.index("radial_position")],
                         full_l[:, LOCAL.index("tilt")], full_g[2:]])
    sol = _solve(model, t, full_l[:, LOCAL.index("azimuth")],
                 full_l[:, LOCAL.index("orbit_speed")], z0)
    u, beta, ring = static.split(sol.z, g.rollers)
    full_l[:, LOCAL.index("radial_position")] = u
    full_l[:, LOCAL.index("tilt")] = beta
    full_g[2:] = ring
    return lay.pack(full_l, full_g) / model.scale, sol.iterations
