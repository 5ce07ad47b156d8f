"""The run's last line: its wall time from the process's start, in phases that add up.

Reference: the wall time of the child process as this process measures it (a monotonic clock
around ``subprocess.run``), which includes the interpreter's start and exit that the line
cannot see; and the sum of the phases the line prints.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SHORT = ["--set", "numerics.warmup_cage_revolutions=0", "--set", "numerics.cage_revolutions=0.05"]
LINE = re.compile(r"^wall time ([\d.]+) s since the command started: ([\d.]+) s (.*?) to the "
                  r"first sample, ([\d.]+) s integrating and writing the record, ([\d.]+) s "
                  r"the summary and the plot$", re.M)


def test_the_phases_add_up_to_the_process_wall_time(tmp_path):
    t0 = time.monotonic()
    r = subprocess.run([sys.executable, "-m", "bearingdae.cli", "run", "-o",
                        str(tmp_path / "r.nc"), *SHORT], capture_output=True, text=True,
                       env={**os.environ, "PYTHONPATH": str(ROOT), "OMP_NUM_THREADS": "1",
                            "MPLBACKEND": "Agg"})
    lived = time.monotonic() - t0
    assert r.returncode == 0, r.stderr
    m = LINE.search(r.stdout)
    assert m, r.stdout
    total, to_first, integrating, rest = (float(m.group(k)) for k in (1, 2, 4, 5))
    assert r.stdout.rstrip().endswith(m.group(0))  # the last line: the plot is counted
    assert abs(to_first + integrating + rest - total) <= 0.15  # three roundings to 0.1 s
    # the process lived a little longer than its line says (the interpreter's exit after it,
    # the start before /proc's 10 ms tick): within 5 %, plus 1 s for the exit on a busy
    # machine (closing files, ending a compile child; measured 0.1-0.3 s at load 1)
    assert total <= lived + 0.05
    assert total >= 0.95 * lived - 1.0, (total, lived)
    assert "solver" in r.stdout and "residual calls" in r.stdout
