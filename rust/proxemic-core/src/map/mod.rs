//! Static geometry, occupancy grid, distance field, cost grid and ray casting.
//!
//! The map is the lowest layer of the core's grids: it imports neither the planners ([`crate::plan`])
//! nor the social cost map ([`crate::social_cost_map`]), which both build on it.
//!
//! - [`cost_grid`]: the cost grid every planner and map layer reads, and its inflation.
//! - [`geometry`]: the world's static polygons and exact queries on them (parry2d underneath).
//! - [`grid`]: the grid frame, conservative rasterisation and the Euclidean distance transform.
//! - [`lidar`]: a 2D range scan against the static geometry plus dynamic discs.
//! - [`raster`]: the cells of a polygon (with a margin).
//! - `sight`: the line-of-sight walk (the cells of a rectangle open to a point, around obstacles).

pub mod cost_grid;
pub mod geometry;
pub mod grid;
pub mod lidar;
pub mod raster;
pub mod raycast;
pub(crate) mod sight;

pub use cost_grid::{CostGrid, INSCRIBED, LETHAL};
pub use geometry::{Bounds, StaticGeometry};
pub use grid::{DistanceField, GridSpec, OccupancyGrid};
pub use lidar::{Scanner, scan};
pub use raster::polygon_cells;

#[cfg(test)]
mod tests {
    /// The modules built on the map; no code line of the map may name one of them.
    const HIGHER: [&str; 11] = [
        "crate::chronemics",
        "crate::control",
        "crate::groups",
        "crate::metrics",
        "crate::pedestrians",
        "crate::perception",
        "crate::plan",
        "crate::proxemics",
        "crate::scenario",
        "crate::social_cost_map",
        "crate::world",
    ];

    #[test]
    fn the_map_imports_no_higher_layer() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/map");
        let mut files = 0;
        for entry in std::fs::read_dir(&dir).expect("src/map is readable") {
            let path = entry.expect("a directory entry").path();
            if path.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            files += 1;
            let text = std::fs::read_to_string(&path).expect("a source file");
            // The code of the file, up to its test module (this test's own list names the layers).
            for (n, line) in text.lines().enumerate().take_while(|(_, l)| l.trim() != "#[cfg(test)]") {
                let code = line.trim_start();
                if code.starts_with("//") {
                    continue;
                }
                for higher in HIGHER {
                    assert!(!code.contains(higher), "{}:{}: the map names {higher}", path.display(), n + 1);
                }
            }
        }
        assert!(files >= 5, "only {files} files read in {}", dir.display());
    }
}
