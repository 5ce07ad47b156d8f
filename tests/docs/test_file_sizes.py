"""docs/user-guide.md's table of file sizes ("Precision"): the default run written as float64
and as float32, measured again and compared with the table.

Tolerance: 3 % of each size. zlib's output depends on the bytes: another CPU computes the
chaotic run's values 1e-5 apart, which moves a compressed size by well under 1 %; a new
output variable moves it by what the variable takes (the table must then be measured again:
this test says by how much). Slow tier: two default runs.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys

import pytest

from doc_blocks import ROOT

SIZE_REL_TOL = 0.03


def _table() -> dict[str, float]:
    page = (ROOT / "docs" / "user-guide.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| (float64|float32)[^|]*\| ([\d.]+) MB", page, re.M)
    return {k: float(v) for k, v in rows}


@pytest.mark.slow
def test_the_file_size_table_is_what_the_default_run_writes(tmp_path):
    table = _table()
    assert set(table) == {"float64", "float32"}, table
    env = {**os.environ, "PYTHONPATH": str(ROOT), "OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    for precision, size_mb in table.items():
        out = tmp_path / f"{precision}.nc"
        r = subprocess.run([sys.executable, "-m", "bearingdae.cli", "run", "-o", str(out),
                            "--no-plot", "--set", f"output.precision={precision}"],
                           capture_output=True, text=True, env=env)
        assert r.returncode == 0, r.stderr[-2000:]
        measured = out.stat().st_size / 1e6
        assert measured == pytest.approx(size_mb, rel=SIZE_REL_TOL), (
            f"{precision}: the user guide says {size_mb} MB, the default run writes "
            f"{measured:.2f} MB: measure the table again")
