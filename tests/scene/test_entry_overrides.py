"""Keys of one entry of an array of tables (``--set defects[0].depth_um=5``) and a whole
array set at once (``defects = []``), scene/overrides.py: what sweeps over defect keys and the
defect benchmark (the case without its defects) stand on.
"""

from __future__ import annotations

import numpy as np
import pytest

from bearingdae import load_scene
from bearingdae.scene import SceneError


def test_an_entry_key_sets_that_entry():
    s = load_scene("defects/outer_spall", {"defects[0].depth_um": 5.0,
                                           "defects[0].angle_deg": 3.0})
    assert s.defects[0].depth_m == pytest.approx(5e-6)
    assert s.defects[0].angle_rad == pytest.approx(np.radians(3.0))
    assert load_scene("defects/outer_spall").defects[0].depth_m == pytest.approx(20e-6)


@pytest.mark.parametrize("key, value, fragments", [
    ("defects[1].depth_um", 5.0, ["defects[1].depth_um", "1 [[defects]] entry",
                                  "indices 0..0"]),
    ("waviness[0].order", 3, ["waviness[0].order", "0 [[waviness]] entries"]),
    ("defects[0].depth_um", -5.0, ["depth_um", "-5"]),
])
def test_a_bad_entry_key_is_one_line_naming_it(key, value, fragments):
    with pytest.raises(SceneError) as err:
        load_scene("defects/outer_spall", {key: value})
    text = str(err.value)
    assert all(f in text for f in fragments), text
    assert "Traceback" not in text


def test_a_misspelt_entry_key_is_an_unknown_key():
    with pytest.raises(SceneError, match="unknown"):
        load_scene("defects/outer_spall", {"defects[0].depth_mm": 5.0})


def test_an_empty_array_removes_every_entry():
    s = load_scene("defects/outer_spall", {"defects": [], "waviness": []})
    assert s.defects == () and s.waviness == ()
    with pytest.raises(SceneError, match=r"\[\[defects\]\] must be an array of tables"):
        load_scene("defects/outer_spall", {"defects": 3})
