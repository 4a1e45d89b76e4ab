//! Objects (`[[object]]`) with their footprints and interaction spaces, and the agenda of
//! activities on them (`[agenda]`, `[[activity]]`).

use super::polygons::{circle_polygon, oriented_rect, signed_area};
use crate::error::{CoreError, Result};
use crate::scenario::check::{Checker, err, parse_time_of_day};
use crate::scenario::model::{ActivitySpec, AgendaSpec, Interaction, InteractionShape, Object, Scenario};
use crate::scenario::raw::{RawActivity, RawAgenda, RawInteraction, RawObject};

/// Checks the objects (unique names, poses inside the `bounds`, either a size or a radius) and
/// computes their footprints and interaction spaces.
pub(super) fn build_objects(ck: &Checker<'_>, raw: &[RawObject], b: [f64; 4]) -> Result<Vec<Object>> {
    let file = ck.file;
    let mut objects = Vec::with_capacity(raw.len());
    for (i, o) in raw.iter().enumerate() {
        let f = format!("object[{i}]");
        if o.name.trim().is_empty() {
            return Err(err(file, format!("{f}.name"), "a non-empty name", "\"\""));
        }
        if let Some(j) = raw[..i].iter().position(|p| p.name == o.name) {
            return Err(err(
                file,
                format!("{f}.name"),
                format!("a unique name (object[{j}] is also called that)"),
                format!("{:?}", o.name),
            ));
        }
        ck.finite(&format!("{f}.pose"), &o.pose)?;
        ck.inside(&format!("{f}.pose"), [o.pose[0], o.pose[1]], b)?;
        let height = o.height.unwrap_or_else(|| o.kind.default_height());
        ck.range(&format!("{f}.height"), height, 0.0, 20.0, true)?;
        let c = [o.pose[0], o.pose[1]];
        let (size, radius, footprint) = match (o.size, o.radius) {
            (Some(sz), None) => {
                ck.range(&format!("{f}.size[0]"), sz[0], 0.0, 50.0, true)?;
                ck.range(&format!("{f}.size[1]"), sz[1], 0.0, 50.0, true)?;
                (sz, None, oriented_rect(c, o.pose[2], sz[0] * 0.5, sz[1] * 0.5))
            }
            (None, Some(r)) => {
                if !o.kind.is_round_capable() {
                    return Err(err(
                        file,
                        format!("{f}.radius"),
                        format!("size = [depth, width] for a {:?}", o.kind),
                        "radius",
                    ));
                }
                ck.range(&format!("{f}.radius"), r, 0.0, 25.0, true)?;
                ([2.0 * r, 2.0 * r], Some(r), circle_polygon(c, r))
            }
            (Some(_), Some(_)) => {
                return Err(err(file, format!("{f}.radius"), "either size or radius, not both", "both"));
            }
            (None, None) => {
                return Err(err(
                    file,
                    format!("{f}.size"),
                    "size = [depth, width] (or radius for round objects)",
                    "nothing",
                ));
            }
        };
        let interaction = match &o.interaction {
            None => None,
            Some(ri) => Some(build_interaction(ck, &format!("{f}.interaction"), ri, o, size, radius, b)?),
        };
        objects.push(Object {
            name: o.name.clone(),
            kind: o.kind,
            pose: o.pose,
            size,
            radius,
            height,
            solid: o.solid,
            footprint,
            interaction,
        });
    }
    Ok(objects)
}

/// Validates the agenda: times of day, objects with interaction spaces, no overlaps.
pub(super) fn build_agenda(
    ck: &Checker<'_>,
    raw: &RawAgenda,
    acts: &[RawActivity],
    objects: &[Object],
) -> Result<(AgendaSpec, Vec<ActivitySpec>)> {
    let file = ck.file;
    ck.range("agenda.idle", raw.idle, 1.0, 5.0, false)?;
    ck.range("agenda.active", raw.active, raw.idle, 5.0, false)?;
    ck.range("agenda.ramp_minutes", raw.ramp_minutes, 0.0, 24.0 * 60.0, false)?;
    let spec = AgendaSpec { idle: raw.idle, active: raw.active, ramp: raw.ramp_minutes * 60.0 };
    let mut out = Vec::with_capacity(acts.len());
    for (i, a) in acts.iter().enumerate() {
        let f = format!("activity[{i}]");
        match objects.iter().find(|o| o.name == a.object) {
            None => {
                return Err(err(
                    file,
                    format!("{f}.object"),
                    format!("the name of an [[object]] ({} objects defined)", objects.len()),
                    format!("{:?}", a.object),
                ));
            }
            Some(o) if o.interaction.is_none() => {
                return Err(err(
                    file,
                    format!("{f}.object"),
                    "an object with an interaction space",
                    format!("{:?} (has none)", a.object),
                ));
            }
            Some(_) => {}
        }
        let start = parse_time_of_day(&a.start).ok_or_else(|| {
            err(file, format!("{f}.start"), "a time of day \"HH:MM\"", format!("{:?}", a.start))
        })?;
        let mut end = parse_time_of_day(&a.end).ok_or_else(|| {
            err(file, format!("{f}.end"), "a time of day \"HH:MM\"", format!("{:?}", a.end))
        })?;
        if end <= start {
            if end == 0.0 {
                end = 86400.0; // "24:00" written as "00:00"
            } else {
                return Err(err(
                    file,
                    format!("{f}.end"),
                    format!("a time after start ({})", a.start),
                    format!("{:?}", a.end),
                ));
            }
        }
        out.push(ActivitySpec { name: a.name.clone(), object: a.object.clone(), start, end });
    }
    let agenda = Scenario::agenda_from(&spec, &out);
    agenda.map_err(|e| match e {
        CoreError::Input { field, expected, found } => {
            err(file, field.replace("activities", "activity"), expected, found)
        }
        other => other,
    })?;
    Ok((spec, out))
}

/// The interaction space of object `o` (field prefix `f`), in the world frame.
fn build_interaction(
    ck: &Checker<'_>,
    f: &str,
    ri: &RawInteraction,
    o: &RawObject,
    size: [f64; 2],
    radius: Option<f64>,
    bounds: [f64; 4],
) -> Result<Interaction> {
    let c = [o.pose[0], o.pose[1]];
    let th = o.pose[2];
    let (shape, polygon) = match ri {
        RawInteraction::Trapezoid { length, near_width, far_width } => {
            ck.range(&format!("{f}.length"), *length, 0.0, 50.0, true)?;
            ck.range(&format!("{f}.near_width"), *near_width, 0.0, 50.0, true)?;
            ck.range(&format!("{f}.far_width"), *far_width, 0.0, 50.0, true)?;
            let x0 = size[0] * 0.5;
            let x1 = x0 + length;
            let (s, co) = th.sin_cos();
            let local = [
                (x0, -near_width * 0.5),
                (x1, -far_width * 0.5),
                (x1, far_width * 0.5),
                (x0, near_width * 0.5),
            ];
            let poly =
                local.iter().map(|&(lx, ly)| [c[0] + co * lx - s * ly, c[1] + s * lx + co * ly]).collect();
            (
                InteractionShape::Trapezoid {
                    length: *length,
                    near_width: *near_width,
                    far_width: *far_width,
                },
                poly,
            )
        }
        RawInteraction::Rectangle { margin } => {
            ck.range(&format!("{f}.margin"), *margin, 0.0, 20.0, true)?;
            let poly = match radius {
                Some(r) => circle_polygon(c, r + margin),
                None => oriented_rect(c, th, size[0] * 0.5 + margin, size[1] * 0.5 + margin),
            };
            (InteractionShape::Rectangle { margin: *margin }, poly)
        }
        RawInteraction::Circle { radius: r } => {
            ck.range(&format!("{f}.radius"), *r, 0.0, 25.0, true)?;
            (InteractionShape::Circle { radius: *r }, circle_polygon(c, *r))
        }
        RawInteraction::Polygon { points } => {
            if points.len() < 3 {
                return Err(err(
                    ck.file,
                    format!("{f}.points"),
                    "at least 3 points",
                    format!("{} point(s)", points.len()),
                ));
            }
            for (k, p) in points.iter().enumerate() {
                ck.inside(&format!("{f}.points[{k}]"), *p, bounds)?;
            }
            let mut poly = points.clone();
            let area = signed_area(&poly);
            if area.abs() < 1e-9 {
                return Err(err(
                    ck.file,
                    format!("{f}.points"),
                    "a polygon with non-zero area",
                    "a degenerate polygon",
                ));
            }
            if let Some(what) = not_simple(&poly) {
                return Err(err(
                    ck.file,
                    format!("{f}.points"),
                    "a simple polygon (edges meet only at their ends, no spike)",
                    what,
                ));
            }
            if area < 0.0 {
                poly.reverse();
            }
            (InteractionShape::Polygon, poly)
        }
    };
    Ok(Interaction { shape, polygon })
}

/// Why `poly` is not a simple polygon, or `None`: two edges that are not neighbours touch or
/// cross (self-intersection), or an edge folds back onto the previous one (a spike of zero
/// width). O(n²) in the vertices, which scenario polygons keep few.
fn not_simple(poly: &[[f64; 2]]) -> Option<String> {
    let n = poly.len();
    let v = |k: usize| crate::math::Vec2::new(poly[k % n][0], poly[k % n][1]);
    for k in 0..n {
        let (a, b, c) = (v(k), v(k + 1), v(k + 2));
        let (u, w) = (b - a, c - b);
        if crate::geom::cross(u, w).abs() <= 1e-12 * u.norm() * w.norm() && u.dot(&w) < 0.0 {
            return Some(format!("a spike at point {}", (k + 1) % n));
        }
    }
    for i in 0..n {
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue; // neighbours through the closing edge
            }
            if segments_touch(v(i), v(i + 1), v(j), v(j + 1)) {
                return Some(format!("edges {i}-{} and {j}-{} cross", (i + 1) % n, (j + 1) % n));
            }
        }
    }
    None
}

/// Whether the closed segments `ab` and `cd` share a point.
fn segments_touch(
    a: crate::math::Vec2,
    b: crate::math::Vec2,
    c: crate::math::Vec2,
    d: crate::math::Vec2,
) -> bool {
    use crate::geom::cross;
    let (d1, d2) = (cross(b - a, c - a), cross(b - a, d - a));
    let (d3, d4) = (cross(d - c, a - c), cross(d - c, b - c));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |p: crate::math::Vec2, q: crate::math::Vec2, r: crate::math::Vec2, side: f64| {
        side == 0.0
            && r.x >= p.x.min(q.x)
            && r.x <= p.x.max(q.x)
            && r.y >= p.y.min(q.y)
            && r.y <= p.y.max(q.y)
    };
    on(a, b, c, d1) || on(a, b, d, d2) || on(c, d, a, d3) || on(c, d, b, d4)
}

/// An object's interaction space must face into the scene: its centroid inside `scene.bounds`
/// and outside every wall (a painting hung facing its wall put its viewers outside the room).
pub(super) fn check_spaces_face_the_room(
    file: &str,
    objects: &[Object],
    walls: &[crate::scenario::model::Wall],
    bounds: [f64; 4],
) -> Result<()> {
    use crate::geom::contains_point_polygon;
    use crate::math::Vec2;
    let to_vec = |p: &[[f64; 2]]| p.iter().map(|q| Vec2::new(q[0], q[1])).collect::<Vec<Vec2>>();
    for (i, o) in objects.iter().enumerate() {
        let Some(space) = &o.interaction else { continue };
        let poly = to_vec(&space.polygon);
        let centroid = poly.iter().fold(Vec2::zeros(), |s, p| s + p) / poly.len() as f64;
        let outside = centroid.x < bounds[0]
            || centroid.x > bounds[2]
            || centroid.y < bounds[1]
            || centroid.y > bounds[3];
        let in_wall = walls.iter().position(|w| contains_point_polygon(centroid, &to_vec(&w.polygon)));
        if outside || in_wall.is_some() {
            let where_ = match in_wall {
                Some(k) => format!("inside wall[{k}]"),
                None => format!("outside scene.bounds {bounds:?}"),
            };
            return Err(err(
                file,
                format!("object[{i}].pose"),
                "an orientation whose interaction space faces into the room (its centre inside the scene, clear of walls)",
                format!("{:?}: the space's centre {:?} is {where_}", o.pose, [centroid.x, centroid.y]),
            ));
        }
    }
    Ok(())
}
