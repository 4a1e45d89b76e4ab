//! Read access to the world (the scenario, geometry, paths, people and metrics) and the few
//! settings and queries the bindings and tests use between steps.

use super::{Layout, World};
use crate::error::{CoreError, Result};
use crate::map::CostGrid;
use crate::map::geometry::StaticGeometry;
use crate::math::Vec2;
use crate::metrics::{EpisodeReport, MetricParams};
use crate::pedestrians::Crowd;
use crate::scenario::Scenario;

use super::planners::plan_path;

impl World {
    /// The validated scenario.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// The static geometry.
    pub fn geometry(&self) -> &StaticGeometry {
        &self.geometry
    }

    /// Layout of the per-robot output rows.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// Number of robots.
    pub fn num_robots(&self) -> usize {
        self.statics.len()
    }

    /// Number of people.
    pub fn num_people(&self) -> usize {
        self.scenario.persons.len()
    }

    /// Control steps since the last reset.
    pub fn steps(&self) -> usize {
        self.steps
    }

    /// Simulation time since the last reset (s).
    pub fn time(&self) -> f64 {
        self.steps as f64 * self.scenario.control_dt()
    }

    /// Time of day (seconds after midnight) at the current step.
    pub fn time_of_day(&self) -> f64 {
        (self.scenario.scene.start_time + self.time()).rem_euclid(86400.0)
    }

    /// The inflated cost grid robot `i` plans on.
    pub fn cost_grid(&self, i: usize) -> Option<&CostGrid> {
        self.statics.get(i).map(|s| &self.grids[s.grid_index].grid)
    }

    /// The global path robot `i` is following (world-frame waypoints).
    pub fn path(&self, i: usize) -> Option<&[Vec2]> {
        self.robots.get(i).map(|r| r.follower.path())
    }

    /// Geodesic (shortest collision-free) distance from robot `i`'s nominal start to its goal (m).
    pub fn geodesic_start_distance(&self, i: usize) -> Option<f64> {
        self.statics.get(i).map(|s| s.geodesic_from_start)
    }

    /// Plans a plain A* path for robot `i`'s footprint between two points.
    pub fn plan(&mut self, i: usize, start: Vec2, goal: Vec2) -> Option<Vec<Vec2>> {
        let grid = &self.grids[self.statics.get(i)?.grid_index].grid;
        plan_path(&mut self.planner, grid, start, goal)
    }

    /// Chooses which robots' built-in planners run (one flag per robot; all run by default).
    /// A robot whose planner is off is driven only by [`World::command`]: it computes no path
    /// updates, local planner or re-plans (saving their cost when a policy drives it), its
    /// `planner_action` is a stop command and its `mode` follow_path. It stays an obstacle, and
    /// the other robots' planners still see it. Kept across resets.
    pub fn set_planning(&mut self, planning: &[bool]) -> Result<()> {
        if planning.len() != self.num_robots() {
            return Err(CoreError::input(
                "planning",
                format!("{} flags (one per robot)", self.num_robots()),
                format!("{} flags", planning.len()),
            ));
        }
        self.planning = planning.to_vec();
        Ok(())
    }

    /// Every metric of every robot's episode so far (`docs/metrics.md`; the zones are the
    /// scenario's Hall zones, the thresholds [`MetricParams::default`]), with the progress
    /// monitor's record ([`crate::metrics::RecoveryMetrics`]).
    ///
    /// # Errors
    /// [`CoreError::Input`] before the first reset, or if a recorded value is not finite.
    pub fn episode_metrics(&self) -> Result<Vec<EpisodeReport>> {
        let all: Vec<usize> = (0..self.robots.len()).collect();
        self.robot_metrics(&all)
    }

    /// [`World::episode_metrics`] of the robots `robots` only (indices, in the order given).
    ///
    /// # Errors
    /// As [`World::episode_metrics`], and [`CoreError::Input`] for an index out of range.
    pub fn robot_metrics(&self, robots: &[usize]) -> Result<Vec<EpisodeReport>> {
        if !self.started {
            return Err(CoreError::input(
                "episode_metrics",
                "a call after reset()",
                "a call before the first reset()",
            ));
        }
        if let Some(&bad) = robots.iter().find(|&&i| i >= self.robots.len()) {
            return Err(CoreError::input(
                "robots",
                format!("robot indices below {}", self.robots.len()),
                bad.to_string(),
            ));
        }
        let z = self.social.config().zones;
        let clearance = |p: Vec2| self.geometry.distance(p);
        let mut robot_free = self.robot_free.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        robot_free.advance(&self.geometry, &self.field);
        let free = robot_free.tracks();
        robots
            .iter()
            .map(|&i| {
                let rb = &self.robots[i];
                let mut report = rb.recorder.evaluate(
                    &self.log,
                    &clearance,
                    [z.intimate, z.personal, z.social],
                    MetricParams::default(),
                    Some(free),
                )?;
                report.recovery.recoveries = rb.progress.recoveries();
                report.recovery.monitor_stalled_time = rb.progress.stalled_time();
                Ok(report)
            })
            .collect()
    }

    /// Wall-clock time spent this episode stepping the people, and stepping them again without
    /// the robots for the robot's cost to people (so far: the robot-free run is stepped when the
    /// metrics are asked for).
    pub fn people_step_times(&self) -> (std::time::Duration, std::time::Duration) {
        let free = self.robot_free.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        (self.crowd_time, free.elapsed())
    }

    /// The recorded poses `[x, y, theta]` of robot `i` since the reset, instant 0 first.
    pub fn trajectory(&self, i: usize) -> Option<&[[f64; 3]]> {
        self.robots.get(i).map(|r| r.recorder.poses())
    }

    /// The plain A* path from robot `i`'s episode start to its goal (Daza et al. 2021's D_A*).
    pub fn astar_path(&self, i: usize) -> Option<&[Vec2]> {
        self.robots.get(i).map(|r| r.recorder.astar_path())
    }

    /// The people: positions, velocities, headings and radii.
    pub fn crowd(&self) -> &Crowd {
        &self.crowd
    }
}
