"""The healthy bearing's varying compliance: the ring's quasi-static displacement over one
roller pitch and its Fourier components at the outer-race roller pass (theory.md §22;
Sunnersjö 1978, J. Sound Vib. 58(3), 363-373).

Pipeline place: analysis (static solves of a scene, analysis/static_state.py). Equally spaced
rollers carry the scene's loads with a stiffness that depends on where the roller set stands;
the configuration repeats after one pitch, so the ring's displacement is periodic in the set's
position and a set turning at f_c moves the ring at BPFO = Z f_c and its harmonics. Far below
the ring's first mode a dynamic ring follows it (tests/analysis/test_varying_compliance.py).
"""

from __future__ import annotations

import numpy as np
import xarray as xr


def varying_compliance(scene, positions: int = 32, harmonics: int = 4) -> xr.Dataset:
    """``ring_displacement`` (position, direction) of the static solves with the roller set
    turned by j/positions of a pitch, j = 0 … positions − 1, and ``amplitude`` (harmonic,
    direction): its single-sided Fourier amplitudes at 1 … ``harmonics`` times the roller
    pass [m]."""
    from ..physics.geometry import make_geometry
    from .static_state import scene_static, turned_azimuths

    if not (isinstance(positions, int) and positions >= 2 * harmonics + 1 and harmonics >= 1):
        raise ValueError(f"positions {positions!r}, harmonics {harmonics!r}: expected whole "
                         "numbers with harmonics >= 1 and positions >= 2 harmonics + 1")
    g = make_geometry(scene)
    Z = g.rollers
    d = np.array([scene_static(scene, g, turned_azimuths(g, j / positions))[0].z[2 * Z:2 * Z + 2]
                  for j in range(positions)])
    amp = 2.0 * np.abs(np.fft.rfft(d, axis=0)[1:harmonics + 1]) / positions
    directions = ["radial", "tangential"]
    return xr.Dataset(
        {"ring_displacement": (("position", "direction"), d,
                               {"units": "m", "long_name": "quasi-static inner ring "
                                "displacement with the roller set turned"}),
         "amplitude": (("harmonic", "direction"), amp,
                       {"units": "m", "long_name": "amplitude of the ring displacement at "
                        "the harmonic of the roller pass (BPFO)"})},
        coords={"position": ("position", np.arange(positions) / positions,
                             {"units": "1", "long_name": "roller-set position in roller "
                              "pitches"}),
                "direction": directions,
                "harmonic": ("harmonic", np.arange(1, harmonics + 1),
                             {"long_name": "harmonic of the outer-race roller pass"})})
