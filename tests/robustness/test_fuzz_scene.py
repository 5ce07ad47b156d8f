"""Property-based fuzzing of scene input.

Random and adversarial scenes go into ``load_scene`` (files), ``scene_from_dict`` (dicts and
dotted overrides) and ``bearingdae static`` (in-process CLI). The contract:

* every case loads into a :class:`Scene` or raises :class:`SceneError`, whose message names
  the offending key when the problem is one key's; no other exception type ever escapes;
* the CLI exits 0, 1 (static solver failure) or 2 with a one-paragraph message, no traceback;
* every scene that loads is solved statically: finite ``contact_force`` or
  :class:`StaticConvergenceError` (which one is counted).

Deterministic for CI (``derandomize=True``, no example database). ``pytest -s`` prints the
number of cases tried per strategy and outcome (``test_zz_fuzz_summary``).
"""

from __future__ import annotations

import atexit
import collections
import math
import shutil
import tempfile
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest
import tomli_w
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pydantic import ValidationError

from bearingdae import Scene, SceneError, load_scene, scene_from_dict, solve_static
from fuzzing import run_cli
from bearingdae.analysis.guards import PlausibilityWarning
from bearingdae.scene.parameters import PRESETS
from bearingdae.scene import _SECTIONS, SceneInput, valid_keys
from bearingdae.solvers.static import StaticConvergenceError

settings.register_profile(
    "fuzz-scene",
    derandomize=True,  # the same examples on every run: CI-stable
    database=None,
    deadline=None,
    print_blob=False,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much,
                           HealthCheck.data_too_large],
)


def fuzz(max_examples: int):
    return settings(settings.get_profile("fuzz-scene"), max_examples=max_examples)


#: (strategy, outcome) -> number of cases; printed by test_zz_fuzz_summary.
COUNTS: collections.Counter = collections.Counter()

#: One scratch folder for the whole module (hypothesis examples overwrite their files).
SCRATCH = Path(tempfile.mkdtemp(prefix="bearingdae-fuzz-"))
atexit.register(shutil.rmtree, SCRATCH, ignore_errors=True)

LEAF_KEYS = ["title"] + [f"{sec}.{name}" for sec, m in _SECTIONS.items() for name in m.model_fields]
NUMERIC_KEYS = [
    f"{sec}.{name}" for sec, m in _SECTIONS.items() for name, f in m.model_fields.items()
    if f.annotation in (float, int, float | None, int | None)
]
#: Every name a scene file or override may use, quoted as in the messages.
QUOTED_KEYS = [f"'{k}" for k in valid_keys()] + [f"[{s}]" for s in _SECTIONS]


def _explicit(preset: str) -> dict:
    """A scene with every key written out (no preset), from a preset's values."""
    data = {sec: {} for sec in _SECTIONS}
    data["title"] = f"explicit {preset}"
    data["bearing"] = dict(PRESETS[preset]["bearing"])
    for sec, model in _SECTIONS.items():
        for name, f in model.model_fields.items():
            if f.default is not None and name not in data[sec]:
                data[sec][name] = f.default
    data["cage"]["pocket_clearance_mm"] = PRESETS[preset]["cage"]["pocket_clearance_mm"]
    return data


BASES_DRAWN: collections.Counter = collections.Counter()  #: base -> cases built on it
BASES = {
    "yang20": {"bearing": {"preset": "yang20"}},
    "harris36": {"bearing": {"preset": "harris36"}},
    "explicit-yang20": _explicit("yang20"),
    "explicit-harris36": _explicit("harris36"),
    # the physics keys beyond the paper's model: flanges with an axial load (theory.md §16),
    # cage whirl on a land-guided cage (§17), the inner ring as a body (§15)
    "nj-axial": {"bearing": {"preset": "yang20", "type": "NJ"},
                 "operating": {"radial_load_N": 800.0, "axial_load_N": 200.0}},
    "nup-whirl": {"bearing": {"preset": "yang20", "type": "NUP"},
                  "physics": {"cage_whirl": True}, "cage": {"guidance": "outer-land"}},
    "ring-dynamic": {"bearing": {"preset": "yang20"}, "physics": {"ring": "dynamic"}},
}


def base_scene(name: str) -> dict:
    BASES_DRAWN[name] += 1
    return {k: dict(v) if isinstance(v, dict) else v for k, v in BASES[name].items()}


# --------------------------------------------------------------------------------------------
# The contract, applied to every case
# --------------------------------------------------------------------------------------------
#: the outcomes of each scene solved so far in this process, by :func:`solve_key`. Many cases
#: load a scene an earlier case already solved (measured: 122 of the 124 solves of
#: test_missing_sections_and_keys, 59 of 64 of test_mutated_case_files, 16 of 31 of
#: test_wrong_types_for_every_key): the static solve is deterministic, so such a case gets the
#: outcome of that solve (counted again) instead of the same solve twice. A scene whose solve
#: failed the contract is not stored: every case with it fails.
SOLVED: dict[str, tuple[str, ...]] = {}


def solve_key(scene: Scene) -> str:
    """The scene as the static solve sees it: its complete TOML without the title line (the
    title is a label, read by no solve)."""
    lines = scene.to_toml(complete=True).splitlines()
    return "\n".join(lines[1:] if lines and lines[0].startswith("title = ") else lines)


def solve(strategy: str, scene: Scene) -> None:
    """Static solve of a loaded scene: finite forces or StaticConvergenceError, counted (a
    scene solved before: that solve's outcome, see :data:`SOLVED`)."""
    key = solve_key(scene)
    if key in SOLVED:
        COUNTS[strategy, "solve: scene of an earlier case, its outcome"] += 1
    else:
        SOLVED[key] = solve_outcomes(scene)
    for outcome in SOLVED[key]:
        COUNTS[strategy, outcome] += 1


def solve_outcomes(scene: Scene) -> tuple[str, ...]:
    """The outcomes of the static solve of ``scene``; fails on non-finite forces."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            ds = solve_static(scene)
        except StaticConvergenceError:
            return ("solve: StaticConvergenceError",)
    q = ds.contact_force.values
    assert np.all(np.isfinite(q)), f"non-finite contact_force for {scene}"
    out = ["solve: converged, finite"]
    if any(issubclass(w.category, PlausibilityWarning) for w in caught):
        out.append("solve: PlausibilityWarning")
    if any(not issubclass(w.category, PlausibilityWarning) for w in caught):
        out.append("solve: numpy RuntimeWarning (result finite)")
    return tuple(out)


def attempt(strategy: str, load, keys=(), *, solve_loaded: bool = True) -> Scene | None:
    """Run ``load()``: a Scene (then solved) or a SceneError naming one of ``keys``.

    Any other exception propagates and fails the test (hypothesis then shrinks the input).
    """
    try:
        scene = load()
    except SceneError as exc:
        msg = str(exc)
        assert msg.strip(), "empty SceneError message"
        if keys:
            assert any(k in msg for k in keys), f"message names none of {keys}:\n{msg}"
        COUNTS[strategy, "SceneError"] += 1
        return None
    assert isinstance(scene, Scene)
    COUNTS[strategy, "loaded"] += 1
    assert_round_trip(scene)
    COUNTS[strategy, "stored TOML loads back equal"] += 1
    if solve_loaded:
        solve(strategy, scene)
    return scene


def assert_round_trip(scene: Scene) -> None:
    """The complete TOML a result file stores (every default and derived value written out)
    loads back to an equal scene: no derived default lies outside its key's range."""
    text = scene.to_toml(complete=True)
    try:
        again = scene_from_dict(tomllib.loads(text))
    except SceneError as exc:
        raise AssertionError(f"the stored TOML does not load: {exc}\n{text}") from None
    assert again == scene, f"the stored TOML loads to another scene:\n{text}"
    assert tomllib.loads(again.to_toml(complete=True)) == tomllib.loads(text)


def field_rejects(key: str, value) -> bool:
    """True when the file-layer model alone rejects ``key = value`` (a key-specific problem)."""
    sec, _, name = key.partition(".")
    data = {"title": value} if key == "title" else {sec: {name: value}}
    try:
        SceneInput.model_validate(data)
    except ValidationError:
        return True
    return False


def names_key(key: str) -> tuple[str, ...]:
    """How a message names ``key``: 'bearing.rollers' (also 'operating.speed_rpm.times_s')."""
    return (f"'{key}",)


def write(name: str, content: bytes | str) -> Path:
    p = SCRATCH / name
    if isinstance(content, str):
        content = content.encode("utf-8", "surrogatepass")
    p.write_bytes(content)
    return p


# --------------------------------------------------------------------------------------------
# Strategies
# --------------------------------------------------------------------------------------------
SPECIAL_FLOATS = [math.nan, math.inf, -math.inf, -0.0, 0.0, 1e308, -1e308, 5e-324, -5e-324,
                  2.2250738585072014e-308, 1.7976931348623157e308, 1e-300, 1e300]
HUGE_INTS = [10**400, -(10**400), 2**63, -(2**63) - 1, 2**64, 10**5000]

#: Values TOML can hold (what a scene file can contain).
toml_scalars = st.one_of(
    st.text(max_size=12),
    st.booleans(),
    st.integers(min_value=-(2**63), max_value=2**63 - 1),
    st.sampled_from([10**400, -(10**400), 2**64]),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from(SPECIAL_FLOATS),
    st.datetimes(), st.dates(), st.times(),
)
toml_values = st.recursive(
    toml_scalars,
    lambda inner: st.one_of(st.lists(inner, max_size=4),
                            st.dictionaries(st.text(max_size=8), inner, max_size=3)),
    max_leaves=8,
)
#: Anything a Python caller might pass (adds None, huge ints, numpy, bytes, objects).
python_values = st.one_of(
    toml_values,
    st.none(),
    st.sampled_from(HUGE_INTS),
    st.binary(max_size=8),
    st.complex_numbers(),
    st.tuples(st.floats(), st.floats()),
    st.sampled_from(["\udcff", "a\ud800b", "yang20\x00", "end-crown "]),
    st.sampled_from([np.float64(math.nan), np.float32(1e-45), np.int64(7), np.bool_(True),
                     np.array([1.0, 2.0]), np.array(3.0), np.float64(1e308), np.uint8(255),
                     np.str_("flat"), object(), Ellipsis, float, {1, 2}, frozenset()]),
)


def field_bounds(key: str) -> list:
    """Each range bound of a numeric key, and its float neighbours on both sides."""
    sec, _, name = key.partition(".")
    out = []
    for c in _SECTIONS[sec].model_fields[name].metadata:
        for attr in ("gt", "ge", "lt", "le"):
            v = getattr(c, attr, None)
            if v is not None:
                out += [v, float(v), math.nextafter(v, -math.inf), math.nextafter(v, math.inf)]
    return out


@st.composite
def extreme_number(draw, key: str):
    bounds = field_bounds(key)
    return draw(st.one_of(
        st.sampled_from(SPECIAL_FLOATS + HUGE_INTS[:-1] + [0, 1, -1, 3, 500, 501]),
        st.sampled_from(bounds) if bounds else st.just(0.5),
        st.floats(min_value=-1e12, max_value=1e12),
        st.integers(min_value=-10**6, max_value=10**6),
    ))


# --------------------------------------------------------------------------------------------
# scene_from_dict
# --------------------------------------------------------------------------------------------
def _set(data: dict, key: str, value) -> None:
    if key == "title":
        data["title"] = value
    else:
        sec, _, name = key.partition(".")
        data.setdefault(sec, {})[name] = value


@fuzz(500)
@given(base=st.sampled_from(sorted(BASES)), key=st.sampled_from(LEAF_KEYS), value=python_values,
       via_override=st.booleans())
def test_wrong_types_for_every_key(base, key, value, via_override):
    data = base_scene(base)
    if via_override:
        load = lambda: scene_from_dict(data, {key: value})  # noqa: E731
    else:
        _set(data, key, value)
        load = lambda: scene_from_dict(data)  # noqa: E731
    # A value the key's own type/range rejects must be reported under that key; a value it
    # accepts may still break a cross-field rule, reported under some key.
    keys = names_key(key) if field_rejects(key, value) else QUOTED_KEYS
    attempt("wrong types (dict + override)", load, keys)


@fuzz(300)
@given(base=st.sampled_from(sorted(BASES)), picks=st.lists(st.sampled_from(NUMERIC_KEYS),
       min_size=1, max_size=4, unique=True), data=st.data())
def test_extreme_magnitudes(base, picks, data):
    scene = base_scene(base)
    for key in picks:
        _set(scene, key, data.draw(extreme_number(key), label=key))
    rejected = [k for k in picks if field_rejects(k, scene_value(scene, k))]
    keys = tuple(f"'{k}" for k in rejected) if rejected else QUOTED_KEYS
    attempt("extreme magnitudes", lambda: scene_from_dict(scene), keys)


def field_range(key: str) -> tuple[float, float]:
    """(lowest, highest) value the key's own range admits."""
    sec, _, name = key.partition(".")
    lo, hi = -1e300, 1e300
    for c in _SECTIONS[sec].model_fields[name].metadata:
        if getattr(c, "ge", None) is not None:
            lo = c.ge
        if getattr(c, "gt", None) is not None:
            lo = math.nextafter(c.gt, math.inf) if isinstance(c.gt, float) or c.gt != int(c.gt) \
                else c.gt + (1 if _SECTIONS[sec].model_fields[name].annotation in (int, int | None)
                             else 5e-324)
        if getattr(c, "le", None) is not None:
            hi = c.le
        if getattr(c, "lt", None) is not None:
            hi = math.nextafter(c.lt, -math.inf)
    return lo, hi


@st.composite
def in_range_extreme(draw, key: str):
    """A value the key's own range accepts, biased to its ends (5e-324 for '> 0')."""
    lo, hi = field_range(key)
    sec, _, name = key.partition(".")
    if _SECTIONS[sec].model_fields[name].annotation in (int, int | None):
        return draw(st.one_of(st.sampled_from([int(lo), int(hi)]),
                              st.integers(int(lo), int(hi))))
    ends = [lo, hi, math.nextafter(lo, math.inf), math.nextafter(hi, -math.inf), 0.0, -0.0,
            5e-324, 1e-300, 1e-12]
    return draw(st.one_of(st.sampled_from([v for v in ends if lo <= v <= hi]),
                          st.floats(lo, hi)))


IN_RANGE_KEYS = [k for k in NUMERIC_KEYS if not k.startswith("operating.speed")] + [
    "operating.speed_rpm"]


@fuzz(250)
@given(base=st.sampled_from(sorted(BASES)), picks=st.lists(st.sampled_from(IN_RANGE_KEYS),
       min_size=1, max_size=3, unique=True), data=st.data())
def test_in_range_extremes_load_and_solve(base, picks, data):
    """Values each key's own range admits, at its ends: load (then solve) or a cross-field
    SceneError; this is where the physics meets 5e-324 mm, 1e8 N, 1000 slices, ..."""
    scene = base_scene(base)
    for key in picks:
        value = (data.draw(st.floats(0.0, 200_000.0), label=key) if key == "operating.speed_rpm"
                 else data.draw(in_range_extreme(key), label=key))
        _set(scene, key, value)
    attempt("in-range extremes (static solve)", lambda: scene_from_dict(scene), QUOTED_KEYS)


def scene_value(data: dict, key: str):
    if key == "title":
        return data["title"]
    sec, _, name = key.partition(".")
    return data[sec][name]


@fuzz(150)
@given(base=st.sampled_from(["explicit-yang20", "explicit-harris36"]),
       drop=st.lists(st.sampled_from(LEAF_KEYS + list(_SECTIONS)), min_size=1, max_size=8,
                     unique=True))
def test_missing_sections_and_keys(base, drop):
    data = base_scene(base)
    for key in drop:
        sec, _, name = key.partition(".")
        if not name:
            data.pop(sec, None)
        elif isinstance(data.get(sec), dict):
            data[sec].pop(name, None)
    attempt("missing sections and keys", lambda: scene_from_dict(data), QUOTED_KEYS)


unknown_names = st.one_of(
    st.text(max_size=24),
    st.sampled_from(["Bearing", "bearings", "operation", "radial_load_N", "rollers", "slices",
                     "bearing ", "", ".", "bearing.rollers", "operating.radial_load", "__class__",
                     "model_config", "title ", "\x00", "\udcff", "ä" * 300]),
    st.builds(lambda k: k.upper(), st.sampled_from(LEAF_KEYS)),
)


@fuzz(250)
@given(base=st.sampled_from(sorted(BASES)), name=st.one_of(unknown_names, st.integers()),
       where=st.sampled_from(["top"] + list(_SECTIONS)), value=toml_values)
def test_unknown_keys_and_sections(base, name, where, value):
    data = base_scene(base)
    valid = ["title", *_SECTIONS] if where == "top" else list(_SECTIONS[where].model_fields)
    if name in valid:
        return
    if where == "top":
        data[name] = value
        named = str(name)
    else:
        data.setdefault(where, {})[name] = value
        named = f"{where}.{name}"
    # a name of more than 100 characters is echoed cut to ~100 (its beginning)
    shown = f"'{named}'" if len(named) <= 100 else f"'{named[:90]}"
    attempt("unknown keys and sections", lambda: scene_from_dict(data), (shown,))


#: Keys whose unit is easy to get wrong, and the factor a user might slip in.
UNIT_SLIPS = {
    **{f"bearing.{k}": [1e-3, 1e3, 25.4] for k in (
        "outer_diameter_mm", "bore_mm", "pitch_diameter_mm", "roller_diameter_mm",
        "roller_length_mm", "effective_length_mm", "crown_radius_mm", "radial_clearance_mm")},
    "materials.youngs_modulus_GPa": [1e9, 1e3, 1e-3],
    "materials.density_kg_m3": [1e-3, 1e-6],
    "operating.speed_rpm": [2 * math.pi / 60, 1 / 60],
    "operating.radial_load_N": [1e-3, 1e3],
    "operating.moment_Nm": [1e3, 1e-3],
    "traction.B_GPa": [1e9],
    "cage.pocket_clearance_mm": [1e-3, 1e3],
    "cage.smoothing_um": [1e-6, 1e3],
    "numerics.contact_smoothing_nm": [1e-9, 1e3],
    "lubricant.viscosity_Pa_s": [1e3],
}
UNIT_DEFAULTS = {"operating.speed_rpm": 2000.0, "operating.radial_load_N": 800.0,
                 "operating.moment_Nm": 3.0, "bearing.pitch_diameter_mm": None}


@fuzz(150)
@given(base=st.sampled_from(["explicit-yang20", "explicit-harris36"]),
       slips=st.lists(st.sampled_from(sorted(UNIT_SLIPS)), min_size=1, max_size=3, unique=True),
       data=st.data())
def test_unit_mistakes(base, slips, data):
    """roller_diameter_mm = 0.004 (metres in a mm key) etc.: loads or a clean SceneError."""
    scene = base_scene(base)
    for key in slips:
        sec, _, name = key.partition(".")
        good = UNIT_DEFAULTS[key] if key in UNIT_DEFAULTS else scene[sec].get(name)
        if good is None:  # pitch diameter: (D + d)/2
            good = 0.5 * (scene["bearing"]["outer_diameter_mm"] + scene["bearing"]["bore_mm"])
        factor = data.draw(st.sampled_from(UNIT_SLIPS[key]), label=key)
        scene[sec][name] = float(good) * factor
    attempt("unit mistakes", lambda: scene_from_dict(scene), QUOTED_KEYS)


#: Unit slips the scene now catches: (key, factor applied to a correct value, outcome).
#: "error": a SceneError naming the key and suggesting the value in the key's unit;
#: "warning": loads (a tiny value is legitimate there) but solve_static warns, naming the key.
DETECTED_SLIPS = [
    *[(f"bearing.{k}", 1e-3, "error") for k in (
        "outer_diameter_mm", "bore_mm", "pitch_diameter_mm", "roller_diameter_mm",
        "roller_length_mm", "effective_length_mm")],
    ("bearing.radial_clearance_mm", 1e-3, "warning"),
    ("cage.pocket_clearance_mm", 1e-3, "warning"),
    ("cage.pocket_clearance_mm", 1e3, "error"),
    ("materials.youngs_modulus_GPa", 1e9, "error"),
    ("materials.youngs_modulus_GPa", 1e3, "error"),
    ("materials.density_kg_m3", 1e-3, "error"),
    ("lubricant.oil_density_kg_m3", 1e-3, "error"),
    ("lubricant.viscosity_Pa_s", 1e3, "warning"),
    ("traction.B_GPa", 1e9, "error"),
    ("cage.smoothing_um", 1e-6, "error"),
    ("numerics.contact_smoothing_nm", 1e-9, "error"),
]


@st.composite
def correct_value(draw, key: str, base: dict):
    """A realistic value of ``key`` in its own unit (the preset's or a drawn one)."""
    sec, _, name = key.partition(".")
    # the clearance below 0.1 mm: 0.1 mm in m (1e-4, read as mm: 1.0000000000000001e-07 m)
    # lands on the guard's threshold 1e-7 m itself, not below it
    drawn = {"bearing.radial_clearance_mm": st.floats(1e-3, 0.1, exclude_max=True),
             "cage.pocket_clearance_mm": st.floats(0.02, 0.5),
             "lubricant.viscosity_Pa_s": st.floats(2e-3, 0.1),
             "materials.youngs_modulus_GPa": st.floats(70.0, 450.0),
             "materials.density_kg_m3": st.floats(2500.0, 16_000.0),
             "lubricant.oil_density_kg_m3": st.floats(700.0, 1100.0),
             "traction.B_GPa": st.floats(0.1, 2.0),
             "cage.smoothing_um": st.floats(0.01, 1.0),
             "numerics.contact_smoothing_nm": st.floats(0.1, 1.0)}
    if key in drawn:
        return draw(drawn[key])
    value = base[sec].get(name)
    return value if value is not None else 0.5 * (base["bearing"]["outer_diameter_mm"]
                                                  + base["bearing"]["bore_mm"])


@fuzz(200)
@given(base=st.sampled_from(["explicit-yang20", "explicit-harris36"]),
       slip=st.sampled_from(DETECTED_SLIPS), data=st.data())
def test_detected_unit_slips_are_named_with_the_unit(base, slip, data):
    """A value in the wrong unit (metres in a mm key, Pa in a GPa key, µm in a mm key, ...) is
    an error naming the key and the corrected value, or where a tiny value is legitimate (a
    clearance) a PlausibilityWarning naming the key."""
    key, factor, outcome = slip
    scene = base_scene(base)
    sec, _, name = key.partition(".")
    good = data.draw(correct_value(key, scene), label="correct value")
    wrong = float(good) * factor
    scene.setdefault(sec, {})[name] = wrong
    if outcome == "error":
        with pytest.raises(SceneError) as e:
            scene_from_dict(scene)
        msg = str(e.value)
        assert f"'{key}' = {wrong!r}" in msg, msg
        assert " write " in msg, f"no corrected value suggested:\n{msg}"
        COUNTS["unit slips (detected)", "SceneError"] += 1
        return
    loaded = scene_from_dict(scene)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        solve_static(loaded)
    named = [str(w.message) for w in caught if issubclass(w.category, PlausibilityWarning)
             and f"'{key}'" in str(w.message) and " write " in str(w.message)]
    assert named, f"no PlausibilityWarning names {key} = {wrong!r}"
    COUNTS["unit slips (detected)", "loaded"] += 1
    assert_round_trip(loaded)
    COUNTS["unit slips (detected)", "stored TOML loads back equal"] += 1
    COUNTS["unit slips (detected)", "PlausibilityWarning naming the key"] += 1


@pytest.mark.parametrize("base", ["explicit-yang20", "explicit-harris36"])
def test_whole_bearing_in_metres_is_refused_with_the_mm_values(base):
    """Every length of [bearing] in metres: consistent geometry, so no cross-field rule
    objects; the lower bounds catch it and each message gives the value in mm."""
    scene = base_scene(base)
    for key in BEARING_LENGTHS:
        if isinstance(scene["bearing"].get(key), float) and key != "radial_clearance_mm":
            scene["bearing"][key] *= 1e-3
    with pytest.raises(SceneError) as e:
        scene_from_dict(scene)
    dw = base_scene(base)["bearing"]["roller_diameter_mm"]
    assert f"if {dw * 1e-3!r} is in m, write {dw:g}." in str(e.value), str(e.value)
    COUNTS["explicit cases", "SceneError"] += 1


def _table_bounds(rng: str) -> tuple[tuple[float, bool], tuple[float, bool]]:
    """'[0.5, 1000]' -> ((0.5, closed), (1000, closed))."""
    lo, hi = rng[1:-1].split(", ")
    return (float(lo), rng[0] == "["), (float(hi), rng[-1] == "]")


TABLE = {key: rng for key, _, rng, _ in __import__("bearingdae.scene",
                                                   fromlist=["key_table"]).key_table()}


@pytest.mark.parametrize("key", [k for k in NUMERIC_KEYS] + ["operating.speed_rpm"])
def test_key_table_ranges_are_the_enforced_ones(key):
    """For every numeric key, the range `bearingdae keys` prints is the one load_scene enforces:
    one ulp (or one unit) outside each bound is a SceneError naming the key and that range; the
    bound itself, when the range includes it, is not rejected for its range."""
    rng = TABLE[key]
    assert rng, f"{key} has no range in the key table"
    sec, _, name = key.partition(".")
    is_int = _SECTIONS[sec].model_fields[name].annotation in (int, int | None)
    for (bound, closed), outward in zip(_table_bounds(rng), (-math.inf, math.inf)):
        if not math.isfinite(bound):
            continue
        outside = (bound + (1 if outward > 0 else -1) if is_int
                   else math.nextafter(bound, outward)) if closed else bound
        data = base_scene("yang20")
        _set(data, key, int(outside) if is_int else float(outside))
        with pytest.raises(SceneError) as e:
            scene_from_dict(data)
        assert f"'{key}' = {_set_shown(outside, is_int)}" in str(e.value) and rng in str(
            e.value), str(e.value)
        COUNTS["key-table ranges", "SceneError"] += 1
        inside = bound if closed else (bound + (1 if outward < 0 else -1) if is_int
                                       else math.nextafter(bound, -outward))
        data = base_scene(base_for(key))
        _set(data, key, int(inside) if is_int else float(inside))
        try:
            assert_round_trip(scene_from_dict(data))  # a bound itself: derived values too
            COUNTS["key-table ranges", "loaded"] += 1
            COUNTS["key-table ranges", "stored TOML loads back equal"] += 1
        except SceneError as exc:  # a cross-field rule may still object, never the range
            assert f"allowed range {rng}" not in str(exc), str(exc)
            COUNTS["key-table ranges", "SceneError"] += 1


def base_for(key: str) -> str:
    """The base scene in which ``key`` is read: flange keys need a bearing type with flanges,
    whirl keys a whirling cage, ring keys a dynamic ring (the switch each key's field names,
    scene/switches.py)."""
    from bearingdae.scene.switches import switched_keys

    switch = switched_keys().get(key, {}).get("switch")
    return {"flange": "nj-axial", "cage_whirl": "nup-whirl",
            "ring": "ring-dynamic"}.get(switch, "yang20")


def _set_shown(value, is_int: bool) -> str:
    return repr(int(value)) if is_int else repr(float(value))


def test_no_in_range_length_underflows_to_zero_metres():
    """Every key in mm/µm/nm either admits 0 or has a lower bound whose SI value is a normal
    float (the underflow check of the first fuzzing round is no longer needed)."""
    import sys

    for key in NUMERIC_KEYS:
        for suffix, scale in (("_mm", 1e-3), ("_um", 1e-6), ("_nm", 1e-9)):
            if key.endswith(suffix):
                (lo, _), _ = _table_bounds(TABLE[key])
                assert lo <= 0.0 or lo * scale >= sys.float_info.min, key


BEARING_LENGTHS = ["outer_diameter_mm", "bore_mm", "pitch_diameter_mm", "roller_diameter_mm",
                   "roller_length_mm", "effective_length_mm", "crown_radius_mm",
                   "radial_clearance_mm"]


@fuzz(80)
@given(base=st.sampled_from(["explicit-yang20", "explicit-harris36"]),
       factor=st.one_of(st.sampled_from([1e-3, 1e-6, 1 / 25.4, 25.4, 40.0, 1e-100, 1e-300,
                                         1e-305, 1e-308, 1e-310, 1e-318, 1e-322, 1e-323]),
                        st.floats(1e-323, 45.0)),
       load_factor=st.sampled_from([1.0, 1e-3, 1e3]))
def test_whole_bearing_in_wrong_units(base, factor, load_factor):
    """Every length of [bearing] scaled alike (a file written in metres, inches, ...): the
    geometry stays consistent, so it loads down to lengths that vanish in SI, and the static
    solve meets bearings of any size."""
    scene = base_scene(base)
    for key in BEARING_LENGTHS:
        if key in scene["bearing"]:
            scene["bearing"][key] *= factor
    scene["operating"]["radial_load_N"] = 800.0 * load_factor
    attempt("whole bearing in wrong units", lambda: scene_from_dict(scene), QUOTED_KEYS)


@st.composite
def plausible_scene(draw):
    """Geometry and loads inside every range, mostly consistent: the static solve's input."""
    dw = draw(st.floats(0.5, 60.0))
    bore = draw(st.floats(5.0, 2000.0))
    outer = bore + 2 * dw * draw(st.floats(1.2, 4.0))
    dm = 0.5 * (bore + outer)
    zmax = max(3, int(math.pi / math.asin(min(1.0, dw / dm)))) if dw < dm else 3
    length = max(0.5, dw * draw(st.floats(0.5, 4.0)))
    eff = max(0.5, length * draw(st.floats(0.5, 1.0)))
    bearing = {
        "rollers": draw(st.integers(3, min(zmax + 2, 120))),
        "outer_diameter_mm": outer, "bore_mm": bore, "roller_diameter_mm": dw,
        "roller_length_mm": length, "effective_length_mm": eff,
        "profile": draw(st.sampled_from(["flat", "end-crown", "full-crown", "logarithmic"])),
        "crown_radius_mm": max(0.5, length * draw(st.floats(0.4, 1e3))),
        "radial_clearance_mm": dw * draw(st.floats(-0.02, 0.05)),
    }
    scene = {
        "bearing": bearing,
        "operating": {
            "speed_rpm": draw(st.floats(0.0, 200_000.0)),
            "radial_load_N": draw(st.floats(0.0, 1e8)),
            "tangential_load_N": draw(st.floats(-1e5, 1e5)),
            "moment_Nm": draw(st.floats(-1e3, 1e3)),
            "tangential_moment_Nm": draw(st.floats(-10.0, 10.0)),
        },
        "materials": {"youngs_modulus_GPa": draw(st.floats(1.5, 2000.0)),
                      "poisson_ratio": draw(st.floats(0.0, 0.49)),
                      "density_kg_m3": draw(st.floats(101.0, 30_000.0))},
        "numerics": {"slices": draw(st.integers(1, 40)),
                     "contact_smoothing_nm": draw(st.floats(1e-4, 1.0))},
        "physics": {"tilt": draw(st.booleans())},
    }
    return scene


@fuzz(120)
@given(scene=plausible_scene())
def test_plausible_scenes_solve_or_fail_cleanly(scene):
    attempt("plausible scenes (static solve)", lambda: scene_from_dict(scene), QUOTED_KEYS)


override_keys = st.one_of(
    st.sampled_from(LEAF_KEYS),
    st.sampled_from(list(_SECTIONS) + ["", ".", "..", "bearing.", ".rollers", "bearing..rollers",
                                       "bearing.rollers.x", "title.x", "Bearing.rollers",
                                       "bearing.rollers ", " bearing.rollers", "x" * 500]),
    st.builds(lambda a, b: f"{a}.{b}", st.text(max_size=10), st.text(max_size=10)),
    st.text(alphabet="abcdefghilmnoprstu_.", max_size=30),
    st.integers(), st.none(), st.tuples(st.text(max_size=3)),
)


@fuzz(400)
@given(base=st.sampled_from(sorted(BASES)),
       overrides=st.lists(st.tuples(override_keys, python_values), min_size=1, max_size=4))
def test_random_dotted_overrides(base, overrides):
    ov = dict(overrides)
    # The first unknown key stops the overrides; it must be named (a string as written).
    unknown = [k for k in ov if k not in LEAF_KEYS]
    if unknown:
        first = unknown[0]
        if isinstance(first, str):  # as typed; more than 100 characters cut to its beginning
            keys = (f"'{first}'" if len(first) <= 100 else f"'{first[:90]}",)
        else:
            keys = (repr(first),)
    else:
        rejected = [k for k, v in ov.items() if field_rejects(k, v)]
        keys = tuple(f"'{k}" for k in rejected) or QUOTED_KEYS
    attempt("random dotted overrides", lambda: scene_from_dict(base_scene(base), ov), keys)


# --------------------------------------------------------------------------------------------
# Deep nesting (RecursionError territory)
# --------------------------------------------------------------------------------------------
def nested_list(depth: int):
    v: object = 1.0
    for _ in range(depth):
        v = [v]
    return v


def nested_dict(depth: int):
    v: object = 1.0
    for _ in range(depth):
        v = {"a": v}
    return v


def nested_toml(depth: int, form: str, where: str) -> str:
    sec, _, name = where.partition(".")
    if form == "array":
        return f"[{sec}]\n{name} = {'[' * depth}1.0{']' * depth}\n"
    if form == "inline-table":
        return f"[{sec}]\n{name} = {'{a = ' * depth}1.0{'}' * depth}\n"
    if form == "dotted-key":
        return f"[{sec}]\n{name}{'.a' * depth} = 1.0\n"
    return f"[{sec}.{name}{'.a' * depth}]\nb = 1.0\n"  # a header table


DEPTHS = st.one_of(st.integers(1, 40), st.sampled_from([100, 250, 333, 500, 999, 1000, 1001,
                                                        2000, 5000]))
NEST_WHERE = ["cage.friction", "operating.speed_rpm", "output.variables", "bearing.preset",
              "numerics.slices", "bearing.rollerz", "extra.deep"]


@fuzz(80)
@given(depth=DEPTHS, form=st.sampled_from(["array", "inline-table", "dotted-key", "header"]),
       where=st.sampled_from(NEST_WHERE), route=st.sampled_from(["file", "dict", "override"]))
def test_deeply_nested_tables_and_arrays(depth, form, where, route):
    base = {"bearing": {"preset": "yang20"}}
    sec, _, name = where.partition(".")
    if sec == "extra":
        named = (f"'{sec}'",)
    else:
        named = (f"'{where}",) if name in _SECTIONS[sec].model_fields else (f"'{where}'",)
    if route == "file":
        text = ("" if sec == "bearing" else "[bearing]\npreset = 'yang20'\n")
        text += nested_toml(depth, form, where)
        if where == "bearing.rollerz":
            text += "[bearing]\npreset = 'yang20'\n" if form == "header" else "preset = 'yang20'\n"
        p = write("nested.toml", text)
        # A file tomllib cannot read is a file-level problem ("scene file ..."); anything it
        # reads is reported under the key.
        attempt("deep nesting", lambda: load_scene(p), named + ("scene file",))
        return
    value = nested_list(depth) if form == "array" else nested_dict(depth)
    if route == "dict":
        data = base_scene("yang20")
        data.setdefault(sec, {})[name] = value
        attempt("deep nesting", lambda: scene_from_dict(data), named)
    else:
        attempt("deep nesting", lambda: scene_from_dict(base, {where: value}),
                named + (f"'{where}'",))


# --------------------------------------------------------------------------------------------
# load_scene: files
# --------------------------------------------------------------------------------------------
BYTES_EXAMPLES = [b"", b"\n", b"\xef\xbb\xbf", b"\xef\xbb\xbf[bearing]\npreset = 'yang20'\n",
                  b"\xff\xfe[\x00b\x00", b"\x00", b"[bearing]\npreset = '\xc3\x28'\n",
                  "[bearing]\npreset = 'yang20'\n".encode("utf-16"), b"\x80" * 10,
                  b"title = \"\\ud800\"", b"[bearing]\r\npreset = 'yang20'\r\n"]


@fuzz(250)
@given(content=st.one_of(st.sampled_from(BYTES_EXAMPLES), st.binary(max_size=200),
                         st.text(max_size=200).map(lambda t: t.encode("utf-8")),
                         st.text(max_size=100).map(lambda t: t.encode("latin-1", "replace"))))
def test_random_bytes_files(content):
    p = write("bytes.toml", content)
    attempt("random bytes files", lambda: load_scene(p))


def toml_document(data: dict) -> str:
    return tomli_w.dumps(data)


@st.composite
def toml_scene_documents(draw):
    """A TOML scene built from valid keys, unknown keys and values of every TOML type."""
    doc: dict = {}
    if draw(st.booleans()):
        doc["title"] = draw(toml_values)
    for sec in draw(st.lists(st.sampled_from(list(_SECTIONS) + ["extra", "Bearing"]),
                             max_size=4, unique=True)):
        fields = list(_SECTIONS[sec].model_fields) if sec in _SECTIONS else ["x"]
        names = draw(st.lists(st.sampled_from(fields + ["unknown_key"]), max_size=4,
                              unique=True))
        doc[sec] = {n: draw(st.one_of(toml_values, extreme_number(f"{sec}.{n}")
                                      if f"{sec}.{n}" in NUMERIC_KEYS else toml_values))
                    for n in names}
    if draw(st.booleans()):
        doc.setdefault("bearing", {})["preset"] = draw(st.sampled_from(["yang20", "harris36"]))
    return doc


@fuzz(300)
@given(doc=toml_scene_documents())
def test_random_toml_scene_files(doc):
    try:
        text = toml_document(doc)
    except (TypeError, ValueError):  # tomli_w cannot write it (e.g. a 5000-digit integer)
        return
    p = write("doc.toml", text)
    attempt("random TOML documents", lambda: load_scene(p), doc_names(doc))


def doc_names(doc: dict) -> list[str]:
    """Every way a message may name a key of ``doc`` (or a required one it lacks)."""
    names = QUOTED_KEYS + ["scene file"]
    for sec, body in doc.items():
        names.append(f"'{sec}")
        if isinstance(body, dict):
            names += [f"'{sec}.{k}" for k in body]
    return names


TOML_CHARS = "[]{}=\"'.,\n#0123456789e+-_ :tfnaiTZ\\"


@fuzz(250)
@given(case=st.sampled_from(["yang20_baseline", "harris36_static"]),
       edits=st.lists(st.tuples(st.integers(0, 10_000), st.sampled_from(["ins", "del", "rep"]),
                                st.text(alphabet=TOML_CHARS, min_size=1, max_size=3)),
                      min_size=1, max_size=5))
def test_mutated_case_files(case, edits):
    from bearingdae.scene import resolve_case

    text = resolve_case(case).read_text()
    for pos, op, chunk in edits:
        i = pos % (len(text) + 1)
        if op == "ins":
            text = text[:i] + chunk + text[i:]
        elif op == "del":
            text = text[:i] + text[i + len(chunk):]
        else:
            text = text[:i] + chunk + text[i + len(chunk):]
    p = write("mutated.toml", text)
    attempt("mutated case files", lambda: load_scene(p))


@fuzz(60)
@given(name=st.one_of(st.text(max_size=40), st.sampled_from(
    ["", ".", "/", "x" * 300, "a\x00b", "yang20", "yang20_baseline.toml", "extreme", "cases",
     "../cases/yang20_baseline", "\udcff.toml", "y" * 5000])))
def test_scene_paths_and_case_names(name):
    attempt("paths and case names", lambda: load_scene(name))


def test_empty_file_and_missing_sections(tmp_path):
    p = tmp_path / "empty.toml"
    p.write_text("")
    with pytest.raises(SceneError, match="bearing.preset"):
        load_scene(p)
    p.write_text("[operating]\nradial_load_N = 10.0\n")
    with pytest.raises(SceneError, match="bearing.roller_diameter_mm"):
        load_scene(p)
    COUNTS["explicit files", "SceneError"] += 2


def test_metres_in_a_millimetre_key_is_named_with_the_fix():
    """roller_diameter_mm = 0.004 (4 mm written in metres) loaded while in range; now the range
    starts at 0.5 mm and the message suggests the value in mm."""
    for extra in ({}, {"radial_clearance_mm": 0.0}):
        with pytest.raises(SceneError) as e:
            scene_from_dict({"bearing": {"preset": "yang20", "roller_diameter_mm": 0.004,
                                         **extra}})
        assert ("'bearing.roller_diameter_mm' = 0.004: outside the allowed range [0.5, 1000]. "
                "The key is in mm: if 0.004 is in m, write 4.") in str(e.value), str(e.value)
        COUNTS["explicit cases", "SceneError"] += 1


# Crashes found by this file, now SceneErrors naming key, value and range.
REGRESSIONS = [
    ({"bearing": {"preset": ["yang20"]}}, None, "'bearing.preset'"),  # unhashable preset
    ({"bearing": {"preset": {}}}, None, "'bearing.preset'"),
    ({"bearing": {"preset": "yang20"}, 1: 2}, None, "'1'"),  # non-string section name
    ({"bearing": {"preset": "yang20"}}, {1: 2}, "override key 1"),  # non-string override key
    ({"bearing": {"preset": "yang20"}, "operating": {"radial_load_N": 10**5000}}, None,
     "'operating.radial_load_N' = <integer of about 5001 digits>"),  # repr() > 4300 digits
    ({"bearing": {"preset": "yang20"}, "cage": {"friction": nested_list(5000)}}, None,
     "'cage.friction'"),  # RecursionError in deepcopy / repr
    ({"bearing": {"preset": "yang20", "roller_diameter_mm": 5e-324,
                  "radial_clearance_mm": 0.0}}, None,
     "'bearing.roller_diameter_mm' = 5e-324: outside the allowed range [0.5, 1000]"),  # 0 m:
    # ZeroDivisionError in physics; first an underflow check, now the key's range
    ({"bearing": {"preset": "yang20", "roller_length_mm": 1e-320,
                  "effective_length_mm": 1e-320}}, None,
     "'bearing.roller_length_mm' = 1e-320"),  # LinAlgError in the static Newton
    ({"bearing": {"preset": "yang20"}, "title": "bad \udcff"}, None, "'title'"),  # NetCDF
]


@pytest.mark.parametrize("data, overrides, fragment", REGRESSIONS)
def test_found_crashes_are_scene_errors(data, overrides, fragment):
    with pytest.raises(SceneError) as e:
        scene_from_dict(data, overrides)
    assert fragment in str(e.value), str(e.value)
    COUNTS["explicit regressions", "SceneError"] += 1


@pytest.mark.parametrize("text, fragment", [
    ("[bearing]\nrollers = 1" + "0" * 5000 + "\n", "scene file"),  # tomllib: int > 4300 digits
    ("[cage]\nfriction = " + "[" * 3000 + "]" * 3000 + "\n", "too deeply"),  # RecursionError
    ("[cage]\nfriction = " + "{a=" * 3000 + "1" + "}" * 3000 + "\n", "too deeply"),
])
def test_found_file_crashes_are_scene_errors(tmp_path, text, fragment):
    p = tmp_path / "s.toml"
    p.write_text(text)
    with pytest.raises(SceneError, match=fragment):
        load_scene(p)
    COUNTS["explicit regressions", "SceneError"] += 1


# --------------------------------------------------------------------------------------------
# CLI: bearingdae static FILE [--set KEY=VALUE ...]
# --------------------------------------------------------------------------------------------
set_values = st.one_of(
    st.text(max_size=12),
    st.sampled_from(["nan", "inf", "-inf", "-0.0", "1e308", "5e-324", "1" + "0" * 400,
                     "1" + "0" * 5000, "[" * 2000 + "]" * 2000, "true", "[1, 2]",
                     "{times_s = [0.0, 0.1], values_rpm = [0.0, 1000.0]}", "'flat'", "flat",
                     "1\n[bearing]\nrollers = 3", "\udcff", "0.004", "20", "20.0", "-1", ""]),
    st.floats().map(repr), st.integers().map(str),
)
set_pairs = st.tuples(st.one_of(st.sampled_from(LEAF_KEYS), override_keys.filter(
    lambda k: isinstance(k, str))), set_values).map(lambda kv: f"{kv[0]}={kv[1]}")
cli_files = st.one_of(
    st.sampled_from(["yang20_baseline", "harris36_static"]),
    st.binary(max_size=120),
    toml_scene_documents(),
    plausible_scene(),
)


@fuzz(120)
@given(content=cli_files, pairs=st.lists(st.one_of(set_pairs, st.text(max_size=10)),
                                         max_size=3))
def test_cli_static_exit_status_and_message(content, pairs):
    if isinstance(content, str):
        case = content
    else:
        if isinstance(content, dict):
            try:
                content = toml_document(content)
            except (TypeError, ValueError):
                return
        case = str(write("cli.toml", content))
    out = SCRATCH / "cli_static.nc"
    out.unlink(missing_ok=True)
    rc, stdout, stderr = run_cli(["static", case, "-o", str(out), *[f"--set={p}" for p in pairs]])
    assert rc in (0, 1, 2), rc
    assert "Traceback" not in stderr and "Traceback" not in stdout
    if rc == 0:
        assert out.exists()
        assert all(line.startswith("bearingdae: warning: ") for line in stderr.splitlines()), \
            stderr
        COUNTS["CLI static", "exit 0 (solved, file written)"] += 1
    else:
        msg = stderr.strip()
        assert msg.startswith("bearingdae: "), stderr
        assert "\n\n" not in msg, f"more than one paragraph:\n{stderr}"
        assert not out.exists()
        kind = " (solver failure)" if rc == 1 else " (input error)"
        COUNTS["CLI static", f"exit {rc}{kind}"] += 1


CLI_REGRESSIONS = [
    # (--set pairs, exit status, fragment of stderr)
    (["cage.friction=" + "[" * 3000 + "]" * 3000], 2, "'cage.friction'"),  # RecursionError
    (["operating.radial_load_N=1" + "0" * 5000], 2, "'operating.radial_load_N'"),  # ValueError
    (["operating.radial_load_N=1\n[bearing]\nrollers = 3"], 2, "'operating.radial_load_N'"),
    (["numerics.static_max_iterations=1"], 1, "static solver failure"),  # RuntimeError traceback
    (["title=caf\udce9"], 2, "'title'"),  # non-UTF-8 argv (surrogateescape): NetCDF write failed
]


@pytest.mark.parametrize("pairs, status, fragment", CLI_REGRESSIONS)
def test_found_cli_crashes(tmp_path, pairs, status, fragment):
    out = tmp_path / "s.nc"
    rc, _, stderr = run_cli(["static", "yang20_baseline", "-o", str(out),
                             *[f"--set={p}" for p in pairs]])
    assert rc == status and fragment in stderr and "Traceback" not in stderr, stderr
    assert not out.exists()
    COUNTS["explicit regressions", "SceneError"] += 1


# --------------------------------------------------------------------------------------------
# Summary
# --------------------------------------------------------------------------------------------
def test_zz_fuzz_summary():
    """Cases tried per strategy and outcome (visible with ``pytest -s``)."""
    if not COUNTS:
        pytest.skip("no fuzz test ran in this session")
    per: dict[str, collections.Counter] = collections.defaultdict(collections.Counter)
    for (strategy, outcome), n in COUNTS.items():
        per[strategy][outcome] += n
    print("\n\nscene fuzzing: cases per strategy (outcome: count)")
    for strategy, outcomes in per.items():
        tried = outcomes["loaded"] + outcomes["SceneError"] if strategy != "CLI static" else \
            sum(outcomes.values())
        detail = ", ".join(f"{o}: {n}" for o, n in sorted(outcomes.items()))
        print(f"  {strategy:34s} {tried:5d} cases  ({detail})")
    total = sum(n for (s, o), n in COUNTS.items() if o in ("loaded", "SceneError")
                or s == "CLI static")
    print(f"  {'total':34s} {total:5d} cases")
    print(f"  cases per base scene: {dict(BASES_DRAWN)}")
    assert total > 0
    for strategy, outcomes in per.items():  # every scene that loaded was round-tripped
        assert outcomes["stored TOML loads back equal"] == outcomes["loaded"], strategy
    if sum(BASES_DRAWN.values()) >= 200:  # the base-drawing strategies ran: each base drawn
        assert set(BASES_DRAWN) == set(BASES) and min(BASES_DRAWN.values()) >= 5, BASES_DRAWN
