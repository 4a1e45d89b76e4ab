//! The scene settings (`[scene]`) and the walls (`[[wall]]`).

use super::polygons::oriented_rect;
use crate::error::Result;
use crate::scenario::check::{Checker, err, parse_time_of_day};
use crate::scenario::model::{Scene, Wall};
use crate::scenario::raw::{RawScene, RawWall};

/// The longest side of a scene's bounds (m): the static geometry is bucketed in 1 m cells.
pub const MAX_SCENE_SIDE: f64 = 1000.0;
/// The most cells a scene's grid may have (2^24, e.g. 400 x 400 m at 0.1 m): every robot's
/// inflated map, distance field and social map is a grid of this size.
pub const MAX_GRID_CELLS: f64 = 16_777_216.0;

/// Checks that `bounds` and `resolution` make a grid the core can hold (see [`MAX_SCENE_SIDE`]
/// and [`MAX_GRID_CELLS`]); the error names both fields, and the resolution that would fit.
fn check_grid_size(file: &str, b: [f64; 4], res: f64) -> Result<()> {
    let (w, h) = (b[2] - b[0], b[3] - b[1]);
    if w > MAX_SCENE_SIDE || h > MAX_SCENE_SIDE {
        return Err(err(
            file,
            "scene.bounds",
            format!("sides of at most {MAX_SCENE_SIDE} m"),
            format!("{b:?} ({w} x {h} m)"),
        ));
    }
    let cells = (w / res).ceil() * (h / res).ceil();
    if cells > MAX_GRID_CELLS {
        let finest = (w * h / MAX_GRID_CELLS).sqrt();
        return Err(err(
            file,
            "scene.resolution",
            format!(
                "a grid of at most {MAX_GRID_CELLS} cells over scene.bounds {b:?} ({w} x {h} m): \
                 a resolution of at least {finest:.3} m"
            ),
            format!("{res} m ({cells} cells)"),
        ));
    }
    Ok(())
}

/// Checks `[scene]`: bounds, grid resolution, start time, rates, wall height, name.
pub(super) fn build_scene(ck: &Checker<'_>, s: &RawScene) -> Result<Scene> {
    let file = ck.file;
    ck.finite("scene.bounds", &s.bounds)?;
    let b = s.bounds;
    if !(b[2] > b[0] && b[3] > b[1]) {
        return Err(err(
            file,
            "scene.bounds",
            "[xmin, ymin, xmax, ymax] with xmax > xmin and ymax > ymin",
            format!("{b:?}"),
        ));
    }
    if (b[2] - b[0]) * (b[3] - b[1]) > 1.0e6 {
        return Err(err(file, "scene.bounds", "an area of at most 1 km^2", format!("{b:?}")));
    }
    ck.range("scene.resolution", s.resolution, 0.0, 1.0, true)?;
    check_grid_size(file, b, s.resolution)?;
    let start_time = parse_time_of_day(&s.start_time).ok_or_else(|| {
        err(
            file,
            "scene.start_time",
            "a time of day \"HH:MM\" or \"HH:MM:SS\"",
            format!("{:?}", s.start_time),
        )
    })?;
    ck.range("scene.control_hz", s.control_hz, 0.0, 1000.0, true)?;
    ck.range("scene.physics_hz", s.physics_hz, 0.0, 10000.0, true)?;
    let ratio = s.physics_hz / s.control_hz;
    if ratio < 1.0 || (ratio - ratio.round()).abs() > 1e-9 {
        return Err(err(
            file,
            "scene.physics_hz",
            format!("an integer multiple of scene.control_hz ({})", s.control_hz),
            format!("{}", s.physics_hz),
        ));
    }
    ck.range("scene.wall_height", s.wall_height, 0.0, 20.0, true)?;
    if s.name.trim().is_empty() {
        return Err(err(file, "scene.name", "a non-empty name", "\"\""));
    }
    Ok(Scene {
        name: s.name.clone(),
        description: s.description.clone(),
        bounds: b,
        resolution: s.resolution,
        start_time,
        control_hz: s.control_hz,
        physics_hz: s.physics_hz,
        wall_height: s.wall_height,
    })
}

/// Checks the walls and computes their footprints (`wall_height` is the scene's default height).
/// How far past `scene.bounds` a wall's end points may lie (m): walls are drawn along the bounds.
pub const WALL_BOUNDS_MARGIN: f64 = 1.0;

pub(super) fn build_walls(
    ck: &Checker<'_>,
    raw: &[RawWall],
    wall_height: f64,
    bounds: [f64; 4],
) -> Result<Vec<Wall>> {
    let file = ck.file;
    let mut walls = Vec::with_capacity(raw.len());
    for (i, w) in raw.iter().enumerate() {
        let f = format!("wall[{i}]");
        let m = WALL_BOUNDS_MARGIN;
        let grown = [bounds[0] - m, bounds[1] - m, bounds[2] + m, bounds[3] + m];
        ck.inside(&format!("{f}.from"), w.from, grown)?;
        ck.inside(&format!("{f}.to"), w.to, grown)?;
        ck.range(&format!("{f}.thickness"), w.thickness, 0.0, 5.0, true)?;
        let height = w.height.unwrap_or(wall_height);
        ck.range(&format!("{f}.height"), height, 0.0, 20.0, true)?;
        let (dx, dy) = (w.to[0] - w.from[0], w.to[1] - w.from[1]);
        let len = dx.hypot(dy);
        if len < 1e-6 {
            return Err(err(
                file,
                format!("{f}.to"),
                "a point different from wall.from",
                format!("{:?}", w.to),
            ));
        }
        let c = [(w.from[0] + w.to[0]) * 0.5, (w.from[1] + w.to[1]) * 0.5];
        // Walls extend half a thickness past their end points so that corners close.
        let polygon = oriented_rect(c, dy.atan2(dx), len * 0.5 + w.thickness * 0.5, w.thickness * 0.5);
        walls.push(Wall { from: w.from, to: w.to, thickness: w.thickness, height, polygon });
    }

    Ok(walls)
}

/// The farthest a robot may move in one control step (m): half the contact-hint range, so the
/// physics never misses a contact the hints rule out, and the robot cannot leave the map or
/// cross a wall between two looks of the core.
pub const MAX_CONTROL_STEP_TRAVEL: f64 = 0.25;
/// The farthest a robot may move in one physics step (m): a quarter of a default wall's
/// thickness, so a body cannot tunnel through a wall between two collision checks.
pub const MAX_PHYSICS_STEP_TRAVEL: f64 = 0.05;

/// The control and physics rates must be fast enough for the fastest robot (see
/// [`MAX_CONTROL_STEP_TRAVEL`] and [`MAX_PHYSICS_STEP_TRAVEL`]).
pub(super) fn check_rates(file: &str, scene: &Scene, robots: &[crate::scenario::model::Robot]) -> Result<()> {
    let vmax = robots.iter().map(|r| r.max_speed).fold(0.0, f64::max);
    let limits = [
        ("scene.control_hz", "control", scene.control_hz, MAX_CONTROL_STEP_TRAVEL),
        ("scene.physics_hz", "physics", scene.physics_hz, MAX_PHYSICS_STEP_TRAVEL),
    ];
    for (field, step, hz, travel) in limits {
        let min_hz = vmax / travel;
        if hz < min_hz {
            return Err(err(
                file,
                field,
                format!(
                    "at least {min_hz:.2} Hz: the fastest robot ({vmax} m/s) may move at most {travel} m per {step} step"
                ),
                format!("{hz} Hz ({:.3} m per step)", vmax / hz),
            ));
        }
    }
    Ok(())
}
