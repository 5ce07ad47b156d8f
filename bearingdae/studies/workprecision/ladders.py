"""The ladders of the work-precision study: which solver runs at which tolerances or steps."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

QUANTITIES = ("cage_speed", "orbit_speed", "spin_speed", "skew_angle", "contact_force")
#: atol / rtol along the ladders: the ratio of the scene defaults (1e-8 / 1e-6)
ATOL_PER_RTOL = 1e-2
ATOL_MAX = 1e-4  # the scene's upper bound on atol
IDA_RTOLS = tuple(10.0 ** -e for e in range(3, 11))  # 1e-3 ... 1e-10
PEER_RTOLS = IDA_RTOLS  # tighter rungs are skipped once a peer exceeds the time limit
QUICK_IDA_RTOLS = (1e-4, 1e-6, 1e-8)
QUICK_PEER_RTOLS = (1e-4,)
#: Newmark-β fixed steps [s] (average acceleration); the finest also confirms the reference
NEWMARK_STEPS_S = (4e-6, 2e-6, 1e-6, 5e-7)
QUICK_NEWMARK_STEPS_S = (2e-6,)
PEERS = ("scipy-BDF", "scipy-Radau", "scipy-LSODA")
#: IDA rung whose wall time sets the peers' time limit, and whose error is compared (Must show)
IDA_TARGET_RTOL = 1e-6
TIME_LIMIT_FACTOR = 20.0
#: tiny window for the JIT warm-up of each solver
WARMUP_OVERRIDES = {"numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 0.01}


def tolerance_overrides(rtol: float) -> dict:
    """Scene overrides of one rtol rung (atol scaled alongside)."""
    return {"numerics.rtol": rtol, "numerics.atol": min(ATOL_PER_RTOL * rtol, ATOL_MAX)}


@dataclass(frozen=True)
class Ladder:
    """One solver's ladder: ``configure(value) -> (scene overrides, solver_options)``."""

    solver: str
    parameter: str  #: "rtol" or "step_s"
    values: tuple
    configure: Callable[[float], tuple[dict, dict]]
    timed_limit: bool = False  #: stop runs after the time limit (the scipy peers)
    confirms_reference: bool = False  #: its finest run is compared with the reference
    label: str = ""  #: name in the table (default: ``solver``)

    @property
    def name(self) -> str:
        return self.label or self.solver


def ladders(quick: bool = False, solvers: tuple[str, ...] | None = None) -> list[Ladder]:
    """The ladders of the study (IDA first: it provides the reference and the time limit)."""
    ida_r, peer_r, nm_h = ((QUICK_IDA_RTOLS, QUICK_PEER_RTOLS, QUICK_NEWMARK_STEPS_S) if quick
                           else (IDA_RTOLS, PEER_RTOLS, NEWMARK_STEPS_S))
    out = [Ladder("ida", "rtol", ida_r, lambda r: (tolerance_overrides(r), {}))]
    out.append(Ladder("newmark", "step_s", nm_h,
                      lambda h: ({"numerics.newmark_step_s": h}, {}), confirms_reference=True))
    out += [Ladder(p, "rtol", peer_r, lambda r: (tolerance_overrides(r), {}), timed_limit=True)
            for p in PEERS]
    if solvers is not None:
        unknown = set(solvers) - {ld.solver for ld in out}
        if unknown:
            raise ValueError(f"solvers {sorted(unknown)}: allowed are "
                             f"{', '.join(ld.solver for ld in out)}")
        out = [ld for ld in out if ld.solver in solvers or ld.solver == "ida"]
    return out


def naive_ladders(rtols=(IDA_TARGET_RTOL,)) -> list[Ladder]:
    """The straightforward nested implementation, for scale: the static solver's numpy Newton
    per right-hand side and scipy's own finite-difference Jacobian (BDF and LSODA). Named
    ``naive-*`` so they are not counted among the peers of the verdict."""
    return [Ladder(f"scipy-{m}", "rtol", tuple(rtols),
                   lambda r: (tolerance_overrides(r), {"inner": "static", "jac": "fd"}),
                   timed_limit=True, label=f"naive-{m}") for m in ("BDF", "LSODA")]


