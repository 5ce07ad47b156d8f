"""util/vector_width.py: the kernels compile for 512-bit vectors where the CPU has AVX-512,
with the same results to the bit.

References: the CPU's flags as the kernel lists them (/proc/cpuinfo, not LLVM's reading), the
machine code numba emits for a loop (zmm registers are the 512-bit ones), and a run compiled for
256-bit vectors (slow tier: every data variable compared bit for bit)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from bearingdae.util import vector_width as vw


def _avx512() -> bool:
    try:
        text = Path("/proc/cpuinfo").read_text()
    except OSError:
        return False
    return any(line.startswith("flags") and "avx512f" in line.split()
               for line in text.splitlines())


HOST = "+sse2,+avx,+avx2,+fma"


def test_features_wide_only_on_avx512_and_unless_the_user_chose():
    wide = HOST + ",+avx512f,-amx-tile"
    assert vw.features(wide, {}) == wide + ",-prefer-256-bit"
    assert vw.features(wide, {vw.ENV: "512"}) == wide + ",-prefer-256-bit"
    assert vw.features(HOST + ",-avx512f", {}) is None  # no AVX-512: nothing to widen
    assert vw.features(HOST, {}) is None
    assert vw.features(wide, {vw.ENV: "256"}) is None  # LLVM's choice kept
    assert vw.features(wide, {"NUMBA_CPU_FEATURES": "+avx2"}) is None  # the user's
    assert vw.features(wide, {"NUMBA_CPU_NAME": "generic"}) is None


def test_a_bad_choice_names_the_variable_its_value_and_the_choices():
    with pytest.warns(UserWarning, match=r"BEARINGDAE_VECTOR_BITS='1024' is not one of 256, "
                                         r"512"):
        got = vw.features(HOST + ",+avx512f", {vw.ENV: "1024"})
    assert got.endswith(",-prefer-256-bit")


_PROBE = """
import json, numpy as np
{before}
import bearingdae.system
from numba import njit
from numba.core import config, registry
@njit
def f(a, b):
    for i in range(a.shape[0]):
        b[i] = a[i] * 2.0 + 1.0
f(np.ones(64), np.ones(64))
tm = registry.cpu_target.target_context.codegen()._tm_features
print(json.dumps({{"features": config.CPU_FEATURES, "tm": tm,
                  "zmm": "zmm" in f.inspect_asm(f.signatures[0])}}))
"""

_EARLY = """
from numba import njit
njit(lambda x: x + 1)(1)  # numba's CPU target made before bearingdae is imported
"""


def _probe(before: str = "", **env) -> dict:
    environ = {k: v for k, v in os.environ.items()
               if k not in ("NUMBA_CPU_FEATURES", "NUMBA_CPU_NAME", vw.ENV)}
    r = subprocess.run([sys.executable, "-c", _PROBE.format(before=before)],
                       capture_output=True, text=True, env={**environ, **env}, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    return json.loads(r.stdout.strip().splitlines()[-1])


def test_a_process_compiles_for_the_widest_vectors_its_cpu_has():
    got = _probe()
    wide = _avx512()
    assert ("-prefer-256-bit" in got["tm"].split(",")) == wide
    assert got["zmm"] == wide  # the loop's machine code uses the 512-bit registers


def test_the_choices_that_keep_llvms_width():
    for got in (_probe(**{vw.ENV: "256"}), _probe(before=_EARLY)):
        assert got["features"] is None and "-prefer-256-bit" not in got["tm"].split(",")
        assert not got["zmm"]


@pytest.mark.slow
@pytest.mark.skipif(not _avx512(), reason="no AVX-512 on this CPU: one width only")
def test_a_run_is_the_same_to_the_bit_with_either_width(tmp_path):
    """Rolling resistance and mixed lubrication (the slice loops that gain most) on the default
    scene, a short window, compiled for 512- and for 256-bit vectors in two processes."""
    code = ("import sys, warnings; warnings.simplefilter('ignore')\n"
            "from bearingdae import load_scene, simulate\n"
            "ds = simulate(load_scene('yang20_baseline', {"
            "'physics.lubrication': 'mixed', "
            "'physics.rolling_resistance': 'biboulet_houpert', "
            "'numerics.warmup_cage_revolutions': 0.0, 'numerics.cage_revolutions': 0.05}))\n"
            "ds.to_netcdf(sys.argv[1])\n")
    environ = {k: v for k, v in os.environ.items() if k != vw.ENV}
    for bits in ("512", "256"):
        r = subprocess.run([sys.executable, "-c", code, str(tmp_path / f"{bits}.nc")],
                           capture_output=True, text=True, env={**environ, vw.ENV: bits},
                           timeout=1200)
        assert r.returncode == 0, r.stderr[-2000:]
    import xarray as xr

    with xr.open_dataset(tmp_path / "512.nc") as a, xr.open_dataset(tmp_path / "256.nc") as b:
        assert set(a.data_vars) == set(b.data_vars) and len(a.data_vars) > 50
        differ = [k for k in a.data_vars
                  if not np.array_equal(a[k].values, b[k].values, equal_nan=True)]
        assert not differ, differ
