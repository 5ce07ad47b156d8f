"""The headlines of the sharp-against-smoothed edge study (studies/workprecision/edges.py) on
records typed here: a roller that loses 60 N of its 100 N for 1 ms (a drop impulse of
0.06 N s by the trapezoidal rule on these samples), an acceleration of known RMS, and the
cheapest run per ramp at a target error."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from bearingdae.studies.workprecision import edges


def _record(force_N, accel):
    t = np.arange(force_N.shape[0]) * 1e-4
    f = np.zeros((t.size, 2, 3, 2))  # (time, roller, slice, race)
    f[:, 0, :, 1] = force_N[:, None] / 3.0
    return xr.Dataset({"contact_force": (("time", "roller", "slice", "race"), f),
                       "ring_acceleration": (("time", "direction"), accel)},
                      coords={"time": t})


def test_drop_impulse_peak_and_rms_against_typed_values():
    n = 41
    healthy = _record(np.full(n, 100.0), np.zeros((n, 2)))
    force = np.full(n, 100.0)
    force[10:21] = 40.0  # 11 samples at 0.1 ms: a flat 1 ms, and half a sample at each side
    a = np.stack([np.full(n, 3.0), np.full(n, 4.0)], axis=1)
    run = _record(force, a)
    assert edges.force_drop_peak(run, healthy) == pytest.approx(60.0)
    assert edges.force_drop_impulse(run, healthy) == pytest.approx(60.0 * 1.1e-3)
    assert edges.ring_acceleration_rms(run) == pytest.approx(5.0)


def test_the_cheapest_run_per_ramp_that_reaches_the_error():
    runs = [{"edge_mm": 0.05, "rtol": 1e-4, "cpu_s": 2.0, "errors": {"x": 0.02}},
            {"edge_mm": 0.05, "rtol": 1e-5, "cpu_s": 3.0, "errors": {"x": 0.005}},
            {"edge_mm": 0.4, "rtol": 1e-4, "cpu_s": 1.0, "errors": {"x": 0.2}},
            {"edge_mm": 0.4, "rtol": 1e-3, "status": "failed", "message": "x"}]
    best = edges.cheapest(runs, "x", 0.01)
    assert best[0.05]["rtol"] == 1e-5 and best[0.4] is None
    assert edges.cheapest(runs, "x", 0.5)[0.4]["cpu_s"] == 1.0


def test_sharper_passes_its_least_ramp_in_the_scene_and_mutates_no_constant(monkeypatch):
    """The study's sharper edge reaches the defect table through each defect's
    ``least_ramp_m`` (scene/defects.Defect): the table's ramp is the one asked for, and
    physics/defects.EDGE_MIN_M keeps its value during the run and after it."""
    from bearingdae.physics import defects as law
    from bearingdae.physics.geometry import make_geometry
    from bearingdae.system.defects import C_RAMP, defect_table
    from conftest import make_scene

    seen = {}

    def fake_timed(scene, repeat):
        seen["ramps"] = defect_table(scene, make_geometry(scene))[1:, C_RAMP]
        seen["constant"] = law.EDGE_MIN_M
        return None, 0.0, 0

    monkeypatch.setattr(edges, "_timed", fake_timed)
    kept = law.EDGE_MIN_M
    scene = make_scene({"defects": [{"on": "outer", "angle_deg": 0.0, "length_mm": 1.0,
                                     "width_mm": 8.0, "depth_um": 10.0, "edge_mm": 0.3}]})
    edges.sharper(scene, 0.5 * kept * 1e3, 1e-6)
    assert seen["ramps"].tolist() == [0.5 * kept]  # edge_mm 0 (sharp) at the smaller floor
    assert seen["constant"] == kept and law.EDGE_MIN_M == kept
    # the scene as given: the module's least ramp under a sharp edge, its own ramp otherwise
    assert defect_table(scene, make_geometry(scene))[1, C_RAMP] == 0.3e-3
    sharp = edges.with_edges(scene, 0.0, {})
    assert defect_table(sharp, make_geometry(sharp))[1, C_RAMP] == kept
