"""Named bearing parameter sets, as cited data (pipeline stage: scene -> **parameters**).

A preset fills the ``[bearing]`` table (and the preset-dependent defaults of other tables) of a
scene in the scene file's own units (mm, GPa, ...). Keys given in the scene file override the
preset. See ``docs/theory.md`` §2 for the reading of each value.
"""

from __future__ import annotations

from types import MappingProxyType

CITATION_YANG2024 = (
    "Yang, Wang, Wang & Wen, 'Dynamic Modeling and Behavior of Cylindrical Roller Bearings "
    "Considering Roller Skew and the Influence of Eccentric Load', Lubricants 2024, 12(9), 317, "
    "doi:10.3390/lubricants12090317"
)

_PRESETS = {
    "harris36": {
        "citation": CITATION_YANG2024 + ", Table 1 (after Harris & Kotzalas, Rolling Bearing "
        "Analysis, 5th ed.). [reading] pitch diameter = (D + d)/2 = 183 mm: d = 146 mm "
        "cannot be the raceway, 36 rollers of 14 mm would not fit.",
        "bearing": {
            "rollers": 36,
            "outer_diameter_mm": 220.0,
            "bore_mm": 146.0,
            "roller_diameter_mm": 14.0,
            "roller_length_mm": 20.0,
            "effective_length_mm": 17.0,
            "crown_radius_mm": 40.0,
            "profile": "end-crown",
            "radial_clearance_mm": 0.064,
        },
        # Not given by the paper: project default (theory.md §2).
        "cage": {"pocket_clearance_mm": 0.25},
    },
    "yang20": {
        "citation": CITATION_YANG2024 + ", Table 2 (the paper's baseline bearing).",
        "bearing": {
            "rollers": 20,
            "outer_diameter_mm": 60.0,
            "bore_mm": 30.0,
            "roller_diameter_mm": 4.0,
            "roller_length_mm": 25.5,
            "effective_length_mm": 22.95,
            "crown_radius_mm": 20.0,
            "profile": "end-crown",
            "radial_clearance_mm": 0.010,
        },
        "cage": {"pocket_clearance_mm": 0.10},
    },
}

#: Read-only view of the presets: ``PRESETS[name]["bearing"]`` etc.
PRESETS = MappingProxyType(_PRESETS)

#: Steel for rollers and rings (theory.md §2).
STEEL = MappingProxyType(
    {"youngs_modulus_GPa": 207.0, "poisson_ratio": 0.3, "density_kg_m3": 7850.0}
)


def preset_names() -> list[str]:
    """Names accepted by ``[bearing] preset``."""
    return sorted(_PRESETS)


# Cage proportions: the paper gives no cage drawing; theory.md §2 reads a design rule. Bearing data,
# so here, below the scene (its pocket check) and physics/cage.py (mass, inertia, churning).
CAGE_THICKNESS_PER_DW = 0.6  # radial thickness 0.6 D_w, centred on the pitch circle (theory.md §2)
CAGE_EXTRA_WIDTH_PER_DW = 0.5  # width L + 0.5 D_w (theory.md §2)


def cage_annulus(pitch_radius_m, roller_diameter_m, roller_length_m):
    """Cage annulus (inner radius, outer radius, width) (theory.md §2), in the units of the
    arguments ([m] in physics): thickness 0.6 D_w centred on the pitch circle, width
    L + 0.5 D_w. The radii serve the side-face churning (theory.md §9)."""
    half_t = 0.5 * CAGE_THICKNESS_PER_DW * roller_diameter_m
    width = roller_length_m + CAGE_EXTRA_WIDTH_PER_DW * roller_diameter_m
    return pitch_radius_m - half_t, pitch_radius_m + half_t, width
