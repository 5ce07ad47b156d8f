"""``bearingdae coefficients``: the bearing's stiffness matrix over speed x radial load, for a
rotor model (docs/theory.md §18).

Pipeline: the cli layer over studies/coefficients.py.
"""

from __future__ import annotations

import sys
from pathlib import Path

from .common import _scene


def _coefficients(args) -> int:
    from ..scene import resolve_case
    from ..studies.coefficients import coefficients
    from ..util.atomic import check_writable, refuse_aliases

    scene = _scene(args)
    source = resolve_case(args.case)
    out = check_writable(args.output or Path(f"{source.stem}_coefficients.nc"))
    refuse_aliases([("output", out)], [("scene file", source)])
    say = (lambda text: print("  " + text, file=sys.stderr))
    table = coefficients(scene, args.speeds, args.loads, output=out, progress=say)
    K = table.stiffness
    print(f"{scene.title}: stiffness over {table.sizes['speed_rpm']} speeds x "
          f"{table.sizes['radial_load_N']} radial loads")
    print("  speed [r/min]  load [N]   k_rr [N/m]   k_tt [N/m]   k_γγ [N m/rad]")
    for n in table.speed_rpm.values:
        for F in table.radial_load_N.values:
            k = K.sel(speed_rpm=n, radial_load_N=F)
            print(f"  {n:13g}  {F:8g}   {float(k.sel(dof='radial', dof_2='radial')):.4e}   "
                  f"{float(k.sel(dof='tangential', dof_2='tangential')):.4e}   "
                  f"{float(k.sel(dof='tilt_radial', dof_2='tilt_radial')):.4e}")
    print(f"wrote {out}")
    return 0
