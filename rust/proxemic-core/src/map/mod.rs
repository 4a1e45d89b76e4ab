//! Static geometry, occupancy grid, distance field and ray casting.
//!
//! - [`geometry`]: the world's static polygons and exact queries on them (parry2d underneath).
//! - [`grid`]: the grid frame, conservative rasterisation and the Euclidean distance transform.
//! - [`lidar`]: a 2D range scan against the static geometry plus dynamic discs.

pub mod geometry;
pub mod grid;
pub mod lidar;
pub mod raycast;

pub use geometry::{Bounds, StaticGeometry};
pub use grid::{DistanceField, GridSpec, OccupancyGrid};
pub use lidar::{Scanner, scan};
