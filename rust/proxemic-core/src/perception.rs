//! Social perception: from people (and robots) to the *individuals* of the social map.
//!
//! Each control step the robot sees the people's poses and velocities. [`perceive`]:
//! 1. detects groups ([`crate::groups`]: Delaunay with the distance and orientation rules of
//!    Sousa 2022, moving groups by the DILMO movement rule of Daza 2021, or the density and
//!    F-formation alternatives);
//! 2. lets a stationary robot standing in a person's personal zone join that person's
//!    interaction (Daza 2021 §4.3): it then counts as a member, with a proxemic zone like a person;
//! 3. makes one *individual* per group (Sousa 2022 §3.3.4: centre at the members' midpoint,
//!    orientation their circular mean, extents from the farthest member in each quadrant, one
//!    aggregated feature value, and its own asymmetric Gaussian) and one per person alone;
//! 4. reshapes each individual's Gaussian with its socialization features and the scenario's
//!    influence vectors (Sousa 2022 §3.3.3, see [`crate::proxemics::adapt`]).
//!
//! Individuals implement [`SpaceFunction`], so the social map can rasterise them.

use serde::Serialize;

use crate::error::Result;
use crate::groups::{
    Accuracy, DetectorMemory, FeatureAggregate, GroupMethod, Groups, JoinParams, MATCH_THRESHOLD,
    PersonState, RobotDisc, detect_with, detection_accuracy, group_as_individual, robot_joins_interaction,
};
use crate::math::Vec2;
use crate::proxemics::{Asymmetric, HallZones, PersonalSpace, Placed, Pose, SideInfluences, adapt};
use crate::social_cost_map::{CostMode, SocialCosts, SpaceFunction};

/// The social model of a scenario (its `[proxemics]` table, validated).
#[derive(Clone, Debug)]
pub struct ProxemicsConfig {
    /// Hall's zone radii (metres, centre to centre).
    pub zones: HallZones,
    /// The base personal-space function of a person.
    pub space: PersonalSpace,
    /// Names of the socialization features, in the order of each person's feature vector.
    pub features: Vec<String>,
    /// Influence vectors per side (one entry per feature).
    pub influence: SideInfluences,
    /// Costs of the social map.
    pub costs: SocialCosts,
    /// Group detection, or `None` to treat everybody as alone.
    pub groups: Option<GroupMethod>,
    /// How a group's feature values are combined.
    pub aggregate: FeatureAggregate,
    /// When a robot joins a person's interaction.
    pub join: JoinParams,
}

impl Default for ProxemicsConfig {
    fn default() -> Self {
        let zones = HallZones::EVALUATION;
        ProxemicsConfig {
            zones,
            space: PersonalSpace::CALDERITA,
            features: Vec::new(),
            influence: SideInfluences::default(),
            costs: SocialCosts {
                intimate: zones.intimate,
                personal: zones.personal,
                social: zones.social,
                ..SocialCosts::default()
            },
            groups: Some(GroupMethod::default()),
            aggregate: FeatureAggregate::Mean,
            join: JoinParams::default(),
        }
    }
}

impl ProxemicsConfig {
    /// The base function as four per-side sigmas (front, rear, right, left).
    pub fn base_sides(&self) -> Asymmetric {
        match self.space {
            PersonalSpace::Symmetric { sigma } => {
                Asymmetric { front: sigma, rear: sigma, right: sigma, left: sigma }
            }
            PersonalSpace::Kirby { sigma_h, sigma_r, sigma_s } => {
                Asymmetric { front: sigma_h, rear: sigma_r, right: sigma_s, left: sigma_s }
            }
            PersonalSpace::Asymmetric(a) => a,
        }
    }

    /// The zone scale of the base function: the side sigma for Kirby's function (sideways zone
    /// distances are Euclidean), sigma for the symmetric one, the geometric mean of the four
    /// sides for the fully asymmetric one.
    pub fn zone_scale(&self) -> f64 {
        match self.space {
            PersonalSpace::Symmetric { sigma } => sigma,
            PersonalSpace::Kirby { sigma_s, .. } => sigma_s,
            PersonalSpace::Asymmetric(a) => (a.front * a.rear * a.right * a.left).powf(0.25),
        }
    }
}

/// One individual of the social map: a person alone, or a group as one individual.
#[derive(Clone, Debug)]
pub struct Individual {
    /// Centre (metres).
    pub centre: Vec2,
    /// Orientation (radians).
    pub heading: f64,
    /// Per-side sigmas after features and group extents (metres).
    pub sides: Asymmetric,
    /// Person indices of the members (one for a person alone).
    pub members: Vec<usize>,
    /// Robot indices that joined this interaction.
    pub robots: Vec<usize>,
    placed: Placed,
    zone_scale: f64,
    bounds: [f64; 4],
}

impl Individual {
    fn new(
        centre: Vec2,
        heading: f64,
        sides: Asymmetric,
        members: Vec<usize>,
        robots: Vec<usize>,
        cfg: &ProxemicsConfig,
    ) -> Self {
        let placed = PersonalSpace::Asymmetric(sides).at(Pose::new(centre.x, centre.y, heading));
        let zone_scale = cfg.zone_scale();
        // Along each half-axis the social zone ends where sqrt(2 q) z = r_s, i.e. at
        // r_s * sigma_side / z; in each quadrant the zone lies inside the box spanned by its two
        // half-axis extents (the exponent is a sum of two squares). Continuous costs fade below
        // 1% of the centre value at sqrt(2 ln 100) sigma.
        let mut scale = cfg.costs.social / zone_scale;
        if let CostMode::Continuous { .. } = cfg.costs.mode {
            scale = scale.max((2.0 * 100f64.ln()).sqrt());
        }
        let (f, r, ri, l) =
            (sides.front * scale, sides.rear * scale, sides.right * scale, sides.left * scale);
        let (sn, cs) = heading.sin_cos();
        let mut bounds = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
        for (lx, ly) in [(f, l), (f, -ri), (-r, l), (-r, -ri)] {
            let x = centre.x + cs * lx - sn * ly;
            let y = centre.y + sn * lx + cs * ly;
            bounds = [bounds[0].min(x), bounds[1].min(y), bounds[2].max(x), bounds[3].max(y)];
        }
        Individual { centre, heading, sides, members, robots, placed, zone_scale, bounds }
    }

    /// The personal-space value at `p` in [0, 1].
    pub fn value(&self, p: Vec2) -> f64 {
        self.placed.value(p)
    }
}

impl SpaceFunction for Individual {
    fn exponent(&self, p: Vec2) -> f64 {
        self.placed.exponent(p)
    }
    fn zone_scale(&self) -> f64 {
        self.zone_scale
    }
    fn bounds(&self) -> [f64; 4] {
        self.bounds
    }
    fn quadratic(&self) -> Option<[f64; 8]> {
        Some(self.placed.coefficients())
    }
    fn centre(&self) -> Option<Vec2> {
        Some(self.centre)
    }
    fn fingerprint(&self) -> [f64; 8] {
        let s = &self.sides;
        [self.centre.x, self.centre.y, self.heading, s.front, s.rear, s.right, s.left, self.bounds[0]]
    }
}

/// Margin (in the exponent) by which an individual's exponent must exceed the best one so far for
/// [`max_value`] to skip its `exp`: `exp(-q)` is then at least a relative 1e-9 below the best
/// value, far more than the libm `exp`'s error of under 1 ulp, so its computed value is not
/// above the best one's either.
const SKIP_MARGIN: f64 = 1e-9;

/// The largest personal-space value of `individuals` at `p`, in [0, 1] (0 with none): the same
/// bits as `individuals.iter().map(|i| i.value(p)).fold(0.0, f64::max)`, but the `exp` of an
/// individual whose exponent exceeds the largest value's exponent so far (by a margin of 1e-9) is
/// not taken: its value cannot raise the maximum (the elastic band's social cost, evaluated at
/// every bubble of the `eband` planner, where the `exp`s were most of its time).
pub fn max_value(individuals: &[Individual], p: Vec2) -> f64 {
    let mut best: f64 = 0.0;
    // The exponent the best value came from (none yet: nothing is skipped).
    let mut best_exponent = f64::INFINITY;
    for ind in individuals {
        let q = ind.placed.exponent(p);
        if q >= best_exponent + SKIP_MARGIN {
            continue;
        }
        let v = ind.placed.value_of_exponent(q);
        if v > best {
            best = v;
            // (A subnormal best skips nothing: the 1-ulp bound is relative to normal numbers.)
            best_exponent = if v >= f64::MIN_POSITIVE { q } else { f64::INFINITY };
        }
    }
    best
}

/// What the robot perceives of the people in one step.
#[derive(Clone, Debug)]
pub struct Perception {
    /// Detected groups (every person is in exactly one; singletons included).
    pub groups: Groups,
    /// For each robot, the index of the group it joined, if any.
    pub robot_joins: Vec<Option<usize>>,
    /// The individuals of the social map, one per detected group.
    pub individuals: Vec<Individual>,
}

/// A [`Perception`] as reported to users, beside the scenario's ground truth
/// ([`crate::world::World::perception_report`]): plain values, in the order of these fields.
#[derive(Clone, Debug, Serialize)]
pub struct PerceptionReport {
    /// Detected group index per person.
    pub labels: Vec<usize>,
    /// Members (person indices) of each detected group.
    pub groups: Vec<Vec<usize>>,
    /// For each robot, the index of the group it joined, if any.
    pub robot_joins: Vec<Option<usize>>,
    /// The individuals of the social map, one per detected group.
    pub individuals: Vec<IndividualReport>,
    /// The scenario's group id per person (`None` for a person alone).
    pub truth: Vec<Option<u32>>,
    /// The detection scored against `truth` with GCFF's tolerant threshold
    /// ([`crate::groups::MATCH_THRESHOLD`]); `None` when it cannot be scored.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accuracy: Option<Accuracy>,
}

/// One [`Individual`] as reported to users.
#[derive(Clone, Debug, Serialize)]
pub struct IndividualReport {
    /// Centre (x, y in metres, world frame).
    pub centre: (f64, f64),
    /// Orientation (radians).
    pub heading: f64,
    /// Gaussian sigmas (metres): front, rear, right, left.
    pub sides: (f64, f64, f64, f64),
    /// The length (metres) that turns `sqrt(2 q)` into a zone distance
    /// ([`crate::proxemics::zone_distance`]).
    pub zone_scale: f64,
    /// Person indices of the members.
    pub members: Vec<usize>,
    /// Robot indices that joined the interaction.
    pub robots: Vec<usize>,
}

impl PerceptionReport {
    /// The report of `perception` against the ground truth `truth` (one entry per person).
    pub fn new(perception: &Perception, truth: Vec<Option<u32>>) -> Self {
        let labels = perception.groups.labels.clone();
        let accuracy = detection_accuracy(&labels, &truth, MATCH_THRESHOLD).ok();
        let individuals = perception
            .individuals
            .iter()
            .map(|ind| IndividualReport {
                centre: (ind.centre.x, ind.centre.y),
                heading: ind.heading,
                sides: (ind.sides.front, ind.sides.rear, ind.sides.right, ind.sides.left),
                zone_scale: ind.zone_scale,
                members: ind.members.clone(),
                robots: ind.robots.clone(),
            })
            .collect();
        PerceptionReport {
            labels,
            groups: perception.groups.members.clone(),
            robot_joins: perception.robot_joins.clone(),
            individuals,
            truth,
            accuracy,
        }
    }
}

/// Builds the social map's individuals from the people's states and feature vectors (one vector
/// per person, with one value per configured feature; empty vectors when no features are
/// configured) and the robots.
pub fn perceive(
    cfg: &ProxemicsConfig,
    people: &[PersonState],
    features: &[Vec<f64>],
    robots: &[RobotDisc],
) -> Result<Perception> {
    perceive_with(cfg, people, features, robots, &mut DetectorMemory::default())
}

/// [`perceive`], with the group detector's memory of the previous call (see [`DetectorMemory`]):
/// the same perception, faster from one control step to the next.
pub fn perceive_with(
    cfg: &ProxemicsConfig,
    people: &[PersonState],
    features: &[Vec<f64>],
    robots: &[RobotDisc],
    memory: &mut DetectorMemory,
) -> Result<Perception> {
    let groups = match &cfg.groups {
        Some(method) => detect_with(people, method, memory)?,
        None => Groups::from_labels(&(0..people.len()).collect::<Vec<usize>>()),
    };
    let robot_joins = if robots.is_empty() {
        Vec::new()
    } else {
        robot_joins_interaction(people, &groups, robots, &cfg.join)?
    };
    let mut individuals = Vec::with_capacity(groups.members.len());
    for (g, members) in groups.members.iter().enumerate() {
        let joined: Vec<usize> = (0..robot_joins.len()).filter(|&k| robot_joins[k] == Some(g)).collect();
        individuals.push(individual_of(cfg, people, features, robots, members, joined)?);
    }
    Ok(Perception { groups, robot_joins, individuals })
}

/// The individual of one detected group (Sousa 2022 §3.3.4): a person alone with their own
/// Gaussian (its sides adapted by their features), or an interaction, its `members` (indices
/// into `people`) plus the `joined` robots (indices into `robots`, taking part as people), as
/// one individual whose Gaussian covers them all and keeps a person's margin beyond them.
pub fn individual_of(
    cfg: &ProxemicsConfig,
    people: &[PersonState],
    features: &[Vec<f64>],
    robots: &[RobotDisc],
    members: &[usize],
    joined: Vec<usize>,
) -> Result<Individual> {
    let base = cfg.base_sides();
    let fv_of = |i: usize| features.get(i).cloned().unwrap_or_default();
    if members.len() == 1 && joined.is_empty() {
        let i = members[0];
        let sides = if cfg.features.is_empty() { base } else { adapt(base, &fv_of(i), &cfg.influence)? };
        return Ok(Individual::new(people[i].pos, people[i].heading, sides, vec![i], vec![], cfg));
    }
    // Members of the interaction: the people plus the robots that joined it (as people).
    let mut states: Vec<PersonState> = members.iter().map(|&i| people[i]).collect();
    for &k in &joined {
        let r = &robots[k];
        let toward = people[members[0]].pos - r.pos;
        states.push(PersonState { pos: r.pos, heading: toward.y.atan2(toward.x), vel: r.vel });
    }
    let nf = cfg.features.len();
    let group_fv: Vec<f64> = if nf == 0 {
        Vec::new()
    } else {
        // One aggregated value per feature (Sousa 2022 §3.3.4); robots carry no features.
        (0..nf)
            .map(|f| {
                let vals: Vec<f64> =
                    members.iter().map(|&i| fv_of(i).get(f).copied().unwrap_or(1.0)).collect();
                let member_states: Vec<PersonState> = members.iter().map(|&i| people[i]).collect();
                group_as_individual(&member_states, &vals, cfg.aggregate).map(|gi| gi.feature)
            })
            .collect::<Result<Vec<f64>>>()?
    };
    let ones = vec![1.0; states.len()];
    let gi = group_as_individual(&states, &ones, cfg.aggregate)?;
    // The group's Gaussian covers its members and keeps a person's margin beyond them.
    let grown = Asymmetric {
        front: base.front + gi.front,
        rear: base.rear + gi.rear,
        right: base.right + gi.right,
        left: base.left + gi.left,
    };
    let sides = if nf == 0 { grown } else { adapt(grown, &group_fv, &cfg.influence)? };
    Ok(Individual::new(gi.centre, gi.heading, sides, members.to_vec(), joined, cfg))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::groups::DelaunayParams;

    fn standing(x: f64, y: f64, th: f64) -> PersonState {
        PersonState::standing(Vec2::new(x, y), th)
    }

    #[test]
    fn max_value_is_the_plain_maximum_bit_for_bit() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(23);
        let cfg = ProxemicsConfig::default();
        let mut skipped_somewhere = false;
        for trial in 0..40 {
            // People scattered, some in conversations (groups), some twice at the same pose.
            let n = 1 + trial % 30;
            let mut people: Vec<PersonState> = (0..n)
                .map(|_| {
                    standing(
                        rng.random_range(-8.0..8.0),
                        rng.random_range(-5.0..5.0),
                        rng.random_range(-3.2..3.2),
                    )
                })
                .collect();
            if n > 2 {
                people.push(people[1]);
            }
            let features = vec![vec![]; people.len()];
            let p = perceive(&cfg, &people, &features, &[]).expect("valid");
            let inds = &p.individuals;
            let mut points: Vec<Vec2> = (0..300)
                .map(|_| Vec2::new(rng.random_range(-12.0..12.0), rng.random_range(-9.0..9.0)))
                .collect();
            // At the centres, and far enough for subnormal and zero values.
            points.extend(inds.iter().map(|i| i.centre));
            points.extend([Vec2::new(60.0, 0.0), Vec2::new(0.0, 90.0), Vec2::new(400.0, 400.0)]);
            for q in points {
                let plain = inds.iter().map(|i| i.value(q)).fold(0.0, f64::max);
                assert_eq!(max_value(inds, q).to_bits(), plain.to_bits(), "trial {trial} at {q:?}");
                // Whether some exp was skipped here (an individual farther than the best one).
                let exps: Vec<f64> = inds.iter().map(|i| i.placed.exponent(q)).collect();
                let mut best = f64::INFINITY;
                for &e in &exps {
                    skipped_somewhere |= e >= best + SKIP_MARGIN;
                    best = best.min(e);
                }
            }
        }
        assert!(skipped_somewhere);
        assert_eq!(max_value(&[], Vec2::zeros()).to_bits(), 0.0f64.to_bits());
    }

    #[test]
    fn a_person_alone_keeps_the_base_function_and_zones_are_euclidean_sideways() {
        let cfg = ProxemicsConfig::default();
        let p = perceive(&cfg, &[standing(0.0, 0.0, 0.0)], &[vec![]], &[]).expect("valid");
        assert_eq!(p.individuals.len(), 1);
        let ind = &p.individuals[0];
        assert_eq!(ind.sides, cfg.base_sides());
        // Kirby: sideways the zone distance equals the Euclidean distance; in front it is shorter
        // (the zone extends farther), behind longer.
        let side = ind.zone_distance(Vec2::new(0.0, 1.0));
        let front = ind.zone_distance(Vec2::new(1.0, 0.0));
        let rear = ind.zone_distance(Vec2::new(-1.0, 0.0));
        assert!((side - 1.0).abs() < 1e-12);
        assert!(front < 1.0 && rear > 1.0);
    }

    #[test]
    fn a_conversation_is_one_individual_covering_its_members() {
        let cfg = ProxemicsConfig::default();
        // two people facing each other 1.2 m apart
        let people = [standing(0.0, 0.0, 0.0), standing(1.2, 0.0, std::f64::consts::PI)];
        let p = perceive(&cfg, &people, &[vec![], vec![]], &[]).expect("valid");
        assert_eq!(p.individuals.len(), 1, "{:?}", p.groups);
        let g = &p.individuals[0];
        assert_eq!(g.members, vec![0, 1]);
        assert!((g.centre - Vec2::new(0.6, 0.0)).norm() < 1e-9);
        // the midpoint between them is deep inside the group's space (intimate: forbidden)
        assert!(g.zone_distance(Vec2::new(0.6, 0.0)) < cfg.zones.intimate);
    }

    #[test]
    fn no_group_detection_keeps_everybody_alone() {
        let cfg = ProxemicsConfig { groups: None, ..ProxemicsConfig::default() };
        let people = [standing(0.0, 0.0, 0.0), standing(1.2, 0.0, std::f64::consts::PI)];
        let p = perceive(&cfg, &people, &[vec![], vec![]], &[]).expect("valid");
        assert_eq!(p.individuals.len(), 2);
        let cfg = ProxemicsConfig {
            groups: Some(GroupMethod::Delaunay(DelaunayParams::default())),
            ..ProxemicsConfig::default()
        };
        assert_eq!(perceive(&cfg, &people, &[vec![], vec![]], &[]).expect("valid").individuals.len(), 1);
    }

    #[test]
    fn features_reshape_the_space() {
        let cfg = ProxemicsConfig {
            features: vec!["emotional_state".into()],
            influence: SideInfluences::single(0.9, 0.0, 0.5, 0.5),
            ..ProxemicsConfig::default()
        };
        let angry = perceive(&cfg, &[standing(0.0, 0.0, 0.0)], &[vec![0.14]], &[]).expect("valid");
        let happy = perceive(&cfg, &[standing(0.0, 0.0, 0.0)], &[vec![0.98]], &[]).expect("valid");
        // a happy person lets the robot come closer in front (Sousa 2022 Fig. 14a)
        assert!(happy.individuals[0].sides.front < angry.individuals[0].sides.front);
        assert_eq!(happy.individuals[0].sides.rear, angry.individuals[0].sides.rear);
    }

    #[test]
    fn a_robot_talking_to_a_person_joins_the_interaction() {
        let cfg = ProxemicsConfig::default();
        let people = [standing(0.0, 0.0, 0.0)];
        let robot = RobotDisc { pos: Vec2::new(0.9, 0.0), radius: 0.24, vel: Vec2::zeros() };
        let p = perceive(&cfg, &people, &[vec![]], &[robot]).expect("valid");
        assert_eq!(p.robot_joins, vec![Some(0)]);
        assert_eq!(p.individuals[0].robots, vec![0]);
        // the interaction covers the space between the person and the robot
        assert!(p.individuals[0].zone_distance(Vec2::new(0.45, 0.0)) < cfg.zones.intimate);
        // a moving robot does not join
        let moving = RobotDisc { vel: Vec2::new(0.5, 0.0), ..robot };
        assert_eq!(perceive(&cfg, &people, &[vec![]], &[moving]).expect("valid").robot_joins, vec![None]);
    }

    /// Hides the quadratic form, so the map takes its generic per-cell path.
    struct Generic<'a>(&'a Individual);

    impl SpaceFunction for Generic<'_> {
        fn exponent(&self, p: Vec2) -> f64 {
            self.0.exponent(p)
        }
        fn zone_scale(&self) -> f64 {
            self.0.zone_scale()
        }
        fn bounds(&self) -> [f64; 4] {
            self.0.bounds()
        }
        fn fingerprint(&self) -> [f64; 8] {
            self.0.fingerprint()
        }
        fn centre(&self) -> Option<Vec2> {
            self.0.centre()
        }
    }

    /// A wall at x = 10 (two cells thick, the grid's resolution 0.1 m) with a doorway at
    /// y 4 - 5.5: zones stop at it on both map paths.
    fn wall_with_doorway(grid: &mut crate::map::CostGrid) {
        for iy in 0..grid.spec.height {
            if !(40..55).contains(&iy) {
                for ix in 100..102 {
                    let i = grid.spec.index(ix, iy);
                    grid.cost[i] = crate::map::LETHAL;
                }
            }
        }
    }

    #[test]
    fn the_row_sweep_equals_the_per_cell_evaluation() {
        use crate::map::CostGrid;
        use crate::map::geometry::Bounds;
        use crate::map::grid::GridSpec;
        use crate::social_cost_map::SocialMap;
        let cfg = ProxemicsConfig::default();
        let people: Vec<PersonState> = (0..12)
            .map(|k| {
                let k = k as f64;
                standing(2.0 + 1.7 * k % 15.0, 2.0 + (k * 2.3) % 9.0, k * 0.7)
            })
            .collect();
        let p = perceive(&cfg, &people, &vec![vec![]; people.len()], &[]).expect("valid");
        let spec =
            GridSpec::covering(Bounds { min: Vec2::zeros(), max: Vec2::new(20.0, 12.0) }, 0.1).expect("grid");
        let mut grid = CostGrid { spec, cost: vec![0; spec.len()] };
        wall_with_doorway(&mut grid);
        let mut fast = SocialMap::new(grid.clone(), &[], cfg.costs);
        let mut slow = SocialMap::new(grid, &[], cfg.costs);
        fast.update_people(&p.individuals);
        let generic: Vec<Generic<'_>> = p.individuals.iter().map(Generic).collect();
        slow.update_people(&generic);
        let (a, b) = (fast.people_layer(), slow.people_layer());
        let differing = a.iter().zip(b).filter(|(x, y)| x != y).count();
        // Cells exactly on a zone boundary may round either way; allow a handful.
        assert!(differing <= 5, "{differing} cells differ");
        assert!(a.iter().any(|f| f.is_infinite()) && a.contains(&2.0));
    }

    #[test]
    fn counted_incremental_updates_equal_a_rebuild() {
        use crate::map::CostGrid;
        use crate::map::geometry::Bounds;
        use crate::map::grid::GridSpec;
        use crate::social_cost_map::SocialMap;
        let cfg = ProxemicsConfig::default();
        let spec =
            GridSpec::covering(Bounds { min: Vec2::zeros(), max: Vec2::new(24.0, 16.0) }, 0.1).expect("grid");
        let mut grid = CostGrid { spec, cost: vec![0; spec.len()] };
        wall_with_doorway(&mut grid);
        let mut people: Vec<PersonState> = (0..20)
            .map(|k| {
                let k = k as f64;
                PersonState {
                    pos: Vec2::new(1.0 + (k * 3.7) % 22.0, 1.0 + (k * 2.9) % 14.0),
                    heading: k,
                    vel: Vec2::zeros(),
                }
            })
            .collect();
        let fv = vec![vec![]; people.len()];
        let mut inc = SocialMap::new(grid.clone(), &[], cfg.costs);
        for step in 0..6 {
            for (k, p) in people.iter_mut().enumerate() {
                if (k + step) % 3 == 0 {
                    p.pos.x = (p.pos.x + 0.37).min(23.0);
                    p.heading += 0.4;
                }
            }
            let per = perceive(&cfg, &people, &fv, &[]).expect("valid");
            inc.update_people(&per.individuals);
            let mut full = SocialMap::new(grid.clone(), &[], cfg.costs);
            let generic: Vec<Generic<'_>> = per.individuals.iter().map(Generic).collect();
            full.update_people(&generic);
            let differing =
                inc.people_layer().iter().zip(full.people_layer()).filter(|(a, b)| a != b).count();
            assert!(differing <= 10, "step {step}: {differing} cells differ");
        }
        // an update with nobody moving touches nothing
        let per = perceive(&cfg, &people, &fv, &[]).expect("valid");
        inc.update_people(&per.individuals);
        assert_eq!(inc.cells_touched(), 0);
    }
}
