//! Object spaces (Calderita et al.'s Ψ per object): the share of instants the robot centre spends
//! inside each object's interaction polygon while its activity is on, or whatever its state, and
//! inside at least one active space (Ψ(Objects)).

use serde::Serialize;

use super::{ObjectSpaces, Samples, pct};
use crate::geom::contains_point_polygon_pnpoly;

/// The object space metrics of an episode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ObjectMetrics {
    /// Calderita's Ψ per object: percentage of instants with the robot centre inside the
    /// object's interaction polygon while its activity is on; `None` entries without samples.
    pub psi_object: Vec<Option<f64>>,
    /// Percentage of instants inside the object's polygon whatever its activity state.
    pub psi_object_any: Vec<Option<f64>>,
    /// Calderita's Ψ(Objects): percentage of instants inside at least one active object space.
    pub psi_objects: Option<f64>,
}

/// The object space metrics of the recording `s` among `objects`.
pub(crate) fn evaluate(s: &Samples, objects: &ObjectSpaces) -> ObjectMetrics {
    let nm = objects.polygons.len();
    let mut obj_active_in = vec![0usize; nm];
    let mut obj_any_in = vec![0usize; nm];
    let mut any_active_in = 0usize;
    for (t, &p) in s.pos.iter().enumerate() {
        let mut hit = false;
        for (k, poly) in objects.polygons.iter().enumerate() {
            if contains_point_polygon_pnpoly(p, poly) {
                obj_any_in[k] += 1;
                if objects.active[t * nm + k] {
                    obj_active_in[k] += 1;
                    hit = true;
                }
            }
        }
        any_active_in += usize::from(hit);
    }
    ObjectMetrics {
        psi_object: obj_active_in.iter().map(|&c| pct(c, s.n)).collect(),
        psi_object_any: obj_any_in.iter().map(|&c| pct(c, s.n)).collect(),
        psi_objects: pct(any_active_in, s.n),
    }
}
