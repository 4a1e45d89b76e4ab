//! Proximity to people and room left (`docs/metrics.md`, Distance to people and Static geometry): distances and
//! gaps to people (with Calderita et al.'s d_min per person), discomfort, personal-space
//! compliance and the share of instants per Hall zone (= Calderita et al.'s Ψ per zone); then,
//! in [`ClearanceMetrics`], the time to collision with people (Francis et al.), the clearance to
//! the static geometry and the social force between the robot and the people.

use serde::Serialize;

use super::{EvalContext, MetricParams, PeopleTracks, Samples, Trajectory, frac, min_avg_max, pct, zone_of};
use crate::math::{EPS, Vec2};

/// The proximity metrics of an episode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ProximityMetrics {
    /// Min centre-to-centre distance to any person over all instants (m, `docs/metrics.md`, Distance to people,
    /// SocNavGym/HuNav); `None` without people or samples.
    pub dist_person_min: Option<f64>,
    /// Min surface gap to any person (m, CrowdNav; negative = overlap); `None` likewise.
    pub gap_person_min: Option<f64>,
    /// CP_avg (m, HuNav; `docs/metrics.md`, Distance to people): mean over instants of the closest person's
    /// centre-to-centre distance (over the instants with someone present); `None` likewise.
    pub cp_avg: Option<f64>,
    /// Calderita's d_min per person (m, centre-to-centre, min over instants); `None` entries for
    /// an empty trajectory, and for a person never present during it.
    pub d_min: Vec<Option<f64>>,
    /// Discomfort frequency (CrowdNav; `docs/metrics.md`, Distance to people): fraction of instants with
    /// `0 <= min_i gap < discomfort_gap` (surface gap); 0 without people; `None` without samples.
    pub discomfort_frequency: Option<f64>,
    /// Mean of `min_i gap` (m, surface) over the discomfort instants; `None` if there are none.
    pub discomfort_gap_avg: Option<f64>,
    /// Personal space compliance (SocNavGym/SEAN; `docs/metrics.md`, Distance to people): fraction of instants with
    /// `min_i (d - r_robot) >= personal_space_tau` (robot surface to person centre); 1 without
    /// people; `None` without samples.
    pub personal_space_compliance: Option<f64>,
    /// Percentage of instants with the closest person's centre distance in `[0, zones[0])`
    /// (`docs/metrics.md`, Distance to people; Calderita Ψ(Intimate)); `None` without samples.
    pub psi_intimate: Option<f64>,
    /// Same in `[zones[0], zones[1])` (Ψ(Personal)).
    pub psi_personal: Option<f64>,
    /// Same in `[zones[1], zones[2])` (Ψ(Social)).
    pub psi_social: Option<f64>,
    /// Same at `>= zones[2]`, or with no person present (Ψ(Public)).
    pub psi_public: Option<f64>,
}

/// How much room the robot left: time to collision, clearance to the static
/// geometry, social force. Its keys follow the object spaces' in the episode record.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ClearanceMetrics {
    /// Minimum time to collision (s, Francis et al.; `docs/metrics.md`, Distance to people) over steps and people:
    /// constant relative velocity from instant `t` (robot `v_t` forward difference, person
    /// recorded velocity), contact at centre distance `r_robot + r_i`; 0 when already
    /// overlapping; `None` when no step had a finite TTC.
    pub ttc_min: Option<f64>,
    /// Fraction of steps whose minimum TTC over people is below `ttc_threshold`; `None` without
    /// a step.
    pub ttc_below_fraction: Option<f64>,
    /// Min clearance of the robot surface to static geometry, `clearance(p_t) - r_robot` (m,
    /// `docs/metrics.md`, Static geometry); `None` when no instant had a finite clearance.
    pub clearance_min: Option<f64>,
    /// Mean of the same over instants with a finite clearance (m).
    pub clearance_avg: Option<f64>,
    /// Sum over instants and people of `|F_{R->i}|` (m/s² summed per instant; `docs/metrics.md`, Distance to people,
    /// HuNav "social force on agents"): `A exp((r_R + r_i - d)/B) (lambda + (1 - lambda)(1 +
    /// cos phi)/2)`, `d` centre distance, `phi` between the person's heading and the direction
    /// person -> robot.
    pub social_force_on_people: f64,
    /// Sum over instants of `|sum_i F_{i->R}|` (m/s² per instant, "social force on robot"), the
    /// same law with the robot's yaw as its heading.
    pub social_force_on_robot: f64,
    /// Social work `W_R + sum_i W_{p_i}`: the sum of the two above.
    pub social_work: f64,
}

/// The proximity of the recording `s` to `people`, per instant.
pub(crate) fn evaluate(
    s: &Samples,
    traj: &Trajectory,
    people: &PeopleTracks,
    ctx: &EvalContext,
) -> ProximityMetrics {
    let (n, np, rr, q) = (s.n, people.count, traj.robot_radius, &ctx.params);
    let mut d_min = vec![if n > 0 { Some(f64::INFINITY) } else { None }; np];
    let mut dist_person_min: Option<f64> = None;
    let mut gap_person_min: Option<f64> = None;
    let mut cp_sum = 0.0;
    // Instants with someone present (every instant unless replayed people come and go).
    let mut with_people = 0usize;
    let mut discomfort = 0usize;
    let mut discomfort_sum = 0.0;
    let mut compliant = 0usize;
    let mut zone_counts = [0usize; 4];
    for t in 0..n {
        let mut closest = f64::INFINITY;
        let mut closest_gap = f64::INFINITY;
        for (i, dm) in d_min.iter_mut().enumerate() {
            if !people.is_present(t, i) {
                continue;
            }
            let d = (people.positions[t * np + i] - s.pos[t]).norm();
            let gap = d - rr - people.radii[i];
            closest = closest.min(d);
            closest_gap = closest_gap.min(gap);
            if let Some(m) = dm.as_mut() {
                *m = m.min(d);
            }
        }
        if closest.is_finite() {
            with_people += 1;
            dist_person_min = Some(dist_person_min.map_or(closest, |m| m.min(closest)));
            gap_person_min = Some(gap_person_min.map_or(closest_gap, |m| m.min(closest_gap)));
            cp_sum += closest;
            if (0.0..q.discomfort_gap).contains(&closest_gap) {
                discomfort += 1;
                discomfort_sum += closest_gap;
            }
        }
        if closest - rr >= q.personal_space_tau {
            compliant += 1;
        }
        zone_counts[zone_of(closest, &ctx.zones)] += 1;
    }
    // A person never present at any instant has no distance.
    for dm in &mut d_min {
        if dm.is_some_and(f64::is_infinite) {
            *dm = None;
        }
    }
    ProximityMetrics {
        dist_person_min,
        gap_person_min,
        cp_avg: (with_people > 0).then(|| cp_sum / with_people as f64),
        d_min,
        discomfort_frequency: frac(discomfort, n),
        discomfort_gap_avg: (discomfort > 0).then(|| discomfort_sum / discomfort as f64),
        personal_space_compliance: frac(compliant, n),
        psi_intimate: pct(zone_counts[0], n),
        psi_personal: pct(zone_counts[1], n),
        psi_social: pct(zone_counts[2], n),
        psi_public: pct(zone_counts[3], n),
    }
}

/// Time to collision, clearance and social force of the recording `s` among `people`.
pub(crate) fn evaluate_clearance(
    s: &Samples,
    traj: &Trajectory,
    people: &PeopleTracks,
    ctx: &EvalContext,
) -> ClearanceMetrics {
    let (np, rr, q) = (people.count, traj.robot_radius, &ctx.params);
    // Time to collision, per step.
    let mut ttc_min = f64::INFINITY;
    let mut ttc_below = 0usize;
    for t in 0..s.steps {
        let mut step_min = f64::INFINITY;
        for i in (0..np).filter(|&i| people.is_present(t, i)) {
            let dp = people.positions[t * np + i] - s.pos[t];
            let dv = people.velocities[t * np + i] - s.vel[t];
            step_min = step_min.min(time_to_collision(dp, dv, rr + people.radii[i]));
        }
        ttc_min = ttc_min.min(step_min);
        ttc_below += usize::from(step_min < q.ttc_threshold);
    }
    let clear = min_avg_max(s.pos.iter().map(|&p| (ctx.clearance)(p) - rr).filter(|c| c.is_finite()));
    let (sf_people, sf_robot) = social_force_sums(s, traj, people, q);
    ClearanceMetrics {
        ttc_min: ttc_min.is_finite().then_some(ttc_min),
        ttc_below_fraction: frac(ttc_below, s.steps),
        clearance_min: clear.map(|c| c.0),
        clearance_avg: clear.map(|c| c.1),
        social_force_on_people: sf_people,
        social_force_on_robot: sf_robot,
        social_work: sf_people + sf_robot,
    }
}

/// Sums over the instants of the social force magnitudes: on the people (each force apart) and on
/// the robot (the resultant per instant).
fn social_force_sums(s: &Samples, traj: &Trajectory, people: &PeopleTracks, q: &MetricParams) -> (f64, f64) {
    let (np, rr) = (people.count, traj.robot_radius);
    let mut sf_people = 0.0;
    let mut sf_robot = 0.0;
    for t in 0..s.n {
        let mut on_robot = Vec2::zeros();
        let robot_dir = Vec2::new(s.yaw[t].cos(), s.yaw[t].sin());
        for i in (0..np).filter(|&i| people.is_present(t, i)) {
            let heading = people.headings[t * np + i];
            let person_dir = Vec2::new(heading.cos(), heading.sin());
            let qi = people.positions[t * np + i];
            let (on_person, by_person) =
                social_forces(s.pos[t], rr, robot_dir, qi, people.radii[i], person_dir, q);
            sf_people += on_person.norm();
            on_robot += by_person;
        }
        sf_robot += on_robot.norm();
    }
    (sf_people, sf_robot)
}

/// Magnitude of the robot's social force on person `i` at instant `t` (m/s², the per-pair term
/// of `social_force_on_people`).
pub(crate) fn force_on_person(
    s: &Samples,
    traj: &Trajectory,
    people: &PeopleTracks,
    q: &MetricParams,
    t: usize,
    i: usize,
) -> f64 {
    let np = people.count;
    let heading = people.headings[t * np + i];
    let robot_dir = Vec2::new(s.yaw[t].cos(), s.yaw[t].sin());
    let person_dir = Vec2::new(heading.cos(), heading.sin());
    let (on_person, _) = social_forces(
        s.pos[t],
        traj.robot_radius,
        robot_dir,
        people.positions[t * np + i],
        people.radii[i],
        person_dir,
        q,
    );
    on_person.norm()
}

/// Francis et al. time to collision of two discs with relative position `dp` (other minus
/// robot), relative velocity `dv` (other minus robot) and contact distance `r` (`docs/metrics.md`,
/// Distance to people).
pub(crate) fn time_to_collision(dp: Vec2, dv: Vec2, r: f64) -> f64 {
    let a = dv.norm_squared();
    let b = 2.0 * dp.dot(&dv);
    let c = dp.norm_squared() - r * r;
    if c <= 0.0 {
        return 0.0;
    }
    let disc = b * b - 4.0 * a * c;
    if b < 0.0 && disc >= 0.0 && a > 0.0 { (-b - disc.sqrt()) / (2.0 * a) } else { f64::INFINITY }
}

/// Anisotropic Helbing-style repulsions between a robot and a person (`docs/metrics.md`,
/// Distance to people): the force the robot (at `robot`, radius `r_robot`) exerts on the person (at
/// `person`, radius `r_person`, facing the unit vector `person_dir`), and the force the person
/// exerts on the robot (facing `robot_dir`). The two share their distance and their exponential
/// (the contact term `(r_robot + r_person - d) / B` is symmetric), so one call costs one `exp`.
fn social_forces(
    robot: Vec2,
    r_robot: f64,
    robot_dir: Vec2,
    person: Vec2,
    r_person: f64,
    person_dir: Vec2,
    q: &MetricParams,
) -> (Vec2, Vec2) {
    let diff = person - robot;
    let d = diff.norm();
    // Unit vectors from the source to the receiver of each force.
    let (to_person, to_robot) =
        if d > EPS { (diff / d, -(diff / d)) } else { (Vec2::new(1.0, 0.0), Vec2::new(1.0, 0.0)) };
    let magnitude = q.sf_a * ((r_robot + r_person - d) / q.sf_b).exp();
    // phi is between the receiver's heading and the direction towards the source.
    let aniso = |dir: Vec2, n: Vec2| q.sf_lambda + (1.0 - q.sf_lambda) * (1.0 + dir.dot(&(-n))) / 2.0;
    (
        to_person * (magnitude * aniso(person_dir, to_person)),
        to_robot * (magnitude * aniso(robot_dir, to_robot)),
    )
}
