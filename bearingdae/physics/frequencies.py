"""Characteristic frequencies of a rolling bearing with the outer ring fixed (theory.md §15).

Stage: physics, used by results (Dataset attributes, the spectrum figure). Kinematic
(pure-rolling) frequencies of a roller bearing, contact angle 0, inner ring turning at f_s
(Harris & Kotzalas, *Rolling Bearing Analysis*, 5th ed., Vol. 1, §8; the same as the
epicyclic speeds of physics/geometry.py), γ = D_w / d_m:

- shaft f_s; cage (fundamental train) f_c = f_s (1 − γ) / 2;
- roller pass on the outer race Z f_c, on the inner race Z (f_s − f_c);
- roller spin relative to the cage f_s d_m / (2 D_w) (1 − γ²) (= f_c (R_m + r) / r).

The same relations from the run's own measured mean cage speed f_c and roller spin f_r
relative to the cage (slip included) give the **defect frequencies** a vibration analyst reads
(:func:`defect_frequencies`): BPFO = Z f_c (a point of the fixed outer race: Z rollers per
cage revolution), BPFI = Z (f_s − f_c) (a point of the inner race), BSF = f_r (a point of a
roller meets one race once per spin relative to the cage), 2×BSF (it meets both races), FTF =
f_c (the fundamental train). With the pure-rolling f_c and f_r these are Harris's

    BPFO = Z/2 f_s (1 − γ),  BPFI = Z/2 f_s (1 + γ),  BSF = d_m/(2 D_w) f_s (1 − γ²),
    FTF = f_s/2 (1 − γ).

The roller pass on the outer race is the period of the varying-compliance vibration of a ring
carried by Z rollers (Sunnersjö 1978, J. Sound Vib. 58(3), 363-373).
"""

from __future__ import annotations

#: names of the frequencies, in the order of :func:`characteristic_frequencies`
NAMES = ("shaft", "cage", "roller_pass_outer", "roller_pass_inner", "roller_spin")


#: the defect frequencies' keys, in the order of :func:`defect_frequencies`
DEFECT_NAMES = ("bpfo", "bpfi", "bsf", "2bsf", "ftf")
#: how a table or legend writes each
DEFECT_LABELS = {"bpfo": "BPFO", "bpfi": "BPFI", "bsf": "BSF", "2bsf": "2×BSF", "ftf": "FTF"}
#: what each is
DEFECT_MEANINGS = {"bpfo": "ball (roller) pass frequency, outer race",
                   "bpfi": "ball (roller) pass frequency, inner race",
                   "bsf": "ball (roller) spin frequency relative to the cage",
                   "2bsf": "twice the ball (roller) spin frequency (a roller defect meets both "
                           "races)",
                   "ftf": "fundamental train (cage) frequency"}


def defect_frequencies(rollers: int, shaft_Hz: float, cage_Hz: float,
                       spin_Hz: float) -> dict[str, float]:
    """BPFO, BPFI, BSF, 2×BSF and FTF [Hz] (module docstring; by :data:`DEFECT_NAMES`) from
    the shaft frequency, the cage frequency and the roller spin frequency relative to the
    cage."""
    return {"bpfo": rollers * cage_Hz, "bpfi": rollers * (shaft_Hz - cage_Hz),
            "bsf": spin_Hz, "2bsf": 2.0 * spin_Hz, "ftf": cage_Hz}


def characteristic_frequencies(rollers: int, roller_diameter_m: float, pitch_diameter_m: float,
                               shaft_Hz: float) -> dict[str, float]:
    """The frequencies of the module docstring [Hz], by :data:`NAMES`."""
    g = roller_diameter_m / pitch_diameter_m
    cage = 0.5 * shaft_Hz * (1.0 - g)
    d = defect_frequencies(rollers, shaft_Hz, cage, shaft_Hz * pitch_diameter_m
                           / (2.0 * roller_diameter_m) * (1.0 - g * g))
    return {"shaft": shaft_Hz, "cage": d["ftf"], "roller_pass_outer": d["bpfo"],
            "roller_pass_inner": d["bpfi"], "roller_spin": d["bsf"]}
