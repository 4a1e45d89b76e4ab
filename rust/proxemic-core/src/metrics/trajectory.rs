//! Post-hoc evaluation of one recorded episode: every metric of `design/metrics.md` §Definitions
//! that applies to a recorded trajectory, plus the seed papers' own metrics under their names
//! (Daza et al. 2021: `l_ratio`, `smooth`; Calderita et al.: `d_t`, `tau`, `chc`, `d_min`,
//! `psi_*`, `psi_object`).
//!
//! # Conventions
//! - The robot is sampled at the control instants `t = 0..=T` (`N = T + 1` samples, `T` steps of
//!   `dt` seconds). Step `k` goes from instant `k` to instant `k + 1`.
//! - **Per-instant** metrics (zones, discomfort, compliance, o-space, object spaces, clearance,
//!   distances to people, social force) are taken over all `N` instants, the start included.
//!   Percentages are `100 * count / N`, fractions `count / N`.
//! - **Per-step** metrics (velocity, collisions, time to collision, crossings) are taken over the
//!   `T` steps.
//! - Distances: `d` is centre-to-centre (robot centre to person centre), `gap = d - r_robot -
//!   r_person` is the surface gap. Each field's documentation says which one it uses.
//! - Angles are radians, lengths metres, times seconds.
//! - Every input must be finite (infinite `geodesic_length` excepted, meaning "unreachable");
//!   otherwise [`evaluate`] returns [`CoreError::Input`] naming the array and index. It never
//!   panics. An empty trajectory gives counts 0, `false` outcomes and `None` for every value that
//!   needs a sample.
//!
//! # Index (metrics.md numbering → [`FullMetrics`] fields)
//! 1 `success`; 2 `hc`/`wc`/`ac` (+`_count`), `collision`; 3 `timeout`; 4 `time_to_goal`;
//! 5 `path_length` (= Calderita `d_t`); 6 `path_length_ratio`; 7 `spl`; 8 `failure_to_progress`;
//! 9 `stalled_time`; 10 `vel_*`; 11 `acc_*`, `jerk_*`; 12 `chc` (body yaw, = Calderita CHC),
//! `chc_motion`; 13 `path_irregularity`; 15 `dist_person_min`, `gap_person_min`, `cp_avg`
//! (+ Calderita `d_min` per person); 16 `discomfort_frequency`, `discomfort_gap_avg`;
//! 17 `personal_space_compliance`; 18 `psi_intimate`/`_personal`/`_social`/`_public` (= Calderita
//! Ψ per zone); 19 `group_psi_*`, `ospace_pct`, `ospace_time`, `ospace_entries`,
//! `interaction_crossings*`; 20 `ttc_min`, `ttc_below_fraction`; 21 `clearance_min`,
//! `clearance_avg`; 22 `social_force_on_people`, `social_force_on_robot`, `social_work`.
//! Daza et al. 2021: `l_ratio`, `smooth`, `smooth_k`. Calderita et al.: `d_t`, `tau`, `chc`,
//! `d_min`, `psi_*`, `psi_object` (activity on), `psi_object_any`, `psi_objects`.
//! Not computed here: STL (needs a reference time), the optional item 14, item 23 (needs a
//! robot-free replay) and the learned scores of item 24.

use serde::Serialize;

use crate::error::{CoreError, Result};
use crate::math::{EPS, Vec2, wrap_angle};

/// Contact bit of [`EvalContext::collision_steps`]: the robot touched a person (as
/// `world::CONTACT_PERSON`).
pub const CONTACT_PERSON: u8 = 1;
/// Contact bit of [`EvalContext::collision_steps`]: the robot touched walls or furniture (as
/// `world::CONTACT_STATIC`).
pub const CONTACT_STATIC: u8 = 2;
/// Contact bit of [`EvalContext::collision_steps`]: the robot touched another robot (as
/// `world::CONTACT_ROBOT`).
pub const CONTACT_ROBOT: u8 = 4;

/// The robot's recorded trajectory.
#[derive(Clone, Copy, Debug)]
pub struct Trajectory<'a> {
    /// Control period (s), finite and > 0.
    pub dt: f64,
    /// Robot pose `[x (m), y (m), theta (rad)]` at the control instants `t = 0..=T`.
    pub robot: &'a [[f64; 3]],
    /// Robot disc radius (m), finite and >= 0.
    pub robot_radius: f64,
    /// Goal position (m).
    pub goal: Vec2,
    /// Success radius (m): the goal is reached when the robot *centre* is within it.
    pub success_radius: f64,
}

/// The people's recorded tracks, row-major: the value of person `i` at instant `t` is at index
/// `t * count + i`; every per-instant array has `N * count` entries.
#[derive(Clone, Copy, Debug)]
pub struct PeopleTracks<'a> {
    /// Person centres (m).
    pub positions: &'a [Vec2],
    /// Person velocities (m/s), used by time to collision and the social force.
    pub velocities: &'a [Vec2],
    /// Person headings (rad), used by the social force's anisotropy.
    pub headings: &'a [f64],
    /// Person disc radii (m), `count` entries.
    pub radii: &'a [f64],
    /// Number of people `P`.
    pub count: usize,
}

impl PeopleTracks<'_> {
    /// No people.
    pub fn none() -> PeopleTracks<'static> {
        PeopleTracks { positions: &[], velocities: &[], headings: &[], radii: &[], count: 0 }
    }
}

/// A group's o-space (F-formation) as a circle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OSpace {
    /// Centre of the o-space (m).
    pub centre: Vec2,
    /// Radius of the o-space (m), >= 0.
    pub radius: f64,
}

/// What an interaction segment connects.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LinkKind {
    /// Two people interacting (talking, walking together).
    PersonPerson,
    /// A person using an object (exhibit viewer and exhibit, human and laptop).
    PersonObject,
}

/// An interaction as a segment between the two parties (world frame, m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InteractionLink {
    /// One end (a person centre).
    pub a: Vec2,
    /// The other end (a person centre, or the object's interaction point).
    pub b: Vec2,
    /// What the segment connects.
    pub kind: LinkKind,
}

/// Per-instant groups and interactions, in compressed rows: the o-spaces present at instant `t`
/// are `ospaces[ospace_offsets[t]..ospace_offsets[t + 1]]`, likewise the links. Each offsets
/// array has `N + 1` non-decreasing entries starting at 0 and ending at the data length, or is
/// empty together with its data (nothing at any instant).
#[derive(Clone, Copy, Debug)]
pub struct Groups<'a> {
    /// Row offsets into `ospaces` (`N + 1` entries, or empty).
    pub ospace_offsets: &'a [usize],
    /// The o-space circles of all instants.
    pub ospaces: &'a [OSpace],
    /// Row offsets into `links` (`N + 1` entries, or empty).
    pub link_offsets: &'a [usize],
    /// The interaction segments of all instants.
    pub links: &'a [InteractionLink],
}

impl Groups<'_> {
    /// No groups and no interactions.
    pub fn none() -> Groups<'static> {
        Groups { ospace_offsets: &[], ospaces: &[], link_offsets: &[], links: &[] }
    }
}

/// Objects' interaction spaces (Calderita et al.'s affordance/activity spaces).
#[derive(Clone, Copy, Debug)]
pub struct ObjectSpaces<'a> {
    /// Per object, the interaction polygon's vertices in order (world frame, m). A polygon with
    /// fewer than 3 vertices contains no point.
    pub polygons: &'a [Vec<Vec2>],
    /// Per instant and object, whether the object's activity is on; row-major, index
    /// `t * polygons.len() + k` (`N * M` entries).
    pub active: &'a [bool],
}

impl ObjectSpaces<'_> {
    /// No objects.
    pub fn none() -> ObjectSpaces<'static> {
        ObjectSpaces { polygons: &[], active: &[] }
    }
}

/// Thresholds and model constants (defaults from the cited sources; see each field).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MetricParams {
    /// Surface gap below which an instant counts as discomfort (m); CrowdNav 0.2.
    pub discomfort_gap: f64,
    /// Personal-space compliance threshold `tau` on `d - r_robot` (m, robot surface to person
    /// centre); SocNavGym/SEAN 2.0 0.45.
    pub personal_space_tau: f64,
    /// Time-to-collision threshold (s) for `ttc_below_fraction`; 2.0.
    pub ttc_threshold: f64,
    /// Distance from the A* polyline within which the robot centre is "on" the A* path, for
    /// Daza's Smooth (m); 0.2.
    pub astar_tolerance: f64,
    /// Speed below which the motion direction is undefined (skipped by `chc_motion`) (m/s); 0.01.
    pub v_eps: f64,
    /// Stalled-time linear speed threshold (m/s); HuNav/SEAN 0.001.
    pub stall_linear: f64,
    /// Stalled-time angular speed threshold (rad/s); HuNav/SEAN 0.01.
    pub stall_angular: f64,
    /// Failure-to-progress window (s); 5.0.
    pub progress_window: f64,
    /// Failure-to-progress minimum decrease of the straight-line goal distance per window (m); 0.1.
    pub progress_delta: f64,
    /// Social-force strength `A` (m/s², force per unit mass); 2.1, Helbing & Molnár 1995's `V0`.
    pub sf_a: f64,
    /// Social-force range `B` (m); 0.3, Helbing & Molnár 1995's `sigma`.
    pub sf_b: f64,
    /// Social-force anisotropy `lambda` (weight of a party straight behind, in [0, 1]); 0.5, the
    /// rear weight `c` of Helbing & Molnár 1995.
    pub sf_lambda: f64,
}

impl Default for MetricParams {
    fn default() -> Self {
        MetricParams {
            discomfort_gap: 0.2,
            personal_space_tau: 0.45,
            ttc_threshold: 2.0,
            astar_tolerance: 0.2,
            v_eps: 0.01,
            stall_linear: 0.001,
            stall_angular: 0.01,
            progress_window: 5.0,
            progress_delta: 0.1,
            sf_a: 2.1,
            sf_b: 0.3,
            sf_lambda: 0.5,
        }
    }
}

/// Default Hall zone radii (m, centre distance): intimate, personal, social.
pub const DEFAULT_ZONES: [f64; 3] = [0.45, 1.2, 3.6];

/// Episode context not contained in the trajectory.
pub struct EvalContext<'a> {
    /// Shortest collision-free start-goal length `l*` (m), >= 0; `f64::INFINITY` when the goal
    /// is unreachable (ratios then `None`).
    pub geodesic_length: f64,
    /// The plain A* path on the same start and goal (m), for Daza's `l_ratio` and `smooth`;
    /// fewer than 2 points makes both `None`.
    pub astar_path: &'a [Vec2],
    /// Distance from a point to the static geometry (m). Non-finite results are skipped.
    pub clearance: &'a dyn Fn(Vec2) -> f64,
    /// Hall zone radii (m, centre distance): intimate, personal, social; non-decreasing, >= 0.
    pub zones: [f64; 3],
    /// Per step `k` (instant `k` to `k + 1`), the `CONTACT_*` bits reported by the physics; `T`
    /// entries, or empty when no contacts were recorded.
    pub collision_steps: &'a [u8],
    /// Thresholds and constants.
    pub params: MetricParams,
}

/// Every metric of one episode. `None` means undefined (reason in each field's doc).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FullMetrics {
    /// Number of control steps `T` (samples minus one, 0 for an empty trajectory).
    pub steps: usize,
    /// Success S (metrics.md 1): the robot centre came within `success_radius` of the goal at
    /// some instant with no collision (any kind) in any step ending at or before it.
    pub success: bool,
    /// Any collision of any kind (metrics.md 2).
    pub collision: bool,
    /// Timeout TO (metrics.md 3): neither success nor any collision in the recording.
    pub timeout: bool,
    /// Time to goal (s, metrics.md 4): first goal instant times `dt`; `None` without success.
    pub time_to_goal: Option<f64>,
    /// Steps with a collision with a person, HC (metrics.md 2): the physics' person bit, or a
    /// negative surface gap anywhere on the swept relative motion over the step (both bodies
    /// moving linearly between the instants, CrowdNav's test).
    pub hc_count: usize,
    /// Steps with a collision with walls or furniture, WC (physics' static bit).
    pub wc_count: usize,
    /// Steps with a collision with another robot, AC (physics' robot bit).
    pub ac_count: usize,
    /// `hc_count > 0`.
    pub hc: bool,
    /// `wc_count > 0`.
    pub wc: bool,
    /// `ac_count > 0`.
    pub ac: bool,
    /// Path length PL (m, metrics.md 5): sum of distances between consecutive robot centres.
    pub path_length: f64,
    /// Path length ratio PLR = PL / `l*` (metrics.md 6, geodesic `l*`); `None` when `l*` is not
    /// finite or below 1e-9 m.
    pub path_length_ratio: Option<f64>,
    /// SPL = S * `l*` / max(PL, `l*`) (Anderson et al. 2018; metrics.md 7); 1 on success with
    /// PL and `l*` both ~0; `None` when `l*` is not finite.
    pub spl: Option<f64>,
    /// Failure to progress FP (metrics.md 8): consecutive, non-overlapping windows of
    /// `progress_window` s in which the straight-line centre-to-goal distance decreased by less
    /// than `progress_delta` (an incomplete final window is not counted).
    pub failure_to_progress: usize,
    /// Stalled time ST (s, metrics.md 9, HuNav/SEAN): `dt` times the steps with finite-difference
    /// speed < `stall_linear` and yaw rate < `stall_angular`.
    pub stalled_time: f64,
    /// Min speed (m/s, metrics.md 10) of `v_t = (p_{t+1} - p_t)/dt`; `None` without a step.
    pub vel_min: Option<f64>,
    /// Mean speed (m/s) over the steps.
    pub vel_avg: Option<f64>,
    /// Max speed (m/s).
    pub vel_max: Option<f64>,
    /// Min `|a_t|`, `a_t = (p_{t+1} - 2 p_t + p_{t-1})/dt²` (m/s², metrics.md 11); `None`
    /// with fewer than 3 samples.
    pub acc_min: Option<f64>,
    /// Mean `|a_t|` (m/s²).
    pub acc_avg: Option<f64>,
    /// Max `|a_t|` (m/s²).
    pub acc_max: Option<f64>,
    /// Min `|j_t|`, `j_t = (p_{t+2} - 3p_{t+1} + 3p_t - p_{t-1})/dt³` (m/s³, metrics.md 11);
    /// `None` with fewer than 4 samples.
    pub jerk_min: Option<f64>,
    /// Mean `|j_t|` (m/s³).
    pub jerk_avg: Option<f64>,
    /// Max `|j_t|` (m/s³).
    pub jerk_max: Option<f64>,
    /// Cumulative heading change of the body yaw, `sum |wrap(theta_{t+1} - theta_t)|` (rad;
    /// metrics.md 12, Pérez-Higueras 2018, HuNav; Calderita et al.'s CHC / H of eq. 18).
    pub chc: f64,
    /// Cumulative change of the motion direction `atan2(v_t)` (rad, metrics.md 12), over
    /// consecutive steps with speed >= `v_eps` (slower steps are skipped).
    pub chc_motion: f64,
    /// Path irregularity PI (rad/m, Guzzi et al. 2013; metrics.md 13):
    /// `(chc - |wrap(atan2(g - p_0) - theta_0)|) / PL`; may be negative (a holonomic robot need
    /// not turn towards the goal); `None` when PL < 1e-9 m.
    pub path_irregularity: Option<f64>,
    /// Min centre-to-centre distance to any person over all instants (m, metrics.md 15,
    /// SocNavGym/HuNav); `None` without people or samples.
    pub dist_person_min: Option<f64>,
    /// Min surface gap to any person (m, CrowdNav; negative = overlap); `None` likewise.
    pub gap_person_min: Option<f64>,
    /// CP_avg (m, HuNav; metrics.md 15): mean over instants of the closest person's
    /// centre-to-centre distance; `None` likewise.
    pub cp_avg: Option<f64>,
    /// Calderita's d_min per person (m, centre-to-centre, min over instants); `None` entries for
    /// an empty trajectory.
    pub d_min: Vec<Option<f64>>,
    /// Discomfort frequency (CrowdNav; metrics.md 16): fraction of instants with
    /// `0 <= min_i gap < discomfort_gap` (surface gap); 0 without people; `None` without samples.
    pub discomfort_frequency: Option<f64>,
    /// Mean of `min_i gap` (m, surface) over the discomfort instants; `None` if there are none.
    pub discomfort_gap_avg: Option<f64>,
    /// Personal space compliance (SocNavGym/SEAN; metrics.md 17): fraction of instants with
    /// `min_i (d - r_robot) >= personal_space_tau` (robot surface to person centre); 1 without
    /// people; `None` without samples.
    pub personal_space_compliance: Option<f64>,
    /// Percentage of instants with the closest person's centre distance in `[0, zones[0])`
    /// (metrics.md 18; Calderita Ψ(Intimate)); `None` without samples.
    pub psi_intimate: Option<f64>,
    /// Same in `[zones[0], zones[1])` (Ψ(Personal)).
    pub psi_personal: Option<f64>,
    /// Same in `[zones[1], zones[2])` (Ψ(Social)).
    pub psi_social: Option<f64>,
    /// Same at `>= zones[2]`, or with no person present (Ψ(Public)).
    pub psi_public: Option<f64>,
    /// Percentage of instants with the robot centre's distance to the closest o-space *centre*
    /// in `[0, zones[0])` (HuNav IS_prox; metrics.md 19); `None` without samples.
    pub group_psi_intimate: Option<f64>,
    /// Same in `[zones[0], zones[1])`.
    pub group_psi_personal: Option<f64>,
    /// Same in `[zones[1], zones[2])`.
    pub group_psi_social: Option<f64>,
    /// Same at `>= zones[2]` or with no group present.
    pub group_psi_public: Option<f64>,
    /// Percentage of instants with the robot centre inside some o-space circle (distance to
    /// its centre <= radius) (metrics.md 19); `None` without samples.
    pub ospace_pct: Option<f64>,
    /// Time with the robot centre inside some o-space (s): instants inside times `dt`.
    pub ospace_time: f64,
    /// Entries into o-spaces: instants inside some o-space after an instant inside none (the
    /// first instant counts if inside).
    pub ospace_entries: usize,
    /// Interaction crossings (metrics.md 19): steps whose centre segment `[p_t, p_{t+1})`
    /// intersects an interaction segment present at instant `t` (half-open, so a crossing
    /// through a sample point counts once; parallel segments never cross).
    pub interaction_crossings: usize,
    /// The person-person part of `interaction_crossings`.
    pub interaction_crossings_person_person: usize,
    /// The person-object part of `interaction_crossings`.
    pub interaction_crossings_person_object: usize,
    /// Calderita's Ψ per object: percentage of instants with the robot centre inside the
    /// object's interaction polygon while its activity is on; `None` entries without samples.
    pub psi_object: Vec<Option<f64>>,
    /// Percentage of instants inside the object's polygon whatever its activity state.
    pub psi_object_any: Vec<Option<f64>>,
    /// Calderita's Ψ(Objects): percentage of instants inside at least one active object space.
    pub psi_objects: Option<f64>,
    /// Minimum time to collision (s, Francis et al.; metrics.md 20) over steps and people:
    /// constant relative velocity from instant `t` (robot `v_t` forward difference, person
    /// recorded velocity), contact at centre distance `r_robot + r_i`; 0 when already
    /// overlapping; `None` when no step had a finite TTC.
    pub ttc_min: Option<f64>,
    /// Fraction of steps whose minimum TTC over people is below `ttc_threshold`; `None` without
    /// a step.
    pub ttc_below_fraction: Option<f64>,
    /// Min clearance of the robot surface to static geometry, `clearance(p_t) - r_robot` (m,
    /// metrics.md 21); `None` when no instant had a finite clearance.
    pub clearance_min: Option<f64>,
    /// Mean of the same over instants with a finite clearance (m).
    pub clearance_avg: Option<f64>,
    /// Sum over instants and people of `|F_{R->i}|` (m/s² summed per instant; metrics.md 22,
    /// HuNav "social force on agents"): `A exp((r_R + r_i - d)/B) (lambda + (1 - lambda)(1 +
    /// cos phi)/2)`, `d` centre distance, `phi` between the person's heading and the direction
    /// person -> robot.
    pub social_force_on_people: f64,
    /// Sum over instants of `|sum_i F_{i->R}|` (m/s² per instant, "social force on robot"), the
    /// same law with the robot's yaw as its heading.
    pub social_force_on_robot: f64,
    /// Social work `W_R + sum_i W_{p_i}`: the sum of the two above.
    pub social_work: f64,
    /// Daza et al. 2021 eq. 1: `L_ratio = D_A* / D_SN`, A* polyline length over the executed
    /// path length; `None` without success, with fewer than 2 A* points, or PL < 1e-9 m.
    pub l_ratio: Option<f64>,
    /// Daza et al. 2021 eq. 2: `Smooth = 1/(k-1) sum_i theta_i²` over the `k` angles (rad)
    /// between the executed step direction and the A* direction where the path leaves (last
    /// instant within `astar_tolerance` of the A* polyline, then outside) and rejoins it; 0 for
    /// `k = 0` and `theta_1²` for `k = 1`; `None` with fewer than 2 A* points.
    pub smooth: Option<f64>,
    /// Number `k` of leave/rejoin angles in `smooth`.
    pub smooth_k: usize,
    /// Calderita's d_t (m): distance travelled, equal to `path_length`.
    pub d_t: f64,
    /// Calderita's tau (s): navigation time of the recording, `T * dt`.
    pub tau: f64,
}

fn bad(field: impl Into<String>, expected: &str, found: impl std::fmt::Display) -> CoreError {
    CoreError::input(field, expected, found.to_string())
}

fn check_finite(field: &str, v: f64) -> Result<()> {
    if v.is_finite() { Ok(()) } else { Err(bad(field, "a finite number", v)) }
}

fn check_vec(field: &str, idx: usize, v: Vec2) -> Result<()> {
    if v.x.is_finite() && v.y.is_finite() {
        Ok(())
    } else {
        Err(bad(format!("{field}[{idx}]"), "finite coordinates", format!("({}, {})", v.x, v.y)))
    }
}

fn check_offsets(field: &str, offsets: &[usize], data_len: usize, n: usize) -> Result<()> {
    if offsets.is_empty() {
        if data_len == 0 {
            return Ok(());
        }
        return Err(bad(field, "N + 1 row offsets for non-empty data", "no offsets"));
    }
    if offsets.len() != n + 1 {
        return Err(bad(field, &format!("{} offsets (N + 1)", n + 1), format!("{}", offsets.len())));
    }
    if offsets[0] != 0 || offsets[n] != data_len || offsets.windows(2).any(|w| w[0] > w[1]) {
        return Err(bad(
            field,
            &format!("non-decreasing offsets from 0 to {data_len}"),
            format!("{offsets:?}"),
        ));
    }
    Ok(())
}

fn validate(
    traj: &Trajectory,
    people: &PeopleTracks,
    groups: &Groups,
    objects: &ObjectSpaces,
    ctx: &EvalContext,
) -> Result<()> {
    let n = traj.robot.len();
    if !(traj.dt.is_finite() && traj.dt > 0.0) {
        return Err(bad("dt", "a finite control period > 0 s", traj.dt));
    }
    if !(traj.robot_radius.is_finite() && traj.robot_radius >= 0.0) {
        return Err(bad("robot_radius", "a finite radius >= 0 m", traj.robot_radius));
    }
    if !(traj.success_radius.is_finite() && traj.success_radius >= 0.0) {
        return Err(bad("success_radius", "a finite radius >= 0 m", traj.success_radius));
    }
    check_vec("goal", 0, traj.goal)?;
    for (t, pose) in traj.robot.iter().enumerate() {
        if let Some(j) = pose.iter().position(|v| !v.is_finite()) {
            return Err(bad(format!("robot[{t}][{j}]"), "a finite pose", pose[j]));
        }
    }
    let p = people.count;
    let rows = n.checked_mul(p).ok_or_else(|| bad("people.count", "a size that fits", p))?;
    for (name, len) in [
        ("people.positions", people.positions.len()),
        ("people.velocities", people.velocities.len()),
        ("people.headings", people.headings.len()),
    ] {
        if len != rows {
            return Err(bad(name, &format!("{rows} entries (N = {n} x P = {p})"), len));
        }
    }
    if people.radii.len() != p {
        return Err(bad("people.radii", &format!("{p} entries"), people.radii.len()));
    }
    for (k, &v) in people.positions.iter().enumerate() {
        check_vec("people.positions", k, v)?;
    }
    for (k, &v) in people.velocities.iter().enumerate() {
        check_vec("people.velocities", k, v)?;
    }
    if let Some(k) = people.headings.iter().position(|h| !h.is_finite()) {
        return Err(bad(format!("people.headings[{k}]"), "a finite angle", people.headings[k]));
    }
    if let Some(k) = people.radii.iter().position(|r| !(r.is_finite() && *r >= 0.0)) {
        return Err(bad(format!("people.radii[{k}]"), "a finite radius >= 0 m", people.radii[k]));
    }
    check_offsets("groups.ospace_offsets", groups.ospace_offsets, groups.ospaces.len(), n)?;
    check_offsets("groups.link_offsets", groups.link_offsets, groups.links.len(), n)?;
    for (k, o) in groups.ospaces.iter().enumerate() {
        check_vec("groups.ospaces.centre", k, o.centre)?;
        if !(o.radius.is_finite() && o.radius >= 0.0) {
            return Err(bad(format!("groups.ospaces[{k}].radius"), "a finite radius >= 0 m", o.radius));
        }
    }
    for (k, l) in groups.links.iter().enumerate() {
        check_vec("groups.links.a", k, l.a)?;
        check_vec("groups.links.b", k, l.b)?;
    }
    let m = objects.polygons.len();
    let arows = n.checked_mul(m).ok_or_else(|| bad("objects.polygons", "a size that fits", m))?;
    if objects.active.len() != arows {
        return Err(bad(
            "objects.active",
            &format!("{arows} entries (N = {n} x M = {m})"),
            objects.active.len(),
        ));
    }
    for (k, poly) in objects.polygons.iter().enumerate() {
        for (j, &v) in poly.iter().enumerate() {
            check_vec(&format!("objects.polygons[{k}]"), j, v)?;
        }
    }
    if ctx.geodesic_length.is_nan() || ctx.geodesic_length < 0.0 {
        return Err(bad(
            "geodesic_length",
            "a length >= 0 m (or +inf when unreachable)",
            ctx.geodesic_length,
        ));
    }
    for (k, &v) in ctx.astar_path.iter().enumerate() {
        check_vec("astar_path", k, v)?;
    }
    let z = ctx.zones;
    if !(z.iter().all(|v| v.is_finite()) && 0.0 <= z[0] && z[0] <= z[1] && z[1] <= z[2]) {
        return Err(bad("zones", "finite radii with 0 <= intimate <= personal <= social", format!("{z:?}")));
    }
    let steps = n.saturating_sub(1);
    if !ctx.collision_steps.is_empty() && ctx.collision_steps.len() != steps {
        return Err(bad(
            "collision_steps",
            &format!("{steps} entries (one per step) or none"),
            ctx.collision_steps.len(),
        ));
    }
    let q = &ctx.params;
    for (name, v) in [
        ("params.discomfort_gap", q.discomfort_gap),
        ("params.personal_space_tau", q.personal_space_tau),
        ("params.ttc_threshold", q.ttc_threshold),
        ("params.astar_tolerance", q.astar_tolerance),
        ("params.v_eps", q.v_eps),
        ("params.stall_linear", q.stall_linear),
        ("params.stall_angular", q.stall_angular),
        ("params.progress_delta", q.progress_delta),
        ("params.sf_a", q.sf_a),
        ("params.sf_lambda", q.sf_lambda),
    ] {
        check_finite(name, v)?;
        if v < 0.0 {
            return Err(bad(name, "a value >= 0", v));
        }
    }
    for (name, v) in [("params.progress_window", q.progress_window), ("params.sf_b", q.sf_b)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(bad(name, "a finite value > 0", v));
        }
    }
    if q.sf_lambda > 1.0 {
        return Err(bad("params.sf_lambda", "a weight in [0, 1]", q.sf_lambda));
    }
    Ok(())
}

/// Min, mean and max of a sequence; `None` when empty.
fn min_avg_max(values: impl Iterator<Item = f64>) -> Option<(f64, f64, f64)> {
    let mut count = 0usize;
    let (mut lo, mut sum, mut hi) = (f64::INFINITY, 0.0, f64::NEG_INFINITY);
    for v in values {
        count += 1;
        lo = lo.min(v);
        hi = hi.max(v);
        sum += v;
    }
    (count > 0).then(|| (lo, sum / count as f64, hi))
}

/// Distance from the origin to the segment `a -> b`.
pub(crate) fn origin_to_segment(a: Vec2, b: Vec2) -> f64 {
    let d = b - a;
    let len2 = d.norm_squared();
    if len2 <= EPS * EPS {
        return a.norm();
    }
    let s = (-a.dot(&d) / len2).clamp(0.0, 1.0);
    (a + d * s).norm()
}

/// Francis et al. time to collision of two discs with relative position `dp` (other minus
/// robot), relative velocity `dv` (other minus robot) and contact distance `r` (metrics.md 20).
fn time_to_collision(dp: Vec2, dv: Vec2, r: f64) -> f64 {
    let a = dv.norm_squared();
    let b = 2.0 * dp.dot(&dv);
    let c = dp.norm_squared() - r * r;
    if c <= 0.0 {
        return 0.0;
    }
    let disc = b * b - 4.0 * a * c;
    if b < 0.0 && disc >= 0.0 && a > 0.0 { (-b - disc.sqrt()) / (2.0 * a) } else { f64::INFINITY }
}

fn cross(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Whether the half-open segment `[p, q)` intersects the closed segment `[a, b]` (parallel or
/// degenerate segments never intersect).
fn crosses(p: Vec2, q: Vec2, a: Vec2, b: Vec2) -> bool {
    let r = q - p;
    let s = b - a;
    let denom = cross(r, s);
    if denom.abs() <= EPS * (r.norm() * s.norm()).max(EPS) {
        return false;
    }
    let ap = a - p;
    let t = cross(ap, s) / denom;
    let u = cross(ap, r) / denom;
    (0.0..1.0).contains(&t) && (0.0..=1.0).contains(&u)
}

/// Even-odd point-in-polygon test; fewer than 3 vertices contain nothing.
pub(crate) fn inside_polygon(pt: Vec2, poly: &[Vec2]) -> bool {
    if poly.len() < 3 {
        return false;
    }
    let mut inside = false;
    let mut j = poly.len() - 1;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[j]);
        if (a.y > pt.y) != (b.y > pt.y) {
            let x = a.x + (pt.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if pt.x < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// Closest point of a polyline (with at least one point) to `pt`: (distance, unit direction of
/// the segment holding it, or `None` when every segment is degenerate).
fn polyline_nearest(pt: Vec2, line: &[Vec2]) -> (f64, Option<Vec2>) {
    let mut best = (f64::INFINITY, None);
    if line.len() == 1 {
        return ((pt - line[0]).norm(), None);
    }
    for w in line.windows(2) {
        let d = w[1] - w[0];
        let len = d.norm();
        if len <= EPS {
            let dist = (pt - w[0]).norm();
            if dist < best.0 {
                best = (dist, best.1);
            }
            continue;
        }
        let s = ((pt - w[0]).dot(&d) / (len * len)).clamp(0.0, 1.0);
        let dist = (pt - (w[0] + d * s)).norm();
        if dist < best.0 || best.1.is_none() && dist <= best.0 {
            best = (dist, Some(d / len));
        }
    }
    best
}

fn polyline_length(line: &[Vec2]) -> f64 {
    line.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}

/// Unsigned angle (rad, in [0, pi]) between two non-zero vectors.
fn angle_between(a: Vec2, b: Vec2) -> f64 {
    wrap_angle(a.y.atan2(a.x) - b.y.atan2(b.x)).abs()
}

/// Daza et al. 2021 eq. 2 angles where the path leaves and rejoins the A* polyline.
fn leave_rejoin_angles(pos: &[Vec2], astar: &[Vec2], tol: f64) -> Vec<f64> {
    let mut angles = Vec::new();
    let near: Vec<(bool, Option<Vec2>)> = pos
        .iter()
        .map(|&p| {
            let (d, dir) = polyline_nearest(p, astar);
            (d <= tol, dir)
        })
        .collect();
    for t in 0..pos.len().saturating_sub(1) {
        let (on0, dir0) = near[t];
        let (on1, dir1) = near[t + 1];
        let step = pos[t + 1] - pos[t];
        if step.norm() <= EPS {
            continue;
        }
        let tangent = match (on0, on1) {
            (true, false) => dir0,
            (false, true) => dir1,
            _ => None,
        };
        if let Some(tan) = tangent {
            angles.push(angle_between(step, tan));
        }
    }
    angles
}

/// Anisotropic Helbing-style repulsions between a robot and a person (metrics.md 22): the force
/// the robot (at `robot`, radius `r_robot`) exerts on the person (at `person`, radius `r_person`,
/// facing the unit vector `person_dir`), and the force the person exerts on the robot (facing
/// `robot_dir`). The two share their distance and their exponential (the contact term
/// `(r_robot + r_person - d) / B` is symmetric), so one call costs one `exp`.
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

fn pct(count: usize, n: usize) -> Option<f64> {
    (n > 0).then(|| 100.0 * count as f64 / n as f64)
}

fn frac(count: usize, n: usize) -> Option<f64> {
    (n > 0).then(|| count as f64 / n as f64)
}

/// Zone index of a centre distance: 0 intimate, 1 personal, 2 social, 3 public.
fn zone_of(d: f64, zones: &[f64; 3]) -> usize {
    zones.iter().position(|&z| d < z).unwrap_or(3)
}

/// Evaluates one recorded episode (see the module documentation for conventions).
///
/// # Errors
/// [`CoreError::Input`] when an array has the wrong length, a value is not finite (except an
/// infinite `geodesic_length`), a radius or threshold is negative, or the zones decrease.
pub fn evaluate(
    traj: &Trajectory,
    people: &PeopleTracks,
    groups: &Groups,
    objects: &ObjectSpaces,
    ctx: &EvalContext,
) -> Result<FullMetrics> {
    validate(traj, people, groups, objects, ctx)?;
    let q = &ctx.params;
    let dt = traj.dt;
    let n = traj.robot.len();
    let steps = n.saturating_sub(1);
    let np = people.count;
    let rr = traj.robot_radius;
    let pos: Vec<Vec2> = traj.robot.iter().map(|r| Vec2::new(r[0], r[1])).collect();
    let yaw: Vec<f64> = traj.robot.iter().map(|r| r[2]).collect();
    let person = |t: usize, i: usize| people.positions[t * np + i];

    // Collisions (per step k, attributed to instant k + 1).
    let (mut hc_count, mut wc_count, mut ac_count) = (0usize, 0usize, 0usize);
    let mut first_collision_instant: Option<usize> = None;
    for k in 0..steps {
        let bits = ctx.collision_steps.get(k).copied().unwrap_or(0);
        let swept = (0..np).any(|i| {
            let a = person(k, i) - pos[k];
            let b = person(k + 1, i) - pos[k + 1];
            origin_to_segment(a, b) - rr - people.radii[i] < 0.0
        });
        let hit_person = bits & CONTACT_PERSON != 0 || swept;
        let hit_static = bits & CONTACT_STATIC != 0;
        let hit_robot = bits & CONTACT_ROBOT != 0;
        hc_count += usize::from(hit_person);
        wc_count += usize::from(hit_static);
        ac_count += usize::from(hit_robot);
        if (hit_person || hit_static || hit_robot) && first_collision_instant.is_none() {
            first_collision_instant = Some(k + 1);
        }
    }
    let collision = first_collision_instant.is_some();
    let goal_instant = pos.iter().position(|p| (p - traj.goal).norm() <= traj.success_radius);
    let success = match (goal_instant, first_collision_instant) {
        (Some(g), Some(c)) => g < c,
        (Some(_), None) => true,
        _ => false,
    };
    let time_to_goal = if success { goal_instant.map(|g| g as f64 * dt) } else { None };

    // Efficiency.
    let path_length: f64 = pos.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    let l_star = ctx.geodesic_length;
    let path_length_ratio = (l_star.is_finite() && l_star > EPS).then(|| path_length / l_star);
    let spl = l_star.is_finite().then(|| {
        if !success {
            0.0
        } else {
            let denom = path_length.max(l_star);
            if denom <= EPS { 1.0 } else { l_star / denom }
        }
    });
    let goal_dist: Vec<f64> = pos.iter().map(|p| (p - traj.goal).norm()).collect();
    let window = ((q.progress_window / dt).round() as usize).max(1);
    let failure_to_progress = (0..steps / window)
        .filter(|w| goal_dist[w * window] - goal_dist[(w + 1) * window] < q.progress_delta)
        .count();

    // Motion quality.
    let vel: Vec<Vec2> = pos.windows(2).map(|w| (w[1] - w[0]) / dt).collect();
    let stalled_time = dt
        * (0..steps)
            .filter(|&k| {
                vel[k].norm() < q.stall_linear
                    && (wrap_angle(yaw[k + 1] - yaw[k]) / dt).abs() < q.stall_angular
            })
            .count() as f64;
    let v_stats = min_avg_max(vel.iter().map(|v| v.norm()));
    let a_stats = min_avg_max(pos.windows(3).map(|w| ((w[2] - w[1] * 2.0 + w[0]) / (dt * dt)).norm()));
    let j_stats = min_avg_max(
        pos.windows(4).map(|w| ((w[3] - w[2] * 3.0 + w[1] * 3.0 - w[0]) / (dt * dt * dt)).norm()),
    );
    let chc: f64 = yaw.windows(2).map(|w| wrap_angle(w[1] - w[0]).abs()).sum();
    let mut chc_motion = 0.0;
    let mut last_dir: Option<f64> = None;
    for v in &vel {
        if v.norm() >= q.v_eps && v.norm() > 0.0 {
            let h = v.y.atan2(v.x);
            if let Some(prev) = last_dir {
                chc_motion += wrap_angle(h - prev).abs();
            }
            last_dir = Some(h);
        }
    }
    let path_irregularity = match (pos.first(), yaw.first()) {
        (Some(p0), Some(&th0)) if path_length > EPS => {
            let to_goal = traj.goal - p0;
            let initial = wrap_angle(to_goal.y.atan2(to_goal.x) - th0).abs();
            Some((chc - initial) / path_length)
        }
        _ => None,
    };

    // Distances to people, per instant.
    let mut d_min = vec![if n > 0 { Some(f64::INFINITY) } else { None }; np];
    let mut dist_person_min: Option<f64> = None;
    let mut gap_person_min: Option<f64> = None;
    let mut cp_sum = 0.0;
    let mut discomfort = 0usize;
    let mut discomfort_sum = 0.0;
    let mut compliant = 0usize;
    let mut zone_counts = [0usize; 4];
    let mut sf_people = 0.0;
    let mut sf_robot = 0.0;
    for t in 0..n {
        let mut closest = f64::INFINITY;
        let mut closest_gap = f64::INFINITY;
        let mut on_robot = Vec2::zeros();
        let robot_dir = Vec2::new(yaw[t].cos(), yaw[t].sin());
        for (i, dm) in d_min.iter_mut().enumerate() {
            let qi = person(t, i);
            let ri = people.radii[i];
            let d = (qi - pos[t]).norm();
            let gap = d - rr - ri;
            closest = closest.min(d);
            closest_gap = closest_gap.min(gap);
            if let Some(m) = dm.as_mut() {
                *m = m.min(d);
            }
            let heading = people.headings[t * np + i];
            let (on_person, by_person) =
                social_forces(pos[t], rr, robot_dir, qi, ri, Vec2::new(heading.cos(), heading.sin()), q);
            sf_people += on_person.norm();
            on_robot += by_person;
        }
        sf_robot += on_robot.norm();
        if np > 0 {
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
    let cp_avg = (np > 0 && n > 0).then(|| cp_sum / n as f64);

    // Groups: zones to the closest o-space centre, time inside, crossings.
    let rows = |offsets: &[usize], t: usize| -> (usize, usize) {
        if offsets.is_empty() { (0, 0) } else { (offsets[t], offsets[t + 1]) }
    };
    let mut group_zone_counts = [0usize; 4];
    let mut inside_count = 0usize;
    let mut ospace_entries = 0usize;
    let mut was_inside = false;
    for (t, &p) in pos.iter().enumerate() {
        let (lo, hi) = rows(groups.ospace_offsets, t);
        let mut closest = f64::INFINITY;
        let mut inside = false;
        for o in &groups.ospaces[lo..hi] {
            let d = (p - o.centre).norm();
            closest = closest.min(d);
            inside |= d <= o.radius;
        }
        group_zone_counts[zone_of(closest, &ctx.zones)] += 1;
        inside_count += usize::from(inside);
        ospace_entries += usize::from(inside && !was_inside);
        was_inside = inside;
    }
    let (mut cross_pp, mut cross_po) = (0usize, 0usize);
    for t in 0..steps {
        let (lo, hi) = rows(groups.link_offsets, t);
        for l in &groups.links[lo..hi] {
            if crosses(pos[t], pos[t + 1], l.a, l.b) {
                match l.kind {
                    LinkKind::PersonPerson => cross_pp += 1,
                    LinkKind::PersonObject => cross_po += 1,
                }
            }
        }
    }

    // Object spaces.
    let nm = objects.polygons.len();
    let mut obj_active_in = vec![0usize; nm];
    let mut obj_any_in = vec![0usize; nm];
    let mut any_active_in = 0usize;
    for (t, &p) in pos.iter().enumerate() {
        let mut hit = false;
        for (k, poly) in objects.polygons.iter().enumerate() {
            if inside_polygon(p, poly) {
                obj_any_in[k] += 1;
                if objects.active[t * nm + k] {
                    obj_active_in[k] += 1;
                    hit = true;
                }
            }
        }
        any_active_in += usize::from(hit);
    }

    // Time to collision, per step.
    let mut ttc_min = f64::INFINITY;
    let mut ttc_below = 0usize;
    for t in 0..steps {
        let mut step_min = f64::INFINITY;
        for i in 0..np {
            let dp = person(t, i) - pos[t];
            let dv = people.velocities[t * np + i] - vel[t];
            step_min = step_min.min(time_to_collision(dp, dv, rr + people.radii[i]));
        }
        ttc_min = ttc_min.min(step_min);
        ttc_below += usize::from(step_min < q.ttc_threshold);
    }

    // Clearance to static geometry.
    let clear = min_avg_max(pos.iter().map(|&p| (ctx.clearance)(p) - rr).filter(|c| c.is_finite()));

    // Daza et al. 2021.
    let astar_ok = ctx.astar_path.len() >= 2;
    let l_ratio =
        (astar_ok && success && path_length > EPS).then(|| polyline_length(ctx.astar_path) / path_length);
    let angles =
        if astar_ok { leave_rejoin_angles(&pos, ctx.astar_path, q.astar_tolerance) } else { Vec::new() };
    let smooth_k = angles.len();
    let smooth = astar_ok.then(|| {
        let sq = angles.iter().fold(0.0, |acc, a| acc + a * a);
        sq / (smooth_k.saturating_sub(1).max(1)) as f64
    });

    Ok(FullMetrics {
        steps,
        success,
        collision,
        timeout: n > 0 && !success && !collision,
        time_to_goal,
        hc_count,
        wc_count,
        ac_count,
        hc: hc_count > 0,
        wc: wc_count > 0,
        ac: ac_count > 0,
        path_length,
        path_length_ratio,
        spl,
        failure_to_progress,
        stalled_time,
        vel_min: v_stats.map(|s| s.0),
        vel_avg: v_stats.map(|s| s.1),
        vel_max: v_stats.map(|s| s.2),
        acc_min: a_stats.map(|s| s.0),
        acc_avg: a_stats.map(|s| s.1),
        acc_max: a_stats.map(|s| s.2),
        jerk_min: j_stats.map(|s| s.0),
        jerk_avg: j_stats.map(|s| s.1),
        jerk_max: j_stats.map(|s| s.2),
        chc,
        chc_motion,
        path_irregularity,
        dist_person_min,
        gap_person_min,
        cp_avg,
        d_min,
        discomfort_frequency: frac(discomfort, n),
        discomfort_gap_avg: (discomfort > 0).then(|| discomfort_sum / discomfort as f64),
        personal_space_compliance: frac(compliant, n),
        psi_intimate: pct(zone_counts[0], n),
        psi_personal: pct(zone_counts[1], n),
        psi_social: pct(zone_counts[2], n),
        psi_public: pct(zone_counts[3], n),
        group_psi_intimate: pct(group_zone_counts[0], n),
        group_psi_personal: pct(group_zone_counts[1], n),
        group_psi_social: pct(group_zone_counts[2], n),
        group_psi_public: pct(group_zone_counts[3], n),
        ospace_pct: pct(inside_count, n),
        ospace_time: inside_count as f64 * dt,
        ospace_entries,
        interaction_crossings: cross_pp + cross_po,
        interaction_crossings_person_person: cross_pp,
        interaction_crossings_person_object: cross_po,
        psi_object: obj_active_in.iter().map(|&c| pct(c, n)).collect(),
        psi_object_any: obj_any_in.iter().map(|&c| pct(c, n)).collect(),
        psi_objects: pct(any_active_in, n),
        ttc_min: ttc_min.is_finite().then_some(ttc_min),
        ttc_below_fraction: frac(ttc_below, steps),
        clearance_min: clear.map(|s| s.0),
        clearance_avg: clear.map(|s| s.1),
        social_force_on_people: sf_people,
        social_force_on_robot: sf_robot,
        social_work: sf_people + sf_robot,
        l_ratio,
        smooth,
        smooth_k,
        d_t: path_length,
        tau: steps as f64 * dt,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9
    }

    fn assert_close(a: Option<f64>, b: f64) {
        let a = a.expect("a defined value");
        assert!(close(a, b), "{a} != {b}");
    }

    fn no_clearance(_: Vec2) -> f64 {
        f64::INFINITY
    }

    fn ctx(geodesic: f64) -> EvalContext<'static> {
        EvalContext {
            geodesic_length: geodesic,
            astar_path: &[],
            clearance: &no_clearance,
            zones: DEFAULT_ZONES,
            collision_steps: &[],
            params: MetricParams::default(),
        }
    }

    fn traj(robot: &[[f64; 3]], dt: f64, goal: Vec2) -> Trajectory<'_> {
        Trajectory { dt, robot, robot_radius: 0.3, goal, success_radius: 0.1 }
    }

    fn run(t: &Trajectory, p: &PeopleTracks, c: &EvalContext) -> FullMetrics {
        evaluate(t, p, &Groups::none(), &ObjectSpaces::none(), c).expect("valid input")
    }

    /// x = 0, 1, ..., `last` on y = 0, yaw 0.
    fn line(last: usize) -> Vec<[f64; 3]> {
        (0..=last).map(|x| [x as f64, 0.0, 0.0]).collect()
    }

    #[test]
    fn straight_line_at_constant_speed() {
        let robot = line(10);
        let t = traj(&robot, 0.5, Vec2::new(10.0, 0.0));
        let wall = |p: Vec2| 2.0 - p.y;
        let mut c = ctx(10.0);
        c.clearance = &wall;
        let m = run(&t, &PeopleTracks::none(), &c);
        assert_eq!(m.steps, 10);
        assert!(m.success && !m.collision && !m.timeout);
        assert_close(m.time_to_goal, 5.0);
        assert!(close(m.path_length, 10.0) && close(m.d_t, 10.0) && close(m.tau, 5.0));
        assert_close(m.path_length_ratio, 1.0);
        assert_close(m.spl, 1.0);
        for v in [m.vel_min, m.vel_avg, m.vel_max] {
            assert_close(v, 2.0);
        }
        for v in [m.acc_min, m.acc_avg, m.acc_max, m.jerk_min, m.jerk_avg, m.jerk_max] {
            assert_close(v, 0.0);
        }
        assert!(close(m.chc, 0.0) && close(m.chc_motion, 0.0));
        assert_close(m.path_irregularity, 0.0);
        assert_eq!(m.failure_to_progress, 0);
        assert!(close(m.stalled_time, 0.0));
        assert_close(m.clearance_min, 1.7);
        assert_close(m.clearance_avg, 1.7);
        // No people: all public, compliant, nothing else defined.
        assert_close(m.psi_public, 100.0);
        assert_close(m.psi_intimate, 0.0);
        assert_close(m.personal_space_compliance, 1.0);
        assert_close(m.discomfort_frequency, 0.0);
        assert_eq!((m.dist_person_min, m.cp_avg, m.ttc_min), (None, None, None));
        assert_close(m.ttc_below_fraction, 0.0);
        assert!(m.d_min.is_empty() && m.psi_object.is_empty());
    }

    #[test]
    fn detour_lowers_spl_and_raises_plr() {
        let robot = line(10);
        let t = traj(&robot, 0.5, Vec2::new(10.0, 0.0));
        let m = run(&t, &PeopleTracks::none(), &ctx(8.0));
        // l* = 8 < PL = 10: SPL = 8 / 10.
        assert_close(m.path_length_ratio, 1.25);
        assert_close(m.spl, 0.8);
        let m = run(&t, &PeopleTracks::none(), &ctx(12.5));
        assert_close(m.path_length_ratio, 0.8);
        assert_close(m.spl, 1.0);
        let short = traj(&robot[..5], 0.5, Vec2::new(10.0, 0.0));
        let m = run(&short, &PeopleTracks::none(), &ctx(10.0));
        assert!(!m.success && m.timeout);
        assert_close(m.spl, 0.0);
        assert_eq!(m.time_to_goal, None);
        let m = run(&t, &PeopleTracks::none(), &ctx(f64::INFINITY));
        assert_eq!((m.path_length_ratio, m.spl), (None, None));
    }

    #[test]
    fn l_shaped_path() {
        let robot = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, FRAC_PI_2],
            [2.0, 1.0, FRAC_PI_2],
            [2.0, 2.0, FRAC_PI_2],
        ];
        let t = traj(&robot, 1.0, Vec2::new(2.0, 2.0));
        let m = run(&t, &PeopleTracks::none(), &ctx(4.0));
        assert!(close(m.chc, FRAC_PI_2));
        assert!(close(m.chc_motion, FRAC_PI_2));
        // (pi/2 - |atan2(2, 2) - 0|) / 4
        assert_close(m.path_irregularity, PI / 16.0);
        let s2 = 2f64.sqrt();
        assert_close(m.acc_min, 0.0);
        assert_close(m.acc_avg, s2 / 3.0);
        assert_close(m.acc_max, s2);
        for v in [m.jerk_min, m.jerk_avg, m.jerk_max] {
            assert_close(v, s2);
        }
        assert_close(m.path_length_ratio, 1.0);
        assert_close(m.time_to_goal, 4.0);
    }

    #[test]
    fn heading_change_wraps_and_motion_direction_skips_stops() {
        // Yaw 3.1 -> -3.1 is a 2 pi - 6.2 turn, not 6.2.
        let robot = [[0.0, 0.0, 3.1], [1.0, 0.0, -3.1], [1.0, 0.0, -3.1], [1.0, 1.0, -3.1]];
        let t = traj(&robot, 1.0, Vec2::new(5.0, 5.0));
        let m = run(&t, &PeopleTracks::none(), &ctx(1.0));
        assert!(close(m.chc, 2.0 * PI - 6.2));
        // The stop at step 1 is skipped: east then north.
        assert!(close(m.chc_motion, FRAC_PI_2));
        assert_close(m.vel_min, 0.0);
        assert!(close(m.stalled_time, 1.0));
    }

    #[test]
    fn stalled_robot_fails_to_progress() {
        let robot = vec![[0.0, 0.0, 0.0]; 12];
        let t = traj(&robot, 1.0, Vec2::new(5.0, 0.0));
        let m = run(&t, &PeopleTracks::none(), &ctx(5.0));
        // 11 steps, windows of 5 s = 5 steps: two complete windows.
        assert_eq!(m.failure_to_progress, 2);
        assert!(close(m.stalled_time, 11.0));
        assert!(m.timeout);
    }

    /// Robot x = 0..9 on y = 0 (radius 0.3), one static person at (5, 0.7) of radius 0.25.
    fn passing_person() -> (Vec<[f64; 3]>, Vec<Vec2>, Vec<Vec2>, Vec<f64>) {
        let robot = line(9);
        let n = robot.len();
        (robot, vec![Vec2::new(5.0, 0.7); n], vec![Vec2::zeros(); n], vec![0.0; n])
    }

    #[test]
    fn person_at_known_position() {
        let (robot, pos, vel, head) = passing_person();
        let people =
            PeopleTracks { positions: &pos, velocities: &vel, headings: &head, radii: &[0.25], count: 1 };
        let t = traj(&robot, 1.0, Vec2::new(9.0, 0.0));
        let m = run(&t, &people, &ctx(9.0));
        let d: Vec<f64> = (0..10).map(|x| ((x as f64 - 5.0).powi(2) + 0.49).sqrt()).collect();
        // Closest 0.7 at x = 5: personal; x = 2..4, 6..8 social; x = 0, 1, 9 public.
        assert_close(m.psi_intimate, 0.0);
        assert_close(m.psi_personal, 10.0);
        assert_close(m.psi_social, 60.0);
        assert_close(m.psi_public, 30.0);
        assert_close(m.d_min[0], 0.7);
        assert_close(m.dist_person_min, 0.7);
        assert_close(m.gap_person_min, 0.15);
        assert_close(m.cp_avg, d.iter().sum::<f64>() / 10.0);
        // Gap 0.15 < 0.2 only at x = 5.
        assert_close(m.discomfort_frequency, 0.1);
        assert_close(m.discomfort_gap_avg, 0.15);
        // d - r_R = 0.4 < 0.45 only at x = 5.
        assert_close(m.personal_space_compliance, 0.9);
        // Lateral offset 0.7 > 0.55: never on a collision course, no contact.
        assert_eq!(m.ttc_min, None);
        assert_close(m.ttc_below_fraction, 0.0);
        assert!(!m.hc && m.success);
    }

    #[test]
    fn custom_zones_move_the_boundaries() {
        let (robot, pos, vel, head) = passing_person();
        let people =
            PeopleTracks { positions: &pos, velocities: &vel, headings: &head, radii: &[0.25], count: 1 };
        let t = traj(&robot, 1.0, Vec2::new(9.0, 0.0));
        let mut c = ctx(9.0);
        c.zones = [1.0, 2.0, 3.0];
        let m = run(&t, &people, &c);
        // 0.7 | 1.22 x2 | 2.12 x2 | 3.08 x2, 4.06 x2, 5.05
        assert_close(m.psi_intimate, 10.0);
        assert_close(m.psi_personal, 20.0);
        assert_close(m.psi_social, 20.0);
        assert_close(m.psi_public, 50.0);
    }

    #[test]
    fn head_on_time_to_collision() {
        let robot = line(2);
        let pos = [Vec2::new(10.0, 0.0), Vec2::new(9.0, 0.0), Vec2::new(8.0, 0.0)];
        let vel = [Vec2::new(-1.0, 0.0); 3];
        let people =
            PeopleTracks { positions: &pos, velocities: &vel, headings: &[PI; 3], radii: &[0.3], count: 1 };
        let t = traj(&robot, 1.0, Vec2::new(20.0, 0.0));
        let mut c = ctx(20.0);
        c.params.ttc_threshold = 4.0;
        let m = run(&t, &people, &c);
        // Step 0: (10 - 0.6) / 2 = 4.7 s; step 1: (8 - 0.6) / 2 = 3.7 s.
        assert_close(m.ttc_min, 3.7);
        assert_close(m.ttc_below_fraction, 0.5);
        assert!(close(time_to_collision(Vec2::new(0.5, 0.0), Vec2::zeros(), 0.6), 0.0));
        assert!(time_to_collision(Vec2::new(5.0, 0.0), Vec2::new(1.0, 0.0), 0.6).is_infinite());
    }

    #[test]
    fn swept_test_catches_tunnelling() {
        let robot = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
        let pos = [Vec2::zeros(); 2];
        let vel = [Vec2::zeros(); 2];
        let people =
            PeopleTracks { positions: &pos, velocities: &vel, headings: &[0.0; 2], radii: &[0.25], count: 1 };
        let t = traj(&robot, 1.0, Vec2::new(1.0, 0.0));
        let m = run(&t, &people, &ctx(2.0));
        // Both samples have a gap of 0.45 m, the swept motion passes through the person.
        assert_close(m.gap_person_min, 0.45);
        assert_eq!(m.hc_count, 1);
        assert!(m.hc && m.collision && !m.success && !m.timeout);
        // Moved 1 m sideways, the swept distance is 1 m: no contact.
        let pos = [Vec2::new(0.0, 1.0); 2];
        let people = PeopleTracks { positions: &pos, ..people };
        let m = run(&t, &people, &ctx(2.0));
        assert_eq!(m.hc_count, 0);
        assert!(m.success);
    }

    #[test]
    fn contact_bits_by_kind_and_success_before_collision() {
        let robot = line(3);
        let t = traj(&robot, 1.0, Vec2::new(3.0, 0.0));
        let mut c = ctx(3.0);
        c.collision_steps = &[0, CONTACT_STATIC, CONTACT_ROBOT | CONTACT_PERSON];
        let m = run(&t, &PeopleTracks::none(), &c);
        assert_eq!((m.hc_count, m.wc_count, m.ac_count), (1, 1, 1));
        assert!(m.hc && m.wc && m.ac && m.collision && !m.success && !m.timeout);
        // Goal at instant 1, collision in step 2 (instant 3): success.
        let t = traj(&robot, 1.0, Vec2::new(1.0, 0.0));
        c.collision_steps = &[0, 0, CONTACT_STATIC];
        let m = run(&t, &PeopleTracks::none(), &c);
        assert!(m.success && m.collision);
        assert_close(m.time_to_goal, 1.0);
        // Collision in the step that reaches the goal: not a success.
        c.collision_steps = &[CONTACT_STATIC, 0, 0];
        let m = run(&t, &PeopleTracks::none(), &c);
        assert!(!m.success && m.collision);
    }

    #[test]
    fn social_force_on_a_single_pair() {
        let robot = [[0.0, 0.0, 0.0]];
        let pos = [Vec2::new(1.0, 0.0)];
        let vel = [Vec2::zeros()];
        let t = Trajectory { robot_radius: 0.3, ..traj(&robot, 1.0, Vec2::new(5.0, 0.0)) };
        let facing =
            PeopleTracks { positions: &pos, velocities: &vel, headings: &[PI], radii: &[0.2], count: 1 };
        let m = run(&t, &facing, &ctx(5.0));
        let f = 2.1 * ((0.5f64 - 1.0) / 0.3).exp();
        assert!(close(m.social_force_on_people, f));
        assert!(close(m.social_force_on_robot, f));
        assert!(close(m.social_work, 2.0 * f));
        // The person faces away: the robot is behind them, weight lambda = 0.5.
        let away = PeopleTracks { headings: &[0.0], ..facing };
        let m = run(&t, &away, &ctx(5.0));
        assert!(close(m.social_force_on_people, 0.5 * f));
        assert!(close(m.social_force_on_robot, f));
    }

    #[test]
    fn object_space_entered_while_active() {
        let robot = line(9);
        let n = robot.len();
        let square =
            vec![Vec2::new(3.5, -1.0), Vec2::new(6.5, -1.0), Vec2::new(6.5, 1.0), Vec2::new(3.5, 1.0)];
        let degenerate = vec![Vec2::new(0.0, -1.0), Vec2::new(0.0, 1.0)];
        let polygons = [square, degenerate];
        // Object 0 active from t = 5, object 1 always active.
        let active: Vec<bool> = (0..n).flat_map(|t| [t >= 5, true]).collect();
        let objects = ObjectSpaces { polygons: &polygons, active: &active };
        let t = traj(&robot, 1.0, Vec2::new(9.0, 0.0));
        let m = evaluate(&t, &PeopleTracks::none(), &Groups::none(), &objects, &ctx(9.0)).expect("valid");
        // Inside at x = 4, 5, 6; active at 5 and 6.
        assert_close(m.psi_object[0], 20.0);
        assert_close(m.psi_object_any[0], 30.0);
        assert_close(m.psi_object[1], 0.0);
        assert_close(m.psi_objects, 20.0);
    }

    #[test]
    fn interaction_crossings_and_ospace() {
        let robot = line(9);
        let n = robot.len();
        let links_at = [
            InteractionLink { a: Vec2::new(5.0, 2.0), b: Vec2::new(5.0, -2.0), kind: LinkKind::PersonObject },
            InteractionLink { a: Vec2::new(7.5, -1.0), b: Vec2::new(7.5, 1.0), kind: LinkKind::PersonPerson },
            // Collinear with the path: not a crossing.
            InteractionLink { a: Vec2::new(0.0, 0.0), b: Vec2::new(9.0, 0.0), kind: LinkKind::PersonPerson },
            // Beside the path.
            InteractionLink { a: Vec2::new(3.0, 0.5), b: Vec2::new(3.0, 2.0), kind: LinkKind::PersonPerson },
        ];
        let links: Vec<InteractionLink> = (0..n).flat_map(|_| links_at).collect();
        let link_offsets: Vec<usize> = (0..=n).map(|t| 4 * t).collect();
        let ospaces = vec![OSpace { centre: Vec2::new(2.0, 0.5), radius: 1.2 }; n];
        let ospace_offsets: Vec<usize> = (0..=n).collect();
        let groups = Groups {
            ospace_offsets: &ospace_offsets,
            ospaces: &ospaces,
            link_offsets: &link_offsets,
            links: &links,
        };
        let t = traj(&robot, 0.5, Vec2::new(9.0, 0.0));
        let m =
            evaluate(&t, &PeopleTracks::none(), &groups, &ObjectSpaces::none(), &ctx(9.0)).expect("valid");
        // x = 5 is a sample point: counted once (half-open steps).
        assert_eq!(m.interaction_crossings_person_object, 1);
        assert_eq!(m.interaction_crossings_person_person, 1);
        assert_eq!(m.interaction_crossings, 2);
        // Inside the o-space at x = 1, 2, 3 (distances 1.118, 0.5, 1.118).
        assert_close(m.ospace_pct, 30.0);
        assert!(close(m.ospace_time, 1.5));
        assert_eq!(m.ospace_entries, 1);
        assert_close(m.group_psi_intimate, 0.0);
        assert_close(m.group_psi_personal, 30.0);
        assert_close(m.group_psi_social, 30.0);
        assert_close(m.group_psi_public, 40.0);
    }

    #[test]
    fn daza_l_ratio_and_smooth() {
        // Leaves the straight A* path at 45 degrees and rejoins it at -45 degrees.
        let pts = [
            (0.0, 0.0),
            (1.0, 0.0),
            (2.0, 0.0),
            (3.0, 1.0),
            (4.0, 2.0),
            (5.0, 2.0),
            (6.0, 2.0),
            (7.0, 1.0),
            (8.0, 0.0),
            (9.0, 0.0),
            (10.0, 0.0),
        ];
        let robot: Vec<[f64; 3]> = pts.iter().map(|&(x, y)| [x, y, 0.0]).collect();
        let astar = [Vec2::new(0.0, 0.0), Vec2::new(10.0, 0.0)];
        let t = traj(&robot, 1.0, Vec2::new(10.0, 0.0));
        let mut c = ctx(10.0);
        c.astar_path = &astar;
        let m = run(&t, &PeopleTracks::none(), &c);
        let pl = 6.0 + 4.0 * 2f64.sqrt();
        assert!(close(m.path_length, pl));
        assert_close(m.l_ratio, 10.0 / pl);
        assert_eq!(m.smooth_k, 2);
        // 1/(k - 1) * (2 (pi/4)^2)
        assert_close(m.smooth, 2.0 * FRAC_PI_4 * FRAC_PI_4);
        // Staying on the A* path: L_ratio 1, Smooth 0.
        let robot = line(10);
        let t = traj(&robot, 1.0, Vec2::new(10.0, 0.0));
        let m = run(&t, &PeopleTracks::none(), &c);
        assert_close(m.l_ratio, 1.0);
        assert_close(m.smooth, 0.0);
        assert_eq!(m.smooth_k, 0);
        // Without an A* path, both undefined.
        let m = run(&t, &PeopleTracks::none(), &ctx(10.0));
        assert_eq!((m.l_ratio, m.smooth), (None, None));
    }

    #[test]
    fn smooth_with_one_angle_and_no_success() {
        // Leaves at 45 degrees and never comes back (and never reaches the goal).
        let robot = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 1.0, 0.0], [3.0, 2.0, 0.0]];
        let astar = [Vec2::new(0.0, 0.0), Vec2::new(10.0, 0.0)];
        let t = traj(&robot, 1.0, Vec2::new(10.0, 0.0));
        let mut c = ctx(10.0);
        c.astar_path = &astar;
        let m = run(&t, &PeopleTracks::none(), &c);
        assert_eq!(m.smooth_k, 1);
        assert_close(m.smooth, FRAC_PI_4 * FRAC_PI_4);
        assert_eq!(m.l_ratio, None);
    }

    #[test]
    fn empty_and_single_point_trajectories() {
        let polygons = [vec![Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)]];
        let objects = ObjectSpaces { polygons: &polygons, active: &[] };
        let people =
            PeopleTracks { positions: &[], velocities: &[], headings: &[], radii: &[0.2, 0.3], count: 2 };
        let t = traj(&[], 0.1, Vec2::zeros());
        let m = evaluate(&t, &people, &Groups::none(), &objects, &ctx(1.0)).expect("empty is valid");
        assert_eq!(m.steps, 0);
        assert!(!m.success && !m.collision && !m.timeout);
        assert!(close(m.path_length, 0.0) && close(m.tau, 0.0));
        assert_eq!(m.d_min, vec![None, None]);
        assert_eq!(m.psi_object, vec![None]);
        assert_eq!((m.psi_public, m.vel_avg, m.ttc_below_fraction, m.smooth), (None, None, None, None));
        assert_close(m.spl, 0.0);

        let robot = [[0.0, 0.0, 0.0]];
        let t = traj(&robot, 0.1, Vec2::zeros());
        let m = run(&t, &PeopleTracks::none(), &ctx(0.0));
        assert!(m.success);
        assert_close(m.time_to_goal, 0.0);
        assert_eq!(m.path_length_ratio, None);
        assert_close(m.spl, 1.0);
        assert_eq!((m.vel_min, m.acc_min, m.jerk_min, m.path_irregularity), (None, None, None, None));
        assert_eq!((m.ttc_min, m.ttc_below_fraction), (None, None));
        assert_close(m.psi_public, 100.0);
    }

    #[test]
    fn clearance_skips_non_finite_samples() {
        let robot = line(2);
        let t = traj(&robot, 1.0, Vec2::new(2.0, 0.0));
        let f = |p: Vec2| if p.x > 0.5 { f64::NAN } else { 1.0 };
        let mut c = ctx(2.0);
        c.clearance = &f;
        let m = run(&t, &PeopleTracks::none(), &c);
        assert_close(m.clearance_min, 0.7);
        assert_close(m.clearance_avg, 0.7);
        let nan = |_: Vec2| f64::NAN;
        c.clearance = &nan;
        let m = run(&t, &PeopleTracks::none(), &c);
        assert_eq!((m.clearance_min, m.clearance_avg), (None, None));
    }

    #[test]
    fn bad_inputs_are_errors_not_panics() {
        let robot = line(2);
        let good = traj(&robot, 1.0, Vec2::new(2.0, 0.0));
        let none = PeopleTracks::none();
        fn is_err(t: &Trajectory, p: &PeopleTracks, g: &Groups, o: &ObjectSpaces, c: &EvalContext) -> bool {
            matches!(evaluate(t, p, g, o, c), Err(CoreError::Input { .. }))
        }
        let (g, o) = (Groups::none(), ObjectSpaces::none());
        let nan_robot = [[0.0, f64::NAN, 0.0]];
        assert!(is_err(&traj(&nan_robot, 1.0, Vec2::zeros()), &none, &g, &o, &ctx(1.0)));
        assert!(is_err(&traj(&robot, 0.0, Vec2::zeros()), &none, &g, &o, &ctx(1.0)));
        assert!(is_err(&traj(&robot, f64::NAN, Vec2::zeros()), &none, &g, &o, &ctx(1.0)));
        assert!(is_err(&traj(&robot, 1.0, Vec2::new(f64::INFINITY, 0.0)), &none, &g, &o, &ctx(1.0)));
        assert!(is_err(&Trajectory { robot_radius: -1.0, ..good }, &none, &g, &o, &ctx(1.0)));
        assert!(is_err(&good, &none, &g, &o, &ctx(f64::NAN)));
        assert!(is_err(&good, &none, &g, &o, &ctx(-1.0)));
        let mut c = ctx(1.0);
        c.zones = [1.0, 0.5, 3.0];
        assert!(is_err(&good, &none, &g, &o, &c));
        let mut c = ctx(1.0);
        c.collision_steps = &[0; 3];
        assert!(is_err(&good, &none, &g, &o, &c));
        let mut c = ctx(1.0);
        c.params.sf_b = 0.0;
        assert!(is_err(&good, &none, &g, &o, &c));
        let nanpath = [Vec2::new(f64::NAN, 0.0), Vec2::zeros()];
        let mut c = ctx(1.0);
        c.astar_path = &nanpath;
        assert!(is_err(&good, &none, &g, &o, &c));
        // People: wrong lengths and non-finite values.
        let pos = [Vec2::zeros(); 2];
        let vel = [Vec2::zeros(); 3];
        let short =
            PeopleTracks { positions: &pos, velocities: &vel, headings: &[0.0; 3], radii: &[0.2], count: 1 };
        assert!(is_err(&good, &short, &g, &o, &ctx(1.0)));
        let pos3 = [Vec2::zeros(), Vec2::new(f64::NAN, 0.0), Vec2::zeros()];
        let nanp = PeopleTracks { positions: &pos3, ..short };
        assert!(is_err(&good, &nanp, &g, &o, &ctx(1.0)));
        let pos3 = [Vec2::new(5.0, 5.0); 3];
        let negr = PeopleTracks { positions: &pos3, radii: &[-0.1], ..short };
        assert!(is_err(&good, &negr, &g, &o, &ctx(1.0)));
        // Groups: offsets of the wrong length, not ending at the data length, decreasing.
        let os = [OSpace { centre: Vec2::zeros(), radius: 1.0 }];
        for offs in [&[0usize, 1][..], &[0, 0, 0, 0][..], &[0, 1, 0, 1][..], &[][..]] {
            let bad = Groups { ospace_offsets: offs, ospaces: &os, link_offsets: &[], links: &[] };
            assert!(is_err(&good, &none, &bad, &o, &ctx(1.0)), "{offs:?}");
        }
        let neg = [OSpace { centre: Vec2::zeros(), radius: -1.0 }];
        let bad = Groups { ospace_offsets: &[0, 1, 1, 1], ospaces: &neg, link_offsets: &[], links: &[] };
        assert!(is_err(&good, &none, &bad, &o, &ctx(1.0)));
        // Objects: activity of the wrong length.
        let polys = [vec![Vec2::zeros(), Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)]];
        let bad = ObjectSpaces { polygons: &polys, active: &[true] };
        assert!(is_err(&good, &none, &g, &bad, &ctx(1.0)));
    }

    #[test]
    fn serializes_with_snake_case_columns() {
        let robot = line(3);
        let t = traj(&robot, 1.0, Vec2::new(3.0, 0.0));
        let m = run(&t, &PeopleTracks::none(), &ctx(3.0));
        let v = serde_json::to_value(&m).expect("serializable");
        for key in [
            "success",
            "l_ratio",
            "smooth",
            "d_t",
            "tau",
            "chc",
            "d_min",
            "psi_intimate",
            "psi_object",
            "spl",
            "ttc_min",
        ] {
            assert!(v.get(key).is_some(), "{key}");
        }
        assert_eq!(v["time_to_goal"], serde_json::json!(3.0));
        assert_eq!(v["ttc_min"], serde_json::Value::Null);
    }

    #[test]
    fn deterministic() {
        let (robot, pos, vel, head) = passing_person();
        let people =
            PeopleTracks { positions: &pos, velocities: &vel, headings: &head, radii: &[0.25], count: 1 };
        let t = traj(&robot, 1.0, Vec2::new(9.0, 0.0));
        assert_eq!(run(&t, &people, &ctx(9.0)), run(&t, &people, &ctx(9.0)));
    }

    fn special(v: f64, pick: u8) -> f64 {
        match pick {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => f64::NEG_INFINITY,
            _ => v,
        }
    }

    proptest::proptest! {
        #[test]
        fn never_panics_and_stays_consistent(
            raw in proptest::collection::vec((-20.0f64..20.0, -20.0f64..20.0, -7.0f64..7.0), 0..12),
            people_raw in proptest::collection::vec((-20.0f64..20.0, -20.0f64..20.0), 0..3),
            dt in 0.01f64..2.0,
            bad_at in proptest::option::of((0usize..40, 0u8..6)),
            links in proptest::collection::vec((-10.0f64..10.0, -10.0f64..10.0, -10.0f64..10.0, -10.0f64..10.0), 0..3),
        ) {
            let mut robot: Vec<[f64; 3]> = raw.iter().map(|&(x, y, th)| [x, y, th]).collect();
            let n = robot.len();
            let np = people_raw.len();
            let mut positions: Vec<Vec2> = (0..n)
                .flat_map(|t| people_raw.iter().map(move |&(x, y)| Vec2::new(x + 0.1 * t as f64, y)))
                .collect();
            let velocities = vec![Vec2::new(1.0, 0.0); n * np];
            let headings = vec![0.5; n * np];
            let radii = vec![0.25; np];
            let mut corrupted = false;
            if let Some((i, pick)) = bad_at {
                let v = special(1.0, pick);
                if !v.is_finite() {
                    if i < 3 * n {
                        robot[i / 3][i % 3] = v;
                        corrupted = true;
                    } else if i - 3 * n < positions.len() {
                        positions[i - 3 * n].x = v;
                        corrupted = true;
                    }
                }
            }
            let all_links: Vec<InteractionLink> = (0..n)
                .flat_map(|_| links.iter().map(|&(ax, ay, bx, by)| InteractionLink {
                    a: Vec2::new(ax, ay),
                    b: Vec2::new(bx, by),
                    kind: LinkKind::PersonObject,
                }))
                .collect();
            let link_offsets: Vec<usize> = if n == 0 { vec![] } else { (0..=n).map(|t| t * links.len()).collect() };
            let groups = Groups { ospace_offsets: &[], ospaces: &[], link_offsets: &link_offsets, links: &all_links };
            let square = vec![vec![Vec2::new(-1.0, -1.0), Vec2::new(1.0, -1.0), Vec2::new(1.0, 1.0), Vec2::new(-1.0, 1.0)]];
            let active: Vec<bool> = (0..n).map(|t| t % 2 == 0).collect();
            let objects = ObjectSpaces { polygons: &square, active: &active };
            let people = PeopleTracks { positions: &positions, velocities: &velocities, headings: &headings, radii: &radii, count: np };
            let astar = [Vec2::new(-5.0, 0.0), Vec2::new(5.0, 3.0)];
            let mut c = ctx(7.0);
            c.astar_path = &astar;
            let t = Trajectory { dt, robot: &robot, robot_radius: 0.3, goal: Vec2::new(1.0, 1.0), success_radius: 0.5 };
            match evaluate(&t, &people, &groups, &objects, &c) {
                Err(_) => proptest::prop_assert!(corrupted),
                Ok(m) => {
                    proptest::prop_assert!(!corrupted);
                    proptest::prop_assert_eq!(m.steps, n.saturating_sub(1));
                    proptest::prop_assert!(!(m.timeout && (m.success || m.collision)));
                    proptest::prop_assert!(m.path_length >= 0.0 && m.chc >= 0.0 && m.chc_motion >= 0.0);
                    if n > 0 {
                        let zones = [m.psi_intimate, m.psi_personal, m.psi_social, m.psi_public];
                        let total: f64 = zones.iter().map(|z| z.unwrap_or(f64::NAN)).sum();
                        proptest::prop_assert!((total - 100.0).abs() < 1e-9, "{}", total);
                        for f in [m.discomfort_frequency, m.personal_space_compliance, m.psi_objects.map(|p| p / 100.0)] {
                            let f = f.unwrap_or(f64::NAN);
                            proptest::prop_assert!((0.0..=1.0).contains(&f), "{}", f);
                        }
                        proptest::prop_assert!(m.psi_object[0] <= m.psi_object_any[0]);
                    }
                    if let Some(r) = m.l_ratio {
                        proptest::prop_assert!(r > 0.0);
                    }
                    proptest::prop_assert!(m.interaction_crossings <= m.steps * links.len());
                    proptest::prop_assert!(serde_json::to_string(&m).is_ok());
                }
            }
        }
    }
}
