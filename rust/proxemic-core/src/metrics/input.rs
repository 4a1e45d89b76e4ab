//! What [`super::evaluate`] takes: the robot's trajectory, the people's tracks, the groups'
//! o-spaces and interaction segments, the objects' interaction spaces, the episode context and
//! the metric parameters; and their validation (every array's length and every value's range,
//! as [`CoreError::Input`] naming the array and index).

use serde::Serialize;

use crate::error::{CoreError, Result};
use crate::math::Vec2;

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
    /// Whether each person is in the scene at each instant (row-major like `positions`); empty:
    /// everyone always is. An absent person (a replayed person before its track starts or after
    /// it ends) counts in no metric at that instant, nor in the step's swept collision test.
    pub present: &'a [bool],
}

impl PeopleTracks<'_> {
    /// No people.
    pub fn none() -> PeopleTracks<'static> {
        PeopleTracks { positions: &[], velocities: &[], headings: &[], radii: &[], count: 0, present: &[] }
    }

    /// Whether person `i` is in the scene at instant `t`.
    pub fn is_present(&self, t: usize, i: usize) -> bool {
        self.present.get(t * self.count + i).copied().unwrap_or(true)
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

    /// Whether `p` (m) lies in some o-space present at instant `t` (distance to its centre at
    /// most its radius); false for an instant beyond the offsets.
    pub fn in_ospace(&self, t: usize, p: Vec2) -> bool {
        match (self.ospace_offsets.get(t), self.ospace_offsets.get(t + 1)) {
            (Some(&lo), Some(&hi)) => self.ospaces[lo..hi].iter().any(|o| (p - o.centre).norm() <= o.radius),
            _ => false,
        }
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

    /// Whether `p` (m) lies in the interaction polygon of an object whose activity is on at
    /// instant `t`.
    pub fn in_active_space(&self, t: usize, p: Vec2) -> bool {
        let m = self.polygons.len();
        self.polygons.iter().enumerate().any(|(k, poly)| {
            self.active.get(t * m + k).copied().unwrap_or(false)
                && crate::geom::contains_point_polygon_pnpoly(p, poly)
        })
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
    /// The plain A* path on the same start and goal (m), for Daza's `l_ratio`, `smooth_rad2` and
    /// `smooth_rad`; fewer than 2 points makes them `None`.
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
    /// The episode replayed without the robots, for the robot's cost to people; `None` leaves
    /// those metrics `None`.
    pub robot_free: Option<super::RobotFreeTracks<'a>>,
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

/// Checks every input of [`super::evaluate`] (see its errors).
pub(crate) fn validate(
    traj: &Trajectory,
    people: &PeopleTracks,
    groups: &Groups,
    objects: &ObjectSpaces,
    ctx: &EvalContext,
) -> Result<()> {
    let n = traj.robot.len();
    validate_trajectory(traj)?;
    validate_people(people, n)?;
    validate_groups(groups, n)?;
    validate_objects(objects, n)?;
    validate_context(ctx, n)?;
    validate_params(&ctx.params)
}

fn validate_trajectory(traj: &Trajectory) -> Result<()> {
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
    Ok(())
}

fn validate_people(people: &PeopleTracks, n: usize) -> Result<()> {
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
    if !people.present.is_empty() && people.present.len() != rows {
        return Err(bad(
            "people.present",
            &format!("0 or {rows} entries (N = {n} x P = {p})"),
            people.present.len(),
        ));
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
    Ok(())
}

fn validate_groups(groups: &Groups, n: usize) -> Result<()> {
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
    Ok(())
}

fn validate_objects(objects: &ObjectSpaces, n: usize) -> Result<()> {
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
    Ok(())
}

fn validate_context(ctx: &EvalContext, n: usize) -> Result<()> {
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
    Ok(())
}

fn validate_params(q: &MetricParams) -> Result<()> {
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
