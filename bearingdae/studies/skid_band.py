"""Where the cage stops skidding, per rolling law: the torque balance's cage speed over load.

Pipeline place: a scene at each radial load -> its DAE model -> the quasi-static torque
balance of solvers/torque_balance.py (every roller at one orbit speed, spins balanced, the
cage speed at which the torque on cage plus rollers vanishes; the residual's own terms,
rolling resistance included when the scene has it) -> the cage speed over the epicyclic one
-> the skid boundary: the least load of the list at which it reaches :data:`SLIP_LIMIT`.

Why the balance and not the dynamic sweep (Fig 11, cases/paper/harris36_cage_speed.toml): one
balance per load and law costs a second, a dynamic point until steady minutes. What it leaves
out (solvers/torque_balance.py): the spin inertia that carries a roller's speed from the
loaded into the unloaded zone, the pocket friction and skew; the user guide ("Where the cage
stops skidding") sets it beside the dynamic sweep where both exist.
"""

from __future__ import annotations

import warnings

#: a cage slower than this fraction of the epicyclic speed skids (1 % cage slip)
SLIP_LIMIT = 0.99


def cage_speed_fractions(case: str, loads_N, overrides: dict | None = None) -> list[float]:
    """The torque balance's cage speed / epicyclic speed at each radial load of ``loads_N``
    (module docstring), the scene ``case`` with ``overrides``."""
    from ..scene import load_scene
    from ..solvers.algebraic import initial_state
    from ..solvers.torque_balance import torque_balance_state
    from ..system.model import build_model

    out = []
    for F in loads_N:
        scene = load_scene(case, {**(overrides or {}), "operating.radial_load_N": float(F)})
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            model = build_model(scene)
            y0, _ = initial_state(model)
            info = torque_balance_state(model, y0)[2]
        out.append(float(info["initial_cage_speed_fraction_of_epicyclic"]))
    return out


def skid_boundary_N(loads_N, fractions) -> float:
    """The least load of ``loads_N`` (ascending) from which on every fraction is at least
    :data:`SLIP_LIMIT`; nan if none."""
    boundary = float("nan")
    for F, x in zip(reversed(list(loads_N)), reversed(list(fractions))):
        if x < SLIP_LIMIT:
            break
        boundary = float(F)
    return boundary
