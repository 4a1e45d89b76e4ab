//! Furniture and people: objects with interaction spaces and their agenda, conversation groups,
//! standing and seated people, walkers on routes through the doorways.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::layout::{Plan, Room, door_path, round2};
use super::params::GenParams;
use crate::map::geometry::StaticGeometry;
use crate::math::Vec2;

/// An object of the scene file (`[[object]]`), with its interaction space as inline TOML.
pub(super) struct GObject {
    pub(super) name: String,
    pub(super) kind: &'static str,
    pub(super) pose: [f64; 3],
    pub(super) size: Option<[f64; 2]>,
    pub(super) radius: Option<f64>,
    pub(super) interaction: Option<String>,
    /// Seats left free (benches): places 0, 1, 2 until taken.
    pub(super) seats: Vec<usize>,
}

/// A person of the scene file (`[[person]]`).
pub(super) enum GPerson {
    Standing { pose: [f64; 3] },
    Seated { seat: String, place: usize },
    Walker { route: Vec<[f64; 2]>, speed: f64, dwell: f64 },
    Conversation { group: u32, home: [f64; 2], spot: [f64; 2], end: f64 },
}

/// Places kept free of furniture and of people standing still: doorways, and what is placed.
pub(super) struct Keep {
    /// Every doorway's centre and half-width (m).
    doors: Vec<(Vec2, f64)>,
    /// What is placed: centre and radius (m).
    discs: Vec<(Vec2, f64)>,
}

/// Free floor kept round a doorway's opening, beyond its half-width (m): its approach.
const DOOR_APPROACH: f64 = 1.4;

impl Keep {
    /// The doorways' approaches: a disc of the door's half-width plus 1.4 m round every door.
    pub(super) fn new(plan: &Plan) -> Self {
        Keep { doors: plan.doors.iter().map(|d| (d.centre, d.width / 2.0)).collect(), discs: Vec::new() }
    }

    /// Whether a disc of radius `r` at `c` keeps clear of every doorway's approach and of what
    /// is placed.
    pub(super) fn free(&self, c: Vec2, r: f64) -> bool {
        self.free_with_door_margin(c, r, DOOR_APPROACH)
    }

    /// [`Keep::free`] with `margin` (m) of floor kept round each doorway's opening instead of its
    /// whole approach.
    pub(super) fn free_with_door_margin(&self, c: Vec2, r: f64, margin: f64) -> bool {
        self.doors.iter().all(|&(q, h)| (q - c).norm() >= r + h + margin)
            && self.discs.iter().all(|&(q, s)| (q - c).norm() >= r + s)
    }

    pub(super) fn add(&mut self, c: Vec2, r: f64) {
        self.discs.push((c, r));
    }
}

/// A uniform point of `room` at least `margin` inside its walls (None if it is too small).
fn point_in(rng: &mut ChaCha8Rng, room: &Room, margin: f64) -> Option<Vec2> {
    let (x0, x1) = (room.min.x + margin, room.max.x - margin);
    let (y0, y1) = (room.min.y + margin, room.max.y - margin);
    if x1 <= x0 || y1 <= y0 {
        return None;
    }
    Some(Vec2::new(round2(rng.random_range(x0..=x1)), round2(rng.random_range(y0..=y1))))
}

/// Up to `objects_per_room` objects in every room (none in the corridor): paintings on the back
/// wall with a trapezoidal viewing space, exhibits with a circular one, plinths with a
/// rectangular one, benches (seats for the seated people) without.
pub(super) fn objects(rng: &mut ChaCha8Rng, plan: &Plan, p: &GenParams, keep: &mut Keep) -> Vec<GObject> {
    let mut out = Vec::new();
    for (ri, room) in plan.rooms.iter().enumerate().filter(|(_, r)| !r.corridor) {
        for j in 0..p.objects_per_room {
            let pick = rng.random_range(0.0..1.0);
            for _attempt in 0..30 {
                let placed = if pick < 0.35 {
                    painting(rng, room, keep, format!("painting_{ri}_{j}"))
                } else if pick < 0.6 {
                    exhibit(rng, room, keep, format!("exhibit_{ri}_{j}"))
                } else if pick < 0.8 {
                    plinth(rng, room, keep, format!("plinth_{ri}_{j}"))
                } else {
                    bench(rng, room, keep, format!("bench_{ri}_{j}"))
                };
                if let Some(o) = placed {
                    out.push(o);
                    break;
                }
            }
        }
    }
    out
}

fn painting(rng: &mut ChaCha8Rng, room: &Room, keep: &mut Keep, name: String) -> Option<GObject> {
    let width = round2(rng.random_range(1.0..=2.2));
    let length = round2(rng.random_range(1.4..=2.0));
    let far = round2(1.5 * width);
    let margin = far / 2.0 + 0.4;
    if room.max.x - room.min.x <= 2.0 * margin {
        return None;
    }
    let x = round2(rng.random_range(room.min.x + margin..=room.max.x - margin));
    let centre = Vec2::new(x, room.back_wall + room.back_dir * length / 2.0);
    let r = (far / 2.0).hypot(length / 2.0) + 0.3;
    if !keep.free(centre, r) {
        return None;
    }
    keep.add(centre, r);
    let theta = if room.back_dir > 0.0 { FRAC_PI_2 } else { -FRAC_PI_2 };
    Some(GObject {
        name,
        kind: "painting",
        pose: [x, round2(room.back_wall + room.back_dir * 0.06), theta],
        size: Some([0.08, width]),
        radius: None,
        interaction: Some(format!(
            "{{ shape = \"trapezoid\", length = {length:?}, near_width = {width:?}, far_width = {far:?} }}"
        )),
        seats: Vec::new(),
    })
}

fn exhibit(rng: &mut ChaCha8Rng, room: &Room, keep: &mut Keep, name: String) -> Option<GObject> {
    let radius = round2(rng.random_range(0.35..=0.6));
    let space = round2(radius + rng.random_range(0.8..=1.1));
    let c = point_in(rng, room, space + 0.7)?;
    let r = space + 0.8;
    if !keep.free(c, r) {
        return None;
    }
    keep.add(c, r);
    Some(GObject {
        name,
        kind: "exhibit",
        pose: [c.x, c.y, 0.0],
        size: None,
        radius: Some(radius),
        interaction: Some(format!("{{ shape = \"circle\", radius = {space:?} }}")),
        seats: Vec::new(),
    })
}

fn plinth(rng: &mut ChaCha8Rng, room: &Room, keep: &mut Keep, name: String) -> Option<GObject> {
    let size = [round2(rng.random_range(0.6..=1.2)), round2(rng.random_range(0.6..=1.2))];
    let margin = 0.7;
    let ext = (size[0] / 2.0).hypot(size[1] / 2.0) + margin;
    let c = point_in(rng, room, ext + 0.7)?;
    let r = ext + 0.8;
    if !keep.free(c, r) {
        return None;
    }
    keep.add(c, r);
    let theta = if rng.random_bool(0.5) { 0.0 } else { FRAC_PI_2 };
    Some(GObject {
        name,
        kind: "plinth",
        pose: [c.x, c.y, theta],
        size: Some(size),
        radius: None,
        interaction: Some(format!("{{ shape = \"rectangle\", margin = {margin:?} }}")),
        seats: Vec::new(),
    })
}

fn bench(rng: &mut ChaCha8Rng, room: &Room, keep: &mut Keep, name: String) -> Option<GObject> {
    let c = point_in(rng, room, 1.3)?;
    let r = 1.4;
    if !keep.free(c, r) {
        return None;
    }
    keep.add(c, r);
    let theta = [0.0, FRAC_PI_2, PI, -FRAC_PI_2][rng.random_range(0..4)];
    Some(GObject {
        name,
        kind: "bench",
        pose: [c.x, c.y, theta],
        size: Some([0.5, 1.8]),
        radius: None,
        interaction: None,
        seats: vec![0, 1, 2],
    })
}

/// The people: `density` per 100 m^2 of floor, `group_share` of them in conversation groups of
/// 2-6, then walkers, seated and standing people by the shares. A person who finds no room
/// (after a bounded number of draws) is left out, so dense settings in small scenes yield fewer
/// people than asked.
pub(super) fn people(
    rng: &mut ChaCha8Rng,
    plan: &Plan,
    p: &GenParams,
    geometry: &StaticGeometry,
    objects: &mut [GObject],
    keep: &mut Keep,
) -> Vec<GPerson> {
    let area: f64 = plan.rooms.iter().map(Room::area).sum();
    let n = (p.density * area / 100.0).round() as usize;
    let in_groups = ((p.group_share * n as f64).round() as usize).min(n);
    let rest = n - in_groups;
    let walkers = (p.walker_share * rest as f64).round() as usize;
    let seated = ((p.seated_share * rest as f64).round() as usize).min(rest - walkers);
    let standing = rest - walkers - seated;
    let rooms: Vec<usize> = (0..plan.rooms.len()).filter(|&r| !plan.rooms[r].corridor).collect();
    let mut out = Vec::new();

    // conversation groups (F-formations): members on a circle of radius 0.4 + 0.1 n round the
    // o-space centre (the spacing the pedestrian scripts use), already talking at the start
    let mut left = in_groups;
    let mut group = 100u32;
    while left >= 2 {
        let mut size = rng.random_range(2..=left.min(6));
        if left - size == 1 {
            size = if size < 6 { size + 1 } else { size - 1 };
        }
        left -= size;
        let ring = 0.4 + 0.1 * size as f64;
        for _ in 0..30 {
            let room = &plan.rooms[rooms[rng.random_range(0..rooms.len())]];
            let Some(c) = point_in(rng, room, ring + 1.4) else { continue };
            let r = ring + 1.2;
            if !keep.free(c, r) || geometry.distance(c) < ring + 1.0 {
                continue;
            }
            keep.add(c, r);
            let a0 = rng.random_range(0.0..TAU);
            for k in 0..size {
                let a = a0 + TAU * k as f64 / size as f64;
                let home = [round2(c.x + (ring + 0.5) * a.cos()), round2(c.y + (ring + 0.5) * a.sin())];
                out.push(GPerson::Conversation { group, home, spot: [c.x, c.y], end: p.max_time + 60.0 });
            }
            group += 1;
            break;
        }
    }

    for _ in 0..standing {
        for _ in 0..30 {
            let room = &plan.rooms[rooms[rng.random_range(0..rooms.len())]];
            let Some(c) = point_in(rng, room, 1.0) else { continue };
            let r = 1.2;
            if !keep.free(c, r) || geometry.distance(c) < 1.0 {
                continue;
            }
            keep.add(c, r);
            out.push(GPerson::Standing { pose: [c.x, c.y, round2(rng.random_range(-PI..PI))] });
            break;
        }
    }

    for _ in 0..seated {
        let free: Vec<usize> = (0..objects.len()).filter(|&o| !objects[o].seats.is_empty()).collect();
        if free.is_empty() {
            break;
        }
        let o = &mut objects[free[rng.random_range(0..free.len())]];
        let place = o.seats.remove(rng.random_range(0..o.seats.len()));
        out.push(GPerson::Seated { seat: o.name.clone(), place });
    }

    for _ in 0..walkers {
        for _ in 0..30 {
            if let Some(route) = walker_route(rng, plan, geometry) {
                let speed = round2(rng.random_range(0.8..=1.3));
                let dwell = round2(rng.random_range(0.0..=4.0));
                out.push(GPerson::Walker { route, speed, dwell });
                break;
            }
        }
    }
    out
}

/// A closed route from a point of one room to a point of another (or of the same) and back,
/// through the doorways' middles at right angles; None if a leg would cross furniture.
fn walker_route(rng: &mut ChaCha8Rng, plan: &Plan, geometry: &StaticGeometry) -> Option<Vec<[f64; 2]>> {
    let n = plan.rooms.len();
    let (a, b) = (rng.random_range(0..n), rng.random_range(0..n));
    let pa = point_in(rng, &plan.rooms[a], 0.6)?;
    let pb = point_in(rng, &plan.rooms[b], 0.6)?;
    let doors = door_path(plan, a, b);
    let mut there = vec![pa];
    let mut room = a;
    for &d in &doors {
        let door = &plan.doors[d];
        let s = if door.a == room { 1.0 } else { -1.0 };
        there.push(door.centre - door.normal * (0.8 * s));
        there.push(door.centre + door.normal * (0.8 * s));
        room = if door.a == room { door.b } else { door.a };
    }
    there.push(pb);
    // back the same way: the door points again in reverse, without repeating pb and pa
    let back: Vec<Vec2> = there[1..there.len() - 1].iter().rev().copied().collect();
    let route: Vec<Vec2> = there.into_iter().chain(back).collect();
    if route.len() < 2 || (route.len() == 2 && (route[0] - route[1]).norm() < 1.0) {
        return None;
    }
    for (k, &q) in route.iter().enumerate() {
        let next = route[(k + 1) % route.len()];
        if geometry.distance(q) < 0.5 || geometry.segment_hits(q, next) || (q - next).norm() < 0.05 {
            return None;
        }
    }
    Some(route.iter().map(|q| [round2(q.x), round2(q.y)]).collect())
}

/// Free floor an encounter group keeps round a doorway's opening, beyond its half-width (m): a
/// person's width, so that the doorway stays passable. Less than the whole approach
/// ([`DOOR_APPROACH`]) that other people keep: with it, the doorways' approaches covered most of
/// the corridor and a group found a place on the way in 4 of tuning scenes 0-29
/// (`encounters = 1`, `density = 2.5`); with 0.6 m, in 9 (chosen on those tuning seeds).
const ENCOUNTER_DOOR_MARGIN: f64 = 0.6;

/// A conversation group of 2-3 standing on a robot's shortest way (`path`, start to goal): the
/// first place between 20% and 80% of the way with room for the group (its members clear of walls
/// and furniture, 0.75 m of free floor beside it across the way, clear of the people standing
/// still and of the objects, [`ENCOUNTER_DOOR_MARGIN`] clear of the doorways' openings, 2.5 m or
/// more from every robot's start and goal), so plain A* walks into it and a social planner has
/// room to go round. Returns the members (None if no such place).
pub(super) fn encounter(
    rng: &mut ChaCha8Rng,
    path: &[Vec2],
    geometry: &StaticGeometry,
    keep: &mut Keep,
    ends: &[Vec2],
    group: u32,
    end: f64,
) -> Option<Vec<GPerson>> {
    let size = rng.random_range(2..=3usize);
    let ring = 0.4 + 0.1 * size as f64;
    let n = path.len();
    if n < 4 {
        return None;
    }
    let first = rng.random_range(0.2..0.3);
    let candidates = (0..60).map(|k| first + 0.01 * k as f64).filter(|f| *f <= 0.8);
    for f in candidates {
        let k = ((n as f64 * f) as usize).min(n - 2);
        let (q, next) = (path[k], path[k + 1]);
        let d = next - q;
        let side = Vec2::new(-d.y, d.x) / d.norm().max(1e-9);
        // the way crosses the o-space: the centre at most 0.6 of the circle's radius off it
        let offsets = [0.0, 0.3 * ring, -0.3 * ring, 0.6 * ring, -0.6 * ring];
        let r = ring + 0.3;
        // room to pass on one side: beside the group, across the way, 0.75 m of free floor (a
        // robot's body with the intimate zone's 0.45 m) past the members' bodies
        let pass = |c: Vec2, s: f64| geometry.distance(c + side * (s * (ring + 1.2))) >= 0.75;
        let Some(c) =
            offsets.iter().map(|&o| q + side * o).map(|c| Vec2::new(round2(c.x), round2(c.y))).find(|&c| {
                geometry.distance(c) >= ring + 0.35
                    && (pass(c, 1.0) || pass(c, -1.0))
                    && keep.free_with_door_margin(c, r, ENCOUNTER_DOOR_MARGIN)
                    && ends.iter().all(|&e| (e - c).norm() >= 2.5)
            })
        else {
            continue;
        };
        keep.add(c, r);
        let a0 = rng.random_range(0.0..TAU);
        let members = (0..size)
            .map(|k| {
                let a = a0 + TAU * k as f64 / size as f64;
                let dir = Vec2::new(a.cos(), a.sin());
                // A member starts 0.5 m outside the ring, or on it when that is too near a wall
                // or furniture (the centre keeps `ring + 0.35` from them, so the ring is clear).
                let out = c + dir * (ring + 0.5);
                let clear = geometry.distance(out) >= 0.3 && !geometry.segment_hits(c + dir * ring, out);
                let home = if clear { out } else { c + dir * ring };
                GPerson::Conversation { group, home: [round2(home.x), round2(home.y)], spot: [c.x, c.y], end }
            })
            .collect();
        return Some(members);
    }
    None
}
