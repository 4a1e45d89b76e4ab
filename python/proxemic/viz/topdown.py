"""A cheap numpy-only top-down RGB renderer for proxemic scenarios.

The static part of the scene (floor, interaction spaces, objects, walls) is rasterised once into a
background image; :meth:`TopDownRenderer.render` copies it and draws the dynamic part (planned
paths, trails, goals, people and robots) with a handful of vectorised numpy operations, so a
640x480 frame with dozens of people takes on the order of a millisecond.

Conventions: world coordinates are metres with y up; pixel coordinates are ``(col, row)`` floats
where pixel ``(r, c)`` covers ``[c, c + 1) x [r, r + 1)`` and its centre is ``(c + 0.5, r + 0.5)``.
Row 0 is the top of the image, so larger world y means a smaller row. The colours are
:mod:`proxemic.palette`'s, the polygons :mod:`proxemic.viz.geometry`'s, the drawing primitives
:mod:`proxemic.viz.raster`'s.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from proxemic.errors import input_error
from proxemic.palette import (
    DEFAULT_OBJECT_COLOR,
    FLOOR_COLOR,
    GROUP_COLOR,
    INTERACTION_ALPHA,
    INTERACTION_COLOR,
    OBJECT_COLORS,
    OBJECT_COST_ALPHA,
    OBJECT_COST_COLORS,
    OSPACE_ALPHA,
    OUTSIDE_COLOR,
    PERSON_COLOR,
    PERSON_OUTLINE,
    PERSON_TICK,
    RGB,
    ROBOT_OUTLINE,
    ROBOT_PALETTE,
    ROBOT_TICK,
    WALL_COLOR,
    ZONE_COLORS,
)
from proxemic.viz.geometry import interaction_polygon, object_polygon, scene_bounds, wall_polygon
from proxemic.viz.raster import (
    blend_discs,
    draw_discs,
    draw_segments,
    mix,
    nearest_people,
    pixel_view,
    pixels,
    polygon_mask,
    ring_segments,
    rows,
)

__all__ = ["FRAME_SIZE", "OVERLAYS", "ZONE_NEAREST", "TopDownRenderer"]

#: The switchable top-down overlays: ``zones`` (Hall's intimate, personal and social rings around
#: each person), ``groups`` (detected groups: their o-space filled, the group outlined),
#: ``object_spaces`` (interaction spaces coloured by the agenda's R(t) now) and ``path`` (the
#: robots' global paths).
OVERLAYS: tuple[str, ...] = ("zones", "groups", "object_spaces", "path")
#: The zones overlay rings only the people nearest to a robot (the closest this many to each robot),
#: so that a crowded scene (the museum's 52 people) stays readable.
ZONE_NEAREST: int = 6

#: The default frame size (width, height) in pixels of every view: the env's renders, videos and
#: the top-down renderer.
FRAME_SIZE: tuple[int, int] = (640, 480)

_DEFAULT_ROBOT_RADIUS = 0.24


class TopDownRenderer:
    """Fast top-down RGB renderer of a scenario (numpy only, no matplotlib).

    The world-to-pixel transform keeps the aspect ratio, fits ``bounds`` grown by ``margin`` into the
    image (centred along the slack axis) and puts world y up. The static background is rasterised
    once at construction; :meth:`render` returns a fresh frame each call and never mutates it.

    Attributes:
        width: Image width in pixels.
        height: Image height in pixels.
        scale: Pixels per metre.
        bounds: Scene bounds ``(xmin, ymin, xmax, ymax)`` in metres.
        margin: Margin around the bounds in metres.

    """

    def __init__(
        self, scenario: Mapping[str, Any], width: int = FRAME_SIZE[0], height: int = FRAME_SIZE[1], margin: float = 0.5
    ) -> None:
        """Precompute the transform and rasterise the static background.

        Args:
            scenario: The scenario dict produced by the Rust core (see the module docstring).
            width: Image width in pixels.
            height: Image height in pixels.
            margin: Extra world space (metres) shown around the scene bounds on every side.

        Raises:
            InputError: If ``width``, ``height`` or ``margin`` is out of range (a ``ValueError``).

        """
        if width < 1 or height < 1:
            raise input_error("width, height", "a positive image size in pixels", f"{width}x{height}")
        if not margin >= 0.0:
            raise input_error("margin", "a margin >= 0 m", margin)
        self.width = int(width)
        self.height = int(height)
        self.margin = float(margin)
        self.bounds = scene_bounds(scenario)
        xmin, ymin, xmax, ymax = self.bounds
        span_x = max(xmax - xmin + 2.0 * self.margin, 1e-9)
        span_y = max(ymax - ymin + 2.0 * self.margin, 1e-9)
        self.scale = min(self.width / span_x, self.height / span_y)
        self._x0 = xmin - self.margin
        self._y1 = ymax + self.margin
        self._off_c = (self.width - span_x * self.scale) / 2.0
        self._off_r = (self.height - span_y * self.scale) / 2.0
        self._robot_radii = np.array(
            [float(r.get("radius", _DEFAULT_ROBOT_RADIUS)) for r in scenario.get("robots", [])],
            dtype=np.float64,
        )
        self._palette = np.array(ROBOT_PALETTE, dtype=np.uint8)
        self._trail_palette = np.array([mix(c, (255, 255, 255), 0.5) for c in ROBOT_PALETTE], dtype=np.uint8)
        self._stencils: dict[float, tuple[np.ndarray, np.ndarray]] = {}
        self._background = self._rasterise_background(scenario)
        self._background.flags.writeable = False

    # -- transform -------------------------------------------------------------------------------

    def world_to_pixel(self, xy: np.ndarray) -> np.ndarray:
        """Map world points to continuous pixel coordinates.

        Args:
            xy: ``(N, 2)`` (or ``(2,)``) world coordinates in metres; extra trailing columns are
                ignored.

        Returns:
            Float pixel coordinates ``(col, row)`` with the same leading shape as ``xy``. Pixel
            ``(r, c)`` covers ``[c, c + 1) x [r, r + 1)``; row 0 is the top of the image.

        """
        p = np.asarray(xy, dtype=np.float64)
        out = np.empty((*p.shape[:-1], 2), dtype=np.float64)
        out[..., 0] = self._off_c + (p[..., 0] - self._x0) * self.scale
        out[..., 1] = self._off_r + (self._y1 - p[..., 1]) * self.scale
        return out

    def pixel_to_world(self, px: np.ndarray) -> np.ndarray:
        """Inverse of :meth:`world_to_pixel`.

        Args:
            px: ``(N, 2)`` (or ``(2,)``) float pixel coordinates ``(col, row)``.

        Returns:
            World coordinates in metres with the same shape.

        """
        p = np.asarray(px, dtype=np.float64)
        out = np.empty((*p.shape[:-1], 2), dtype=np.float64)
        out[..., 0] = self._x0 + (p[..., 0] - self._off_c) / self.scale
        out[..., 1] = self._y1 - (p[..., 1] - self._off_r) / self.scale
        return out

    @property
    def background(self) -> np.ndarray:
        """The static background image (read-only ``(height, width, 3)`` uint8 view)."""
        return self._background

    def robot_color(self, index: int) -> tuple[int, int, int]:
        """Return the palette colour used for robot ``index`` (its disc, goal, path and trail).

        Args:
            index: Robot index (wraps around the palette).

        Returns:
            An ``(r, g, b)`` tuple of ints.

        """
        return ROBOT_PALETTE[index % len(ROBOT_PALETTE)]

    # -- background ------------------------------------------------------------------------------

    def _fill_polygon(self, img: np.ndarray, poly: np.ndarray, color: RGB, alpha: float = 1.0) -> None:
        """Fill a world-frame polygon into ``img`` (optionally alpha-blended)."""
        res = polygon_mask(self.world_to_pixel(poly), self.height, self.width)
        if res is None:
            return
        rs, cs, mask = res
        region = img[rs, cs]
        if alpha >= 1.0:
            region[mask] = color
        else:
            blended = region[mask].astype(np.float64) * (1.0 - alpha) + np.asarray(color, np.float64) * alpha
            region[mask] = np.rint(blended).astype(np.uint8)

    def _outline_polygon(self, img: np.ndarray, poly: np.ndarray, color: RGB) -> None:
        """Draw the closed outline of a world-frame polygon into ``img``."""
        px = self.world_to_pixel(poly)
        p1 = np.roll(px, -1, axis=0)
        draw_segments(img, px, p1, np.tile(np.asarray(color, np.uint8), (len(px), 1)))

    def _rasterise_background(self, scenario: Mapping[str, Any]) -> np.ndarray:
        """Rasterise floor, interaction spaces, objects and walls into a new image.

        Also records, for the ``object_spaces`` overlay, which visible floor pixels lie in which
        object's interaction space (the later object wins where spaces overlap) and their floor
        colour before tinting.
        """
        img = np.empty((self.height, self.width, 3), dtype=np.uint8)
        img[:] = OUTSIDE_COLOR
        xmin, ymin, xmax, ymax = self.bounds
        floor = np.array([[xmin, ymin], [xmax, ymin], [xmax, ymax], [xmin, ymax]])
        self._fill_polygon(img, floor, FLOOR_COLOR)
        untinted = img.copy()
        label = np.full((self.height, self.width), -1, dtype=np.int32)
        objects = list(scenario.get("objects", []))
        names: list[str] = []
        for obj in objects:
            space = interaction_polygon(obj)
            if space is not None:
                self._fill_polygon(img, space, INTERACTION_COLOR, INTERACTION_ALPHA)
                res = polygon_mask(self.world_to_pixel(space), self.height, self.width)
                if res is not None:
                    label[res[0], res[1]][res[2]] = len(names)
                names.append(str(obj.get("name", len(names))))
        tinted = img.copy()
        for obj in objects:
            poly = object_polygon(obj)
            color = OBJECT_COLORS.get(str(obj.get("kind")), DEFAULT_OBJECT_COLOR)
            if not obj.get("solid", True):
                color = mix(color, FLOOR_COLOR, 0.5)  # non-solid objects are drawn faded
            self._fill_polygon(img, poly, color)
            self._outline_polygon(img, poly, mix(color, (0, 0, 0), 0.45))
        for wall in scenario.get("walls", []):
            self._fill_polygon(img, wall_polygon(wall), WALL_COLOR)
        label[np.any(img != tinted, axis=2)] = -1  # covered by an object, its outline or a wall
        self._space_names = tuple(names)
        flat = np.flatnonzero(label.reshape(-1) >= 0)
        self._space_pixels = flat
        self._space_label = label.reshape(-1)[flat]
        self._space_floor = untinted.reshape(-1, 3)[flat].astype(np.float32)
        agenda = scenario.get("agenda") or {}
        self._cost_range = (float(agenda.get("idle", 1.5)), float(agenda.get("active", 3.5)))
        self._space_cache: tuple[tuple[float, ...], np.ndarray] | None = None
        return img

    # -- frames ----------------------------------------------------------------------------------

    def render(
        self,
        robots: np.ndarray,
        people: np.ndarray,
        *,
        goals: np.ndarray | None = None,
        paths: Sequence[np.ndarray] | None = None,
        trails: Sequence[np.ndarray] | None = None,
        zones: Sequence[float] | None = None,
        groups: Sequence[Sequence[int]] | None = None,
        object_costs: Mapping[str, float] | None = None,
    ) -> np.ndarray:
        """Render one frame.

        Draw order: background, object spaces by R(t), group o-spaces, zone rings, trails, planned
        paths (dashed), goals (crosses), group outlines, people, robots. Goals, paths and trails are
        matched to robots by index and share the robot's palette colour (trails lightened). The
        overlays (see :data:`OVERLAYS`) are drawn only when their argument is given.

        Args:
            robots: ``(R, 3)`` robot poses ``x, y, theta`` (R may be 0). Robot ``i`` is drawn with the
                radius of the scenario's robot ``i`` (0.24 m if the scenario has fewer robots).
            people: ``(P, 4)`` people ``x, y, theta, radius`` (P may be 0). Rows with non-finite
                values are skipped.
            goals: Optional ``(R, 2)`` goal positions.
            paths: Optional list of ``(K, 2)`` planned paths (world frame), one per robot.
            trails: Optional list of ``(K, 2)`` past positions, one per robot.
            zones: Optional radii in metres (e.g. Hall's intimate, personal and social: 0.45, 1.2,
                3.6) of rings drawn around the people nearest to each robot (:data:`ZONE_NEAREST`
                per robot; every person when there is no robot), in :data:`ZONE_COLORS` order.
            groups: Optional member index lists (into ``people``) of detected groups; groups of two
                or more get their o-space filled and an outline around the members. The o-space is
                drawn as the circle centred at the members' mean position whose radius is their
                mean distance to it minus their mean body radius (at least 0.2 m).
            object_costs: Optional R(t) per object name (``World.object_costs``): interaction
                spaces are coloured from the agenda's idle cost (pale) to its active cost (red).
                Objects missing from the mapping are drawn at the idle cost.

        Returns:
            A new ``(height, width, 3)`` uint8 RGB image.

        Raises:
            ValueError: If an input has the wrong shape.

        """
        robots_a = rows(robots, 3, "robots")
        people_a = rows(people, 4, "people")
        frame = self._background.copy()
        if object_costs is not None:
            self._draw_object_costs(frame, object_costs)
        outlines = None
        if groups:
            outlines = self._draw_groups(frame, people_a, groups)

        if zones is not None and len(people_a):
            self._draw_zone_rings(frame, nearest_people(people_a, robots_a, ZONE_NEAREST), zones)

        overlay = [
            self._polyline_batch(trails, self._trail_palette, dashed=False),
            self._polyline_batch(paths, self._palette, dashed=True),
        ]
        if goals is not None:
            overlay.append(self._cross_batch(rows(goals, 2, "goals")))
        if outlines is not None:
            overlay.append(outlines)
        overlay = [b for b in overlay if len(b[0])]
        if overlay:
            p0, p1, colors, dashed = (np.concatenate(parts) for parts in zip(*overlay, strict=True))
            draw_segments(frame, p0, p1, colors, thickness=2, dashed=dashed)
        if len(people_a):
            n = len(people_a)
            self._draw_bodies(
                frame,
                people_a[:, :3],
                people_a[:, 3],
                np.tile(np.asarray(PERSON_COLOR, np.uint8), (n, 1)),
                np.tile(np.asarray(PERSON_OUTLINE, np.uint8), (n, 1)),
                np.tile(np.asarray(PERSON_TICK, np.uint8), (n, 1)),
            )
        if len(robots_a):
            n = len(robots_a)
            radii = np.full(n, _DEFAULT_ROBOT_RADIUS)
            m = min(n, len(self._robot_radii))
            radii[:m] = self._robot_radii[:m]
            self._draw_bodies(
                frame,
                robots_a,
                radii,
                self._palette[np.arange(n) % len(self._palette)],
                np.tile(np.asarray(ROBOT_OUTLINE, np.uint8), (n, 1)),
                np.tile(np.asarray(ROBOT_TICK, np.uint8), (n, 1)),
            )
        return frame

    def _draw_object_costs(self, frame: np.ndarray, costs: Mapping[str, float]) -> None:
        """Colour the visible interaction-space pixels by their object's R(t) (cached per cost set)."""
        if len(self._space_pixels) == 0:
            return
        lo, hi = self._cost_range
        values = tuple(float(costs.get(name, lo)) for name in self._space_names)
        if self._space_cache is None or self._space_cache[0] != values:
            t = np.clip((np.asarray(values) - lo) / max(hi - lo, 1e-9), 0.0, 1.0)
            t = np.nan_to_num(t, nan=0.0)
            c0, c1 = (np.asarray(c, np.float32) for c in OBJECT_COST_COLORS)
            lut = c0[None, :] * (1.0 - t[:, None]) + c1[None, :] * t[:, None]  # (objects, 3)
            a = OBJECT_COST_ALPHA
            colours = self._space_floor * (1.0 - a) + lut[self._space_label] * a
            self._space_cache = (values, np.rint(colours).astype(np.uint8))
        pixel_view(frame)[self._space_pixels] = pixels(self._space_cache[1])

    def _draw_groups(
        self, frame: np.ndarray, people: np.ndarray, groups: Sequence[Sequence[int]]
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Blend the groups' o-spaces into ``frame``; return their outlines as dashed segments."""
        centres, ospace, outline = [], [], []
        n = len(people)
        for members in groups:
            idx = np.asarray([int(m) for m in members if 0 <= int(m) < n], dtype=np.intp)
            if len(idx) < 2:
                continue
            pts = people[idx, :2]
            c = pts.mean(axis=0)
            d = np.linalg.norm(pts - c, axis=1)
            centres.append(c)
            ospace.append(max(float(d.mean() - people[idx, 3].mean()), 0.2))
            outline.append(float(d.max() + people[idx, 3].max() + 0.15))
        empty = (np.zeros((0, 2)), np.zeros((0, 2)), np.zeros((0, 3), np.uint8), np.zeros(0, bool))
        if not centres:
            return empty
        cpx = self.world_to_pixel(np.asarray(centres))
        blend_discs(frame, cpx, np.asarray(ospace) * self.scale, GROUP_COLOR, OSPACE_ALPHA)
        starts, ends = [], []
        for c, r in zip(centres, outline, strict=True):
            a, b = ring_segments(c[None, :], r, 40)
            starts.append(a)
            ends.append(b)
        p0 = self.world_to_pixel(np.concatenate(starts))
        p1 = self.world_to_pixel(np.concatenate(ends))
        colors = np.broadcast_to(np.asarray(GROUP_COLOR, np.uint8), (len(p0), 3))
        return p0, p1, colors, np.ones(len(p0), dtype=bool)

    def _draw_zone_rings(self, frame: np.ndarray, people: np.ndarray, radii: Sequence[float]) -> None:
        """One-pixel rings of the given radii (metres) around every person, from cached stencils."""
        ok = people[np.all(np.isfinite(people[:, :2]), axis=1)]
        if len(ok) == 0:
            return
        centres = self.world_to_pixel(ok[:, :2])
        rows0 = np.floor(centres[:, 1]).astype(np.intp)
        cols0 = np.floor(centres[:, 0]).astype(np.intp)
        view = pixel_view(frame)
        for k, r in enumerate(radii):
            dr, dc = self._ring_stencil(float(r) * self.scale)
            rows = rows0[:, None] + dr[None, :]
            cols = cols0[:, None] + dc[None, :]
            inside = (rows >= 0) & (rows < self.height) & (cols >= 0) & (cols < self.width)
            view[(rows * self.width + cols)[inside]] = pixels(np.asarray(ZONE_COLORS[k % len(ZONE_COLORS)]))[0]

    def _ring_stencil(self, radius_px: float) -> tuple[np.ndarray, np.ndarray]:
        """Row and column offsets of the pixels whose centres lie within half a pixel of a circle."""
        key = round(radius_px, 3)
        cached = self._stencils.get(key)
        if cached is None:
            k = math.ceil(radius_px) + 1
            off = np.arange(-k, k + 1)
            dist = np.hypot(off[:, None], off[None, :])
            dr, dc = np.nonzero(np.abs(dist - radius_px) < 0.5)
            cached = (off[dr], off[dc])
            self._stencils[key] = cached
        return cached

    def _draw_bodies(
        self,
        frame: np.ndarray,
        poses: np.ndarray,
        radii_m: np.ndarray,
        fill: np.ndarray,
        outline: np.ndarray,
        tick: np.ndarray,
    ) -> None:
        """Draw discs with a heading tick from 0.25 r to 0.9 r along the facing direction."""
        centres = self.world_to_pixel(poses[:, :2])
        radii_px = np.maximum(radii_m * self.scale, 2.0)
        draw_discs(frame, centres, radii_px, fill, outline)
        direction = np.stack([np.cos(poses[:, 2]), -np.sin(poses[:, 2])], axis=1)  # row axis points down
        p0 = centres + direction * (0.25 * radii_px)[:, None]
        p1 = centres + direction * (0.9 * radii_px)[:, None]
        thickness = 2 if float(np.nanmax(radii_px)) >= 6.0 else 1
        draw_segments(frame, p0, p1, tick, thickness=thickness)

    def _polyline_batch(
        self, lines: Sequence[np.ndarray | None] | None, palette: np.ndarray, *, dashed: bool
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Pixel-space segments of world polylines, line ``i`` coloured ``palette[i % len]``."""
        starts: list[np.ndarray] = [np.zeros((0, 2))]
        ends: list[np.ndarray] = [np.zeros((0, 2))]
        colors: list[np.ndarray] = [np.zeros((0, 3), dtype=np.uint8)]
        for i, line in enumerate(lines or ()):
            if line is None:
                continue
            pts = np.asarray(line, dtype=np.float64)
            if pts.ndim != 2 or pts.shape[1] < 2 or len(pts) < 2:
                continue
            px = self.world_to_pixel(pts[:, :2])
            starts.append(px[:-1])
            ends.append(px[1:])
            colors.append(np.broadcast_to(palette[i % len(palette)], (len(px) - 1, 3)))
        p0 = np.concatenate(starts)
        return p0, np.concatenate(ends), np.concatenate(colors), np.full(len(p0), dashed)

    def _cross_batch(self, goals: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Pixel-space segments of an X-shaped cross at each goal, in its robot's colour."""
        c = self.world_to_pixel(goals)
        h = max(4.0, 0.2 * self.scale)
        cols = self._palette[np.arange(len(c)) % len(self._palette)]
        p0 = np.concatenate([c + np.array([-h, -h]), c + np.array([-h, h])])
        p1 = np.concatenate([c + np.array([h, h]), c + np.array([h, -h])])
        return p0, p1, np.concatenate([cols, cols]), np.zeros(len(p0), dtype=bool)
