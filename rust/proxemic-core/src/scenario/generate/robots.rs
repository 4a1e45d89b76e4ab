//! Robot tasks sampled where they are free and reachable: starts and goals on the robot's
//! inflated grid, clear of walls, furniture, interaction spaces, people standing still or on their
//! way, and the other robots, with the goal reachable from the start (geodesic distance over the
//! same grid the world plans on, [`GoalField`]).

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::error::{CoreError, Result};
use crate::geom::contains_point_polygon;
use crate::map::CostGrid;
use crate::map::grid::{DistanceField, GridSpec, OccupancyGrid};
use crate::math::Vec2;
use crate::plan::geodesic::GoalField;
use crate::scenario::model::{Behaviour, Scenario};
use crate::world::START_CLEARANCE;

/// Extra room (m) kept round a sampled start or goal beyond the robot's inflated radius, so the
/// robot does not begin or end pressed against a wall.
const WALL_ROOM: f64 = 0.3;
/// Shortest geodesic distance (m) from a sampled start to its goal, unless the scene has no such
/// pair (then half the longest reachable distance from that start).
const MIN_TRIP: f64 = 8.0;
/// Draws of a start before giving up.
const TRIES: usize = 64;

/// A sampled robot task: start pose `[x, y, theta]` (facing the goal) and goal `[x, y]`.
pub type Task = ([f64; 3], [f64; 2]);

/// Samples `n` robot tasks in scenario `s` for robots shaped like its robot 0 (radius, inflation
/// margin), respecting its first `keep` robots' starts and goals and the start jitter of its
/// episode. Deterministic in `seed`. Errors name `robots` when the scene has no room left.
pub fn sample_tasks(s: &Scenario, keep: usize, n: usize, seed: u64) -> Result<Vec<Task>> {
    let template = s.robots.first().ok_or_else(|| no_room(s, n, "a scenario with a robot to copy"))?;
    let geometry = s.static_geometry()?;
    let spec = GridSpec::covering(geometry.bounds(), s.scene.resolution)?;
    let field = DistanceField::from_occupancy(&OccupancyGrid::rasterize(&geometry, spec));
    let inflate = template.radius + template.inflation_margin;
    let grid = CostGrid::inflated(&field, inflate);
    let jitter = s.episode.randomize.robot_start_jitter * std::f64::consts::SQRT_2;
    let r = template.radius;

    // people's places: standing, seated, conversations (home and circle), walkers' stops
    let mut people: Vec<(Vec2, f64)> = Vec::new();
    for p in &s.persons {
        let pose = Vec2::new(p.pose[0], p.pose[1]);
        match p.behaviour {
            Behaviour::Standing | Behaviour::Seated => people.push((pose, p.radius)),
            _ => {}
        }
        if let Some(h) = p.home {
            people.push((Vec2::new(h[0], h[1]), p.radius));
        }
        if let Some(c) = p.spot {
            people.push((Vec2::new(c[0], c[1]), 1.2 + p.radius));
        }
        people.extend(p.route.iter().map(|w| (Vec2::new(w[0], w[1]), p.radius)));
    }
    let spaces: Vec<Vec<Vec2>> = s
        .objects
        .iter()
        .filter_map(|o| o.interaction.as_ref())
        .map(|i| i.polygon.iter().map(|q| Vec2::new(q[0], q[1])).collect())
        .collect();
    let mut robots: Vec<Vec2> = Vec::new();
    for q in &s.robots[..keep.min(s.robots.len())] {
        robots.push(Vec2::new(q.start[0], q.start[1]));
        robots.push(Vec2::new(q.goal[0], q.goal[1]));
    }
    let free = |c: Vec2, robots: &[Vec2]| -> bool {
        field.at(c) >= inflate + WALL_ROOM
            && !spaces.iter().any(|poly| contains_point_polygon(c, poly))
            && people.iter().all(|&(q, pr)| (q - c).norm() >= pr + r + jitter + START_CLEARANCE + 0.3)
            && robots.iter().all(|&q| (q - c).norm() >= 2.0 * r + 2.0 * jitter + 0.5)
    };
    // candidate cells, every third one in each direction
    let cells: Vec<Vec2> = (0..spec.height)
        .step_by(3)
        .flat_map(|iy| (0..spec.width).step_by(3).map(move |ix| (ix, iy)))
        .filter(|&(ix, iy)| grid.passable(ix, iy))
        .map(|(ix, iy)| spec.center(ix, iy))
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Vec::with_capacity(n);
    'robot: for _ in 0..n {
        let starts: Vec<Vec2> = cells.iter().copied().filter(|&c| free(c, &robots)).collect();
        if starts.is_empty() {
            return Err(no_room(s, n, "a free place for every robot's start"));
        }
        for _ in 0..TRIES {
            let start = starts[rng.random_range(0..starts.len())];
            let Some(cell) = spec.cell_of(start) else { continue };
            let from_start = GoalField::compute(&grid, cell);
            let mut with_start = robots.clone();
            with_start.push(start);
            let goals: Vec<(Vec2, f64)> = starts
                .iter()
                .copied()
                .filter(|&g| free(g, &with_start))
                .map(|g| (g, from_start.cell_distance(g)))
                .filter(|&(_, d)| d.is_finite())
                .collect();
            let longest = goals.iter().map(|g| g.1).fold(0.0, f64::max);
            let trip = MIN_TRIP.min(0.5 * longest);
            let far: Vec<Vec2> = goals.iter().filter(|g| g.1 >= trip && g.1 > 1.0).map(|g| g.0).collect();
            if far.is_empty() {
                continue;
            }
            let goal = far[rng.random_range(0..far.len())];
            let theta = (goal.y - start.y).atan2(goal.x - start.x);
            let round = |v: f64| (v * 100.0).round() / 100.0;
            out.push(([round(start.x), round(start.y), round(theta)], [round(goal.x), round(goal.y)]));
            robots.push(start);
            robots.push(goal);
            continue 'robot;
        }
        return Err(no_room(s, n, "a start with a reachable goal for every robot"));
    }
    Ok(out)
}

use rand::SeedableRng;

fn no_room(s: &Scenario, n: usize, what: &str) -> CoreError {
    CoreError::Scenario {
        file: s.source.clone(),
        field: "robots".to_string(),
        expected: format!("room for {n} more robots ({what})"),
        found: format!("{n}"),
    }
}
