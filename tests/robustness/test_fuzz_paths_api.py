"""Property-based fuzzing of paths and of the Python API's arguments.

* **Output paths that alias an input**: the scene, sweep or plotted file reached again as the
  output under another name (``./x``, absolute, ``d/../x``, a symlink, a chain of symlinks, a
  hard link), and outputs that collide with each other (``run -o x.png``: the overview PNG).
  Refused before computing: exit 2, one line naming both, the input's bytes unchanged.
* **Non-regular and oversized inputs**: a FIFO, ``/dev/zero``, ``/dev/null``, a directory, a
  symlink to a FIFO, a dangling symlink, a file over 1 MiB, handed to every command that reads
  one. Exit 2 with one line, nothing read (a FIFO would block, ``/dev/zero`` never ends).
* **Long inputs and names**: values, keys and paths of up to 100 000 characters are echoed cut
  to ~100 characters; legal output names of 225-255 bytes are written.
* **API argument types**: every entry point and option class with arbitrary Python values:
  either accepted or a TypeError/ValueError naming the argument; NewmarkOptions accepts a value
  exactly when the scene key it shares accepts it.

Deterministic (``derandomize=True``); ``pytest -s`` prints the cases per surface.
"""

from __future__ import annotations

import collections
import hashlib
import os
import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from hypothesis import given
from hypothesis import strategies as st

from bearingdae import (IDA, Checkpoint, NewmarkOptions, SceneError, ScipyPeer, load_scene, save,
                        scene_from_dict, simulate, solve_static)
from bearingdae.analysis.summary import summary
from bearingdae.studies.sweep import load_sweep, run_sweep
from fuzzing import fuzz, run_cli

ROOT = Path(__file__).resolve().parents[2]
SHORT = ["--set", "numerics.warmup_cage_revolutions=0", "--set", "numerics.cage_revolutions=0.05",
         "--set", "numerics.samples_per_cage_revolution=100"]
COUNTS: collections.Counter = collections.Counter()


def one_error_line(rc: int, stdout: str, stderr: str) -> str:
    """The message of a refusal: one line, or a scene validation's paragraph (its first line
    and one ``  - KEY = VALUE: ...`` line per invalid key); returned joined."""
    assert rc == 2, (rc, stderr)
    assert "Traceback" not in stdout + stderr
    lines = stderr.strip().splitlines()
    assert lines[0].startswith("bearingdae: error: "), stderr
    assert all(ln.startswith("  - ") for ln in lines[1:]), stderr
    return " ".join(lines)


def digest(p: Path) -> str:
    return hashlib.sha256(p.read_bytes()).hexdigest()


@pytest.fixture(scope="module")
def place(tmp_path_factory):
    d = tmp_path_factory.mktemp("paths")
    scene = (ROOT / "cases" / "yang20_baseline.toml").read_bytes()
    (d / "scene.toml").write_bytes(scene)
    (d / "scene.png").write_bytes(scene)  # a scene whose name is its run's PNG name
    (d / "sweep.toml").write_text('base = "scene.toml"\n[axes]\n"operating.speed_rpm" = '
                                  '[2000, 4000]\n')
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        save(simulate(load_scene(d / "scene.toml", {
            "numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 0.05})),
            d / "run.nc")
    (d / "sub").mkdir()
    return d


# --------------------------------------------------------------------------------------------
# Output paths that alias an input
# --------------------------------------------------------------------------------------------
def alias(place: Path, target: str, how: str, n: int) -> Path:
    """Another name of ``place / target``."""
    t = place / target
    if how == "as given":
        return t
    if how == "relative ./":
        return Path(os.path.relpath(t)) if n % 2 else Path(os.curdir) / os.path.relpath(t)
    if how == "through ..":
        return place / "sub" / ".." / target
    link = place / f"alias{n}{'.nc' if n % 2 else '.png'}"
    if link.exists() or link.is_symlink():
        link.unlink()
    if how == "symlink":
        link.symlink_to(t)
    elif how == "symlink chain":
        mid = place / f"mid{n}"
        if mid.exists() or mid.is_symlink():
            mid.unlink()
        mid.symlink_to(t)
        link.symlink_to(mid)
    elif how == "hard link":
        os.link(t, link)
    return link


ALIASES = ["as given", "relative ./", "through ..", "symlink", "symlink chain", "hard link"]


@fuzz(60)
@given(command=st.sampled_from(["static", "run", "sweep", "plot", "run --resume"]),
       how=st.sampled_from(ALIASES), n=st.integers(0, 9))
def test_output_that_aliases_an_input_is_refused(place, command, how, n):
    target = {"static": "scene.toml", "run": "scene.toml", "run --resume": "scene.toml",
              "sweep": "sweep.toml", "plot": "run.nc"}[command]
    inputs = [place / "scene.toml", place / "sweep.toml", place / "run.nc"]
    before = [digest(p) for p in inputs]
    out = alias(place, target, how, n)
    args = {"static": ["static", str(place / "scene.toml")],
            "run": ["run", str(place / "scene.toml"), "--no-progress", *SHORT],
            "run --resume": ["run", str(place / "scene.toml"), "--resume", "--no-progress"],
            "sweep": ["sweep", str(place / "sweep.toml"), "--scheduler", "synchronous"],
            "plot": ["plot", str(place / "run.nc"), "--figure", "12"]}[command]
    line = one_error_line(*run_cli([*args, "-o", str(out)]))
    assert " is the " in line and "give another output name" in line, line
    assert [digest(p) for p in inputs] == before
    COUNTS["output aliases an input", "exit 2, input intact"] += 1


@pytest.mark.parametrize("args, fragment", [
    (["run", "scene.png", "--no-progress"], "overview PNG"),  # x.png -> x.nc + x.png = the scene
    (["run", "scene.toml", "-o", "same.png", "--no-progress"], "would both be"),
    (["static", "scene.toml", "-o", "scene.toml.checkpoint.npz"], None),  # not an alias: works
])
def test_outputs_colliding_with_the_scene_or_each_other(place, args, fragment, monkeypatch):
    monkeypatch.chdir(place)
    before = digest(place / "scene.png")
    rc, out, err = run_cli(args + SHORT if args[0] == "run" else args)
    if fragment is None:
        assert rc == 0, err
    else:
        assert fragment in one_error_line(rc, out, err)
    assert digest(place / "scene.png") == before
    COUNTS["output aliases an input", f"exit {rc}, input intact"] += 1


# --------------------------------------------------------------------------------------------
# Non-regular and oversized inputs
# --------------------------------------------------------------------------------------------
def special(place: Path, kind: str) -> Path:
    p = place / f"special-{kind.replace(' ', '_')}.toml"
    if p.is_dir() and not p.is_symlink():
        shutil.rmtree(p)
    elif os.path.lexists(p):
        p.unlink()
    if kind == "FIFO":
        os.mkfifo(p)
    elif kind == "symlink to a FIFO":
        fifo = special(place, "FIFO")
        p.symlink_to(fifo)
    elif kind == "dangling symlink":
        p.symlink_to(place / "nowhere")
    elif kind == "directory":
        p.mkdir()
    elif kind == "over 1 MiB":
        with open(p, "wb") as fh:
            fh.write(b"# " + b"x" * 100 + b"\n")
            fh.truncate((1 << 20) + 1)  # sparse: a 1 MiB + 1 byte file, nothing to write
    elif kind in ("/dev/zero", "/dev/null", "/dev/urandom"):
        return Path(kind)
    return p


KINDS = ["FIFO", "symlink to a FIFO", "dangling symlink", "directory", "over 1 MiB",
         "/dev/zero", "/dev/null", "/dev/urandom"]


@fuzz(50)
@given(kind=st.sampled_from(KINDS),
       command=st.sampled_from(["static", "run", "sweep", "plot", "cases --copy", "skidmap"]))
def test_non_regular_and_oversized_inputs(place, kind, command):
    p = special(place, kind)
    out = place / "never.nc"
    args = {"static": ["static", str(p), "-o", str(out)],
            "run": ["run", str(p), "-o", str(out), "--no-progress"],
            "sweep": ["sweep", str(p), "-o", str(out), "--scheduler", "synchronous"],
            "plot": ["plot", str(p), "-o", str(place / "never.png")],
            "cases --copy": ["cases", "--copy", str(p), str(place / "never.toml")],
            "skidmap": ["skidmap", str(p), "--speeds", "1000", "2000", "--loads", "100", "200",
                        "-o", str(out), "--scheduler", "synchronous"]}[command]
    line = one_error_line(*run_cli(args))
    if kind not in ("dangling symlink",) and command != "plot":
        assert any(w in line for w in ("FIFO", "device", "directory", "1 MiB")), line
    assert not out.exists() and not (place / "never.toml").exists()
    COUNTS["non-regular or oversized input", "exit 2"] += 1


# --------------------------------------------------------------------------------------------
# Long inputs are echoed cut; long legal output names work
# --------------------------------------------------------------------------------------------
LONG = st.sampled_from([1_000, 5_000, 100_000]).flatmap(
    lambda n: st.sampled_from(["9", "x", "[", "é", "k."]).map(lambda c: (c * n)[:n]))


@fuzz(40)
@given(text=LONG, where=st.sampled_from(["value", "key", "pair", "path", "sweep base",
                                         "figure"]))
def test_long_inputs_are_echoed_cut(place, text, where):
    args = {"value": ["static", "--set", f"numerics.slices={text}"],
            "key": ["static", "--set", f"numerics.{text}=3"],
            "pair": ["static", "--set", text],
            "path": ["static", text],
            "sweep base": ["sweep", str(_sweep_with_base(place, text))],
            "figure": ["plot", str(place / "run.nc"), "--figure", text]}[where]
    line = one_error_line(*run_cli(args + ["-o", str(place / "never.nc")]))
    assert len(line) < 1200, len(line)
    assert text[:150] not in line  # never the whole of a long input
    COUNTS["inputs of 1 000-100 000 characters", "exit 2, echo cut"] += 1


def _sweep_with_base(place: Path, base: str) -> Path:
    p = place / "long_base.toml"
    p.write_text(f'base = "{base}"\n' if '"' not in base else "base = 1\n")
    return p


@pytest.mark.parametrize("length", [200, 225, 240, 255])
@pytest.mark.parametrize("command", ["static", "run"])
def test_legal_long_output_names_are_written(tmp_path, length, command):
    out = tmp_path / ("r" * (length - 3) + ".nc")
    args = [command, "-o", str(out)] + (["--no-progress", *SHORT] if command == "run" else [])
    rc, stdout, err = run_cli(args)
    assert rc == 0, err
    assert out.exists() and xr.open_dataset(out).close() is None
    if command == "run":  # the overview PNG beside it, its name shortened if it must be
        assert [p for p in tmp_path.iterdir() if p.suffix == ".png"]
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".part")]
    COUNTS["output names of 200-255 bytes", "exit 0, written"] += 1


# --------------------------------------------------------------------------------------------
# API argument types
# --------------------------------------------------------------------------------------------
VALUES = st.one_of(
    st.none(), st.booleans(), st.integers(-10**6, 10**6), st.floats(allow_nan=True),
    st.text(max_size=8), st.binary(max_size=4), st.lists(st.integers(), max_size=3),
    st.dictionaries(st.text(max_size=3), st.integers(), max_size=2),
    st.sampled_from([np.float64(1e-6), np.int64(3), np.array([1.0, 2.0]), np.nan, object(),
                     Path("yang20_baseline"), 10**400, -0.0, 5e-324, 1e308]))


def api_case(name: str, call, argument: str) -> None:
    try:
        call()
    except (TypeError, ValueError) as exc:
        assert argument in str(exc), (argument, str(exc))
        assert len(str(exc)) < 1000
        COUNTS["API argument types", f"{type(exc).__name__} naming the argument"] += 1
        return
    COUNTS["API argument types", "accepted"] += 1


@pytest.fixture(scope="module")
def scene():
    return load_scene("yang20_baseline")


@fuzz(150)
@given(entry=st.sampled_from(["simulate scene", "simulate progress", "simulate checkpoint",
                              "solve_static scene", "solve_static z0", "load_scene path",
                              "load_scene overrides", "scene_from_dict", "save ds", "save path",
                              "IDA linsolver", "IDA suppress_alg", "IDA delta_cj_lsetup",
                              "ScipyPeer method", "ScipyPeer time_limit_s",
                              "Checkpoint every_samples", "load_sweep path",
                              "run_sweep sweep", "summary ds"]),
       value=VALUES)
def test_api_argument_types(scene, tmp_path_factory, entry, value):
    if entry in ("simulate progress", "simulate checkpoint") and (
            isinstance(value, bool) or value is None):
        return  # a valid value: the run itself is not what is fuzzed here
    if entry in ("load_scene path", "save path", "load_sweep path", "run_sweep sweep") \
            and isinstance(value, (str, Path)):
        return  # a valid type: a str or Path is looked up as a case (the scene fuzz's part)
    if entry in ("scene_from_dict", "load_scene overrides") and isinstance(value, dict):
        return  # a valid type: the dict's keys are the scene fuzz's part (SceneError)
    calls = {
        "simulate scene": (lambda: simulate(value), "scene"),
        "simulate progress": (lambda: simulate(scene, progress=value), "progress"),
        "simulate checkpoint": (lambda: simulate(scene, checkpoint=value), "checkpoint"),
        "solve_static scene": (lambda: solve_static(value), "scene"),
        "solve_static z0": (lambda: solve_static(scene, z0=value), "z0"),
        "load_scene path": (lambda: load_scene(value), "path"),
        "load_scene overrides": (lambda: load_scene("yang20_baseline", overrides=value),
                                 "overrides"),
        "scene_from_dict": (lambda: scene_from_dict(value), "data"),
        "save ds": (lambda: save(value, tmp_path_factory.mktemp("s") / "x.nc"), "ds"),
        "save path": (lambda: save(xr.Dataset(), value), "path"),
        "IDA linsolver": (lambda: IDA(linsolver=value), "linsolver"),
        "IDA suppress_alg": (lambda: IDA(suppress_alg=value), "suppress_alg"),
        "IDA delta_cj_lsetup": (lambda: IDA(delta_cj_lsetup=value), "delta_cj_lsetup"),
        "ScipyPeer method": (lambda: ScipyPeer(method=value), "method"),
        "ScipyPeer time_limit_s": (lambda: ScipyPeer(time_limit_s=value), "time_limit_s"),
        "Checkpoint every_samples": (lambda: Checkpoint("x.npz", every_samples=value),
                                     "every_samples"),
        "load_sweep path": (lambda: load_sweep(value), "path"),
        "run_sweep sweep": (lambda: run_sweep(value, tmp_path_factory.mktemp("w") / "s.nc"),
                            "sweep"),
        "summary ds": (lambda: summary(value), "ds"),
    }
    call, argument = calls[entry]
    if entry in ("simulate scene", "solve_static scene", "save ds", "simulate progress",
                 "simulate checkpoint", "scene_from_dict", "load_sweep path",
                 "run_sweep sweep", "summary ds"):
        with pytest.raises((TypeError, ValueError, SceneError)):  # never a valid value here
            call()
    api_case(entry, call, argument)


NEWMARK_KEYS = {"step_s": "numerics.newmark_step_s", "beta": "numerics.newmark_beta",
                "gamma": "numerics.newmark_gamma", "alpha": "numerics.hht_alpha",
                "error_estimate": "numerics.newmark_error_estimate"}


@fuzz(150)
@given(field=st.sampled_from(sorted(NEWMARK_KEYS)), value=st.one_of(
    VALUES, st.floats(-1.0, 1.0), st.floats(1e-11, 0.02), st.floats(0.2, 0.55),
    st.floats(0.45, 1.05), st.floats(-0.4, 0.01), st.sampled_from(
        [-1 / 3, 0.5, 1.0, 1e-10, 1e-2, 0.25, 0.0, 2e-6, True, False, "yes"]))
)
def test_newmark_options_accept_what_the_scene_key_accepts(field, value):
    """NewmarkOptions and the scene share each option's range: a value the scene key refuses
    is refused by the option (naming it), and one the scene key accepts is accepted unless
    it breaks β's stability bound for the default γ (checked the same way in both)."""
    key = NEWMARK_KEYS[field]
    try:
        scene_from_dict({"bearing": {"preset": "yang20"},
                         "numerics": {key.split(".")[1]: value}})
        scene_ok = True
    except SceneError:
        scene_ok = False
    try:
        NewmarkOptions(**{field: value})
        options_ok = True
    except (TypeError, ValueError) as exc:
        assert str(exc).startswith("NewmarkOptions.") and field in str(exc), str(exc)
        options_ok = False
    if not scene_ok:
        assert not options_ok, (field, value)
    elif not options_ok:  # in range, but unstable with the default beta/gamma pairing
        assert field in ("beta", "gamma", "alpha"), (field, value)
    COUNTS["NewmarkOptions against the scene key", f"{'accepted' if options_ok else 'refused'}"
           f" (scene {'accepts' if scene_ok else 'refuses'})"] += 1


def test_zz_summary():
    if not COUNTS:
        pytest.skip("no fuzz test ran in this session")
    per: dict[str, collections.Counter] = collections.defaultdict(collections.Counter)
    for (surface, outcome), n in COUNTS.items():
        per[surface][outcome] += n
    print("\n\npath and API fuzzing: cases per surface (outcome: count), 0 tracebacks")
    for surface, outcomes in sorted(per.items()):
        detail = ", ".join(f"{o}: {n}" for o, n in sorted(outcomes.items()))
        print(f"  {surface:40s} {sum(outcomes.values()):4d}  ({detail})")
    print(f"  {'total':40s} {sum(COUNTS.values()):4d}")
    # every alias was refused with the input intact, every long input echoed cut, every long
    # output name written
    assert set(per["output aliases an input"]) <= {"exit 2, input intact",
                                                   "exit 0, input intact"}
    assert set(per["inputs of 1 000-100 000 characters"]) <= {"exit 2, echo cut"}
    # an API argument is accepted or refused naming it; both happen when the surface ran
    api = per["API argument types"]
    assert all(o == "accepted" or o.endswith(" naming the argument") for o in api), api
    if sum(api.values()) >= 100:
        assert api["accepted"] >= 1 and sum(api.values()) - api["accepted"] >= 1, api
    # NewmarkOptions never accepts what the scene key refuses
    assert per["NewmarkOptions against the scene key"]["accepted (scene refuses)"] == 0
    assert sum(COUNTS.values()) >= 1
