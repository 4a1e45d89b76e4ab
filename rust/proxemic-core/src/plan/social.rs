//! The social global planner: social A* on the social cost map, and its re-planning triggers.
//!
//! The map combines the static layer, the people who stay where they are (the individuals of
//! [`crate::perception::perceive`] whose members all move slower than [`MAP_STILL_SPEED`]: people
//! standing, sitting, talking or looking at an exhibit) and the objects' interaction spaces at
//! R(t) from the agenda. People who walk are left to the local planner, which predicts their
//! motion: where a walker is now says little about where they will be when the robot gets there,
//! and mapping them sent the robot on long detours around a corridor's passing traffic. The
//! path is re-planned when
//! - the agenda changes an object's cost along the path,
//! - people move into the path (a point of the path ahead is now in someone's zone with a
//!   higher cost than when it was planned), or
//! - the path is blocked (a point ahead is in an intimate zone).
//!
//! The checks run on points sampled along the path ahead, so they cost little; the map itself is
//! updated (incrementally) only when a plan is made.
//!
//! Two people models ([`PeopleModel`]): proxemic's own (each perceived individual's Hall zones on
//! its space function, searched by A*: the `social_astar` and `social` planners) and Calderita's
//! (the zones as contours of the summed density `G_d`, [`crate::social_cost_map::DensityLayer`],
//! searched by Dijkstra: the `calderita` planner). Each model has its own maps; a path remembers
//! its model, so its checks see the map it was planned on.

use crate::chronemics::Agenda;
use crate::error::Result;
use crate::geom::contains_point_polygon;
use crate::groups::{DensityParams, DetectorMemory, GroupMethod, PersonState, RobotDisc};
use crate::map::CostGrid;
use crate::math::Vec2;
use crate::pedestrians::Crowd;
use crate::perception::{Individual, Perception, ProxemicsConfig, perceive_with};
use crate::plan::{PathPlanner, SearchMode, smooth_path};
use crate::proxemics::DensityZones;
use crate::scenario::Scenario;
use crate::social_cost_map::{DensityLayer, SocialMap, density_factor};

/// Spacing of the points sampled along a path for the re-planning checks (metres).
pub const SAMPLE_SPACING: f64 = 0.25;
/// How far ahead along the path the checks look (metres).
const LOOKAHEAD: f64 = 8.0;
/// A sampled point whose traversal factor rose by at least this much triggers a re-plan.
const FACTOR_RISE: f64 = 0.75;
/// Individuals whose members all move slower than this (m/s) are in the global map; the others
/// are walking and left to the local planner.
pub const MAP_STILL_SPEED: f64 = 0.25;

/// Why a path should be re-planned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Trigger {
    /// Nothing changed enough.
    None,
    /// Someone's intimate zone covers the path ahead.
    Blocked,
    /// People moved into the path ahead.
    People,
    /// The agenda raised an object's cost on the path ahead.
    Agenda,
}

/// How the people enter a social map.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PeopleModel {
    /// Each perceived individual (a person, a group as one individual, a robot that joined)
    /// with its Hall zones on its space function; searched by A* (proxemic's `social_astar`).
    #[default]
    Individuals,
    /// Calderita §4.1/§5.2.1: the zones as contours of the summed density `G_d` of the people,
    /// a group's space `G_d >= φ` at least personal; searched by Dijkstra (the `calderita`
    /// planner). Tie-breaks of the search: see [`crate::plan::astar`] (larger `g`, then the
    /// smaller cell index; the paper does not say).
    Density,
}

/// A planned social path with the traversal factors seen along it when it was planned.
#[derive(Clone, Debug, Default)]
pub struct SocialPath {
    /// Waypoints (world frame).
    pub points: Vec<Vec2>,
    samples: Vec<(Vec2, f64, f64)>,
    /// The people model the path was planned with (its checks use the same).
    pub model: PeopleModel,
    /// Cells the search that found it expanded (its cost in work, for the refresh period).
    pub expansions: usize,
}

/// State of the social planner for all robots of a world.
pub struct SocialPlanning {
    cfg: ProxemicsConfig,
    agenda: Agenda,
    object_names: Vec<String>,
    object_polygons: Vec<Vec<Vec2>>,
    /// The y range (lowest, highest vertex) of each of `object_polygons` ([`object_factor`]).
    object_spans: Vec<(f64, f64)>,
    maps: Vec<SocialMap>,
    /// The maps of [`PeopleModel::Density`], one per inflated grid, and their people layers.
    density_maps: Vec<SocialMap>,
    density_layers: Vec<DensityLayer>,
    /// Calderita's density zones (the scenario's density parameters if it groups by density,
    /// else the paper's defaults) on the scenario's Hall radii.
    density: DensityZones,
    /// The people who stand still (the density model's people).
    still: Vec<PersonState>,
    features: Vec<Vec<f64>>,
    perception: Option<Perception>,
    /// The perceived individuals that stay where they are (the global map's people).
    mapped: Vec<Individual>,
    people: Vec<PersonState>,
    /// The group detector's memory from the previous perception.
    detector: DetectorMemory,
}

impl SocialPlanning {
    /// Builds the social model and one social map per inflated grid, given with its inflation
    /// radius (m): the map widens the objects' interaction spaces by it, so the robot's body
    /// keeps out of a space whose edge its path follows.
    pub fn new(scenario: &Scenario, grids: &[(&CostGrid, f64)]) -> Result<Self> {
        let cfg = scenario.proxemics_config();
        let agenda = scenario.agenda()?;
        let mut object_names = Vec::new();
        let mut object_polygons = Vec::new();
        for o in &scenario.objects {
            if let Some(space) = &o.interaction {
                object_names.push(o.name.clone());
                object_polygons
                    .push(space.polygon.iter().map(|q| Vec2::new(q[0], q[1])).collect::<Vec<Vec2>>());
            }
        }
        let maps: Vec<SocialMap> = grids
            .iter()
            .map(|&(g, radius)| {
                let costs = crate::social_cost_map::SocialCosts { object_margin: radius, ..cfg.costs };
                SocialMap::new(g.clone(), &object_polygons, costs)
            })
            .collect();
        let object_spans = object_polygons.iter().map(|poly| y_span(poly)).collect();
        let density_maps = maps.clone();
        let params = match cfg.groups {
            Some(GroupMethod::Density(p)) => p,
            _ => DensityParams::default(),
        };
        let density = DensityZones::new(params, cfg.zones)?;
        let density_layers =
            density_maps.iter().map(|m| DensityLayer::new(m.grid().spec, density, m.costs())).collect();
        let features = scenario.persons.iter().map(|p| p.features.clone()).collect();
        Ok(SocialPlanning {
            cfg,
            agenda,
            object_names,
            object_polygons,
            object_spans,
            maps,
            density_maps,
            density_layers,
            density,
            still: Vec::new(),
            features,
            perception: None,
            detector: DetectorMemory::default(),
            mapped: Vec::new(),
            people: Vec::new(),
        })
    }

    /// The social model.
    pub fn config(&self) -> &ProxemicsConfig {
        &self.cfg
    }

    /// The social map of inflated grid `k`.
    pub fn map(&self, k: usize) -> Option<&SocialMap> {
        self.maps.get(k)
    }

    /// The density map of inflated grid `k` (the `calderita` planner's; as last planned on).
    pub fn density_map(&self, k: usize) -> Option<&SocialMap> {
        self.density_maps.get(k)
    }

    /// Calderita's density zones ([`PeopleModel::Density`]).
    pub fn density_zones(&self) -> &DensityZones {
        &self.density
    }

    /// The latest perception (groups and individuals), if any.
    pub fn perception(&self) -> Option<&Perception> {
        self.perception.as_ref()
    }

    /// Names of the objects with interaction spaces, in the order of the object layer.
    pub fn object_names(&self) -> &[String] {
        &self.object_names
    }

    /// Whether each object's activity is on at `time_of_day` (seconds after midnight), in the
    /// order of [`Self::object_names`], written into `out`.
    pub fn object_activity(&self, time_of_day: f64, out: &mut Vec<bool>) {
        out.clear();
        out.extend(self.object_names.iter().map(|n| self.agenda.active(n, time_of_day)));
    }

    /// The object factor at `p` for the per-object `factors` (in the order of
    /// [`Self::object_names`]): the largest factor of the interaction polygons containing `p`,
    /// at least 1 (infinite where an infinite factor's polygon contains `p`).
    pub fn object_factor_at(&self, p: Vec2, factors: &[f64]) -> f64 {
        object_factor(p, &self.object_polygons, &self.object_spans, factors)
    }

    /// The interaction polygons of the objects with one (world frame, m), in the order of
    /// [`Self::object_names`].
    pub fn object_polygons(&self) -> &[Vec<Vec2>] {
        &self.object_polygons
    }

    /// R(t) of every object with an interaction space at `time_of_day`.
    pub fn object_factors(&self, time_of_day: f64) -> Vec<f64> {
        self.object_names.iter().map(|n| self.agenda.cost(n, time_of_day)).collect()
    }

    /// Perceives the people (and the robots that may join their interactions).
    pub fn perceive(&mut self, crowd: &Crowd, robots: &[RobotDisc]) -> Result<()> {
        self.people.clear();
        for k in 0..crowd.len() {
            self.people.push(PersonState { pos: crowd.pos[k], heading: crowd.heading[k], vel: crowd.vel[k] });
        }
        let perception = perceive_with(&self.cfg, &self.people, &self.features, robots, &mut self.detector)?;
        let people = &self.people;
        self.mapped.clear();
        self.mapped.extend(
            perception
                .individuals
                .iter()
                .filter(|ind| ind.members.iter().all(|&k| people[k].vel.norm() < MAP_STILL_SPEED))
                .cloned(),
        );
        self.still.clear();
        self.still.extend(self.people.iter().filter(|p| p.vel.norm() < MAP_STILL_SPEED).copied());
        self.perception = Some(perception);
        Ok(())
    }

    /// Brings social map `k` up to date with the latest perception and the agenda at
    /// `time_of_day` (incrementally).
    pub fn update_map(&mut self, k: usize, time_of_day: f64) {
        let factors = self.object_factors(time_of_day);
        let Some(map) = self.maps.get_mut(k) else { return };
        // One factor per object name, the names the maps were made with (`SocialPlanning::new`),
        // finite for the world's finite clock.
        let set = map.set_object_factors(&factors);
        debug_assert!(set.is_ok(), "{set:?}");
        if self.perception.is_some() {
            map.update_people(&self.mapped);
        }
    }

    /// Brings density map `k` up to date with the people standing still and the agenda at
    /// `time_of_day` (the people layer incrementally, [`DensityLayer::update`]).
    fn update_density_map(&mut self, k: usize, time_of_day: f64) {
        let factors = self.object_factors(time_of_day);
        let (Some(map), Some(layer)) = (self.density_maps.get_mut(k), self.density_layers.get_mut(k)) else {
            return;
        };
        let set = map.set_object_factors(&factors);
        debug_assert!(set.is_ok(), "{set:?}");
        layer.update(&self.still);
        // The layer was made for this map's grid (`SocialPlanning::new`), so they always agree.
        let written = layer.write_to(map);
        debug_assert!(written.is_ok(), "{written:?}");
    }

    /// Traversal factor at `p` from the people (under `model`) and the objects at
    /// `time_of_day`: (people factor, object factor).
    fn factors_at(&self, p: Vec2, object_factors: &[f64], model: PeopleModel) -> (f64, f64) {
        let mut people: f64 = 1.0;
        match model {
            PeopleModel::Individuals => {
                for ind in &self.mapped {
                    let [x0, y0, x1, y1] = ind_bounds(ind);
                    if p.x >= x0 && p.x <= x1 && p.y >= y0 && p.y <= y1 {
                        people = people.max(self.cfg.costs.factor(ind, p));
                    }
                }
            }
            PeopleModel::Density => {
                people = density_factor(&self.density, &self.cfg.costs, &self.still, p);
            }
        }
        (people, object_factor(p, &self.object_polygons, &self.object_spans, object_factors))
    }

    /// Plans a social A* path on map `k` from `start` to `goal` at `time_of_day` (updating the
    /// map first). `None` when the goal is unreachable on the social map.
    pub fn plan(
        &mut self,
        planner: &mut PathPlanner,
        k: usize,
        start: Vec2,
        goal: Vec2,
        time_of_day: f64,
    ) -> Option<SocialPath> {
        self.plan_with(planner, k, start, goal, time_of_day, PeopleModel::Individuals)
    }

    /// Plans a path on map `k` of the people model `model` from `start` to `goal` at
    /// `time_of_day` (updating the map first): A* for [`PeopleModel::Individuals`], Dijkstra (no
    /// heuristic, as Calderita §5.1) for [`PeopleModel::Density`]. The grid path is shortcut by
    /// [`smooth_path`], which never raises its cost. `None` when the goal is unreachable.
    pub fn plan_with(
        &mut self,
        planner: &mut PathPlanner,
        k: usize,
        start: Vec2,
        goal: Vec2,
        time_of_day: f64,
        model: PeopleModel,
    ) -> Option<SocialPath> {
        let map = match model {
            PeopleModel::Individuals => {
                self.update_map(k, time_of_day);
                self.maps.get(k)?
            }
            PeopleModel::Density => {
                self.update_density_map(k, time_of_day);
                self.density_maps.get(k)?
            }
        };
        let grid = map.grid();
        let weight = self.cfg.costs.weight();
        let s = crate::plan::snap_to_passable(grid, start)?;
        let g = crate::plan::snap_to_passable(grid, goal)?;
        let heuristic = model == PeopleModel::Individuals;
        let path = planner.plan(grid, s, g, SearchMode { weight, heuristic })?;
        let mut points = smooth_path(grid, &path, weight);
        if let Some(first) = points.first_mut() {
            *first = start;
        }
        points.push(goal);
        let factors = self.object_factors(time_of_day);
        let samples = sample_path(&points, 0.0, f64::INFINITY)
            .into_iter()
            .map(|q| {
                let (pf, of) = self.factors_at(q, &factors, model);
                (q, pf, of)
            })
            .collect();
        Some(SocialPath { points, samples, model, expansions: path.expansions })
    }

    /// Cost of `path` when it was planned: its length weighted by the traversal factor seen
    /// along it (m; people and objects, the larger of the two), as the social A* counts it.
    pub fn planned_cost(path: &SocialPath) -> f64 {
        path.samples.iter().map(|&(_, pf, of)| SAMPLE_SPACING * pf.max(of)).sum()
    }

    /// Cost of what is left of `path` for a robot at `from`, on today's map: the straight
    /// way to the nearest sample that `visible` says can be reached in a straight line, then
    /// the remaining samples weighted by their traversal factor now (m; infinite when no sample
    /// can be reached straight or someone's intimate zone now covers the rest).
    pub fn remaining_cost(
        &self,
        path: &SocialPath,
        from: Vec2,
        time_of_day: f64,
        visible: impl Fn(Vec2, Vec2) -> bool,
    ) -> f64 {
        let factors = self.object_factors(time_of_day);
        // The nearest visible sample (the first in path order among equally near ones): samples
        // are tried nearest first, so the line-of-sight test runs only until one passes.
        let mut order: Vec<(f64, usize)> =
            path.samples.iter().enumerate().map(|(i, s)| ((s.0 - from).norm(), i)).collect();
        order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let Some((first, q)) =
            order.iter().map(|&(_, i)| (i, path.samples[i].0)).find(|&(_, q)| visible(from, q))
        else {
            return f64::INFINITY;
        };
        let mut cost = (q - from).norm();
        for &(q, _, _) in &path.samples[first + 1..] {
            let (pf, of) = self.factors_at(q, &factors, path.model);
            cost += SAMPLE_SPACING * pf.max(of);
        }
        cost
    }

    /// Whether `path` should be re-planned, looking ahead from the sample nearest to `from`.
    pub fn check(&self, path: &SocialPath, from: Vec2, time_of_day: f64) -> Trigger {
        let factors = self.object_factors(time_of_day);
        let Some(first) = path
            .samples
            .iter()
            .enumerate()
            .min_by(|a, b| (a.1.0 - from).norm().total_cmp(&(b.1.0 - from).norm()))
            .map(|(i, _)| i)
        else {
            return Trigger::None;
        };
        let ahead = (LOOKAHEAD / SAMPLE_SPACING) as usize;
        let mut trigger = Trigger::None;
        for &(q, people_then, objects_then) in path.samples.iter().skip(first + 1).take(ahead) {
            let (people_now, objects_now) = self.factors_at(q, &factors, path.model);
            if people_now.is_infinite() {
                return Trigger::Blocked;
            }
            if people_now >= people_then + FACTOR_RISE {
                trigger = Trigger::People;
            } else if objects_now >= objects_then + FACTOR_RISE && trigger == Trigger::None {
                trigger = Trigger::Agenda;
            }
        }
        trigger
    }
}

/// The y range of `poly`: its lowest and highest vertex (`(inf, -inf)` when empty).
fn y_span(poly: &[Vec2]) -> (f64, f64) {
    poly.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), q| (lo.min(q.y), hi.max(q.y)))
}

/// The object factor at `p`: the largest of `factors` (finite) of the `polygons` containing `p`,
/// at least 1. `spans` holds each polygon's [`y_span`]. A polygon is tested only when its factor
/// could raise the maximum so far and `p.y` is in its y range (lowest vertex included, highest
/// excluded): [`contains_point_polygon`] counts the edges whose ends lie on either side of the
/// line `y = p.y` (one above it, the other on or below), and no edge does otherwise, so the
/// skipped tests are false, and the result is the plain maximum's bit for bit.
fn object_factor(p: Vec2, polygons: &[Vec<Vec2>], spans: &[(f64, f64)], factors: &[f64]) -> f64 {
    let mut objects: f64 = 1.0;
    for ((poly, &(lo, hi)), &f) in polygons.iter().zip(spans).zip(factors) {
        if f > objects && p.y >= lo && p.y < hi && contains_point_polygon(p, poly) {
            objects = f;
        }
    }
    objects
}

fn ind_bounds(ind: &crate::perception::Individual) -> [f64; 4] {
    use crate::social_cost_map::SpaceFunction;
    ind.bounds()
}

/// Points every [`SAMPLE_SPACING`] metres along a polyline between arc lengths `from` and `to`.
fn sample_path(points: &[Vec2], from: f64, to: f64) -> Vec<Vec2> {
    let mut out = Vec::new();
    let mut s = 0.0;
    let mut next = from;
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = (b - a).norm();
        while next <= s + len && next <= to {
            let t = if len > 0.0 { (next - s) / len } else { 0.0 };
            out.push(a + (b - a) * t);
            next += SAMPLE_SPACING;
        }
        s += len;
    }
    if let Some(&last) = points.last() {
        out.push(last);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`object_factor`] (a polygon tested only when its factor could raise the maximum and the
    /// point is in its y range) against the plain maximum over every containing polygon, bit for
    /// bit, at random points and at points on the polygons' vertex rows and vertices.
    #[test]
    fn object_factor_skips_only_tests_that_cannot_change_it() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(19);
        for _ in 0..200 {
            let polygons: Vec<Vec<Vec2>> = (0..rng.random_range(0..6))
                .map(|_| {
                    let c = Vec2::new(rng.random_range(0.0..10.0), rng.random_range(0.0..10.0));
                    // Star-shaped, some with a horizontal bottom or top edge (two vertices at the
                    // same y), some empty.
                    let n = rng.random_range(0..7);
                    let mut poly: Vec<Vec2> = (0..n)
                        .map(|k| {
                            let a = k as f64 / n as f64 * std::f64::consts::TAU;
                            c + Vec2::new(a.cos(), a.sin()) * rng.random_range(0.5..3.0)
                        })
                        .collect();
                    if n >= 3 && rng.random_bool(0.5) {
                        poly[1].y = poly[0].y;
                    }
                    poly
                })
                .collect();
            let spans: Vec<(f64, f64)> = polygons.iter().map(|p| y_span(p)).collect();
            let factors: Vec<f64> = polygons.iter().map(|_| rng.random_range(0.5..4.0)).collect();
            let vertices: Vec<Vec2> = polygons.iter().flatten().copied().collect();
            for k in 0..400 {
                let mut p = Vec2::new(rng.random_range(-2.0..12.0), rng.random_range(-2.0..12.0));
                if !vertices.is_empty() && k % 2 == 0 {
                    let v = vertices[rng.random_range(0..vertices.len())];
                    p.y = v.y;
                    if k % 4 == 0 {
                        p.x = v.x;
                    }
                }
                let plain = polygons
                    .iter()
                    .zip(&factors)
                    .filter(|(poly, _)| contains_point_polygon(p, poly))
                    .fold(1.0_f64, |m, (_, &f)| m.max(f));
                let fast = object_factor(p, &polygons, &spans, &factors);
                assert_eq!(fast.to_bits(), plain.to_bits(), "{p:?} {polygons:?} {factors:?}");
            }
        }
    }

    #[test]
    fn samples_are_evenly_spaced_and_end_at_the_goal() {
        let pts = [Vec2::zeros(), Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0)];
        let s = sample_path(&pts, 0.0, f64::INFINITY);
        assert_eq!(s.len(), 10);
        assert!((s[4] - Vec2::new(1.0, 0.0)).norm() < 1e-12);
        assert_eq!(*s.last().expect("non-empty"), Vec2::new(1.0, 1.0));
    }
}
