"""The ring damping a bundled case's comment states, against the physics.

A case with a dynamic ring damps it through its support (``[ring] support_damping_N_s_m``),
and its comment says how much that is: the damping ratio ζ = c / (2 √(k m)) of the ring's
translation on the bearing's static stiffness k in each direction, with k and, for a preloaded
case, the mode's frequency √(k/m) / 2π. A vibration analyst reads the ringing after each
impact from ζ. Each number is solved here afresh (analysis/stiffness.py) and compared within
half a unit of its last stated digit, plus 1 % for the spread between machines.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from bearingdae import load_scene
from bearingdae.analysis.stiffness import scene_stiffness
from bearingdae.physics.geometry import make_geometry
from bearingdae.system.model import ring_body

ROOT = Path(__file__).resolve().parents[2]
DAMPED = sorted(p for p in (ROOT / "cases").rglob("*.toml")
                if "support_damping_N_s_m" in p.read_text(encoding="utf-8"))
NUMBER = r"(\d+(?:\.\d+)?(?:e[+-]?\d+)?)"


def stated(text: str) -> str:
    """The comment lines just above the support damping, joined."""
    lines = text.splitlines()
    at = next(i for i, line in enumerate(lines) if line.startswith("support_damping_N_s_m"))
    above = []
    for line in reversed(lines[:at]):
        if not line.startswith("#"):
            break
        above.insert(0, line.lstrip("# ").strip())
    return " ".join(above)


def close(value: float, text: str) -> bool:
    """``value`` equals the number ``text`` states, to half its last digit plus 1 %."""
    mantissa = text.split("e")[0]
    digits = len(mantissa.split(".")[1]) if "." in mantissa else 0
    scale = 10.0 ** int(text.split("e")[1]) if "e" in text else 1.0
    return abs(value - float(text)) <= 0.5 * 10.0 ** -digits * scale + 0.01 * abs(value)


def test_every_damped_case_is_checked():
    assert len(DAMPED) >= 6, [p.name for p in DAMPED]


@pytest.mark.parametrize("path", DAMPED, ids=lambda p: p.relative_to(ROOT / "cases").as_posix())
def test_the_stated_ring_damping_is_the_physics(path):
    comment = stated(path.read_text(encoding="utf-8"))
    scene = load_scene(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a film-parameter warning of the case is not under test
        k = scene_stiffness(scene, warn=False).stiffness.values
    m, _ = ring_body(scene, make_geometry(scene))
    c = scene.ring.support_damping_N_s_m
    k_r, k_t = k[0, 0], k[1, 1]
    zeta_r, zeta_t = (100 * c / (2 * np.sqrt(kk * m)) for kk in (k_r, k_t))
    two = re.search(rf"ζ ≈ {NUMBER} % of critical radially and {NUMBER} % tangentially", comment)
    if two:
        assert close(zeta_r, two[1]) and close(zeta_t, two[2]), (comment, zeta_r, zeta_t)
        ks = re.search(rf"\({NUMBER} and {NUMBER} N/m", comment)
        assert ks and close(k_r, ks[1]) and close(k_t, ks[2]), (comment, k_r, k_t)
        return
    one = re.search(rf"ζ ≈ {NUMBER} % of critical", comment)
    assert one, f"{path.name}: no damping ratio stated above support_damping_N_s_m: {comment!r}"
    assert close(zeta_r, one[1]) and close(zeta_t, one[1]), (comment, zeta_r, zeta_t)
    ks = re.search(rf"\({NUMBER} N/m in both directions", comment)
    assert ks and close(k_r, ks[1]) and close(k_t, ks[1]), (comment, k_r, k_t)
    f_kHz = np.sqrt(np.array([k_r, k_t]) / m) / (2 * np.pi) / 1e3
    near = re.search(r"mode near (\d+) kHz", comment)
    assert near and all(close(f, near[1]) for f in f_kHz), (comment, f_kHz)
