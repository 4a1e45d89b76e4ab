"""MuJoCo models of the scenario's object kinds (paintings, tables, benches, a TV on a stand, ...).

Every object gets one collision geom named ``object/<name>``: its footprint (a box of
``size = [depth, width]`` or a cylinder of ``radius``) extruded to its height, the shape the Rust
core plans and checks contacts against. That geom is put in geom group :data:`COLLISION_GROUP`,
which the renderers hide; what the cameras see are visual parts (no contacts, no mass) shaped
after the kind, inside the same footprint and height, named ``object/<name>/<part>``.

Object frame: x along the depth (the object faces +x, where its interaction space lies), y along
the width, z up from the floor.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import mujoco

from proxemic.palette import DEFAULT_OBJECT_COLOR, OBJECT_COLORS, rgba

#: Geom group of the collision geoms (MuJoCo's default visual options show groups 0-2 only).
COLLISION_GROUP = 3

#: Colours of static objects by kind (RGBA): the main material of each model, the palette's
#: (:data:`proxemic.palette.OBJECT_COLORS`, the top-down view's too).
OBJECT_COLOURS: dict[str, tuple[float, float, float, float]] = {kind: rgba(c) for kind, c in OBJECT_COLORS.items()}
_DEFAULT = rgba(DEFAULT_OBJECT_COLOR)
_METAL = (0.55, 0.56, 0.6, 1.0)
_DARK = (0.15, 0.13, 0.12, 1.0)
_LINEN = (0.95, 0.95, 0.97, 1.0)

Rgba = tuple[float, float, float, float]


def _shade(c: Rgba, f: float) -> Rgba:
    return (c[0] * f, c[1] * f, c[2] * f, c[3])


class _Parts:
    """Adds visual geoms to the world body in an object's frame."""

    def __init__(self, wb: mujoco.MjsBody, obj: dict[str, Any], visual: bool = True) -> None:
        self.wb, self.name, self.visual = wb, obj["name"], visual
        self.x, self.y, self.th = (float(v) for v in obj["pose"])
        self.count = 0

    def _place(self, lx: float, ly: float) -> list[float]:
        c, s = math.cos(self.th), math.sin(self.th)
        return [self.x + c * lx - s * ly, self.y + s * lx + c * ly]

    def _quat(self) -> list[float]:
        return [math.cos(self.th / 2.0), 0.0, 0.0, math.sin(self.th / 2.0)]

    def box(self, part: str, centre: tuple[float, float, float], half: tuple[float, float, float], rgba: Rgba) -> None:
        """A box with half sizes `half` centred at `centre` (object frame)."""
        self._add(part, mujoco.mjtGeom.mjGEOM_BOX, centre, list(half), rgba)

    def cylinder(self, part: str, centre: tuple[float, float, float], radius: float, half_h: float, rgba: Rgba) -> None:
        """An upright cylinder."""
        self._add(part, mujoco.mjtGeom.mjGEOM_CYLINDER, centre, [radius, half_h, 0.0], rgba)

    def sphere(self, part: str, centre: tuple[float, float, float], radius: float, rgba: Rgba) -> None:
        """A sphere."""
        self._add(part, mujoco.mjtGeom.mjGEOM_SPHERE, centre, [radius, 0.0, 0.0], rgba)

    def _add(self, part: str, kind: Any, centre: tuple[float, float, float], size: list[float], rgba: Rgba) -> None:
        self.count += 1
        if not self.visual:  # the physics model: counted (the collision geom's group), not added
            return
        self.wb.add_geom(
            name=f"object/{self.name}/{part}",
            type=kind,
            size=size,
            pos=[*self._place(centre[0], centre[1]), centre[2]],
            quat=self._quat(),
            rgba=list(rgba),
            contype=0,
            conaffinity=0,
            mass=0.0,
        )


def _legs(p: _Parts, hx: float, hy: float, top: float, r: float, rgba: Rgba) -> None:
    inset = r * 1.5
    for i, (sx, sy) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1))):
        p.box(f"leg{i}", (sx * (hx - inset), sy * (hy - inset), top / 2.0), (r, r, top / 2.0), rgba)


def _wall_hung(p: _Parts, d: float, w: float, h: float, c: Rgba, frame: Rgba) -> None:
    """A painting or poster: a framed canvas on the wall, its top at the object's height."""
    ch = min(1.0, 0.6 * h)
    p.box("frame", (-d * 0.1, 0.0, h - ch / 2.0), (d * 0.4, w / 2.0, ch / 2.0), frame)
    p.box("canvas", (d * 0.1, 0.0, h - ch / 2.0), (d * 0.4, w / 2.0 - 0.05, ch / 2.0 - 0.05), c)


def _model(kind: str) -> Callable[[_Parts, float, float, float, Rgba], None] | None:
    """The box-footprint model of `kind`: a function of (parts, depth, width, height, colour)."""

    def painting(p: _Parts, d: float, w: float, h: float, c: Rgba) -> None:
        _wall_hung(p, d, w, h, c, (0.7, 0.55, 0.2, 1.0))

    def poster(p: _Parts, d: float, w: float, h: float, c: Rgba) -> None:
        _wall_hung(p, d, w, h, c, _LINEN)

    def tv(p: _Parts, d: float, w: float, h: float, c: Rgba) -> None:
        sh = min(0.7, 0.5 * h)
        p.box("screen", (0.0, 0.0, h - sh / 2.0), (min(d, 0.08) / 2.0, w / 2.0, sh / 2.0), c)
        p.box(
            "picture",
            (min(d, 0.08) / 2.0, 0.0, h - sh / 2.0),
            (0.005, w / 2.0 - 0.04, sh / 2.0 - 0.04),
            (0.2, 0.35, 0.55, 1.0),
        )
        p.box("pole", (0.0, 0.0, (h - sh) / 2.0), (0.03, 0.03, (h - sh) / 2.0), _METAL)
        p.box("foot", (0.0, 0.0, 0.01), (min(d, 0.3) / 2.0, min(w, 0.4) / 2.0, 0.01), _METAL)

    def table(p: _Parts, d: float, w: float, h: float, c: Rgba) -> None:
        p.box("top", (0.0, 0.0, h - 0.025), (d / 2.0, w / 2.0, 0.025), c)
        _legs(p, d / 2.0, w / 2.0, h - 0.05, 0.03, _shade(c, 0.7))

    def bench(p: _Parts, d: float, w: float, h: float, c: Rgba) -> None:
        p.box("seat", (0.0, 0.0, h - 0.03), (d / 2.0, w / 2.0, 0.03), c)
        for i, sy in enumerate((1, -1)):
            p.box(
                f"side{i}",
                (0.0, sy * (w / 2.0 - 0.05), (h - 0.06) / 2.0),
                (d / 2.0 - 0.02, 0.03, (h - 0.06) / 2.0),
                _shade(c, 0.7),
            )

    def sofa(p: _Parts, d: float, w: float, h: float, c: Rgba) -> None:
        seat = min(0.45, 0.55 * h)
        p.box("seat", (0.05 * d, 0.0, seat / 2.0), (0.45 * d, w / 2.0 - 0.1, seat / 2.0), c)
        p.box("back", (-0.4 * d, 0.0, h / 2.0), (0.1 * d, w / 2.0, h / 2.0), _shade(c, 0.85))
        for i, sy in enumerate((1, -1)):
            p.box(
                f"arm{i}",
                (0.05 * d, sy * (w / 2.0 - 0.05), 0.6 * h / 2.0 + 0.05),
                (0.45 * d, 0.05, 0.6 * h / 2.0),
                _shade(c, 0.85),
            )

    def bed(p: _Parts, d: float, w: float, h: float, c: Rgba) -> None:
        p.box("mattress", (0.0, 0.0, h - 0.08), (d / 2.0, w / 2.0, 0.08), c)
        p.box("frame", (0.0, 0.0, h - 0.19), (d / 2.0, w / 2.0, 0.03), _METAL)
        _legs(p, d / 2.0, w / 2.0, h - 0.22, 0.025, _METAL)
        # a pillow at the head end of the long side
        if d >= w:
            p.box("pillow", (-d / 2.0 + 0.2, 0.0, h + 0.03), (0.15, min(w, 0.6) / 2.0 - 0.05, 0.04), _LINEN)
        else:
            p.box("pillow", (0.0, -w / 2.0 + 0.2, h + 0.03), (min(d, 0.6) / 2.0 - 0.05, 0.15, 0.04), _LINEN)

    def plinth(p: _Parts, d: float, w: float, h: float, c: Rgba) -> None:
        p.box("block", (0.0, 0.0, h / 2.0), (d / 2.0, w / 2.0, h / 2.0), c)
        p.box("cap", (0.0, 0.0, h - 0.02), (d / 2.0 + 0.02, w / 2.0 + 0.02, 0.02), _shade(c, 0.9))

    def exhibit(p: _Parts, d: float, w: float, h: float, c: Rgba) -> None:
        base = 0.6 * h
        plinth(p, d, w, base, OBJECT_COLOURS["plinth"])
        r = min(d, w, h - base) / 2.0
        p.sphere("piece", (0.0, 0.0, base + r), r, c)

    def cabinet(p: _Parts, d: float, w: float, h: float, c: Rgba) -> None:
        p.box("body", (0.0, 0.0, h / 2.0), (d / 2.0, w / 2.0, h / 2.0), c)
        p.box("door_gap", (d / 2.0, 0.0, h / 2.0), (0.003, 0.005, h / 2.0 - 0.05), _DARK)

    def chair(p: _Parts, d: float, w: float, h: float, c: Rgba) -> None:
        seat = min(0.45, 0.5 * h)
        p.box("seat", (0.0, 0.0, seat - 0.02), (d / 2.0, w / 2.0, 0.02), c)
        p.box("back", (-d / 2.0 + 0.02, 0.0, (seat + h) / 2.0), (0.02, w / 2.0, (h - seat) / 2.0), c)
        _legs(p, d / 2.0, w / 2.0, seat - 0.04, 0.02, _shade(c, 0.7))

    def pillar(p: _Parts, d: float, w: float, h: float, c: Rgba) -> None:
        p.box("shaft", (0.0, 0.0, h / 2.0), (d / 2.0, w / 2.0, h / 2.0), c)

    return {
        "painting": painting,
        "poster": poster,
        "tv": tv,
        "table": table,
        "bench": bench,
        "sofa": sofa,
        "bed": bed,
        "stretcher": bed,
        "plinth": plinth,
        "exhibit": exhibit,
        "cabinet": cabinet,
        "chair": chair,
        "pillar": pillar,
    }.get(kind)


def _round_model(p: _Parts, kind: str, r: float, h: float, c: Rgba) -> None:
    """Models on a round footprint."""
    if kind in ("round_table", "table"):
        p.cylinder("top", (0.0, 0.0, h - 0.025), r, 0.025, c)
        p.cylinder("pole", (0.0, 0.0, (h - 0.05) / 2.0), 0.05, (h - 0.05) / 2.0, _shade(c, 0.7))
        p.cylinder("foot", (0.0, 0.0, 0.015), min(r, 0.3), 0.015, _shade(c, 0.7))
    elif kind == "exhibit":
        base = 0.6 * h
        p.cylinder("plinth", (0.0, 0.0, base / 2.0), r, base / 2.0, OBJECT_COLOURS["plinth"])
        q = min(r, (h - base) / 2.0)
        p.sphere("piece", (0.0, 0.0, base + q), q, c)
    else:  # pillars, round plinths and anything else round: a column with a cap
        p.cylinder("shaft", (0.0, 0.0, h / 2.0), r, h / 2.0, c)
        p.cylinder("cap", (0.0, 0.0, h - 0.03), r * 1.08, 0.03, _shade(c, 0.9))


def add_object(wb: mujoco.MjsBody, obj: dict[str, Any], *, visual: bool = True) -> int:
    """Adds an object's collision geom and its kind's visual model to the world body `wb`.

    Args:
        wb: The spec's world body.
        obj: A validated object of the scenario dict (``name``, ``kind``, ``pose``, ``size`` or
            ``radius``, ``height``, ``solid``).
        visual: False for the physics model: only the collision geom of a solid object is added
            (a non-solid object then adds nothing).

    Returns:
        The number of visual parts of the kind's model (0 for a kind without a model: the
        collision geom is then shown instead).
    """
    x, y, th = (float(v) for v in obj["pose"])
    h = float(obj["height"])
    colour = OBJECT_COLOURS.get(obj["kind"], _DEFAULT)
    collide = 1 if obj["solid"] else 0
    parts = _Parts(wb, obj, visual)
    if obj["radius"] is not None:
        r = float(obj["radius"])
        _round_model(parts, obj["kind"], r, h, colour)
        shape, size = mujoco.mjtGeom.mjGEOM_CYLINDER, [r, h / 2.0, 0.0]
    else:
        d, w = (float(v) for v in obj["size"])
        model = _model(obj["kind"])
        if model is not None:
            model(parts, d, w, h, colour)
        shape, size = mujoco.mjtGeom.mjGEOM_BOX, [d / 2.0, w / 2.0, h / 2.0]
    if not visual and not collide:
        return parts.count
    wb.add_geom(
        name=f"object/{obj['name']}",
        type=shape,
        size=size,
        pos=[x, y, h / 2.0],
        quat=[math.cos(th / 2.0), 0.0, 0.0, math.sin(th / 2.0)],
        rgba=list(colour),
        contype=collide,
        conaffinity=collide,
        group=COLLISION_GROUP if parts.count else 0,
    )
    return parts.count
