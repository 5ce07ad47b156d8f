"""``roller_spin_angle_rad``: the rollers' spin angles, written only where they are unknowns
(a ``[[defects]]`` or ``[[waviness]]`` entry on a roller; system/defects.py).

Reference: the spin angle is the integral of the spin speed relative to the orbiting frame
(φ' = ω, the row of system/defects.spin_angle_rows), so its change over the record equals the
trapezoidal integral of the written ``spin_speed`` over the samples, within the trapezoidal
rule's error (computed here with numpy, not the model).
"""

from __future__ import annotations

import numpy as np
import pytest

from bearingdae import load_scene, simulate
from bearingdae.scene.errors import SceneError


def test_the_spin_angle_is_the_integral_of_the_spin_speed_and_has_cf_metadata():
    s = load_scene("defects/roller_spall", {"numerics.cage_revolutions": 0.02,
                                            "numerics.warmup_cage_revolutions": 0.0})
    ds = simulate(s, progress=False)
    phi = ds["roller_spin_angle_rad"]
    assert phi.dims == ("time", "roller")
    assert phi.attrs["units"] == "rad" and "spin angle" in phi.attrs["long_name"]
    t = ds.time.values
    w = ds.spin_speed.values
    turned = np.concatenate([np.zeros((1, w.shape[1])),
                             np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t)[:, None], axis=0)])
    change = phi.values - phi.values[0]
    assert np.abs(change[-1]).min() > 1.0  # every roller turned by more than a radian
    assert np.abs(change - turned).max() < 1e-3 * np.abs(change[-1]).max()
    assert abs(float(phi.values[0, 0])) < 1e-9 or t[0] > 0.0  # 0 at t = 0


def test_a_scene_without_a_roller_surface_neither_writes_nor_accepts_it():
    with pytest.raises(SceneError) as err:
        load_scene("defects/outer_spall", {"output.variables": ["roller_spin_angle_rad"]})
    text = str(err.value)
    assert "\n" not in text and "'roller_spin_angle_rad'" in text and 'on = "roller"' in text
    s = load_scene("defects/outer_spall", {"numerics.cage_revolutions": 0.005,
                                           "numerics.warmup_cage_revolutions": 0.0})
    assert "roller_spin_angle_rad" not in simulate(s, progress=False)
