"""Property-based fuzzing of the files bearingdae reads back: ``plot`` inputs and ``--resume``
checkpoints.

``plot`` gets real run, static and sweep files that were truncated, bit-flipped, given extra or
renamed dimensions, missing variables, damaged attributes, mislabelled coordinates, or that are
foreign NetCDF files or no NetCDF at all. ``run --resume`` gets checkpoints that were truncated,
bit-flipped, foreign, or whose contents were altered behind a valid fingerprint (times
reversed, shifted, NaN, 1e300, fewer, repeated; states NaN or of another shape; metadata not an
object). The contract for every case:

* exit status 0, 1 or 2 and no traceback; status 2 is exactly one line ``bearingdae: error:``;
* the input file is unchanged (its bytes) unless the command succeeded;
* a resumed run that succeeds has the uninterrupted run's time axis.

Deterministic (``derandomize=True``, fixed numpy seeds). ``pytest -s`` prints the cases per
surface and outcome (``test_zz_summary``); docs/robustness.md quotes them.
"""

from __future__ import annotations

import collections
import hashlib
import json
import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from hypothesis import given
from hypothesis import strategies as st

from bearingdae import Checkpoint, load_scene, save, simulate, solve_static
from fuzzing import fuzz, run_cli

SHORT = {"numerics.warmup_cage_revolutions": 0.0, "numerics.cage_revolutions": 0.05,
         "numerics.samples_per_cage_revolution": 100}
SHORT_ARGS = [a for k, v in SHORT.items() for a in ("--set", f"{k}={v}")]
COUNTS: collections.Counter = collections.Counter()


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else ""


def check_outcome(surface: str, rc: int, stdout: str, stderr: str) -> None:
    """The contract of every case; counts the outcome."""
    assert rc in (0, 1, 2), (rc, stderr)
    assert "Traceback" not in stderr + stdout and "Exception ignored" not in stderr, stderr
    if rc == 2:
        lines = stderr.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("bearingdae: error: "), stderr
        assert len(lines[0]) < 600, lines[0]
    COUNTS[surface, f"exit {rc}"] += 1
    if "cannot make it (" in stderr or "is not a usable bearingdae" in stderr:
        COUNTS[surface, "one line from the last-resort handler"] += 1  # a check to add


# --------------------------------------------------------------------------------------------
# The genuine files, made once
# --------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def genuine(tmp_path_factory):
    d = tmp_path_factory.mktemp("genuine")
    scene = load_scene("yang20_baseline", SHORT)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = save(simulate(scene), d / "run.nc")
        static = save(solve_static(scene), d / "static.nc")
        from bearingdae.studies.sweep import run_sweep

        (d / "s.toml").write_text('title = "fuzz"\nbase = "yang20_baseline"\n[overrides]\n'
                                  + "".join(f'"{k}" = {v}\n' for k, v in SHORT.items())
                                  + '[axes]\n"operating.speed_rpm" = [2000, 4000]\n')
        run_sweep(d / "s.toml", d / "sweep.nc", scheduler="synchronous", progress=False)
        ckpt = Checkpoint(d / "ckpt.npz")
        simulate(scene, checkpoint=ckpt)  # simulate leaves the file (the CLI discards it)
    files = {"run": run, "static": static, "sweep": d / "sweep.nc", "checkpoint": ckpt.path}
    # each file read once: the structural cases mutate a deep copy of its Dataset
    loaded = {k: xr.load_dataset(files[k]) for k in ("run", "static", "sweep")}
    return {k: (p, p.read_bytes()) for k, p in files.items()} | {"dir": d, "loaded": loaded}


def scratch(genuine, name: str) -> Path:
    d = genuine["dir"] / "cases"
    d.mkdir(exist_ok=True)
    p = d / name
    if p.is_dir():
        shutil.rmtree(p)
    for stale in d.glob("*.png"):
        stale.unlink()
    return p


# --------------------------------------------------------------------------------------------
# plot: damaged bytes
# --------------------------------------------------------------------------------------------
FIGURES = st.sampled_from([[], ["--figure", "trends"], ["--figure", "11"], ["--figure", "14"],
                           ["--figure", "all"], ["--select", "speed_rpm=2000"],
                           ["--select", "roller=1"], ["--select", "speed_rpm=3000"]])


def plot_case(genuine, surface: str, data: bytes, args: list[str]) -> None:
    p = scratch(genuine, "f.nc")
    p.write_bytes(data)
    before = digest(p)
    rc, out, err = run_cli(["plot", str(p), *args, "-o", str(p.with_name("fig.png"))])
    check_outcome(surface, rc, out, err)
    assert digest(p) == before, "plot changed its input"


@fuzz(40)
@given(kind=st.sampled_from(["run", "static", "sweep"]), cut=st.floats(0.0, 0.999),
       args=FIGURES)
def test_plot_truncated_files(genuine, kind, cut, args):
    data = genuine[kind][1]
    plot_case(genuine, "plot: truncated", data[: int(cut * len(data))], args)


@fuzz(40)
@given(kind=st.sampled_from(["run", "static", "sweep"]), seed=st.integers(0, 2**32 - 1),
       flips=st.integers(1, 64), where=st.sampled_from(["anywhere", "header", "tail"]),
       args=FIGURES)
def test_plot_bit_flipped_files(genuine, kind, seed, flips, where, args):
    data = bytearray(genuine[kind][1])
    rng = np.random.default_rng(seed)
    lo, hi = {"anywhere": (0, len(data)), "header": (0, min(4096, len(data))),
              "tail": (len(data) // 2, len(data))}[where]
    for i in rng.integers(lo, hi, flips):
        data[i] ^= 1 << int(rng.integers(0, 8))
    plot_case(genuine, "plot: bit-flipped", bytes(data), args)


@fuzz(30)
@given(data=st.one_of(st.binary(max_size=300), st.sampled_from([
    b"", b"CDF\x01", b"\x89HDF\r\n\x1a\n", b"title = 'a scene'\n", b"\x89PNG\r\n\x1a\n"])),
    args=FIGURES)
def test_plot_files_that_are_no_netcdf(genuine, data, args):
    plot_case(genuine, "plot: not NetCDF", data, args)


# --------------------------------------------------------------------------------------------
# plot: well-formed NetCDF of the wrong structure
# --------------------------------------------------------------------------------------------
def mutate(ds: xr.Dataset, how: str, rng: np.random.Generator) -> xr.Dataset:
    names = sorted(ds.data_vars)
    name = names[int(rng.integers(len(names)))]
    if how == "extra dimension":
        ds[name] = ds[name].expand_dims(extra=int(rng.integers(1, 4)),
                                        axis=int(rng.integers(0, ds[name].ndim + 1)))
    elif how == "drop variable":
        ds = ds.drop_vars(name)
    elif how == "transpose":
        if ds[name].ndim > 1:
            ds[name] = ds[name].transpose(*reversed(ds[name].dims))
        else:
            ds = ds.rename_dims({ds[name].dims[0]: "renamed"}) if ds[name].ndim else ds
    elif how == "rename dimension":
        dim = sorted(ds.dims)[int(rng.integers(len(ds.dims)))]
        ds = ds.rename({dim: f"{dim}_x"})
    elif how == "text values":
        ds[name] = ds[name].astype(str)
    elif how == "attributes":
        key = ["Conventions", "bearingdae_version", "sweep_axes", "figures",
               "epicyclic_cage_speed_rad_s", "title"][int(rng.integers(6))]
        value = [None, "", "[", "[{}]", '[{"dim": "nope", "key": "k", "values": [1]}]',
                 "not a number", 7, '{"a": 1}', "[1e999]"][int(rng.integers(9))]
        if value is None:
            ds.attrs.pop(key, None)
        else:
            ds.attrs[key] = value
    elif how == "labels":
        for dim in ("race", "end", "direction", "roller", "slice", "time"):
            if dim in ds.coords:
                values = ds[dim].values.copy()
                ds = ds.assign_coords({dim: values[::-1]})
                break
    elif how == "values":  # NaN, inf, 1e300 in a variable or coordinate
        target = [*names, *[c for c in ("time", "azimuth") if c in ds.coords]]
        v = target[int(rng.integers(len(target)))]
        arr = np.array(ds[v].values, dtype=float) if ds[v].dtype.kind in "fiu" else None
        if arr is not None and arr.size:
            arr.flat[int(rng.integers(arr.size))] = [np.nan, np.inf, 1e300][int(rng.integers(3))]
            ds = ds.assign({v: (ds[v].dims, arr)}) if v in names else \
                ds.assign_coords({v: (ds[v].dims, arr)})
    return ds


MUTATIONS = ["extra dimension", "drop variable", "transpose", "rename dimension", "text values",
             "attributes", "labels", "values"]


@fuzz(80)
@given(kind=st.sampled_from(["run", "static", "sweep"]), how=st.sampled_from(MUTATIONS),
       seed=st.integers(0, 2**32 - 1), args=FIGURES)
def test_plot_structural_damage(genuine, kind, how, seed, args):
    ds = genuine["loaded"][kind].copy(deep=True)  # the file as read, not read again
    try:
        ds = mutate(ds, how, np.random.default_rng(seed))
        p = scratch(genuine, "m.nc")
        ds.to_netcdf(p)
    except (ValueError, TypeError, KeyError):  # a mutation xarray cannot write: not a case
        return
    before = digest(p)
    rc, out, err = run_cli(["plot", str(p), *args, "-o", str(p.with_name("fig.png"))])
    check_outcome(f"plot: structure ({how})", rc, out, err)
    assert digest(p) == before


@fuzz(30)
@given(dims=st.lists(st.sampled_from(["time", "roller", "speed_rpm", "x", "azimuth", "foo"]),
                     min_size=0, max_size=3, unique=True),
       attrs=st.sampled_from([{}, {"Conventions": "CF-1.10"},
                              {"Conventions": "CF-1.10", "bearingdae_version": "0.1.0"},
                              {"Conventions": "CF-1.10", "bearingdae_version": "0.1.0",
                               "sweep_axes": '[{"dim": "speed_rpm", "key": "k", "values": [1]}]'}]),
       args=FIGURES)
def test_plot_foreign_netcdf(genuine, dims, attrs, args):
    shape = tuple(range(2, 2 + len(dims)))
    ds = xr.Dataset({"v": (dims, np.ones(shape)), "cage_speed": (dims, np.zeros(shape))},
                    coords={d: np.arange(n, dtype=float) for d, n in zip(dims, shape)},
                    attrs=attrs)
    p = scratch(genuine, "foreign.nc")
    ds.to_netcdf(p)
    rc, out, err = run_cli(["plot", str(p), *args, "-o", str(p.with_name("fig.png"))])
    check_outcome("plot: foreign NetCDF", rc, out, err)


# --------------------------------------------------------------------------------------------
# run --resume: damaged and inconsistent checkpoints
# --------------------------------------------------------------------------------------------
def resume_case(genuine, surface: str, write) -> None:
    """Put a checkpoint beside OUT (``write(path)``), resume, check the contract; a run that
    succeeds must have the genuine run's time axis."""
    d = scratch(genuine, "resume")
    d.mkdir()
    out = d / "r.nc"
    ckpt = d / "r.nc.checkpoint.npz"
    write(ckpt)
    before = digest(ckpt)
    rc, stdout, stderr = run_cli(["run", "yang20_baseline", "-o", str(out), "--resume",
                                  "--no-progress", "--no-plot", *SHORT_ARGS])
    check_outcome(surface, rc, stdout, stderr)
    if rc == 0:
        with xr.open_dataset(genuine["run"][0]) as ref, xr.open_dataset(out) as got:
            np.testing.assert_allclose(got.time.values, ref.time.values, rtol=0, atol=1e-12)
        COUNTS[surface, "resumed: time axis as the uninterrupted run"] += 1
    else:
        assert digest(ckpt) == before, "a refused checkpoint was changed"
        assert not out.exists()


@fuzz(40)
@given(cut=st.floats(0.0, 0.999), seed=st.integers(0, 2**32 - 1), flips=st.integers(0, 32))
def test_resume_truncated_or_bit_flipped_checkpoints(genuine, cut, seed, flips):
    data = bytearray(genuine["checkpoint"][1])
    rng = np.random.default_rng(seed)
    for i in rng.integers(0, len(data), flips):
        data[i] ^= 1 << int(rng.integers(0, 8))
    if flips == 0:
        data = data[: int(cut * len(data))]
    resume_case(genuine, "resume: truncated / bit-flipped",
                lambda p: p.write_bytes(bytes(data)))


def _prefix(a: dict, keep: int) -> None:
    """The checkpoint ``a`` as an interrupted run's after ``keep`` samples: its samples and
    their interval peaks cut; the window's step maxima (of the whole run) dropped, as a
    checkpoint without step extremes has none."""
    a.update(t=a["t"][:keep], y=a["y"][:keep], yp=a["yp"][:keep])
    if "peaks" in a:
        a["peaks"] = a["peaks"][:keep]
    a.pop("extremes", None)


def _arrays(genuine) -> dict:
    with np.load(genuine["checkpoint"][0], allow_pickle=False) as z:
        return {k: np.array(z[k]) for k in z.files}


EDITS = {
    "times reversed": lambda a: a["t"].__setitem__(slice(None), a["t"][::-1].copy()),
    "times shifted": lambda a: a["t"].__iadd__(1e-4),
    "a time 1e300": lambda a: a["t"].__setitem__(-1, 1e300),
    "a time NaN": lambda a: a["t"].__setitem__(len(a["t"]) // 2, np.nan),
    "times repeated": lambda a: a["t"].__setitem__(1, a["t"][0]),
    "a state NaN": lambda a: a["y"].__setitem__((-1, 0), np.nan),
    "fewer times than states": lambda a: a.update(t=a["t"][:-1]),
    "states of another size": lambda a: a.update(y=a["y"][:, :-1], yp=a["yp"][:, :-1]),
    "integer times": lambda a: a.update(t=np.arange(a["t"].size)),
    "text states": lambda a: a.update(y=a["y"].astype(str)),
    "2-D times": lambda a: a.update(t=a["t"][:, None]),
}
METAS = {
    "metadata a list": lambda m: [m],
    "metadata a number": lambda m: 3,
    "metadata a string": lambda m: "meta",
    "stats a list": lambda m: {**m, "stats": [1, 2]},
    "metadata of another format": lambda m: {**m, "format": 99},
    "no fingerprint": lambda m: {k: v for k, v in m.items() if k != "fingerprint"},
}


@fuzz(60)
@given(edit=st.sampled_from(sorted(EDITS) + sorted(METAS) + ["unchanged", "a prefix only"]),
       keep=st.integers(1, 6))
def test_resume_inconsistent_checkpoint_behind_a_valid_fingerprint(genuine, edit, keep):
    a = _arrays(genuine)
    meta = json.loads(str(a["meta"]))
    if edit in EDITS:
        EDITS[edit](a)
    elif edit in METAS:
        a["meta"] = np.array(json.dumps(METAS[edit](meta)))
    elif edit == "a prefix only":  # a genuine interrupted run: continues from sample `keep`
        _prefix(a, keep)

    def write(p):
        with open(p, "wb") as fh:
            np.savez(fh, **a)

    resume_case(genuine, f"resume: {edit}" if edit in ("unchanged", "a prefix only")
                else "resume: inconsistent contents", write)
    if edit not in ("unchanged", "a prefix only"):
        assert COUNTS["resume: inconsistent contents", "exit 0"] == 0


@pytest.mark.parametrize("keep", [None, 1, 3])
def test_resume_of_a_genuine_checkpoint(genuine, keep):
    """The genuine checkpoint, whole (nothing left to integrate) or cut to its first samples
    (an interrupted run): resumed, with the uninterrupted run's time axis."""
    a = _arrays(genuine)
    if keep:
        _prefix(a, keep)

    def write(p):
        with open(p, "wb") as fh:
            np.savez(fh, **a)

    resume_case(genuine, "resume: genuine (whole or a prefix)", write)
    assert COUNTS["resume: genuine (whole or a prefix)", "exit 0"] >= 1


@fuzz(20)
@given(arrays=st.dictionaries(st.sampled_from(["t", "y", "yp", "meta", "other"]),
                              st.sampled_from([np.zeros(3), np.ones((2, 2)), np.array("x"),
                                               np.array('{"format": 1}'), np.arange(5)]),
                              max_size=5))
def test_resume_foreign_npz(genuine, arrays):
    def write(p):
        with open(p, "wb") as fh:
            np.savez(fh, **arrays)

    resume_case(genuine, "resume: foreign .npz", write)


# --------------------------------------------------------------------------------------------
# Summary
# --------------------------------------------------------------------------------------------
def test_zz_summary():
    """Cases per surface and outcome (``pytest -s``); every case passed the contract."""
    if not COUNTS:
        pytest.skip("no fuzz test ran in this session")
    per: dict[str, collections.Counter] = collections.defaultdict(collections.Counter)
    for (surface, outcome), n in COUNTS.items():
        per[surface][outcome] += n
    print("\n\nresult-file fuzzing: cases per surface (outcome: count), 0 tracebacks")
    for surface, outcomes in sorted(per.items()):
        cases = sum(n for o, n in outcomes.items() if o.startswith("exit"))
        detail = ", ".join(f"{o}: {n}" for o, n in sorted(outcomes.items()))
        print(f"  {surface:44s} {cases:4d}  ({detail})")
    print(f"  {'total':44s} {sum(n for (s, o), n in COUNTS.items() if o.startswith('exit')):4d}")
    for surface, outcomes in per.items():
        exits = {o: n for o, n in outcomes.items() if o.startswith("exit")}
        assert exits and set(exits) <= {"exit 0", "exit 1", "exit 2"}, (surface, outcomes)
        if surface.startswith("resume"):  # every resumed run had the uninterrupted time axis
            assert outcomes["resumed: time axis as the uninterrupted run"] == \
                exits.get("exit 0", 0), (surface, outcomes)
    # a checkpoint altered behind its fingerprint is never resumed; a genuine one always
    assert per["resume: inconsistent contents"]["exit 0"] == 0
    genuine = per["resume: genuine (whole or a prefix)"]
    assert sum(genuine.values()) == 0 or genuine["exit 0"] == 3, genuine
    # the damaged files are refused at least sometimes (the fuzzing reaches the checks)
    refused = sum(n for (s, o), n in COUNTS.items() if o in ("exit 1", "exit 2"))
    assert refused >= 1, dict(COUNTS)
