"""``bearingdae spectrum RUN.nc --envelope --peaks N`` (cli/spectrum.py): the table on a
synthetic run file whose envelope holds impacts at a known BPFO, on a short healthy run, and
bad input as one-line errors with exit status 2."""

from __future__ import annotations

import warnings

import pytest

from fuzzing import run_cli
from tests.analysis.test_spectrum_peaks import BAND, BPFO, synthetic


@pytest.fixture(scope="module")
def synthetic_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("spectrum") / "impacts.nc"
    synthetic(BPFO).assign_attrs(Conventions="CF-1.10",
                                      bearingdae_version="test").to_netcdf(path)
    return path


def test_the_table_matches_the_strongest_peak_to_bpfo(synthetic_file):
    rc, out, err = run_cli(["spectrum", str(synthetic_file), "--envelope", "--peaks", "3",
                            "--band", f"{BAND[0]},{BAND[1]}", "--fmax", "400"])
    assert rc == 0, err
    lines = out.strip().splitlines()
    assert "envelope spectrum of ring_acceleration (2000-4000 Hz)" in lines[0]
    rows = lines[4:]
    assert len(rows) == 3
    assert rows[0].split()[0] == "1" and rows[0].split()[-2] == "BPFO"
    assert float(rows[0].split()[1]) == pytest.approx(BPFO, abs=1.25)  # one bin


def test_fewer_peaks_than_asked_end_with_the_reason(synthetic_file):
    rc, out, err = run_cli(["spectrum", str(synthetic_file), "--envelope", "--peaks", "50",
                            "--band", f"{BAND[0]},{BAND[1]}", "--fmax", "10.5"])
    assert rc == 0, err
    lines = out.strip().splitlines()
    rows = [r for r in lines[4:-1] if r.split()[0].isdigit()]
    assert 0 < len(rows) < 50
    assert lines[-1].startswith(f"{len(rows)} of the 50 peaks asked for: the spectrum has "
                                f"only {len(rows)} local maxima"), lines[-1]
    assert "0-10.5 Hz, 8 bins of 1.25 Hz" in lines[-1]


@pytest.mark.slow
def test_a_short_healthy_run_prints_its_table(tmp_path):
    from bearingdae import load_scene, save, simulate

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = simulate(load_scene("yang20_baseline", {
            "physics.ring": "dynamic", "numerics.warmup_cage_revolutions": 0.0,
            "numerics.cage_revolutions": 0.3}), progress=False)
    path = save(ds, tmp_path / "run.nc")
    rc, out, err = run_cli(["spectrum", str(path), "--envelope", "--peaks", "4"])
    assert rc == 0, err
    lines = out.strip().splitlines()
    assert "measured (mean cage and roller spin speeds)" in lines[2]
    assert len(lines) == 4 + 4 and all(r.split()[0] == str(i + 1)
                                       for i, r in enumerate(lines[4:]))
    rc, out, _ = run_cli(["spectrum", str(path), "--peaks", "2"])  # the amplitude spectrum
    assert rc == 0 and "amplitude spectrum of ring_acceleration" in out


@pytest.mark.parametrize("argv, words", [
    (["--peaks", "0"], "--peaks 0"), (["--peaks", "-3"], "--peaks -3"),
    (["--peaks", "many"], "--peaks 'many'"), (["--fmax", "-1"], "--fmax -1.0"),
    (["--band", "1,2"], "with --envelope"), (["--envelope", "--band", "9,3"], "--band '9,3'")])
def test_bad_options_are_one_line_errors(synthetic_file, argv, words):
    rc, out, err = run_cli(["spectrum", str(synthetic_file), *argv])
    assert rc == 2 and out == ""
    assert "\n" not in err.strip() and err.startswith("bearingdae: error:") and words in err, err


def test_a_missing_file_or_one_that_is_no_result_is_one_line(tmp_path):
    text = tmp_path / "notes.nc"
    text.write_text("not NetCDF")
    for path, words in ((tmp_path / "missing.nc", "No such file"), (text, "not a readable"),
                        (tmp_path, "directory")):
        rc, out, err = run_cli(["spectrum", str(path), "--envelope", "--peaks", "5"])
        assert rc == 2 and out == "", (path, err)
        assert "\n" not in err.strip() and words in err, err
