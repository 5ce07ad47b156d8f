"""docs/user-guide.md's table of file sizes ("Precision"): the default run written as float64
and as float32, measured again and compared with the table.

Tolerance: 3 % of each size. zlib's output depends on the bytes: another CPU computes the
chaotic run's values 1e-5 apart, which moves a compressed size by well under 1 %; a new
output variable moves it by what the variable takes (the table must then be measured again:
this test says by how much). Slow tier: two default runs, through the command line in the
test's process (tests/fuzzing.run_cli: the file is what the command writes; a process of its
own would only load the libraries and the compiled kernels again).
"""

from __future__ import annotations

import re

import pytest

from doc_blocks import ROOT
from fuzzing import run_cli

SIZE_REL_TOL = 0.03


def _table() -> dict[str, float]:
    page = (ROOT / "docs" / "user-guide.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| (float64|float32)[^|]*\| ([\d.]+) MB", page, re.M)
    return {k: float(v) for k, v in rows}


@pytest.mark.slow
def test_the_file_size_table_is_what_the_default_run_writes(tmp_path):
    table = _table()
    assert set(table) == {"float64", "float32"}, table
    for precision, size_mb in table.items():
        out = tmp_path / f"{precision}.nc"
        status, _, err = run_cli(["run", "-o", str(out), "--no-plot", "--set",
                                  f"output.precision={precision}"])
        assert status == 0, err[-2000:]
        measured = out.stat().st_size / 1e6
        assert measured == pytest.approx(size_mb, rel=SIZE_REL_TOL), (
            f"{precision}: the user guide says {size_mb} MB, the default run writes "
            f"{measured:.2f} MB: measure the table again")
