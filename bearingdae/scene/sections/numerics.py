"""``[numerics]``: solver, tolerances, slices, sampling and the run's length, as written."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from ..histories import _Section


class NumericsInput(_Section):
    """Slices, tolerances, the recorded window and the settings of the solvers."""

    slices: int = Field(default=10, ge=1, le=1000, description="slices k along the roller length")
    rtol: float = Field(default=1e-6, ge=1e-12, le=1e-1, description="IDA relative tolerance")
    # Upper bound measured: atol = 1e-3 (with rtol 1e-3) failed within 8 ms on the baseline,
    # 1e-4 ran; atol = 1e-6 already costs 15x the cage-speed error of 1e-8.
    atol: float = Field(default=1e-8, ge=1e-14, le=1e-4, description="IDA absolute tolerance "
                        "in units of each unknown's scale (see output metadata)")
    warmup_cage_revolutions: float = Field(default=1.0, ge=0.0, le=1e4, description="simulated "
                                           "cage revolutions before recording")
    cage_revolutions: float = Field(default=3.0, gt=0.0, le=1e5, description="recorded cage "
                                    "revolutions")
    samples_per_cage_revolution: int = Field(default=200, ge=2, le=100_000, description=
                                             "output samples per cage revolution")
    max_steps: int = Field(default=500_000, ge=100, le=100_000_000, description="step limit (IDA; "
                           "Newmark refuses a run needing more fixed steps)")
    # Lower bound 1e-4 nm (0.1 pm): smaller lengths vanish against a µm approach in double
    # precision; it also catches 1 nm written in metres (1e-9).
    contact_smoothing_nm: float = Field(
        default=1.0, ge=1e-4, le=1.0,
        description="contact-onset regularisation length ε (theory.md §5: at most 1 nm)")
    # Lower bound: the relative residual of a force balance summed over Z x k slices stalls at
    # 1e-16 .. 4e-15 (measured on yang20, harris36, 30 000 r/min, zero load); 1e-14 is reachable.
    static_tolerance: float = Field(default=1e-12, ge=1e-14, le=1e-3,
                                    description="relative force residual of the static Newton")
    static_max_iterations: int = Field(default=100, ge=1, le=10_000,
                                       description="Newton iteration limit per stage")
    # Newmark-β (solver="newmark", theory.md §12). Default step, measured on the baseline
    # (docs/theory.md "Newmark-β"): ~20 steps per period of the ~24 kHz skew-pocket mode, and
    # the stiffest traction mode (λ ≈ -7e5 1/s, h λ ≈ -1.4) still decays ~6x per step.
    newmark_step_s: float = Field(default=2e-6, ge=1e-10, le=1e-2, description="Newmark-β "
                                  "fixed step h (the largest step; output times are hit exactly)")
    newmark_beta: float | None = Field(default=None, gt=0.0, le=0.5, description="Newmark β "
                                       "(default (1 - hht_alpha)²/4: 1/4 = average acceleration)")
    newmark_gamma: float | None = Field(default=None, ge=0.5, le=1.0, description="Newmark γ "
                                        "(default 1/2 - hht_alpha: 1/2 = no numerical damping)")
    hht_alpha: float = Field(default=0.0, ge=-1.0 / 3.0, le=0.0, description="HHT-α numerical "
                             "damping (0 = plain Newmark; -1/3 = most damping)")
    newmark_error_estimate: bool = Field(default=False, description="Newmark: run a second "
                                         "solution at h/2 beside the first and report the "
                                         "Richardson estimate of the global error (3x cost)")
    # Steady state on demand (bearingdae/run/steady.py). The tolerance is a fraction of
    # the epicyclic cage speed: 1e-3 resolves Fig 11's 0.1 %-level saturation; below 1e-6 the
    # block means of a skidding bearing never settle (pocket impacts make ~1e-5 noise).
    until_steady: bool = Field(default=False, description="run the warm-up in blocks until the "
                               "cage speed is steady (criterion: docs/user-guide.md, "
                               "bearingdae/run/steady.py), then record cage_revolutions")
    steady_tolerance: float = Field(default=1e-3, ge=1e-6, le=0.1, description="until_steady: "
                                    "allowed change of the block-mean cage speed between blocks "
                                    "(and extrapolated remaining drift), as a fraction of the "
                                    "epicyclic cage speed")
    steady_block_cage_revolutions: float = Field(default=1.0, ge=0.05, le=100.0, description=
                                                 "until_steady: length of one block of the "
                                                 "warm-up [cage revolutions]")
    max_warmup_cage_revolutions: float = Field(default=200.0, ge=0.05, le=1e5, description=
                                               "until_steady: cap on the warm-up [cage "
                                               "revolutions]; a run reaching it is marked not "
                                               "steady")
    initial_speeds: Literal["auto", "epicyclic", "torque_balance"] = Field(
        default="auto", description="initial cage and roller speeds: 'epicyclic' (pure "
        "rolling), 'torque_balance' (quasi-static skid estimate, bearingdae/solvers/"
        "torque_balance.py) or 'auto' (torque_balance with until_steady, which then starts "
        "near the steady state it looks for; epicyclic otherwise)")
    # Sharp defect edges (physics/defects.py, system/defect_sides.py): smoothed over the least
    # ramp (the default), or sharp and located by IDA's root finding with a restart at each
    # crossing (measured against each other: docs/user-guide.md, "Sharp edges").
    defect_edges: Literal["smooth", "locate"] = Field(
        default="smooth", description="sharp defect edges (edge_mm below 0.0025 mm): 'smooth' "
        "(a ramp of 0.0025 mm) or 'locate' (sharp, each crossing located by IDA's root "
        "finding and IDA restarted there; solver IDA only)")
