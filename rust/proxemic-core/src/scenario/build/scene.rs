//! The scene settings (`[scene]`) and the walls (`[[wall]]`).

use super::polygons::oriented_rect;
use crate::error::Result;
use crate::scenario::check::{Checker, err, parse_time_of_day};
use crate::scenario::model::{Scene, Wall};
use crate::scenario::raw::{RawScene, RawWall};

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
pub(super) fn build_walls(ck: &Checker<'_>, raw: &[RawWall], wall_height: f64) -> Result<Vec<Wall>> {
    let file = ck.file;
    let mut walls = Vec::with_capacity(raw.len());
    for (i, w) in raw.iter().enumerate() {
        let f = format!("wall[{i}]");
        ck.finite(&format!("{f}.from"), &w.from)?;
        ck.finite(&format!("{f}.to"), &w.to)?;
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
