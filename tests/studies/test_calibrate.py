"""Calibrating the inlet film (studies/calibrate.py, ``bearingdae calibrate``).

References: a torque produced by a run at a known film (the film found must come back near it
and its run within 2 % of the torque), and for the search alone a torque law typed here (B&H's
starvation ratio of a fixed flooded film, monotone in the film) whose root is known in closed
form.
"""

from __future__ import annotations

import contextlib
import io
import math
import subprocess
import sys
import tomllib
import warnings

import pytest

from bearingdae import load_scene, simulate
from bearingdae.studies import calibrate as cal
from tests.conftest import make_scene

SHORT = ["numerics.cage_revolutions=0.05", "numerics.warmup_cage_revolutions=0"]
H_M_UM = 0.2  # the flooded film of the typed law


def _typed_torque(scene) -> float:
    """100 N mm times B&H's eq. (44) at S = h_a / 0.2 µm (flooded: 100)."""
    h = scene.lubricant.inlet_film_m
    if h is None:
        return 100.0
    S = h * 1e6 / H_M_UM
    return 100.0 * (S * S + 162.8 * S) / (S * S + 193.1 * S + 1257.0)


def _scene_at(film_um):
    over = {"physics.rolling_resistance": True}
    if film_um is not None:
        over["lubricant.inlet_film_um"] = film_um
    return make_scene(over)


def test_the_search_finds_the_root_of_a_known_law():
    # S = 1 at 0.2 µm: T = 100 (1 + 162.8) / (1 + 193.1 + 1257) = 11.288 N mm
    target = 100.0 * 163.8 / 1451.1
    fit = cal.calibrate_inlet_film(_scene_at, target, torque_of=_typed_torque)
    assert abs(fit.torque_N_mm / target - 1) <= cal.TORQUE_RTOL
    assert fit.film_um == pytest.approx(H_M_UM, rel=0.02)
    assert 3 <= fit.runs == len(fit.trials) <= 12  # the two ends, then Brent's steps
    assert fit.trials[0][0] == cal.FILM_RANGE_UM[0] and fit.trials[1][0] == cal.FILM_RANGE_UM[1]


@pytest.mark.parametrize("target", [0.001, 99.9, 150.0])
def test_a_torque_out_of_reach_is_refused_naming_the_span(target):
    with pytest.raises(ValueError) as exc:
        cal.calibrate_inlet_film(_scene_at, target, torque_of=_typed_torque)
    text = str(exc.value)
    lo, hi = _typed_torque(_scene_at(1e-3)), _typed_torque(_scene_at(1e3))
    assert len(text.splitlines()) == 1 and f"{target:g} N mm" in text
    assert f"[{lo:.4g}, {hi:.4g}] N mm" in text, text


def test_a_scene_without_rolling_resistance_is_refused():
    with pytest.raises(ValueError, match="no rolling resistance"):
        cal.calibrate_inlet_film(lambda f: make_scene(), 10.0, torque_of=_typed_torque)
    with pytest.raises(ValueError, match="greater than 0"):
        cal.calibrate_inlet_film(_scene_at, -1.0, torque_of=_typed_torque)


def _print_warning(message, category, filename, lineno, file=None, line=None):
    sys.stderr.write(warnings.formatwarning(message, category, filename, lineno, line))


def _cli(*args):
    """``bearingdae calibrate ARGS`` in this process (cli.main, the program's exit status;
    a process of its own would cost an interpreter start and the kernels' load, ~3 s of CPU a
    call), stdout and stderr captured, a warning printed to stderr as the program prints it
    (Python's filters of a process started without -W)."""
    from bearingdae.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), \
            warnings.catch_warnings():
        warnings.resetwarnings()
        for category in (DeprecationWarning, PendingDeprecationWarning, ImportWarning,
                         ResourceWarning):
            warnings.simplefilter("ignore", category)
        warnings.showwarning = _print_warning
        status = main(["calibrate", *args])
    return subprocess.CompletedProcess(args, status, out.getvalue(), err.getvalue())


def test_calibrate_recovers_the_film_of_a_run(tmp_path):
    """A short window of the yang20 baseline with B&H's law at a 0.1 µm inlet film gives T;
    ``bearingdae calibrate --friction-torque-Nmm T`` finds a film near 0.1 µm and writes a
    scene whose run is within 2 % of T."""
    sets = [*SHORT, "physics.rolling_resistance=true"]
    over = dict(s.split("=") for s in sets)
    over = {k: float(v) if k.startswith("numerics") else True for k, v in over.items()}

    def torque(film_um):
        extra = {} if film_um is None else {"lubricant.inlet_film_um": film_um}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ds = simulate(load_scene("yang20_baseline", {**over, **extra}), progress=False)
        return cal.catalogue_torque_N_mm(ds)

    target = torque(0.1)
    out = tmp_path / "calibrated.toml"
    args = ["yang20_baseline", "--friction-torque-Nmm", f"{target:.6g}", "-o", str(out)]
    for s in sets:
        args += ["--set", s]
    done = _cli(*args)
    assert done.returncode == 0, done.stderr
    data = tomllib.loads(out.read_text())
    film = data["lubricant"]["inlet_film_um"]
    assert film == pytest.approx(0.1, rel=0.1)
    assert f"inlet film {film:.4g} µm" in done.stdout and " runs" in done.stdout
    again = torque(film)
    assert abs(again / target - 1) <= 0.02
    assert data["physics"]["rolling_resistance"] in (True, "biboulet_houpert")
    # refused in one line, status 2: a torque the film cannot reach, a scene without the law
    done = _cli("yang20_baseline", "--friction-torque-Nmm", "1e6", "-o", str(out),
                *sum((["--set", s] for s in sets), []))
    # (the two runs at the ends of the range are reported as they go: "  run N: ...")
    lines = [ln for ln in done.stderr.splitlines() if ln and not ln.startswith("  run ")]
    assert done.returncode == 2 and len(lines) == 1 and "spans [" in lines[0], done.stderr
    done = _cli("yang20_baseline", "--friction-torque-Nmm", "10", "-o", str(out),
                *sum((["--set", s] for s in SHORT), []))
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 2 and len(lines) == 1 and "no rolling resistance" in lines[0]


def test_the_catalogue_torque_leaves_the_drag_out():
    """Against the sum over the non-drag sources of the recorded friction torque, averaged
    here by hand (trapezoids), and the drag's share separately."""
    import numpy as np

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = simulate(load_scene("yang20_baseline", {
            "numerics.cage_revolutions": 0.05, "numerics.warmup_cage_revolutions": 0.0}),
            progress=False)
    t = ds.time.values
    total = ds.friction_torque_N_m.sum("loss_source").values
    drag = ds.friction_torque_N_m.sel(loss_source=["orbit_drag", "roller_churning",
                                                   "cage_churning"]).sum("loss_source").values
    mean = np.sum(0.5 * (total - drag)[1:] * np.diff(t) + 0.5 * (total - drag)[:-1]
                  * np.diff(t)) / (t[-1] - t[0])
    assert cal.catalogue_torque_N_mm(ds) == pytest.approx(mean * 1e3, rel=1e-12)
    assert math.isfinite(cal.catalogue_torque_N_mm(ds))
