"""The colours of proxemic's views: one palette for the top-down renderer, the plots and MuJoCo.

RGB triples of 0-255 integers; :func:`rgba` converts one to MuJoCo's 0-1 RGBA.
"""

from __future__ import annotations

import types
from collections.abc import Mapping

RGB = tuple[int, int, int]

#: Colour of the walkable floor inside the scene bounds.
FLOOR_COLOR: RGB = (244, 242, 236)
#: Colour of the image area outside the scene bounds (the margin).
OUTSIDE_COLOR: RGB = (214, 214, 214)
#: Colour of wall footprints.
WALL_COLOR: RGB = (64, 64, 64)
#: Tint blended over the floor inside interaction spaces.
INTERACTION_COLOR: RGB = (255, 196, 64)
#: Alpha of the interaction-space tint.
INTERACTION_ALPHA: float = 0.3
#: Fill colour of people.
PERSON_COLOR: RGB = (226, 96, 70)
#: Outline colour of people.
PERSON_OUTLINE: RGB = (120, 40, 25)
#: Heading tick colour of people.
PERSON_TICK: RGB = (50, 20, 10)
#: Outline and heading tick colour of robots.
ROBOT_OUTLINE: RGB = (20, 20, 20)
ROBOT_TICK: RGB = (255, 255, 255)
#: Categorical palette for robots (and their goals, paths and trails), indexed by robot index.
ROBOT_PALETTE: tuple[RGB, ...] = (
    (31, 119, 180),
    (44, 160, 44),
    (148, 103, 189),
    (23, 190, 207),
    (188, 189, 34),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
)
#: Fill colour of static objects by kind.
OBJECT_COLORS: Mapping[str, RGB] = types.MappingProxyType(
    {
        "painting": (150, 92, 40),
        "exhibit": (122, 102, 172),
        "bench": (166, 124, 72),
        "plinth": (172, 170, 160),
        "table": (186, 146, 96),
        "round_table": (186, 146, 96),
        "tv": (40, 40, 48),
        "poster": (206, 164, 60),
        "bed": (150, 182, 212),
        "stretcher": (186, 198, 212),
        "sofa": (118, 150, 108),
        "pillar": (108, 108, 108),
        "cabinet": (146, 108, 78),
        "chair": (172, 132, 90),
    }
)
#: Ring colours of the intimate, personal and social zones.
ZONE_COLORS: tuple[RGB, RGB, RGB] = ((200, 30, 30), (235, 140, 20), (70, 130, 200))
#: Colour of group outlines and o-space fills.
GROUP_COLOR: RGB = (128, 50, 170)
#: Alpha of the o-space fill.
OSPACE_ALPHA: float = 0.35
#: Interaction-space colours at the agenda's idle cost and at its active cost (R(t) in between is
#: interpolated linearly).
OBJECT_COST_COLORS: tuple[RGB, RGB] = ((255, 226, 120), (215, 35, 25))
#: Alpha of the R(t) colour over the floor.
OBJECT_COST_ALPHA: float = 0.55
#: Fill colour of objects of an unknown kind.
DEFAULT_OBJECT_COLOR: RGB = (150, 150, 150)


def rgba(rgb: RGB, alpha: float = 1.0) -> tuple[float, float, float, float]:
    """`rgb` (0-255) as MuJoCo's RGBA (0-1)."""
    return (rgb[0] / 255.0, rgb[1] / 255.0, rgb[2] / 255.0, alpha)
