"""The trends table of ``bearingdae paper --trends`` (bearingdae/studies/trends.py) from
synthetic run files whose slip grows by a known factor along each sweep: the table has the
contracted columns and one row per claim x reading x point, and the verdicts follow the
scaling that was built in (slip x1, x2, x3 ... rises: "rises" claims hold, "falls" claims are
contradicted)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pandas as pd
import xarray as xr

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "analysis"))
from test_trends import synthetic  # noqa: E402  (the synthetic bearing of the readings test)

from bearingdae.studies import trends as S  # noqa: E402

AXES = {"yang20_speed_sweep": ("speed_rpm", [2000.0, 6000.0, 10000.0, 14000.0]),
        "yang20_radial_load_sweep": ("radial_load_N", [200.0, 400.0, 800.0, 1200.0, 1600.0]),
        "yang20_moment_sweep": ("moment_Nm", [0.0, 3.0, 5.0, 10.0])}


def fake_sweeps(folder: Path) -> dict:
    base = synthetic()
    rng = np.random.default_rng(3)
    sweeps = {}
    for name, (dim, values) in AXES.items():
        files = []
        for i, _ in enumerate(values):
            ds = base.copy(deep=True)
            # slip x (i + 1) plus 1 % noise per sample: every slip reading rises along the axis
            noise = 1 + 0.01 * rng.standard_normal(ds.slip_velocity.shape)
            ds["slip_velocity"] = ds.slip_velocity * (i + 1) * noise
            ds["slip_velocity_peak"] = ds.slip_velocity_peak * (i + 1)
            path = folder / f"{name}_{i}.nc"
            ds.to_netcdf(path)
            files.append(path.name)
        sweeps[name] = xr.Dataset({"status": (dim, ["completed"] * len(values)),
                                   "run_file": (dim, files)}, coords={dim: values})
    return sweeps


def test_table_columns_rows_and_built_in_verdicts(tmp_path):
    table, verdicts = S.trend_table(fake_sweeps(tmp_path), tmp_path)
    assert list(table.columns) == ["claim", "reading", "sweep_variable", "sweep_value", "value",
                                   "stderr", "n_blocks", "units"]
    from bearingdae.analysis.trends import READINGS

    expected = sum(len(READINGS[q][1]) * len(AXES[sw][1]) for sw, q, _, _ in S.CLAIMS.values())
    assert len(table) == expected
    assert (table.n_blocks == 4).all() and (table.stderr > 0).all()
    slip = verdicts[verdicts.claim.str.contains("sliding speed")]
    assert len(slip) == 12
    for _, v in slip.iterrows():
        assert v.verdict == ("holds" if v.direction > 0 else "contradicted"), v.to_dict()
    from bearingdae.studies.trends_report import write_trends

    write_trends(table, verdicts, tmp_path / "out", figures=False)
    back = pd.read_csv(tmp_path / "out" / "trends.csv")
    assert list(back.columns) == list(table.columns) and len(back) == len(table)
    md = (tmp_path / "out" / "trends.md").read_text()
    rows = [line for line in md.splitlines() if line.startswith("| ") and "±" in line]
    assert sum(line.count("±") for line in rows) == len(table)  # every number, its error
    from bearingdae.plots.plot_trends import claim_figure

    claim = next(iter(S.CLAIMS))
    assert claim_figure(table, verdicts, claim, tmp_path / "claim.png").stat().st_size > 0
    nc = xr.open_dataset(tmp_path / "out" / "trends.nc")
    assert nc.sizes["row"] == len(table) and nc.sizes["test"] == len(verdicts)
