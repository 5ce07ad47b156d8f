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
