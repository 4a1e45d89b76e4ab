"""Rasterisation primitives of the top-down renderer, in pixel coordinates, in place on an (H, W, 3) image.

Pixel coordinates are ``(col, row)`` floats where pixel ``(r, c)`` covers ``[c, c + 1) x [r, r + 1)``
and its centre is ``(c + 0.5, r + 0.5)``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from proxemic.errors import input_error
from proxemic.palette import RGB

_RGB_ITEM = np.dtype((np.void, 3))


def pixels(colors: np.ndarray) -> np.ndarray:
    """View a C-contiguous ``(..., 3)`` uint8 array as a flat array of 3-byte RGB items.

    Gathering and scattering whole pixels through this view is about twice as fast as indexing the
    ``(..., 3)`` array. The result is a view when ``colors`` is already contiguous uint8, so writes
    to it land in ``colors``.
    """
    return np.ascontiguousarray(colors, dtype=np.uint8).view(_RGB_ITEM).reshape(-1)


def pixel_view(img: np.ndarray) -> np.ndarray:
    """Writable flat view of an ``(H, W, 3)`` uint8 image as 3-byte RGB items (see :func:`pixels`).

    Raises:
        ValueError: If ``img`` is not a C-contiguous uint8 image (a copy would silently drop writes).

    """
    if img.dtype != np.uint8 or not img.flags.c_contiguous or not img.flags.writeable:
        raise ValueError("drawing needs a writable C-contiguous uint8 image")
    return img.view(_RGB_ITEM).reshape(-1)


def polygon_mask(poly_px: np.ndarray, height: int, width: int) -> tuple[slice, slice, np.ndarray] | None:
    """Even-odd point-in-polygon test over the pixel centres of the polygon's bounding box.

    Returns the row slice, column slice and boolean mask of that box, or None if it is empty.
    """
    c0 = max(math.floor(poly_px[:, 0].min()), 0)
    c1 = min(math.ceil(poly_px[:, 0].max()) + 1, width)
    r0 = max(math.floor(poly_px[:, 1].min()), 0)
    r1 = min(math.ceil(poly_px[:, 1].max()) + 1, height)
    if c0 >= c1 or r0 >= r1:
        return None
    xs = (np.arange(c0, c1, dtype=np.float64) + 0.5)[None, :]
    ys = (np.arange(r0, r1, dtype=np.float64) + 0.5)[:, None]
    inside = np.zeros((r1 - r0, c1 - c0), dtype=bool)
    nxt = np.roll(poly_px, -1, axis=0)
    for (xi, yi), (xj, yj) in zip(poly_px, nxt, strict=True):
        if yi == yj:
            continue  # a horizontal edge never crosses a horizontal scanline
        crosses = (yi > ys) != (yj > ys)
        x_int = xi + (xj - xi) * (ys - yi) / (yj - yi)
        inside ^= crosses & (xs < x_int)
    return slice(r0, r1), slice(c0, c1), inside


def clip_segments(p0: np.ndarray, p1: np.ndarray, height: int, width: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Liang-Barsky clipping of segments to a box slightly larger than the image.

    Returns the clipped start points, end points and the indices of the kept segments.
    """
    lo_x, hi_x, lo_y, hi_y = -1.0, width + 1.0, -1.0, height + 1.0
    d = p1 - p0
    t0 = np.zeros(len(p0))
    t1 = np.ones(len(p0))
    keep = np.all(np.isfinite(p0), axis=1) & np.all(np.isfinite(p1), axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        for p, q in (
            (-d[:, 0], p0[:, 0] - lo_x),
            (d[:, 0], hi_x - p0[:, 0]),
            (-d[:, 1], p0[:, 1] - lo_y),
            (d[:, 1], hi_y - p0[:, 1]),
        ):
            r = q / p
            keep &= ~((p == 0.0) & (q < 0.0))
            t0 = np.where(p < 0.0, np.maximum(t0, r), t0)
            t1 = np.where(p > 0.0, np.minimum(t1, r), t1)
    keep &= t0 <= t1
    idx = np.nonzero(keep)[0]
    d = d[idx]
    return p0[idx] + t0[idx, None] * d, p0[idx] + t1[idx, None] * d, idx


def segment_pixels(
    p0: np.ndarray, p1: np.ndarray, height: int, width: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Vectorised DDA over many segments.

    Returns ``(rows, cols, seg, order)``: integer pixel coordinates of every sample, the index of the
    (input) segment each sample belongs to, and the running sample index along the concatenation of
    all segments (used for dash patterns). Samples outside the image are dropped.
    """
    empty = np.zeros(0, dtype=np.intp)
    if len(p0) == 0:
        return empty, empty, empty, empty
    size = np.array([width, height], dtype=np.float64)
    # fast path: every endpoint on the image (NaN fails the comparisons and takes the slow path)
    if bool(np.all((p0 >= 0.0) & (p0 < size) & (p1 >= 0.0) & (p1 < size))):
        q0, q1, idx = p0, p1, None
    else:
        q0, q1, idx = clip_segments(p0, p1, height, width)
        if len(idx) == 0:
            return empty, empty, empty, empty
    d = q1 - q0
    steps = np.ceil(np.abs(d).max(axis=1)).astype(np.intp)
    counts = steps + 1
    seg = np.repeat(np.arange(len(q0)), counts)
    order = np.arange(len(seg))
    t = (order - (np.cumsum(counts) - counts)[seg]) / np.maximum(steps, 1)[seg]
    pts = q0[seg] + t[:, None] * d[seg]
    cols = np.floor(pts[:, 0]).astype(np.intp)
    rows = np.floor(pts[:, 1]).astype(np.intp)
    if idx is None:
        return rows, cols, seg, order
    ok = (cols >= 0) & (cols < width) & (rows >= 0) & (rows < height)
    return rows[ok], cols[ok], idx[seg[ok]], order[ok]


def nearest_people(people: np.ndarray, robots: np.ndarray, k: int) -> np.ndarray:
    """The rows of `people` among the `k` nearest to some robot (all of them without robots)."""
    finite = np.all(np.isfinite(people[:, :2]), axis=1)
    if len(robots) == 0 or int(finite.sum()) <= k:
        return people
    d = np.linalg.norm(people[None, :, :2] - robots[:, None, :2], axis=2)
    d[:, ~finite] = np.inf
    keep = np.zeros(len(people), dtype=bool)
    keep[np.argsort(d, axis=1, kind="stable")[:, :k].ravel()] = True
    return people[keep & finite]


def draw_segments(
    img: np.ndarray,
    p0: np.ndarray,
    p1: np.ndarray,
    colors: np.ndarray,
    *,
    thickness: int = 1,
    dashed: np.ndarray | None = None,
    dash: int = 4,
) -> None:
    """Draw segments ``p0[i] -> p1[i]`` (pixel coordinates) in ``colors[i]`` (``(N, 3)`` uint8).

    Lines are ``thickness`` pixels wide (a square brush). Segments flagged in the boolean ``dashed``
    array are drawn ``dash`` pixels on, ``dash`` pixels off, the pattern running continuously along
    consecutive segments.
    """
    height, width = img.shape[:2]
    rows, cols, seg, order = segment_pixels(p0, p1, height, width)
    if dashed is not None and bool(np.any(dashed)):
        on = ~dashed[seg] | ((order // dash) % 2 == 0)
        rows, cols, seg = rows[on], cols[on], seg[on]
    if thickness > 1:
        offs = np.arange(thickness) - (thickness - 1) // 2
        rows = np.clip(rows, -offs[0], height - 1 - offs[-1])  # keep the brush on the image
        cols = np.clip(cols, -offs[0], width - 1 - offs[-1])
        brush = (offs[:, None] * width + offs[None, :]).ravel()
        flat = ((rows * width + cols)[:, None] + brush).ravel()
        seg = np.repeat(seg, len(brush))
    else:
        flat = rows * width + cols
    pixel_view(img)[flat] = pixels(colors)[seg]


def draw_discs(
    img: np.ndarray,
    centres: np.ndarray,
    radii: np.ndarray,
    fill: np.ndarray,
    outline: np.ndarray,
    *,
    outline_width: float = 1.0,
) -> None:
    """Draw filled discs with an outline ring, all at once over a shared bounding-box stencil.

    ``centres`` is ``(N, 2)`` pixel coordinates, ``radii`` ``(N,)`` pixels, ``fill`` and ``outline``
    ``(N, 3)`` uint8. A pixel belongs to a disc when its centre is within the radius. Later discs are
    drawn over earlier ones.
    """
    height, width = img.shape[:2]
    ok = np.all(np.isfinite(centres), axis=1) & np.isfinite(radii)
    if not np.all(ok):
        centres, radii, fill, outline = centres[ok], radii[ok], fill[ok], outline[ok]
    n = len(centres)
    if n == 0:
        return
    radii = np.clip(radii, 1.0, float(max(height, width)))
    k = math.ceil(float(radii.max())) + 1
    off = np.arange(-k, k + 1)
    cols = np.floor(centres[:, 0]).astype(np.intp)[:, None] + off  # (N, S)
    rows = np.floor(centres[:, 1]).astype(np.intp)[:, None] + off
    dc2 = (cols + 0.5 - centres[:, 0, None]) ** 2
    dr2 = (rows + 0.5 - centres[:, 1, None]) ** 2
    dc2[(cols < 0) | (cols >= width)] = np.inf  # off-image pixels are never inside
    dr2[(rows < 0) | (rows >= height)] = np.inf
    d2 = dr2[:, :, None] + dc2[:, None, :]  # (N, S, S)
    inside = d2 <= (radii * radii)[:, None, None]
    inner = np.maximum(radii - outline_width, 0.0)
    disc = np.arange(n)[:, None, None]
    colour_index = np.where(d2 > (inner * inner)[:, None, None], disc + n, disc)
    flat = rows[:, :, None] * width + cols[:, None, :]
    table = pixels(np.concatenate([fill, outline]))
    pixel_view(img)[flat[inside]] = table[colour_index[inside]]


def blend_discs(img: np.ndarray, centres: np.ndarray, radii: np.ndarray, color: RGB, alpha: float) -> None:
    """Alpha-blend ``color`` over the union of discs (a pixel covered twice is blended once).

    ``centres`` is ``(N, 2)`` pixel coordinates and ``radii`` ``(N,)`` pixels; a pixel belongs to a
    disc when its centre is within the radius.
    """
    height, width = img.shape[:2]
    ok = np.all(np.isfinite(centres), axis=1) & np.isfinite(radii) & (radii > 0.0)
    centres, radii = centres[ok], np.minimum(radii[ok], float(max(height, width)))
    if len(centres) == 0:
        return
    k = math.ceil(float(radii.max())) + 1
    off = np.arange(-k, k + 1)
    cols = np.floor(centres[:, 0]).astype(np.intp)[:, None] + off
    rows = np.floor(centres[:, 1]).astype(np.intp)[:, None] + off
    dc2 = (cols + 0.5 - centres[:, 0, None]) ** 2
    dr2 = (rows + 0.5 - centres[:, 1, None]) ** 2
    dc2[(cols < 0) | (cols >= width)] = np.inf
    dr2[(rows < 0) | (rows >= height)] = np.inf
    inside = (dr2[:, :, None] + dc2[:, None, :]) <= (radii * radii)[:, None, None]
    flat = np.unique((rows[:, :, None] * width + cols[:, None, :])[inside])
    pix = img.reshape(-1, 3)
    blended = pix[flat].astype(np.float32) * (1.0 - alpha) + np.asarray(color, np.float32) * alpha
    pix[flat] = np.rint(blended).astype(np.uint8)


def ring_segments(centres: np.ndarray, radius: float, segments: int) -> tuple[np.ndarray, np.ndarray]:
    """Start and end points of ``segments``-gon approximations of circles (world frame, metres)."""
    ang = np.linspace(0.0, 2.0 * math.pi, segments + 1)
    ring = np.stack([np.cos(ang), np.sin(ang)], axis=1) * radius  # (S + 1, 2)
    pts = centres[:, None, :2] + ring[None, :, :]  # (N, S + 1, 2)
    return pts[:, :-1].reshape(-1, 2), pts[:, 1:].reshape(-1, 2)


def mix(a: Sequence[int], b: Sequence[int], t: float) -> RGB:
    """Linear mix of two RGB colours: ``(1 - t) * a + t * b``, rounded."""
    r, g, bl = (round((1.0 - t) * x + t * y) for x, y in zip(a, b, strict=True))
    return (r, g, bl)


def rows(arr: Any, ncols: int, name: str) -> np.ndarray:
    """Coerce ``arr`` to a float ``(N, ncols)`` array (an empty input gives ``(0, ncols)``)."""
    a = np.asarray(arr if arr is not None else [], dtype=np.float64)
    if a.size == 0:
        return np.zeros((0, ncols), dtype=np.float64)
    if a.ndim == 1 and a.shape[0] == ncols:
        a = a[None, :]
    if a.ndim != 2 or a.shape[1] != ncols:
        raise input_error(name, f"shape (N, {ncols})", f"shape {a.shape}")
    return a
