"""Time series of every sweep point, stacked along the axes (``[sweep] signals``).

Pipeline place: studies -> results. A sweep whose axes are defect keys (depth × length ×
speed × load) gives labelled signals, e.g. the ring acceleration, for a classifier or a
diagnostic method: each run's recorded window (from ``record_start_s``) along a dimension
``sample``, with ``signal_time``, the time since that window's start, per point (the sample
interval follows each point's speed). Points with fewer samples (another window length) are
padded with NaN; a failed or missing point is NaN throughout.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

#: the stacked dimension: one recorded sample of a run
SAMPLE = "sample"


def record_signals(ds: xr.Dataset, names: list[str]) -> dict[str, xr.DataArray]:
    """The named series of a run over its recorded window, and ``signal_time`` [s] since the
    window's start; a name the run did not record is left out."""
    start = float(ds["record_start_s"]) if "record_start_s" in ds else float(ds.time[0])
    rec = ds.isel(time=np.flatnonzero(ds.time.values >= start))
    out = {n: rec[n] for n in names if n in rec and "time" in rec[n].dims}
    out["signal_time"] = xr.DataArray(rec.time.values - start, dims=("time",), attrs={
        "units": "s", "long_name": "time since the start of the run's recorded window"})
    return out


def stack_signals(shape: tuple, dims: tuple, per_point: dict[tuple, dict]
                  ) -> tuple[dict[str, xr.Variable], dict[str, xr.Variable]]:
    """(variables, coordinates) of the signals of every point (``per_point``: index on the
    axes -> :func:`record_signals`), time replaced by ``sample``."""
    if not per_point:
        return {}, {}
    samples = max(s["signal_time"].size for s in per_point.values())
    names = sorted({n for s in per_point.values() for n in s})
    data, coords = {}, {}
    for name in names:
        template = next(s[name] for s in per_point.values() if name in s)
        rest = [d for d in template.dims if d != "time"]
        order = ("time", *rest)
        arr = np.full(shape + (samples,) + tuple(template.sizes[d] for d in rest), np.nan)
        for i, s in per_point.items():
            if name in s:
                v = s[name].transpose(*order).values
                arr[i][: v.shape[0]] = v
        attrs = dict(template.attrs)
        if name != "signal_time":
            attrs["long_name"] = (f"{attrs.get('long_name', name)}, over each run's recorded "
                                  "window (signal_time)")
            attrs["coordinates"] = "signal_time"
        data[name] = xr.Variable(dims + (SAMPLE, *rest), arr, attrs)
        for d in rest:
            if d in template.coords:
                coords[d] = template[d].variable
    return data, coords
