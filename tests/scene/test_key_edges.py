"""Every positive physical key at its range's edges: finite results or a one-line refusal.

A key whose range was open at 0 accepted 5e-324 and let its law overflow (the oil's thermal
conductivity gave NaN power losses, a land clearance of 5e-324 a singular Newmark matrix): each
positive physical key now has a lower bound that keeps its laws finite. The property test takes
every such key (with the switches that make it matter) to the ends of its range and to 5e-324,
and asserts that the scene is either refused in one line naming the key, or loads and gives a
finite static solution with no numpy overflow warning; the two reproducers of the dynamic laws
run as processes.
"""

from __future__ import annotations

import math
import re
import subprocess
import sys
import warnings

import numpy as np
import pytest

from bearingdae import SceneError, solve_static
from bearingdae.solvers.static import StaticConvergenceError
from bearingdae.scene.schema import key_table
from tests.conftest import make_scene

#: the sections of physical keys (numerics, output and life are not physics)
PHYSICAL = ("bearing", "materials", "operating", "traction", "cage", "lubricant", "ring",
            "thermal")
LAND = {"physics.cage_whirl": True, "cage.guidance": "outer-land"}
#: key prefix -> the switches under which the key is read
CONTEXT = {
    "bearing.flange": {"bearing.type": "NJ"}, "bearing.roller_end": {"bearing.type": "NJ"},
    "bearing.roller_corner": {"bearing.type": "NJ"}, "cage.mass_kg": LAND, "cage.land": LAND,
    "lubricant.temperature_viscosity": {"physics.rolling_resistance": True},
    "lubricant.thermal_conductivity": {"physics.rolling_resistance": True},
    "lubricant.inlet_film": {"physics.rolling_resistance": True},
    "lubricant.boundary_friction": {"physics.lubrication": "mixed"},
    "lubricant.viscosity_40C": {"physics.thermal": "steady"},
    "lubricant.viscosity_100C": {"physics.thermal": "steady"},
    "thermal.": {"physics.thermal": "steady"}, "ring.": {"physics.ring": "dynamic"},
}
RANGE = re.compile(r"^([\[(])\s*([-+0-9.e]+|-inf),\s*([-+0-9.e]+|inf)\s*([\])])$")


def positive_keys() -> list[tuple[str, float, bool, float]]:
    """(key, lower bound, whether it is included, upper bound) of every physical key whose
    range starts at or above 0 and is numeric."""
    out = []
    for key, _default, text, _ in key_table():
        m = RANGE.match(text.strip())
        if not m or key.split(".")[0] not in PHYSICAL:
            continue
        lo, hi = float(m.group(2)), float(m.group(3))
        if lo >= 0.0 and math.isfinite(hi) and hi > 0:
            out.append((key, lo, m.group(1) == "[", hi))
    return out


KEYS = positive_keys()


def _context(key: str) -> dict:
    for prefix, extra in CONTEXT.items():
        if key.startswith(prefix):
            return dict(extra)
    return {}


def _finite(ds) -> list[str]:
    return [n for n, v in ds.data_vars.items() if v.dtype.kind == "f"
            and not np.all(np.isfinite(v.values[~np.isnan(v.values)]))]


def test_the_keys_covered():
    """Every positive physical key is covered; none is left open at 0 but the two a derived
    check bounds (the rib angle and the end radius: scene/flanges.py names the least angle)
    and the loads and speed, where 0 is the operating point itself."""
    assert len(KEYS) >= 60, len(KEYS)
    open_at_zero = sorted(k for k, lo, closed, _ in KEYS if lo == 0.0 and not closed)
    assert open_at_zero == ["bearing.flange_angle_deg", "bearing.roller_end_radius_mm"], \
        open_at_zero


@pytest.mark.slow
@pytest.mark.parametrize("key, lo, closed, hi", KEYS, ids=[k[0] for k in KEYS])
def test_each_positive_key_at_its_edges_is_finite_or_refused(key, lo, closed, hi):
    values = [hi, lo if closed else math.nextafter(lo, math.inf), 5e-324]
    for value in values:
        over = {**_context(key), key: value}
        try:
            scene = make_scene(over)
        except SceneError as exc:  # one line per problem, each naming its key and value
            assert _refusal(str(exc)), (key, value, str(exc))
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("error", RuntimeWarning)  # numpy's overflow warnings
            try:
                ds = solve_static(scene)
            except (SceneError, StaticConvergenceError) as exc:  # named, in one line
                assert len(str(exc).splitlines()) == 1, (key, value, str(exc))
                continue
        assert not _finite(ds), (key, value, _finite(ds))


PROBLEM = re.compile(r"'[a-z_]+\.[a-zA-Z0-9_]+' = ")


def _refusal(text: str) -> bool:
    """A scene error as the program prints it: a header, then one line per problem naming a
    key and its value (or the one problem on the header line)."""
    lines = text.splitlines()
    if len(lines) == 1:
        return bool(PROBLEM.search(lines[0]))
    return all(PROBLEM.search(ln) and ln.strip().startswith("- ") for ln in lines[1:])


def _run(*sets: str):
    args = [sys.executable, "-m", "bearingdae.cli", "run", "yang20_baseline", "--no-plot",
            "--no-progress", "-o", "/dev/null/never.nc"]
    for s in sets:
        if s.startswith("--"):
            args.append(s)
            continue
        args += ["--set", s]
    return subprocess.run(args, capture_output=True, text=True)


@pytest.mark.parametrize("sets, key", [
    (["physics.rolling_resistance=true", "lubricant.thermal_conductivity_W_m_K=5e-324"],
     "lubricant.thermal_conductivity_W_m_K"),
    (["physics.cage_whirl=true", 'cage.guidance="outer-land"', "cage.land_clearance_mm=5e-324",
      "--solver=newmark"], "cage.land_clearance_mm"),
])
def test_the_reproducers_are_refused_in_one_line(sets, key):
    """M7 (NaN power loss and numpy's overflow warnings) and M8 ("Factor is exactly
    singular"): refused before any computing, status 2, the scene error's one problem line
    naming the key and its range (under the line naming the scene), no traceback."""
    done = _run(*sets)
    lines = done.stderr.strip().splitlines()
    problems = [ln for ln in lines if ln.strip().startswith("- ")]
    assert done.returncode == 2 and len(lines) == 2 and len(problems) == 1, done.stderr
    assert f"'{key}' = 5e-324" in problems[0] and "allowed range [" in problems[0], lines
