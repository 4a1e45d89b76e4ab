//! Grid path planning: one 8-connected A* with two modes (plain and cost-aware), a Dijkstra oracle,
//! and line-of-sight path smoothing (`docs/algorithms.md` §5).
//!
//! - [`astar`]: the search on the cost grid ([`crate::map::CostGrid`]) and the goal-relocation
//!   helper.
//! - `open_list`: the search's open list (packed keys, a ring of buckets and a 4-ary heap).
//! - [`geodesic`]: the geodesic distance field to a goal (progress reward, re-plan bounds).
//! - [`smooth`]: greedy line-of-sight shortcutting and polyline cost evaluation.
//! - [`social`]: the social global planner: social A* on the social cost map and its re-planning
//!   triggers.

pub mod astar;
pub mod geodesic;
mod open_list;
pub mod smooth;
pub mod social;

pub use astar::{GridPath, PathPlanner, SearchMode, nearest_passable, snap_to_passable};
pub use smooth::{path_cost, smooth_path};
