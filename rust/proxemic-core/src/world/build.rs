//! Building a world from a validated scenario: the static map, the robots' grids, goal fields
//! and plain paths, the people's scripts, and the checks that the scenario is playable.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::planners::plan_path;
use super::{GroundTruth, InflatedGrid, Layout, RobotStatic, World};
use crate::control::Limits;
use crate::control::mode_switch::ModeSwitchParams;
use crate::control::orca::{ObstacleSet, Orca, OrcaParams};
use crate::error::{CoreError, Result};
use crate::map::CostGrid;
use crate::map::geometry::StaticGeometry;
use crate::map::grid::{DistanceField, GridSpec, OccupancyGrid};
use crate::map::lidar::Scanner;
use crate::math::Vec2;
use crate::metrics::{InteractionObject, SceneLog};
use crate::pedestrians::scripts::plan_scripts;
use crate::pedestrians::{Crowd, SocialForceParams};
use crate::plan::geodesic::GoalField;
use crate::plan::social::SocialPlanning;
use crate::plan::{PathPlanner, snap_to_passable};
use crate::scenario::{Behaviour, Scenario};

/// Free space (m) kept between a robot's start area and the people who start walking near it:
/// the common evaluation radius of the intimate zone, 0.45 m, so that no episode begins with an
/// intrusion the robot could not avoid.
pub const START_CLEARANCE: f64 = 0.45;

fn v2(p: [f64; 2]) -> Vec2 {
    Vec2::new(p[0], p[1])
}

fn scenario_err(s: &Scenario, field: String, expected: String, found: String) -> CoreError {
    CoreError::Scenario { file: s.source.clone(), field, expected, found }
}

impl World {
    /// Builds the world: static geometry, inflated grids, goal fields and the plain A* paths
    /// from the nominal starts. Fails if a robot's start or goal is inside or too close to the
    /// static geometry, if a goal is unreachable, if a person starts or walks through it, or if
    /// a person's behaviour finds no room (a viewing place, a place at an activity or in a
    /// conversation, a tour's gathering arc) or no path ([`plan_scripts`]).
    pub fn new(scenario: Scenario) -> Result<Self> {
        let geometry = scenario.static_geometry()?;
        let spec = GridSpec::covering(geometry.bounds(), scenario.scene.resolution)?;
        let occupancy = OccupancyGrid::rasterize(&geometry, spec);
        let field = DistanceField::from_occupancy(&occupancy);

        check_people(&scenario, &geometry)?;

        let mut grids: Vec<InflatedGrid> = Vec::new();
        let mut planner = PathPlanner::new();
        let mut statics = Vec::with_capacity(scenario.robots.len());
        for i in 0..scenario.robots.len() {
            check_robot_places(&scenario, i, &geometry)?;
            statics.push(robot_static(&scenario, i, &field, &mut grids, &mut planner)?);
        }
        // People's places and paths after the robots' (a tour's stops must be valid first).
        let scripts = plan_scripts(&scenario, &geometry, &field)?;
        let layout = Layout::new(
            scenario.sensors.k_nearest,
            scenario.sensors.lidar_rays,
            scenario.robots.len(),
            scenario.sensors.subgoal > 0.0,
        );
        let grid_refs: Vec<(&CostGrid, f64)> = grids.iter().map(|g| (&g.grid, g.radius)).collect();
        let social = SocialPlanning::new(&scenario, &grid_refs)?;
        let obstacles = ObstacleSet::from_geometry(&geometry)?;
        let orca = Orca::new(OrcaParams::default())?;
        let mut world = World {
            control: ModeSwitchParams::default(),
            orca,
            obstacles,
            geometry,
            field,
            social,
            grids,
            statics,
            robots: Vec::new(),
            crowd: Crowd::default(),
            scripts,
            planner,
            layout,
            rng: ChaCha8Rng::seed_from_u64(0),
            seed: 0,
            steps: 0,
            started: false,
            scratch_people: Vec::new(),
            scratch_discs: Vec::new(),
            learned: None,
            scanners: vec![Scanner::default(); scenario.robots.len()],
            ended: vec![false; scenario.robots.len()],
            planning: vec![true; scenario.robots.len()],
            interaction_objects: scenario
                .objects
                .iter()
                .filter_map(|o| {
                    o.interaction.as_ref().map(|space| InteractionObject {
                        polygon: space.polygon.iter().map(|q| v2(*q)).collect(),
                        centre: Vec2::new(o.pose[0], o.pose[1]),
                    })
                })
                .collect(),
            now: GroundTruth::default(),
            log: SceneLog::new(Vec::new(), Vec::new()),
            robot_free: std::sync::Mutex::new(crate::pedestrians::RobotFree::default()),
            crowd_time: std::time::Duration::ZERO,
            scenario,
        };
        // The objects are the world's for good; the people's radii come with each reset.
        world.log =
            SceneLog::new(Vec::new(), world.interaction_objects.iter().map(|o| o.polygon.clone()).collect());
        let clear = world.start_areas();
        world.crowd = Crowd::spawn_scripted(
            &world.scenario.persons,
            &world.scripts,
            &world.scenario.episode.randomize,
            SocialForceParams::default(),
            &clear,
            &mut world.rng,
        );
        Ok(world)
    }

    /// The discs no walker may start in (centre, radius in m): each robot's nominal start with
    /// the robot's radius, its start jitter and [`START_CLEARANCE`].
    pub(super) fn start_areas(&self) -> Vec<(Vec2, f64)> {
        let jitter = self.scenario.episode.randomize.robot_start_jitter * std::f64::consts::SQRT_2;
        self.scenario
            .robots
            .iter()
            .zip(&self.statics)
            .map(|(r, st)| (Vec2::new(r.start[0], r.start[1]), st.radius + jitter + START_CLEARANCE))
            .collect()
    }
}

/// Robot `i`'s start, waypoints and goal must be at least its radius from the static geometry.
fn check_robot_places(scenario: &Scenario, i: usize, geometry: &StaticGeometry) -> Result<()> {
    let r = &scenario.robots[i];
    let clearance_needed = r.radius;
    let places = std::iter::once(("start".to_string(), Vec2::new(r.start[0], r.start[1])))
        .chain(r.waypoints.iter().enumerate().map(|(k, w)| (format!("waypoints[{k}]"), v2(*w))))
        .chain(std::iter::once(("goal".to_string(), v2(r.goal))));
    for (name, p) in places {
        let clear = geometry.distance(p);
        if geometry.contains(p) || clear < clearance_needed {
            let what = if geometry.contains(p) {
                "inside a wall or object".to_string()
            } else {
                format!("only {clear:.2} m from a wall or object")
            };
            return Err(scenario_err(
                scenario,
                format!("robot[{i}].{name}"),
                format!(
                    "a position at least {clearance_needed:.2} m (the robot radius) from walls and furniture"
                ),
                format!("{:?} ({what})", [p.x, p.y]),
            ));
        }
    }
    Ok(())
}

/// The index in `grids` of the cost grid inflated by `inflate` (m), added if new.
fn grid_for(grids: &mut Vec<InflatedGrid>, field: &DistanceField, inflate: f64) -> usize {
    match grids.iter().position(|g| (g.radius - inflate).abs() < 1e-12) {
        Some(k) => k,
        None => {
            grids.push(InflatedGrid { radius: inflate, grid: CostGrid::inflated(field, inflate) });
            grids.len() - 1
        }
    }
}

/// Robot `i`'s state for every episode: its grid, the goal field of each target of its route,
/// the plain paths from its nominal start along the route, and its limits.
fn robot_static(
    scenario: &Scenario,
    i: usize,
    field: &DistanceField,
    grids: &mut Vec<InflatedGrid>,
    planner: &mut PathPlanner,
) -> Result<RobotStatic> {
    let r = &scenario.robots[i];
    let inflate = r.radius + r.inflation_margin;
    let grid_index = grid_for(grids, field, inflate);
    let grid = &grids[grid_index].grid;
    let goal = v2(r.goal);
    let start = Vec2::new(r.start[0], r.start[1]);
    let route: Vec<Vec2> = r.waypoints.iter().map(|w| v2(*w)).chain(std::iter::once(goal)).collect();
    let target_field = |k: usize| {
        if k + 1 == route.len() { format!("robot[{i}].goal") } else { format!("robot[{i}].waypoints[{k}]") }
    };
    let mut fields = Vec::with_capacity(route.len());
    let mut paths: Vec<Vec<Vec2>> = Vec::with_capacity(route.len());
    let mut geodesic_from_start = 0.0;
    for (k, &target) in route.iter().enumerate() {
        let cell = snap_to_passable(grid, target).ok_or_else(|| {
            scenario_err(
                scenario,
                target_field(k),
                format!("a place with {inflate:.2} m clearance (robot radius + inflation margin) nearby"),
                format!("{:?}", [target.x, target.y]),
            )
        })?;
        let from = if k == 0 { start } else { route[k - 1] };
        let f = GoalField::compute(grid, cell);
        geodesic_from_start += f.distance(from);
        fields.push(f);
        paths.push(plan_path(planner, grid, from, target).ok_or_else(|| CoreError::Planning {
            file: scenario.source.clone(),
            field: target_field(k),
            message: format!(
                "no collision-free path for a robot of radius {:.2} m from {:?} to {:?}",
                r.radius,
                [from.x, from.y],
                [target.x, target.y]
            ),
        })?);
    }
    check_tour(scenario, i, &paths)?;
    let nominal_path = paths.remove(0);
    let limits = Limits {
        max_speed: r.max_speed,
        max_angular_speed: r.max_angular_speed,
        max_accel: r.max_accel,
        max_angular_accel: r.max_angular_accel,
    };
    Ok(RobotStatic {
        planner: r.planner,
        eband: r.eband.params(),
        face: r.approach.as_ref().map(|a| v2(a.face)),
        limits,
        drive: r.drive,
        nh_set: super::planners::nh_orca(r.drive, r.planner).then(|| {
            crate::control::orca::nonholonomic::TrackableSet::new(
                r.max_speed,
                r.max_angular_speed,
                crate::control::orca_crowd::NH_PARAMS,
            )
        }),
        radius: r.radius,
        goal,
        grid_index,
        route,
        fields,
        dwell: r.dwell,
        geodesic_from_start,
        nominal_path,
        legs: paths,
    })
}

/// A tour must not lead robot `i` across its goal before the end (the episode would succeed
/// there): the `paths` to its waypoints stay clear of the goal.
fn check_tour(scenario: &Scenario, i: usize, paths: &[Vec<Vec2>]) -> Result<()> {
    let r = &scenario.robots[i];
    let goal = v2(r.goal);
    let success = scenario.episode.success_radius;
    if let Some(k) = paths[..paths.len() - 1]
        .iter()
        .position(|path| path.iter().any(|q| (q - goal).norm() <= success + 0.5))
    {
        return Err(scenario_err(
            scenario,
            format!("robot[{i}].waypoints[{k}]"),
            format!(
                "a tour whose paths to its waypoints stay more than {:.2} m (success radius + 0.5 m) from the goal",
                success + 0.5
            ),
            format!("the path to waypoints[{k}] passes the goal {:?}", r.goal),
        ));
    }
    Ok(())
}

/// People must start clear of the static geometry (seated people excepted: they sit on it),
/// wait at homes clear of it, and walk routes that do not cross it.
fn check_people(s: &Scenario, geometry: &StaticGeometry) -> Result<()> {
    for (i, p) in s.persons.iter().enumerate() {
        let (field, pos) = match (p.behaviour, p.home) {
            (Behaviour::Standing, _) => ("pose", Vec2::new(p.pose[0], p.pose[1])),
            (_, Some(h)) => ("home", v2(h)),
            _ => ("", Vec2::zeros()),
        };
        if !field.is_empty() && (geometry.contains(pos) || geometry.distance(pos) < p.radius) {
            return Err(scenario_err(
                s,
                format!("person[{i}].{field}"),
                format!(
                    "a position at least {:.2} m (the person's radius) from walls and furniture",
                    p.radius
                ),
                format!("[{}, {}]", pos.x, pos.y),
            ));
        }
        for (k, w) in p.route.iter().enumerate() {
            let a = v2(*w);
            if geometry.contains(a) || geometry.distance(a) < p.radius {
                return Err(scenario_err(
                    s,
                    format!("person[{i}].route[{k}]"),
                    format!(
                        "a waypoint at least {:.2} m (the person's radius) from walls and furniture",
                        p.radius
                    ),
                    format!("[{}, {}]", a.x, a.y),
                ));
            }
            let b = v2(p.route[(k + 1) % p.route.len()]);
            if geometry.segment_hits(a, b) {
                return Err(scenario_err(
                    s,
                    format!("person[{i}].route[{k}]"),
                    format!(
                        "a route leg to route[{}] that does not cross walls or furniture",
                        (k + 1) % p.route.len()
                    ),
                    format!("a leg from [{}, {}] to [{}, {}] through static geometry", a.x, a.y, b.x, b.y),
                ));
            }
        }
    }
    Ok(())
}
