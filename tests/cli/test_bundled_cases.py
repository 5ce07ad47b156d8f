"""Every bundled case (``cases/**/*.toml``) through the command a user types.

Scenes go through ``bearingdae static`` and ``bearingdae run``, sweep files through
``bearingdae sweep``, each with settings cut down to a few samples (the machinery, not the
physics, is under test here: tests/robustness/test_extreme.py and the validation tests run the
physics). The stability suite calls the Python API; a bundled case that crashed only on the
command line (the zero-speed run's summary) went unnoticed there. Each command must exit 0,
print its summary and write files that read back as the kind they are (results/readers.py);
no traceback. One of them also runs as a process of its own, as the ``bearingdae`` program.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from bearingdae.cli import main
from bearingdae.results.readers import open_result
from bearingdae.scene import bundled_case_dirs
from bearingdae.studies.sweep import is_sweep_file

ROOT = Path(__file__).resolve().parents[2]
CASES = sorted(p for p in (ROOT / "cases").rglob("*.toml"))
SCENES = [p for p in CASES if not is_sweep_file(p)]
#: (test, case) pairs of ~20 s each, run in the slow tier (the CI physics step) to keep the
#: fast tier within its budget
SLOW = {("static", "extreme/flanged_reversed_axial"), ("static", "yang20_nj_axial"),
        ("run", "extreme/cage_whirl_unloaded"),
        ("run", "extreme/edge_loading"), ("run", "extreme/flanged_reversed_axial"),
        ("run", "extreme/harris36_heavy"),
        # a defect scene compiles its own kernels (system/defects.py): minutes on a cold cache
        ("run", "defects/outer_spall"), ("run", "defects/inner_spall"),
        ("run", "defects/outer_waviness"), ("run", "defects/roller_spall"),
        ("run", "extreme/sharp_spall"), ("run", "extreme/sharp_roller_spall")}


def cases_for(test: str) -> list:
    """The scenes, those of :data:`SLOW` for ``test`` marked slow."""
    return [pytest.param(p, marks=pytest.mark.slow)
            if (test, p.relative_to(ROOT / "cases").with_suffix("").as_posix()) in SLOW else p
            for p in SCENES]
SWEEPS = [p for p in CASES if is_sweep_file(p)]
#: a few samples from t = 0: 0.02 cage revolutions at 100 samples per revolution
SHORT = ["--set", "numerics.warmup_cage_revolutions=0", "--set", "numerics.cage_revolutions=0.02",
         "--set", "numerics.samples_per_cage_revolution=100"]
#: the same for the runs of a sweep, with until_steady's warm-up capped at one short block
SHORT_SWEEP = SHORT + ["--set", "numerics.steady_block_cage_revolutions=0.05",
                       "--set", "numerics.max_warmup_cage_revolutions=0.05"]


def name(p: Path) -> str:
    return p.relative_to(ROOT / "cases").with_suffix("").as_posix()


def no_traceback(text: str) -> None:
    assert "Traceback" not in text and "Exception ignored" not in text, text[-3000:]


def test_every_bundled_case_is_covered():
    """The lists above are the bundled cases (the installed ones are the same files)."""
    assert len(CASES) >= 18 and SCENES and SWEEPS
    bundled = {q.relative_to(d).as_posix() for d in bundled_case_dirs() for q in d.rglob("*.toml")}
    assert {p.relative_to(ROOT / "cases").as_posix() for p in CASES} == bundled


@pytest.mark.parametrize("case", cases_for("static"), ids=name)
def test_static_of_every_bundled_scene(case, tmp_path, capsys):
    out = tmp_path / "s.nc"
    status = main(["static", name(case), "-o", str(out)])
    printed, err = capsys.readouterr()
    assert status == 0, err
    no_traceback(err)
    assert "Newton iterations" in printed and f"wrote {out}" in printed
    assert open_result(out, ("static",))[0] == "static"


@pytest.mark.parametrize("case", cases_for("run"), ids=name)
def test_run_of_every_bundled_scene(case, tmp_path, capsys):
    out = tmp_path / "r.nc"
    status = main(["run", name(case), "-o", str(out), "--no-progress", *SHORT])
    printed, err = capsys.readouterr()
    assert status == 0, err
    no_traceback(err)
    assert "wall time" in printed and f"wrote {out}" in printed, printed
    kind, ds = open_result(out, ("run",))
    assert ds.sizes["time"] >= 2
    if "cage_speed" in ds:  # the summary line, "n/a" where the slip is undefined (zero speed)
        assert "mean cage speed" in printed
    if "flange_force" in ds:  # the flange lines, read back from the streamed file
        assert "axial load (flanges)" in printed and "flange friction (mean)" in printed
    assert (tmp_path / "r.png").stat().st_size > 1000  # the overview figure
    assert not (tmp_path / "r.nc.checkpoint.npz").exists()


@pytest.mark.parametrize("sweep", SWEEPS, ids=name)
def test_sweep_of_every_bundled_sweep_file(sweep, tmp_path, capsys):
    out = tmp_path / "w.nc"
    status = main(["sweep", name(sweep), "-o", str(out), "--scheduler", "synchronous",
                   "--no-progress", *SHORT_SWEEP])
    printed, err = capsys.readouterr()
    assert status == 0, err
    no_traceback(err)
    assert f"wrote {out}" in printed
    kind, ds = open_result(out, ("sweep",))
    assert ds.attrs["runs_completed"] == ds.attrs["runs_total"] >= 1


def test_zero_speed_case_as_the_program(tmp_path):
    """The zero-speed case through the installed ``bearingdae`` program's entry, in a process
    of its own: the summary (slip "n/a": no epicyclic speed at standstill), the file, the PNG."""
    out = tmp_path / "zs.nc"
    program = "import sys; from bearingdae.cli.program import main; sys.exit(main())"
    r = subprocess.run([sys.executable, "-c", program, "run", "extreme/zero_speed", "-o",
                        str(out), "--no-progress", *SHORT],
                       capture_output=True, text=True, timeout=600, cwd=tmp_path,
                       env={**os.environ, "PYTHONPATH": str(ROOT), "OMP_NUM_THREADS": "1"})
    no_traceback(r.stderr + r.stdout)
    assert r.returncode == 0, r.stderr
    assert "slip n/a" in r.stdout, r.stdout
    assert out.exists() and (tmp_path / "zs.png").stat().st_size > 1000
