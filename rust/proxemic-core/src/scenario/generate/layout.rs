//! The floor plan: an east-west corridor with rooms on both sides, a doorway from every room to
//! the corridor and, at random, doorways between neighbouring rooms.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::params::{GenParams, MIN_ROOM_DEPTH, perr};
use crate::error::Result;
use crate::math::Vec2;

/// Outer wall thickness (m); the centre line runs half of it inside the bounds.
pub(super) const OUTER: f64 = 0.3;
/// Interior wall thickness (m).
pub(super) const INNER: f64 = 0.2;

/// A wall centre-line segment and its thickness (m).
pub(super) struct WallSeg {
    pub(super) from: Vec2,
    pub(super) to: Vec2,
    pub(super) thickness: f64,
}

/// A room's clear interior (axis-aligned rectangle, m).
#[derive(Clone, Copy)]
pub(super) struct Room {
    pub(super) min: Vec2,
    pub(super) max: Vec2,
    /// The corridor (no furniture, no standing people: it keeps the room to pass).
    pub(super) corridor: bool,
    /// For a room: the y of its wall away from the corridor's side and the direction into the
    /// room from it (+1 north, -1 south); paintings hang there.
    pub(super) back_wall: f64,
    pub(super) back_dir: f64,
}

impl Room {
    pub(super) fn area(&self) -> f64 {
        (self.max.x - self.min.x) * (self.max.y - self.min.y)
    }
}

/// A doorway: its centre, the unit normal from room `a` to room `b`, its clear width (m).
pub(super) struct Door {
    pub(super) centre: Vec2,
    pub(super) normal: Vec2,
    pub(super) width: f64,
    pub(super) a: usize,
    pub(super) b: usize,
}

/// The floor plan: rooms (index 0 is the corridor), doorways and wall segments.
pub(super) struct Plan {
    pub(super) rooms: Vec<Room>,
    pub(super) doors: Vec<Door>,
    pub(super) walls: Vec<WallSeg>,
}

/// Centre-line segments of a straight wall from `a` to `b` (along x or y) with gaps `(lo, hi)`
/// in the running coordinate: a wall's polygon extends thickness/2 past its ends, so a gap of
/// clear width `w` leaves `w + thickness` between the end points.
fn wall_with_gaps(a: Vec2, b: Vec2, thickness: f64, gaps: &mut [(f64, f64)], out: &mut Vec<WallSeg>) {
    let along_x = (b.y - a.y).abs() < 1e-12;
    let coord = |p: Vec2| if along_x { p.x } else { p.y };
    let point = |t: f64| if along_x { Vec2::new(t, a.y) } else { Vec2::new(a.x, t) };
    gaps.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut t = coord(a);
    for &(lo, hi) in gaps.iter() {
        let end = lo - thickness / 2.0;
        if end - t > 0.05 {
            out.push(WallSeg { from: point(t), to: point(end), thickness });
        }
        t = hi + thickness / 2.0;
    }
    if coord(b) - t > 0.05 {
        out.push(WallSeg { from: point(t), to: point(coord(b)), thickness });
    }
}

/// Splits `[lo, hi]` into rooms 5-9 m wide; returns the divider centre lines.
fn dividers(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> Vec<f64> {
    let span = hi - lo;
    let k = ((span / 7.0).round() as usize).max(1);
    let w = span / k as f64;
    (1..k).map(|i| round2(lo + w * i as f64 + rng.random_range(-0.8..=0.8))).collect()
}

/// `v` rounded to centimetres (the scene file then holds exactly the values the generator used).
pub(super) fn round2(v: f64) -> f64 {
    (v * 100.0).round() / 100.0
}

/// Clear wall kept each side of a doorway (m).
const DOOR_MARGIN: f64 = 0.6;

/// A doorway centre drawn in `[lo, hi]` (a room side, m) leaving [`DOOR_MARGIN`] of wall each
/// side of a door `dw` wide; a `door_width` error of the spec `source` when the side is too short
/// (`what` says which side).
fn door_centre(rng: &mut ChaCha8Rng, lo: f64, hi: f64, dw: f64, source: &str, what: &str) -> Result<f64> {
    let margin = dw / 2.0 + DOOR_MARGIN;
    if lo + margin > hi - margin {
        let fits = hi - lo - 2.0 * DOOR_MARGIN;
        return Err(perr(
            source,
            "door_width",
            format!(
                "a door width that fits {what} of {:.2} m with {DOOR_MARGIN} m of wall each side (at most {:.2} m for \
                 this seed; or larger rooms: a larger width or height)",
                hi - lo,
                fits.max(0.0)
            ),
            format!("{dw}"),
        ));
    }
    Ok(round2(rng.random_range(lo + margin..=hi - margin)))
}

/// Draws the floor plan of the spec `source`.
///
/// # Errors
/// A `door_width` error when a doorway does not fit a room's side (a wide door in small rooms).
pub(super) fn plan(rng: &mut ChaCha8Rng, p: &GenParams, source: &str) -> Result<Plan> {
    let (w, h) = (round2(p.width), round2(p.height));
    let (x0, x1, y0, y1) = (OUTER, w - OUTER, OUTER, h - OUTER);
    let cw = p.corridor_width;
    // corridor centre: leaves rooms of at least MIN_ROOM_DEPTH on both sides
    let lo = y0 + MIN_ROOM_DEPTH + INNER + cw / 2.0;
    let hi = y1 - MIN_ROOM_DEPTH - INNER - cw / 2.0;
    let yc = round2(if hi > lo { rng.random_range(lo..=hi) } else { (lo + hi) / 2.0 });
    let ys = round2(yc - cw / 2.0 - INNER / 2.0); // south corridor wall centre line
    let yn = round2(yc + cw / 2.0 + INNER / 2.0); // north corridor wall centre line
    let corridor = Room {
        min: Vec2::new(x0, ys + INNER / 2.0),
        max: Vec2::new(x1, yn - INNER / 2.0),
        corridor: true,
        back_wall: 0.0,
        back_dir: 0.0,
    };
    let mut rooms = vec![corridor];
    let mut doors = Vec::new();
    let mut walls = Vec::new();
    // outer walls (centre lines OUTER/2 inside the bounds)
    let (o0, ox, oy) = (OUTER / 2.0, w - OUTER / 2.0, h - OUTER / 2.0);
    for (a, b) in [
        (Vec2::new(o0, o0), Vec2::new(ox, o0)),
        (Vec2::new(o0, oy), Vec2::new(ox, oy)),
        (Vec2::new(o0, o0), Vec2::new(o0, oy)),
        (Vec2::new(ox, o0), Vec2::new(ox, oy)),
    ] {
        walls.push(WallSeg { from: a, to: b, thickness: OUTER });
    }
    let dw = p.door_width;
    for (side, wall_y) in [(-1.0, ys), (1.0, yn)] {
        let divs = dividers(rng, x0, x1);
        let mut edges = vec![x0 - INNER / 2.0];
        edges.extend(divs.iter().copied());
        edges.push(x1 + INNER / 2.0);
        let (ry0, ry1) = if side < 0.0 { (y0, ys - INNER / 2.0) } else { (yn + INNER / 2.0, y1) };
        let first = rooms.len();
        let mut corridor_gaps = Vec::new();
        for k in 0..edges.len() - 1 {
            let room = Room {
                min: Vec2::new(edges[k] + INNER / 2.0, ry0),
                max: Vec2::new(edges[k + 1] - INNER / 2.0, ry1),
                corridor: false,
                back_wall: if side < 0.0 { y0 } else { y1 },
                back_dir: -side,
            };
            let index = rooms.len();
            rooms.push(room);
            // the doorway to the corridor
            let xc = door_centre(rng, room.min.x, room.max.x, dw, source, "a room's corridor side")?;
            corridor_gaps.push((xc - dw / 2.0, xc + dw / 2.0));
            doors.push(Door {
                centre: Vec2::new(xc, wall_y),
                normal: Vec2::new(0.0, -side),
                width: dw,
                a: index,
                b: 0,
            });
        }
        wall_with_gaps(Vec2::new(o0, wall_y), Vec2::new(ox, wall_y), INNER, &mut corridor_gaps, &mut walls);
        // dividers, some with a doorway to the neighbour
        let (wy0, wy1) = if side < 0.0 { (o0, ys) } else { (yn, oy) };
        for (k, &x) in divs.iter().enumerate() {
            let mut gaps = Vec::new();
            if rng.random_bool(0.5) {
                let yd = door_centre(rng, ry0, ry1, dw, source, "the wall between two rooms")?;
                gaps.push((yd - dw / 2.0, yd + dw / 2.0));
                doors.push(Door {
                    centre: Vec2::new(x, yd),
                    normal: Vec2::new(1.0, 0.0),
                    width: dw,
                    a: first + k,
                    b: first + k + 1,
                });
            }
            wall_with_gaps(Vec2::new(x, wy0), Vec2::new(x, wy1), INNER, &mut gaps, &mut walls);
        }
    }
    Ok(Plan { rooms, doors, walls })
}

/// The room sequence (by doorways) from room `a` to room `b`: breadth first over the doorways,
/// the door indices in order (empty if `a == b`).
pub(super) fn door_path(plan: &Plan, a: usize, b: usize) -> Vec<usize> {
    let n = plan.rooms.len();
    let mut prev: Vec<Option<(usize, usize)>> = vec![None; n];
    let mut seen = vec![false; n];
    seen[a] = true;
    let mut queue = std::collections::VecDeque::from([a]);
    while let Some(r) = queue.pop_front() {
        if r == b {
            break;
        }
        for (d, door) in plan.doors.iter().enumerate() {
            let other = if door.a == r {
                door.b
            } else if door.b == r {
                door.a
            } else {
                continue;
            };
            if !seen[other] {
                seen[other] = true;
                prev[other] = Some((r, d));
                queue.push_back(other);
            }
        }
    }
    let mut out = Vec::new();
    let mut r = b;
    while let Some((p, d)) = prev[r] {
        out.push(d);
        r = p;
    }
    out.reverse();
    out
}
