//! The social cost map: layers on the map grid that the social planner searches.
//!
//! Layers (Calderita et al. §5.2.1-5.2.2, with the cost values of the paper as defaults):
//! - **static**: the inflated static map; lethal cells stay lethal;
//! - **people**: for every individual (a person, a group treated as one individual, or a robot
//!   that has joined an interaction), its intimate zone is forbidden (lethal), its personal zone
//!   costs 4.0, its social zone 2.0, and the public zone 1.0 (the free-space cost); or, in the
//!   continuous mode, the cost is `1 + gain * f(p)` with `f` the individual's personal-space
//!   function;
//! - **objects**: the cells of each object's interaction space cost R(t), the object's
//!   time-dependent cost from the agenda (1.5 idle, up to 3.5 during an activity);
//! - **combined**: the maximum of the layers, as the `u8` cost grid the A* searches.
//!
//! Costs are traversal *factors* (a path's cost is the sum of the factors of the cells it
//! enters times the step lengths, as in Calderita's Dijkstra). The A* grid stores a factor `f`
//! as `c = round((f - 1) / (max_factor - 1) * 252)` and searches with weight
//! `w = max_factor - 1`, so that its edge cost `len * (1 + w * c / 252)` is `len * f` up to the
//! 1/252 quantisation.
//!
//! Zones: a point's zone around an individual is decided by its *zone distance*, the distance
//! that the individual's space function assigns to the point (the Euclidean distance for a
//! symmetric function; stretched in front and shrunk behind for asymmetric ones), compared with
//! Hall's radii. Distances are centre to centre.
//!
//! Updates are incremental: moving individuals re-evaluate only the cells of their old and new
//! bounding boxes, and a change of the clock re-evaluates only the objects whose cost changed.
//!
//! Files:
//! - `cost_model`: what the map needs of an individual ([`SpaceFunction`]), the cost parameters
//!   ([`SocialCosts`], [`CostMode`]) and the `u8` encoding of factors;
//! - `zone_sweep`: the row sweeps that decide the zone of every cell of an individual's box;
//! - `incremental`: the layered map ([`SocialMap`]) and its incremental updates;
//! - `calderita`: the density layer of Calderita et al. ([`DensityLayer`]) and its tiled
//!   accelerator.

mod calderita;
mod cost_model;
mod incremental;
mod zone_sweep;

pub use calderita::{DensityLayer, density_factor, density_layer};
pub use cost_model::{CostMode, SocialCosts, SpaceFunction};
pub use incremental::SocialMap;

#[cfg(test)]
mod tests;
