"""State vector <-> (roller, variable) maps; which unknowns exist (theory.md §11).

The DAE unknowns are ordered roller-major — roller 1's unknowns, roller 2's, ..., then the
global ones (cage, ring) — so that the Jacobian is block-arrow: one dense block per roller on
the diagonal, coupled only through the last few global rows and columns.

The compiled kernel always works on the *full* per-roller set (``LOCAL``) and the full global
set (``GLOBAL``); a switched-off effect simply has no entry in the compact vector that IDA sees
(its unknowns are held at zero and its equations are not assembled), so switching ``skew`` off
removes 2 Z unknowns and 2 Z equations.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Full per-roller unknowns, in kernel order (indices A_* in system/residual.py).
LOCAL = ("azimuth", "orbit_speed", "spin_speed", "skew_angle", "skew_rate", "radial_position",
         "tilt", "axial_position", "spin_angle")
#: The rollers' spin angles φ_j (φ' = spin_speed): assembled only with a defect or waviness on a
#: roller (theory.md §4), whose contact points they place on the roller's surface.
SPIN_ANGLE = "spin_angle"
#: Full global unknowns, in kernel order (indices G_* in system/residual.py): cage, ring
#: displacement and tilt, then the ring's velocities (a dynamic ring only, theory.md §15), then
#: the ring's axial displacement (flanges with an axial load only, theory.md §16), then the cage
#: centre and its velocity (cage whirl only, theory.md §17; x along the ring's δ_r, y along δ_t).
GLOBAL = ("cage_angle", "cage_speed", "ring_dr", "ring_dt", "ring_gr", "ring_gt",
          "ring_vr", "ring_vt", "ring_wr", "ring_wt", "ring_axial",
          "cage_x", "cage_y", "cage_vx", "cage_vy")
#: The cage centre's position unknowns and their velocities, in the same order (cage whirl).
CAGE_CENTRE = ("cage_x", "cage_y")
CAGE_CENTRE_RATES = ("cage_vx", "cage_vy")
#: The ring's position unknowns (algebraic with a quasi-static ring, differential otherwise).
RING = ("ring_dr", "ring_dt", "ring_gr", "ring_gt")
#: The ring's velocity unknowns, in the order of RING (a dynamic ring only).
RING_RATES = ("ring_vr", "ring_vt", "ring_wr", "ring_wt")
#: Unknowns of the algebraic (quasi-static) equations of theory.md §5.
ALGEBRAIC = {"radial_position", "tilt", "ring_dr", "ring_dt", "ring_gr", "ring_gt",
             "axial_position", "ring_axial"}


def split_static(z: np.ndarray, Z: int):
    """The unknowns of the algebraic equations alone (theory.md §5, the static problem) in their
    order z = (u (Z,), β (Z,), ring (δ_r, δ_t, γ_r, γ_t)) -> (u, β, ring)."""
    return z[:Z], z[Z : 2 * Z], z[2 * Z :]


@dataclass(frozen=True)
class Layout:
    rollers: int
    skew: bool
    cage: bool
    tilt: bool
    ring_dynamic: bool = False  #: the ring as a body: its velocities are unknowns (§15)
    flange: bool = False  #: roller end-flange contacts: the rollers' axial positions (§16)
    ring_axial: bool = False  #: the ring's axial displacement (flanges and an axial load, §16)
    whirl: bool = False  #: the cage centre and its velocity (cage whirl, §17)
    spin_angle: bool = False  #: the rollers' spin angles (a defect or waviness on a roller, §4)

    @property
    def local_names(self) -> tuple[str, ...]:
        off = set()
        if not self.skew:
            off |= {"skew_angle", "skew_rate"}
        if not self.tilt:
            off |= {"tilt"}
        if not self.flange:
            off |= {"axial_position"}
        if not self.spin_angle:
            off |= {SPIN_ANGLE}
        return tuple(n for n in LOCAL if n not in off)

    @property
    def global_names(self) -> tuple[str, ...]:
        off = set()
        if not self.cage:
            off |= {"cage_angle", "cage_speed"}
        if not self.tilt:
            off |= {"ring_gr", "ring_gt", "ring_wr", "ring_wt"}
        if not self.ring_dynamic:
            off |= set(RING_RATES)
        if not self.ring_axial:
            off |= {"ring_axial"}
        if not self.whirl:
            off |= set(CAGE_CENTRE + CAGE_CENTRE_RATES)
        return tuple(n for n in GLOBAL if n not in off)

    @property
    def n_local(self) -> int:
        return len(self.local_names)

    @property
    def n_global(self) -> int:
        return len(self.global_names)

    @property
    def size(self) -> int:
        return self.rollers * self.n_local + self.n_global

    @property
    def local_map(self) -> np.ndarray:
        """Kernel index (into ``LOCAL``) of each compact local unknown."""
        return np.array([LOCAL.index(n) for n in self.local_names], dtype=np.int64)

    @property
    def global_map(self) -> np.ndarray:
        """Kernel index (into ``GLOBAL``) of each compact global unknown."""
        return np.array([GLOBAL.index(n) for n in self.global_names], dtype=np.int64)

    def index(self, name: str, roller: int | None = None) -> int:
        """Compact index of unknown ``name`` (of roller ``roller``, zero-based, if local)."""
        if name in self.local_names:
            if roller is None:
                raise ValueError(f"'{name}' is per roller: give roller=0..{self.rollers - 1}")
            return roller * self.n_local + self.local_names.index(name)
        if name in self.global_names:
            return self.rollers * self.n_local + self.global_names.index(name)
        raise KeyError(f"'{name}' is not an unknown of this scene (physics switched off?)")

    def names(self) -> list[str]:
        """Name of every compact unknown, e.g. ``orbit_speed[3]``."""
        out = [f"{n}[{j}]" for j in range(self.rollers) for n in self.local_names]
        return out + list(self.global_names)

    @property
    def algebraic(self) -> np.ndarray:
        """Boolean mask of the algebraic unknowns."""
        loc = [n in ALGEBRAIC for n in self.local_names] * self.rollers
        alg = ALGEBRAIC - set(RING) if self.ring_dynamic else ALGEBRAIC
        return np.array(loc + [n in alg for n in self.global_names])

    def sparsity(self) -> tuple[np.ndarray, np.ndarray]:
        """Block-arrow pattern as (rows, cols) of the structurally non-zero entries."""
        Z, nl, ng = self.rollers, self.n_local, self.n_global
        rows, cols = [], []
        blk = np.arange(nl)
        glob = Z * nl + np.arange(ng)
        for j in range(Z):
            loc = j * nl + blk
            r, c = np.meshgrid(loc, loc, indexing="ij")
            rows.append(r.ravel()), cols.append(c.ravel())
            r, c = np.meshgrid(loc, glob, indexing="ij")
            rows.append(r.ravel()), cols.append(c.ravel())
            rows.append(c.ravel()), cols.append(r.ravel())
        r, c = np.meshgrid(glob, glob, indexing="ij")
        rows.append(r.ravel()), cols.append(c.ravel())
        return np.concatenate(rows), np.concatenate(cols)

    def unpack(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Compact (unscaled) vector or (..., N) array -> full (..., Z, len(LOCAL)) and (..., len(GLOBAL)) arrays."""
        y = np.asarray(y)
        lead = y.shape[:-1]
        Z, nl = self.rollers, self.n_local
        full_l = np.zeros(lead + (Z, len(LOCAL)))
        full_g = np.zeros(lead + (len(GLOBAL),))
        full_l[..., self.local_map] = y[..., : Z * nl].reshape(lead + (Z, nl))
        full_g[..., self.global_map] = y[..., Z * nl :]
        return full_l, full_g

    def pack(self, full_l: np.ndarray, full_g: np.ndarray) -> np.ndarray:
        """Inverse of :meth:`unpack` for one state."""
        return np.concatenate([full_l[:, self.local_map].ravel(), full_g[self.global_map]])
