"""The characteristic defect frequencies of a run (BPFO, BPFI, BSF, 2×BSF, FTF) and the orders
an envelope spectrum is read against: their harmonics and the sidebands that apply.

Pipeline place: analysis (reads a Dataset, or the attributes of one being made). The
relations are physics/frequencies.py's (:func:`~bearingdae.physics.frequencies.
defect_frequencies`), fed twice:

- **pure rolling** (``defect_frequency_<name>_pure_rolling_Hz``): the epicyclic cage and roller
  spin at the final inner-ring speed, from the geometry (the run's
  ``characteristic_frequencies_Hz``);
- **measured** (``defect_frequency_<name>_Hz``): the run's own mean cage speed and mean roller
  spin speed (relative to the cage, mean over rollers and the recorded window; slip
  included), the shaft at the final inner-ring speed (prescribed).

**Orders** (:func:`orders`). An outer-race defect repeats at BPFO, an inner-race one at BPFI
and, since it turns with the shaft through the load zone, is amplitude-modulated once per shaft
revolution: sidebands BPFI ± f_s; a roller defect strikes both races once per spin relative to
the cage (2×BSF), modulated as the roller goes round with the cage: sidebands 2×BSF ± FTF
(Randall & Antoni 2011, Mech. Syst. Signal Process. 25(2), 485-520, §2.1). Each comes with
its harmonics up to the frequency asked for.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..physics.frequencies import DEFECT_LABELS, DEFECT_NAMES, defect_frequencies
from .result_variables import defect_variable as variable_name

#: how a table or legend writes each defect frequency
LABELS = DEFECT_LABELS


def defect_frequency_attrs(characteristic: dict, rollers: int, cage_rad_s: float | None,
                           spin_rad_s: float | None) -> dict:
    """The defect-frequency results [Hz] of a run (module docstring) from its pure-rolling
    ``characteristic`` frequencies (physics/frequencies.characteristic_frequencies: shaft,
    cage, roller_spin) and its measured mean cage and roller spin speeds (None or NaN: not
    measured, those left out)."""
    if not characteristic or rollers <= 0:
        return {}
    f_s = float(characteristic["shaft"])
    pure = defect_frequencies(rollers, f_s, float(characteristic["cage"]),
                              float(characteristic["roller_spin"]))
    out = {variable_name(k, True): float(v) for k, v in pure.items()}
    two_pi = 2.0 * np.pi
    cage = cage_rad_s / two_pi if cage_rad_s is not None and np.isfinite(cage_rad_s) else None
    spin = spin_rad_s / two_pi if spin_rad_s is not None and np.isfinite(spin_rad_s) else None
    if cage is None:
        return out
    measured = defect_frequencies(rollers, f_s, cage, np.nan if spin is None else spin)
    out.update({variable_name(k): float(v) for k, v in measured.items()
                if np.isfinite(v)})
    return out


def statistics_defect_attrs(ds, estimates: dict) -> dict:
    """:func:`defect_frequency_attrs` of a run being recorded (``ds``: its global attributes
    hold ``characteristic_frequencies_Hz`` as JSON, or a Dataset that has them) with the mean
    cage and roller spin speeds of its statistics ``estimates`` (analysis/statistics.py)."""
    import json

    from .spectrum import characteristic

    text = ds.attrs.get("characteristic_frequencies_Hz")
    freqs = json.loads(text) if isinstance(text, str) else characteristic(ds)
    if not freqs or not freqs.get("cage", 0.0) > 0:
        return {}
    rollers = int(round(freqs["roller_pass_outer"] / freqs["cage"]))

    def mean(key):
        return float(estimates[key].mean) if key in estimates else None

    return defect_frequency_attrs(freqs, rollers, mean("mean_cage_speed_rad_s"),
                                  mean("mean_roller_spin_speed_rad_s"))


#: where a run's defect frequencies come from when it measured no speeds
PURE_ROLLING = "pure rolling"


def run_defect_frequencies(ds) -> tuple[dict[str, float], float, str]:
    """(defect frequencies by :data:`DEFECT_NAMES` [Hz], shaft frequency [Hz], where they come
    from) of a run's Dataset: its measured variables; else (a file without them) the means of
    its ``cage_speed`` and ``spin_speed``; else pure rolling; ``({}, nan, "none")`` for a file
    without characteristic frequencies."""
    from .spectrum import characteristic

    freqs = characteristic(ds)
    shaft = float(freqs.get("shaft", np.nan))
    if all(variable_name(k) in ds for k in DEFECT_NAMES):
        return ({k: float(ds[variable_name(k)].values) for k in DEFECT_NAMES}, shaft,
                "measured (mean cage and roller spin speeds)")
    if not all(freqs.get(k) for k in ("shaft", "cage", "roller_spin", "roller_pass_outer")):
        return {}, np.nan, "none"  # (a file with only some of them: no defect frequencies)
    rollers = int(round(freqs["roller_pass_outer"] / freqs["cage"]))
    from .spectrum import recorded_window

    def recorded_mean(name):  # over the recorded window, as the spectra read it
        if name not in ds:
            return None
        v = ds[name]
        return float((recorded_window(ds, v) if "time" in v.dims else v).mean())

    cage, spin = recorded_mean("cage_speed"), recorded_mean("spin_speed")
    attrs = defect_frequency_attrs(freqs, rollers, cage, spin)
    measured = all(variable_name(k) in attrs for k in DEFECT_NAMES)
    return ({k: attrs[variable_name(k, not measured)] for k in DEFECT_NAMES}, shaft,
            "measured (mean cage and roller spin speeds)" if measured else PURE_ROLLING)


#: the characteristic frequency (physics/frequencies.NAMES) each defect frequency is
CHARACTERISTIC_NAMES = {"ftf": "cage", "bpfo": "roller_pass_outer",
                        "bpfi": "roller_pass_inner", "bsf": "roller_spin"}


def run_characteristic(ds) -> tuple[dict[str, float], str]:
    """(the run's characteristic frequencies by physics/frequencies.NAMES [Hz], where they come
    from): those of :func:`run_defect_frequencies`, so that the spectra mark the frequencies
    the envelope panel and the peaks table read (measured where the run has them), in the
    order of :func:`~bearingdae.analysis.spectrum.characteristic`; ``({}, "none")`` for a
    file without them."""
    from .spectrum import characteristic

    freqs, shaft, source = run_defect_frequencies(ds)
    if not freqs or source == PURE_ROLLING:  # the file's own, as many as it has
        given = characteristic(ds)
        return (given, PURE_ROLLING) if given else ({}, "none")
    out = {"shaft": shaft, **{CHARACTERISTIC_NAMES[k]: v for k, v in freqs.items()
                              if k in CHARACTERISTIC_NAMES}}
    return {k: out[k] for k in characteristic(ds) if k in out}, source


class Order(NamedTuple):
    """One characteristic order: its ``label`` ("2×BPFO", "BPFI−fs"), frequency [Hz], the
    defect it belongs to (``family``: a key of :data:`LABELS`, or "shaft"), its harmonic and
    its sideband (−1, 0, +1); ``rank`` orders the ones that fall together (simplest first)."""

    label: str
    frequency_Hz: float
    family: str
    harmonic: int
    sideband: int
    rank: int


#: the most harmonics taken of each: few of the slow shaft and cage lines (their many
#: harmonics would lie within a bin of almost any peak); every harmonic of BPFI and 2×BSF
#: taken carries its sidebands (2×BSF's harmonics are BSF's even ones)
MAX_HARMONICS = {"shaft": 3, "ftf": 3, "bpfo": 10, "bpfi": 10, "bsf": 10}


def orders(freqs: dict[str, float], shaft_Hz: float, fmax_Hz: float,
           sidebands: int = 1) -> list[Order]:
    """The characteristic orders up to ``fmax_Hz`` (module docstring): the harmonics of FTF,
    BPFO, BPFI, BSF (2×BSF is its second) and the shaft (at most :data:`MAX_HARMONICS`),
    and the sidebands BPFI ± m f_s and 2×BSF ± m FTF, m = 1 .. ``sidebands``, of each of
    those harmonics of BPFI and 2×BSF, wherever the sideband falls below ``fmax_Hz`` (also
    the lower one of a harmonic just above it; a load zone modulates more than sinusoidally:
    the peaks table reads the second pair too)."""
    out: list[Order] = []

    def add(label, f, family, k, side):
        if 0.0 < f <= fmax_Hz and np.isfinite(f):
            out.append(Order(label, float(f), family, k, side, k + 2 * abs(side)))

    def times(k, name):
        return name if k == 1 else f"{k}×{name}"

    if np.isfinite(shaft_Hz) and shaft_Hz > 0:
        for k in range(1, MAX_HARMONICS["shaft"] + 1):
            add(times(k, "fs"), k * shaft_Hz, "shaft", k, 0)
    for key in ("ftf", "bpfo", "bpfi", "bsf"):
        f1 = freqs.get(key, np.nan)
        if not (np.isfinite(f1) and f1 > 0):
            continue
        for k in range(1, min(int(fmax_Hz // f1), MAX_HARMONICS[key]) + 1):
            label = "2×BSF" if (key, k) == ("bsf", 2) else times(k, LABELS[key])
            add(label, k * f1, "2bsf" if key == "bsf" and k % 2 == 0 else key, k, 0)
    for key, mod, name in (("bpfi", shaft_Hz, "fs"), ("2bsf", freqs.get("ftf", np.nan), "FTF")):
        f1 = freqs.get(key, np.nan)
        if not (np.isfinite(f1) and f1 > 0 and np.isfinite(mod) and mod > 0):
            continue
        harmonics = MAX_HARMONICS["bpfi"] if key == "bpfi" else MAX_HARMONICS["bsf"] // 2
        for k in range(1, harmonics + 1):
            base = times(k, LABELS[key]) if key == "bpfi" else times(2 * k, "BSF")
            for m in range(1, sidebands + 1):
                add(f"{base}−{times(m, name)}", k * f1 - m * mod, key, k, -m)
                add(f"{base}+{times(m, name)}", k * f1 + m * mod, key, k, +m)
    return sorted(out, key=lambda o: o.frequency_Hz)


#: the order families each defect kind (``[[defects]]`` ``on``) can produce; the shaft's and
#: the cage's lines (FTF) come from any bearing (unbalance, the load zone going round)
FAMILIES = {"outer": ("bpfo",), "inner": ("bpfi",), "roller": ("bsf", "2bsf")}
ANY_BEARING = ("shaft", "ftf")


def defect_kinds(ds) -> frozenset:
    """The surfaces (``on``) of the ``[[defects]]`` of the scene a result was run from (its
    ``scene_toml`` attribute); empty for a file without a scene or without defects."""
    import tomllib

    text = getattr(ds, "attrs", {}).get("scene_toml")
    if not isinstance(text, str):
        return frozenset()
    try:
        entries = tomllib.loads(text).get("defects", [])
    except tomllib.TOMLDecodeError:
        return frozenset()
    return frozenset(str(d.get("on")) for d in entries if isinstance(d, dict))


def matches(frequency_Hz: float, candidates: list[Order], tolerance_Hz: float,
            kinds: frozenset = frozenset()) -> list[Order]:
    """The orders within ``tolerance_Hz`` of ``frequency_Hz``, the likeliest first: where the
    defect ``kinds`` are known, only the orders they (or any bearing) can produce, if one of
    them is near; then the nearest, the simplest of equally near ones. An analyst reading a
    simulated inner spall expects its BPFI − 2 f_s sideband named so, not the BPFO that
    falls in the same bin; without a defect named, both are candidates."""
    near = [o for o in candidates if abs(o.frequency_Hz - frequency_Hz) <= tolerance_Hz]
    if kinds:
        allowed = set(ANY_BEARING).union(*(FAMILIES.get(k, ()) for k in kinds))
        possible = [o for o in near if o.family in allowed]
        near = possible or near
    return sorted(near, key=lambda o: (abs(o.frequency_Hz - frequency_Hz), o.rank))


def match(frequency_Hz: float, candidates: list[Order], tolerance_Hz: float) -> Order | None:
    """The order within ``tolerance_Hz`` of ``frequency_Hz`` (the nearest when several are,
    the simplest of equally near ones), or None: the first of :func:`matches`."""
    near = matches(frequency_Hz, candidates, tolerance_Hz)
    return near[0] if near else None
