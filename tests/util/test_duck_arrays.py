"""The ``bearingdae`` program spares xarray's imports of dask.array, pint and dask.distributed
for the commands that hold numpy arrays only (bearingdae/util/duck_arrays.py); library use
keeps xarray's look."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

# a NetCDF write through xarray, then which duck-array libraries the process imported
_WRITE = """
import json, sys
import numpy as np
import xarray as xr
{before}
xr.Dataset({{"a": ("x", np.zeros(3))}}).to_netcdf(sys.argv[1])
from xarray.namedarray.pycompat import array_type
print(json.dumps({{"spared": spared, "dask.array": "dask.array" in sys.modules,
                  "pint": "pint" in sys.modules,
                  "pint_type": [t.__name__ for t in array_type("pint")]}}))
"""


def _write(tmp_path, before: str) -> dict:
    out = subprocess.run([sys.executable, "-c", _WRITE.format(before=before),
                          str(tmp_path / "a.nc")], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_xarray_imports_them_unless_spared(tmp_path):
    pytest.importorskip("dask.array")
    pytest.importorskip("pint")
    looked = _write(tmp_path, "spared = None")
    assert looked["dask.array"]  # what a write costs without sparing
    assert looked["pint_type"] == ["Quantity"]  # (pint: at xarray's first look for it)
    spared = _write(tmp_path, "from bearingdae.util.duck_arrays import spare_duck_array_imports"
                              "\nspared = spare_duck_array_imports()")
    assert {"dask", "pint"} <= set(spared["spared"])
    assert not spared["dask.array"] and not spared["pint"] and spared["pint_type"] == []


def test_a_library_already_imported_stays_known_to_xarray(tmp_path):
    pytest.importorskip("pint")
    got = _write(tmp_path, "import pint\nfrom bearingdae.util.duck_arrays import "
                           "spare_duck_array_imports\nspared = spare_duck_array_imports()")
    assert "pint" not in got["spared"] and got["pint_type"] == ["Quantity"]


def test_the_program_runs_without_importing_them(tmp_path):
    """``bearingdae run`` as the program (``python -m bearingdae.cli``): Python's import log
    names neither dask.array nor pint, and the result file is written."""
    pytest.importorskip("dask.array")
    target = tmp_path / "r.nc"
    env = {**os.environ, "OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    out = subprocess.run(
        [sys.executable, "-X", "importtime", "-m", "bearingdae.cli", "run", "--no-plot",
         "--no-progress", "--set", "numerics.warmup_cage_revolutions=0",
         "--set", "numerics.cage_revolutions=0.01", "-o", str(target)],
        capture_output=True, text=True, timeout=900, env=env)
    assert out.returncode == 0, out.stderr[-2000:]
    imported = {line.rsplit("|", 1)[-1].strip() for line in out.stderr.splitlines()
                if line.startswith("import time:")}
    assert "xarray" in imported and "numba" in imported  # the log is complete
    assert "dask.array" not in imported and "pint" not in imported
    # (the spared check's failing imports of "distributed" are logged too, at a few µs: the
    # package's own modules are what an import of it loads)
    assert not any(name.startswith("distributed.") for name in imported)
    assert target.stat().st_size > 0


# xarray's scheduler check at a NetCDF write, with or without the spare; then a real import
_SCHEDULER = """
import json, sys
import numpy as np
import xarray as xr
from xarray.backends import locks
{before}
xr.Dataset({{"a": ("x", np.zeros(3))}}).to_netcdf(sys.argv[1])
imported = "distributed" in sys.modules
answer = locks.get_dask_scheduler()
import dask.distributed
print(json.dumps({{"spared": spared, "imported_by_write": imported, "answer": answer,
                  "client": dask.distributed.Client.__name__,
                  "after_import": locks.get_dask_scheduler()}}))
"""


def test_a_write_spared_of_distributed_answers_as_xarray_does(tmp_path):
    pytest.importorskip("dask.distributed")

    def run(before):
        out = subprocess.run([sys.executable, "-c", _SCHEDULER.format(before=before),
                              str(tmp_path / "a.nc")], capture_output=True, text=True,
                             timeout=300)
        assert out.returncode == 0, out.stderr
        return json.loads(out.stdout.strip().splitlines()[-1])

    looked = run("spared = None")
    assert looked["imported_by_write"]  # what a write costs without sparing
    spared = run("from bearingdae.util.duck_arrays import spare_distributed_import\n"
                 "spared = spare_distributed_import()")
    assert spared["spared"] and not spared["imported_by_write"]
    # no client in either process: dask's threaded scheduler, as xarray itself says; after a
    # real import of dask.distributed the check is xarray's own again
    assert spared["answer"] == looked["answer"] == "threaded"
    assert spared["client"] == "Client" and spared["after_import"] == "threaded"
