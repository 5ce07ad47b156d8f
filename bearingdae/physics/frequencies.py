"""Characteristic frequencies of a rolling bearing with the outer ring fixed (theory.md §15).

Stage: physics, used by results (Dataset attributes, the spectrum figure). Kinematic
(pure-rolling) frequencies of a roller bearing, contact angle 0, inner ring turning at f_s
(Harris & Kotzalas, *Rolling Bearing Analysis*, 5th ed., Vol. 1, §8; the same as the
epicyclic speeds of physics/geometry.py), γ = D_w / d_m:

- shaft f_s; cage (fundamental train) f_c = f_s (1 − γ) / 2;
- roller pass on the outer race Z f_c, on the inner race Z (f_s − f_c);
- roller spin relative to the cage f_s d_m / (2 D_w) (1 − γ²) (= f_c (R_m + r) / r).

The roller pass on the outer race is the period of the varying-compliance vibration of a ring
carried by Z rollers (Sunnersjö 1978, J. Sound Vib. 58(3), 363-373).
"""

from __future__ import annotations

#: names of the frequencies, in the order of :func:`characteristic_frequencies`
NAMES = ("shaft", "cage", "roller_pass_outer", "roller_pass_inner", "roller_spin")


def characteristic_frequencies(rollers: int, roller_diameter_m: float, pitch_diameter_m: float,
                               shaft_Hz: float) -> dict[str, float]:
    """The frequencies of the module docstring [Hz], by :data:`NAMES`."""
    g = roller_diameter_m / pitch_diameter_m
    cage = 0.5 * shaft_Hz * (1.0 - g)
    return {"shaft": shaft_Hz, "cage": cage, "roller_pass_outer": rollers * cage,
            "roller_pass_inner": rollers * (shaft_Hz - cage),
            "roller_spin": shaft_Hz * pitch_diameter_m / (2.0 * roller_diameter_m)
            * (1.0 - g * g)}
