"""Sharp defect edges located by IDA's root finding (``numerics.defect_edges = "locate"``:
system/defect_sides.py, solvers/ida_edges.py, solvers/sundials/roots.py).

References: the edge crossings computed afresh here from the geometry (a contact on the outer
race at the roller's orbit angle θX, on the inner race at θX - ω t (the shaft at constant
speed ω), on a roller at the surface point -φ or π - φ, the arc
length R wrap(angle - centre) against half the defect's length) and from the recorded
trajectory (cubic Hermite interpolation of the recorded angles and speeds between the samples
around each crossing); the smooth ramps' first-order convergence (Richardson: the sharp edge
≈ 2 S(e/2) - S(e), S(e) the outputs with the least ramp e) for the located edge's outputs;
central differences of the residual for the Jacobian with frozen sides.
"""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys
import tomllib

import numpy as np
import pytest

from bearingdae import load_scene, simulate
from bearingdae.physics.defects import EDGE_MIN_M
from bearingdae.physics.geometry import make_geometry
from bearingdae.scene import scene_from_dict
from bearingdae.scene.errors import SceneError

#: the two scenes of the edge study (benchmarks/workprecision.py EDGE_SCENES), short windows
OUTER = ("defects/outer_spall", {"numerics.warmup_cage_revolutions": 0.0,
                                 "numerics.cage_revolutions": 0.2})
INNER = ("defects/inner_spall", {"numerics.warmup_cage_revolutions": 0.0,
                                 "numerics.cage_revolutions": 0.1})
ROLLER = ("extreme/sharp_roller_spall", {"physics.ring": "dynamic",
                                         "ring.support_damping_N_s_m": 600.0,
                                         "numerics.warmup_cage_revolutions": 0.0,
                                         "numerics.cage_revolutions": 0.1})


def _sharp(case, overrides, mode="locate"):
    """The case with every defect's edge sharp (edge_mm = 0) and ``defect_edges = mode``."""
    s = load_scene(case, {**overrides, "numerics.defect_edges": mode})
    data = tomllib.loads(s.to_toml())
    data["defects"] = [{**d, "edge_mm": 0.0} for d in data["defects"]]
    return scene_from_dict(data)


def _located(case, overrides):
    from bearingdae.solvers.ida import IDA

    s = _sharp(case, overrides)
    solver = IDA()
    ds = simulate(s, solver=solver, progress=False)
    return s, ds, solver.last_edge_crossings


def _wrap(a):
    return (a + math.pi) % (2.0 * math.pi) - math.pi


def _hermite(t, T, X, V):
    """Cubic Hermite interpolation of samples X (speeds V) at times T, at t."""
    i = int(np.searchsorted(T, t)) - 1
    h = T[i + 1] - T[i]
    s = (t - T[i]) / h
    return ((2 * s**3 - 3 * s**2 + 1) * X[i] + (s**3 - 2 * s**2 + s) * h * V[i]
            + (-2 * s**3 + 3 * s**2) * X[i + 1] + (s**3 - s**2) * h * V[i + 1])


@pytest.mark.parametrize("case", [OUTER, INNER, ROLLER],
                         ids=["outer spall", "inner spall", "roller spall"])
def test_each_root_is_an_edge_crossing(case):
    """At each located root the contact is at an edge of the defect: | |arc| - l/2 | below
    1 pm (the contact moves ~2 m/s, so within ~1e-12 s of the crossing; IDA's root tolerance
    is ~100 ulp of t), entering where the direction is +1 (inside after, the arc shrinking);
    and the recorded trajectory, interpolated to the root's time, puts the contact there
    too within its interpolation error (10 nm of arc; measured: below 1 nm)."""
    s, ds, crossings = _located(*case)
    d = s.defects[0]
    g = make_geometry(s)
    R = {"outer": g.outer_race_radius_m, "inner": g.inner_race_radius_m,
         "roller": g.roller_radius_m}[d.surface]
    shaft_rad_s = s.operating.speed_rpm * math.pi / 30.0  # (constant: ψ = ω t)
    T = ds.time.values
    assert sum(c[0] <= T[-1] for c in crossings) >= 2
    for t, j, _, p, direction, th, phi in crossings:
        if d.surface == "outer":
            angle, rec = th, (ds.roller_azimuth, ds.orbit_speed)
        elif d.surface == "inner":  # the inner race turns with the shaft
            angle, rec = th - shaft_rad_s * t, (ds.roller_azimuth, ds.orbit_speed)
        else:
            assert j == d.roller
            angle = -phi if p == 0 else math.pi - phi
            rec = (ds.roller_spin_angle_rad, ds.spin_speed)
        arc = R * _wrap(angle - d.angle_rad)
        assert abs(abs(arc) - 0.5 * d.length_m) < 1e-12, (t, arc)
        if t > T[-1]:  # (the ring's taps go on past the last sample: system/taps.py)
            continue
        # entering (+1) where |arc| falls: the arc and its rate (recorded) of opposite signs
        x = _hermite(t, T, rec[0].isel(roller=j).values, rec[1].isel(roller=j).values)
        rate = float(np.interp(t, T, rec[1].isel(roller=j).values))
        rate = {"outer": rate, "inner": rate - shaft_rad_s, "roller": -rate}[d.surface]
        assert (arc * rate < 0) == (direction > 0), (t, arc, rate, direction)
        here = {"outer": x, "inner": x - shaft_rad_s * t,
                "roller": -x if p == 0 else math.pi - x}[d.surface]
        assert abs(R * _wrap(here - d.angle_rad) - arc) < 1e-8, (t, here, angle)


def _headlines(s, healthy):
    from bearingdae.studies.workprecision import edges as ed

    return ed.headline_values(simulate(s, progress=False), healthy)


def test_located_edges_agree_with_the_smooth_limit():
    """The outer spall over 0.2 cage revolution (rtol 1e-6): the located sharp edge's ring
    acceleration RMS and force-drop impulse against the sharp edge extrapolated from the least
    ramp e and e/2 (first order: 2 S(e/2) - S(e)), within a quarter of the smoothing error
    |S(e) - S(e/2)| plus 1e-4 (measured: 0.06 and 0.02 of it); its acceleration signal as far
    from the e/2 ramp's as the least ramp's is, on the other side (first order: twice as far
    from the least ramp's), within 10 %."""
    from bearingdae.studies.workprecision import edges as ed

    smooth = _sharp(*OUTER, mode="smooth")
    healthy = simulate(ed.with_edges(smooth, "none", {}), progress=False)
    half = dataclasses.replace(smooth, defects=tuple(dataclasses.replace(
        d, least_ramp_m=0.5 * EDGE_MIN_M) for d in smooth.defects))
    run_e = simulate(smooth, progress=False)
    run_half = simulate(half, progress=False)
    run_loc = simulate(_sharp(*OUTER), progress=False)
    se, sh, loc = (ed.headline_values(r, healthy) for r in (run_e, run_half, run_loc))
    for k in ("ring_acceleration_rms", "force_drop_impulse"):
        sharp = 2.0 * sh[k] - se[k]
        assert abs(loc[k] - sharp) <= 0.25 * abs(se[k] - sh[k]) + 1e-4 * abs(sharp), (
            k, loc, se, sh)
    signal = "ring_acceleration_signal"
    to_half = ed.headline_errors(run_loc, run_half, loc, sh)[signal]
    e_to_half = ed.headline_errors(run_e, run_half, se, sh)[signal]
    to_e = ed.headline_errors(run_loc, run_e, loc, se)[signal]
    assert abs(to_half / e_to_half - 1.0) < 0.1, (to_half, e_to_half)
    assert abs(to_e / (2.0 * e_to_half) - 1.0) < 0.1, (to_e, e_to_half)


def test_the_jacobian_with_frozen_sides_matches_central_differences():
    """A sharp spall under roller 0 (inside, frozen): central differences of the residual
    against the analytic iteration matrix (the bound of tests/system/test_defect_rows.py); the
    static solve saw the sharp defect (the residual's algebraic rows vanish)."""
    from bearingdae.solvers.algebraic import initial_state
    from bearingdae.solvers.ida import check_jacobian
    from bearingdae.system.defect_sides import freeze_sides, has_sharp, thaw_sides
    from bearingdae.system.model import build_model

    s = scene_from_dict({"bearing": {"preset": "yang20"}, "operating": {
        "radial_load_N": 2000.0, "moment_Nm": 0.0, "speed_rpm": 2000.0},
        "numerics": {"defect_edges": "locate"},
        "defects": [{"on": "outer", "angle_deg": 0.0, "length_mm": 2.0, "width_mm": 6.0,
                     "depth_um": 2.0, "edge_mm": 0.0}]})
    m = build_model(s)
    assert has_sharp(m.defect_table)
    y0, yp0 = initial_state(m)
    assert freeze_sides(m, 0.0, y0) == m.layout.rollers  # one root per roller
    D = m.defect_table
    assert D[1 + 1 + 0, 0] == 1.0 and D[1 + 1 + 10, 0] == 0.0  # roller 0 inside, 10 not
    res = m.residual(0.0, y0, np.zeros_like(y0))
    assert np.abs(res[m.layout.algebraic]).max() < 1e-9
    assert check_jacobian(m, y0, yp0, jacobian="analytic", rel_step=1e-7) < 2e-4
    thaw_sides(m)


def test_smooth_is_the_default_and_keeps_the_ramp():
    """The default "smooth": the defect table as before (the least ramp, no side rows), no
    root machinery; "locate" marks the sharp edge (ramp 0) and adds a side row per roller."""
    from bearingdae.system.defect_sides import has_sharp
    from bearingdae.system.defects import C_RAMP, COLUMNS, defect_table

    smooth = _sharp(*OUTER, mode="smooth")
    assert load_scene(*OUTER).dynamics.defect_edges == "smooth"
    g = make_geometry(smooth)
    D = defect_table(smooth, g)
    assert D.shape == (2, COLUMNS) and D[1, C_RAMP] == EDGE_MIN_M and not has_sharp(D)
    L = defect_table(_sharp(*OUTER), g)
    assert L.shape == (2 + g.rollers, COLUMNS) and L[1, C_RAMP] == 0.0 and has_sharp(L)
    # a stated ramp longer than the least is smooth already: kept, not located
    ramped = load_scene(OUTER[0], {"numerics.defect_edges": "locate"})
    assert not has_sharp(defect_table(ramped, g))


def test_a_scene_without_defects_assembles_no_root_machinery():
    """The default scene, run briefly in a fresh process: neither the root function nor the
    edge driver is imported (nothing of them is typed, compiled or called)."""
    code = ("import sys; from bearingdae import load_scene, simulate; "
            "simulate(load_scene('yang20_baseline', {'numerics.cage_revolutions': 0.002, "
            "'numerics.warmup_cage_revolutions': 0.0}), progress=False); "
            "print([m for m in ('bearingdae.solvers.sundials.roots', "
            "'bearingdae.solvers.ida_edges') if m in sys.modules])")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip().splitlines()[-1] == "[]", out.stdout


@pytest.mark.parametrize("value", ["sharp", "", 1, True, None])
def test_a_bad_value_is_refused_in_one_line(value):
    with pytest.raises(SceneError) as err:
        scene_from_dict({"bearing": {"preset": "yang20"},
                         "numerics": {"defect_edges": value}})
    lines = [ln for ln in str(err.value).splitlines() if not ln.endswith(":")]
    assert len(lines) == 1, str(err.value)
    assert "'numerics.defect_edges'" in lines[0] and repr(value) in lines[0]
    assert "'smooth' or 'locate'" in lines[0] or "wrong type" in lines[0], lines[0]


@pytest.mark.parametrize("solver", ["newmark", "scikit-sundae"])
def test_other_solvers_refuse_located_edges_in_one_line(solver):
    """Newmark-β (fixed steps, no root finding) and the scikit-sundae cross-check refuse a
    scene with located edges."""
    from bearingdae.solvers.ida_scikit_sundae import IDAScikitSundae

    with pytest.raises(ValueError) as err:
        simulate(_sharp(*OUTER), solver=IDAScikitSundae() if solver != "newmark" else solver,
                 progress=False)
    msg = str(err.value)
    assert "\n" not in msg and "numerics.defect_edges = 'locate'" in msg and "'smooth'" in msg


def test_the_command_line_locates_edges_as_simulate_does(tmp_path):
    """``bearingdae run`` wraps IDA in its checkpoints (run/checkpoint.Checkpointed): the
    wrapped solver locates the edges as IDA does, the same samples as ``simulate``."""
    import xarray as xr

    from bearingdae.cli import main

    case, overrides = OUTER
    scene = _sharp(case, {**overrides, "numerics.cage_revolutions": 0.05})
    path = tmp_path / "sharp.toml"
    path.write_text(scene.to_toml())
    out = tmp_path / "sharp.nc"
    assert main(["run", str(path), "--no-plot", "--no-progress", "-o", str(out)]) == 0
    ds = simulate(scene, progress=False)
    with xr.open_dataset(out) as cli:
        np.testing.assert_allclose(cli.contact_force.values, ds.contact_force.values,
                                   rtol=1e-12, atol=1e-9)
        assert cli.sizes["time"] == ds.sizes["time"] > 1


def _fuzzed_values():
    from hypothesis import strategies as st

    return st.one_of(st.sampled_from(["smooth", "locate", "Locate", " smooth", "sharp", "ramp",
                                      "root", "", "none"]),
                     st.text(max_size=8), st.integers(-3, 3), st.floats(allow_nan=True),
                     st.booleans(), st.none(), st.lists(st.just("locate"), max_size=2))


def test_the_key_is_fuzzed():
    """Random values of the key: exactly "smooth" and "locate" load; anything else is one line
    naming the key (scene dict), and the command line exits 2 with one line (after its
    header, as for every key)."""
    from hypothesis import given

    from fuzzing import fuzz, run_cli

    @fuzz(60)
    @given(value=_fuzzed_values())
    def check(value):
        try:
            s = scene_from_dict({"bearing": {"preset": "yang20"},
                                 "numerics": {"defect_edges": value}})
        except SceneError as exc:
            lines = [ln for ln in str(exc).splitlines() if not ln.endswith(":")]
            assert len(lines) == 1 and "'numerics.defect_edges'" in lines[0], str(exc)
            assert value not in ("smooth", "locate")
            return
        assert value in ("smooth", "locate") and s.dynamics.defect_edges == value

    check()
    rc, out, err = run_cli(["static", "yang20_baseline", "--set",
                            'numerics.defect_edges="sharp"'])
    problems = [ln for ln in err.strip().splitlines() if not ln.endswith(":")]
    assert rc == 2 and len(problems) == 1, err  # (after the header naming the --set)
    assert "'numerics.defect_edges' = 'sharp'" in err and "'smooth' or 'locate'" in err


def test_a_failed_restart_at_an_edge_is_reported_as_a_failure(monkeypatch):
    """A restart that cannot be made consistent (the projection fails) ends the run as IDA's
    failures do: a SimulationError naming the time and the cause, the samples before it kept."""
    import bearingdae.solvers.ida as ida
    from bearingdae.api import SimulationError

    monkeypatch.setattr(ida, "_restart", lambda *a: False)
    with pytest.raises(SimulationError) as err:
        simulate(_sharp(*OUTER), progress=False)
    msg = str(err.value)
    assert "after crossing a sharp defect edge" in msg and "IDA failed at t = " in msg, msg
