//! Object spaces (Calderita et al.'s Ψ per object): the share of instants the robot centre spends
//! inside each object's interaction polygon, whatever the activity state (Calderita's definition)
//! or only while its activity is on (ours), and inside at least one space under each reading
//! (Ψ(Objects)).
//!
//! Calderita et al. count any time inside an object's interaction space: their Table 1 Path 1 (the
//! social planner's own path) scores a Ψ(Objects) of 34.98% by crossing the TV's space while no
//! therapy uses it.
//! `psi_objects_any` is that definition; `psi_objects_active` counts only the instants when the
//! activity that gives the space its meaning is on (an idle TV's space bothers nobody).

use serde::Serialize;

use super::{ObjectSpaces, Samples, pct};
use crate::geom::contains_point_polygon_pnpoly;

/// The object space metrics of an episode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ObjectMetrics {
    /// Percentage of instants with the robot centre inside the object's interaction polygon
    /// while its activity is on, per object; `None` entries without samples.
    pub psi_object_active: Vec<Option<f64>>,
    /// Calderita's Ψ per object: percentage of instants inside the object's polygon whatever its
    /// activity state; `None` entries without samples.
    pub psi_object_any: Vec<Option<f64>>,
    /// Calderita et al.'s Ψ(Objects) as they define it: percentage of instants inside at least
    /// one object space, active or not; `None` without samples.
    pub psi_objects_any: Option<f64>,
    /// Ψ(Objects) counting only active spaces: percentage of instants inside at least one object
    /// space whose activity is on; `None` without samples.
    pub psi_objects_active: Option<f64>,
}

/// The object space metrics of the recording `s` among `objects`.
pub(crate) fn evaluate(s: &Samples, objects: &ObjectSpaces) -> ObjectMetrics {
    let nm = objects.polygons.len();
    let mut obj_active_in = vec![0usize; nm];
    let mut obj_any_in = vec![0usize; nm];
    let (mut any_in, mut any_active_in) = (0usize, 0usize);
    for (t, &p) in s.pos.iter().enumerate() {
        let (mut inside, mut active) = (false, false);
        for (k, poly) in objects.polygons.iter().enumerate() {
            if contains_point_polygon_pnpoly(p, poly) {
                obj_any_in[k] += 1;
                inside = true;
                if objects.active[t * nm + k] {
                    obj_active_in[k] += 1;
                    active = true;
                }
            }
        }
        any_in += usize::from(inside);
        any_active_in += usize::from(active);
    }
    ObjectMetrics {
        psi_object_active: obj_active_in.iter().map(|&c| pct(c, s.n)).collect(),
        psi_object_any: obj_any_in.iter().map(|&c| pct(c, s.n)).collect(),
        psi_objects_any: pct(any_in, s.n),
        psi_objects_active: pct(any_active_in, s.n),
    }
}
