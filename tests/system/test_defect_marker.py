"""A defect scene's marker (system/optional.py) holds its defect table and the pattern of its
effects compiled apart: its kernels, typed by the marker, compile the defects' passes and
those of the effects it switches on, no others (before, the table alone was the marker and
compiled every optional pass). What decides which passes a kernel compiles is the numba type of
the marker it is called with (``compiles``), so the reference here is that type, of the model
built from the scene, against the switches the test sets."""

from __future__ import annotations

import numba
import numpy as np
import pytest

from bearingdae.scene import scene_from_dict
from bearingdae.solvers.sundials.callbacks import python_callback
from bearingdae.system.model import build_model
from bearingdae.system.optional import (APART, DEFECTS, EXTENSION, FLANGE, MIXED, compiles,
                                        defect_marker, flange_marker, mixed_marker, variant)
from conftest import make_scene

SPALL = {"on": "outer", "angle_deg": 0.0, "length_mm": 1.5, "width_mm": 8.0, "depth_um": 20.0}
#: switches -> the effects compiled apart they turn on, and the tag of the IDA callbacks
CASES = {"no optional effect": ({}, (), "defects"),
         "mixed lubrication": ({"physics.lubrication": "mixed"}, (MIXED,), "defects_0001"),
         "flanges": ({"bearing.type": "NJ", "operating.axial_load_N": 200.0}, (FLANGE,),
                     "defects_1000")}


def _model(over):
    return build_model(scene_from_dict({"bearing": {"preset": "yang20"}, "defects": [SPALL]},
                                       over))


@pytest.mark.parametrize("name", list(CASES))
def test_a_defect_scene_compiles_the_defects_and_its_own_effects_passes_only(name):
    over, on, tag = CASES[name]
    model = _model(over)
    marker = model.data[-1]
    kind = numba.typeof(marker)
    assert compiles(kind, DEFECTS) and not compiles(kind, EXTENSION)
    assert [k for k in range(len(APART)) if compiles(kind, k)] == list(on), name
    # the kernels that run one effect's passes take the marker narrowed to it: the contact
    # passes of a defect scene without mixed lubrication are the default scene's (None)
    assert (mixed_marker(marker) is None) == (MIXED not in on)
    narrowed = numba.typeof(flange_marker(marker))
    assert compiles(narrowed, DEFECTS) and compiles(narrowed, FLANGE) == (FLANGE in on)
    assert not any(compiles(narrowed, k) for k in range(len(APART)) if k != FLANGE)
    assert numba.typeof(defect_marker(marker)).types[:DEFECTS] == (numba.types.none,) * DEFECTS
    # the table is the model's own (the memory the kernels write the shaft angle into)
    assert model.defect_table is marker[DEFECTS]
    assert np.shares_memory(model.defect_table, model.work[0])
    # the IDA callbacks of the scene: their own variant, named after its pattern
    assert python_callback("residual", marker)[0].__name__ == f"_residual_{tag}"
    # the tag a cold start's second process is handed (callbacks.compile_aside: the pattern's
    # 0s and 1s, "d" for the defects) names the same variant: it compiles the run's callbacks
    pattern = "".join("1" if k in on else "0" for k in range(len(APART))) + "d"
    assert variant(pattern) == variant(marker)
    assert python_callback("analytic", pattern)[0] is python_callback("analytic", marker)[0]


def test_a_scene_without_defects_has_no_table():
    model = build_model(make_scene({"physics.lubrication": "mixed"}))
    kind = numba.typeof(model.data[-1])
    assert not compiles(kind, DEFECTS) and compiles(kind, MIXED)
    assert model.defect_table is None
    assert build_model(make_scene({})).data[-1] is None  # the default scene: no marker
