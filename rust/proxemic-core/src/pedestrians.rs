//! Scripted pedestrians.
//!
//! The crowd is kept as a structure of arrays. Each control step every person advances by `dt`:
//! - a **walker** walks its closed route at its preferred speed, pausing `dwell` seconds at each
//!   waypoint; its facing turns toward the direction of motion at a bounded rate, so the body
//!   orientation is always visible and never snaps;
//! - a **standing** person stays at its pose.
//!
//! People who are *aware* (the default) see the robots: a walker whose next position would bring
//! its body within [`YIELD_GAP`] of a robot's body waits in place for that step instead. People are
//! updated from a snapshot of the previous state (Jacobi order), so the result does not depend on
//! the order of the people, and every random draw (initial route phase, speed jitter) comes from
//! the episode's seeded generator.

use rand::Rng;

use crate::math::{Vec2, wrap_angle};
use crate::scenario::{Behaviour, Person, Randomize};

/// Surface gap (metres) below which an aware walker stops rather than step toward a robot.
pub const YIELD_GAP: f64 = 0.1;

/// Maximum rate at which a walker turns its body toward its walking direction (rad/s).
pub const TURN_RATE: f64 = 4.0;

/// The scripted crowd.
#[derive(Clone, Debug, Default)]
pub struct Crowd {
    /// Positions (metres).
    pub pos: Vec<Vec2>,
    /// Velocities over the last step (m/s).
    pub vel: Vec<Vec2>,
    /// Body orientation (radians).
    pub heading: Vec<f64>,
    /// Body radius (metres).
    pub radius: Vec<f64>,
    speed: Vec<f64>,
    target: Vec<usize>,
    dwell_left: Vec<f64>,
    routes: Vec<Vec<Vec2>>,
    dwell: Vec<f64>,
    walker: Vec<bool>,
    aware: Vec<bool>,
}

impl Crowd {
    /// Number of people.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// Whether there are no people.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Builds the crowd for a new episode, drawing the randomised parts from `rng`.
    pub fn spawn<R: Rng>(persons: &[Person], randomize: &Randomize, rng: &mut R) -> Self {
        let mut c = Crowd::default();
        for p in persons {
            let route: Vec<Vec2> = p.route.iter().map(|w| Vec2::new(w[0], w[1])).collect();
            let walker = p.behaviour == Behaviour::Walker;
            let jitter = randomize.speed_jitter;
            let speed = if walker && jitter > 0.0 {
                p.speed * rng.random_range(1.0 - jitter..=1.0 + jitter)
            } else {
                p.speed
            };
            let (pos, target, heading) = if walker {
                if randomize.person_phase {
                    let (pos, target) = point_at_fraction(&route, rng.random::<f64>());
                    let d = route[target] - pos;
                    (pos, target, d.y.atan2(d.x))
                } else {
                    (route[0], 1, p.pose[2])
                }
            } else {
                (Vec2::new(p.pose[0], p.pose[1]), 0, p.pose[2])
            };
            c.pos.push(pos);
            c.vel.push(Vec2::zeros());
            c.heading.push(heading);
            c.radius.push(p.radius);
            c.speed.push(speed);
            c.target.push(target);
            c.dwell_left.push(0.0);
            c.routes.push(route);
            c.dwell.push(p.dwell);
            c.walker.push(walker);
            c.aware.push(p.aware);
        }
        c
    }

    /// Advances every person by `dt` seconds. `robots` are the robots' (centre, radius) discs,
    /// which aware people yield to.
    pub fn step(&mut self, dt: f64, robots: &[(Vec2, f64)]) {
        for i in 0..self.len() {
            if !self.walker[i] {
                self.vel[i] = Vec2::zeros();
                continue;
            }
            let start = self.pos[i];
            let saved = (self.target[i], self.dwell_left[i]);
            let mut pos = start;
            let mut budget = dt;
            let mut moving_dir = None;
            // Walk (possibly past several close waypoints) until the step's time is used up.
            for _ in 0..8 {
                if budget <= 0.0 {
                    break;
                }
                if self.dwell_left[i] > 0.0 {
                    let used = self.dwell_left[i].min(budget);
                    self.dwell_left[i] -= used;
                    budget -= used;
                    continue;
                }
                let route = &self.routes[i];
                let goal = route[self.target[i]];
                let to_goal = goal - pos;
                let dist = to_goal.norm();
                let reach = self.speed[i] * budget;
                if dist <= reach {
                    pos = goal;
                    budget -= dist / self.speed[i];
                    self.target[i] = (self.target[i] + 1) % route.len();
                    self.dwell_left[i] = self.dwell[i];
                    if dist > 0.0 {
                        moving_dir = Some(to_goal / dist);
                    }
                } else {
                    pos += to_goal * (reach / dist);
                    moving_dir = Some(to_goal / dist);
                    budget = 0.0;
                }
            }
            if self.aware[i]
                && blocked_by_robot(pos, self.radius[i], robots)
                && !blocked_by_robot(start, self.radius[i], robots)
            {
                // Yield: stay put this step, as if the step had not been taken.
                self.vel[i] = Vec2::zeros();
                (self.target[i], self.dwell_left[i]) = saved;
                continue;
            }
            self.vel[i] = (pos - start) / dt;
            self.pos[i] = pos;
            let desired = match moving_dir {
                Some(d) => d.y.atan2(d.x),
                None => {
                    // Dwelling: face the direction of the next leg.
                    let d = self.routes[i][self.target[i]] - pos;
                    if d.norm() > 1e-9 { d.y.atan2(d.x) } else { self.heading[i] }
                }
            };
            let turn = wrap_angle(desired - self.heading[i]).clamp(-TURN_RATE * dt, TURN_RATE * dt);
            self.heading[i] = wrap_angle(self.heading[i] + turn);
        }
    }
}

fn blocked_by_robot(p: Vec2, r: f64, robots: &[(Vec2, f64)]) -> bool {
    robots.iter().any(|(c, rr)| (p - c).norm() - r - rr < YIELD_GAP)
}

/// The point at `frac` (in [0, 1)) of a closed route's length, and the index of the waypoint
/// that follows it.
fn point_at_fraction(route: &[Vec2], frac: f64) -> (Vec2, usize) {
    let n = route.len();
    let lens: Vec<f64> = (0..n).map(|k| (route[(k + 1) % n] - route[k]).norm()).collect();
    let total: f64 = lens.iter().sum();
    let mut s = frac.clamp(0.0, 1.0) * total;
    for k in 0..n {
        if s < lens[k] || k == n - 1 {
            let t = (s / lens[k].max(1e-12)).min(1.0);
            return (route[k] + (route[(k + 1) % n] - route[k]) * t, (k + 1) % n);
        }
        s -= lens[k];
    }
    (route[0], 1 % n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn walker(route: &[[f64; 2]], speed: f64, dwell: f64) -> Person {
        Person {
            name: "p".into(),
            behaviour: Behaviour::Walker,
            pose: [route[0][0], route[0][1], 0.0],
            route: route.to_vec(),
            speed,
            dwell,
            radius: 0.2,
            height: 1.7,
            group: None,
            aware: true,
        }
    }

    fn fixed() -> Randomize {
        Randomize { person_phase: false, speed_jitter: 0.0, robot_start_jitter: 0.0 }
    }

    #[test]
    fn walker_moves_at_its_speed_and_turns_corners() {
        let p = walker(&[[0.0, 0.0], [2.0, 0.0], [2.0, 2.0]], 1.0, 0.0);
        let mut rng = ChaCha8Rng::seed_from_u64(0);
        let mut c = Crowd::spawn(&[p], &fixed(), &mut rng);
        c.step(0.5, &[]);
        assert!((c.pos[0] - Vec2::new(0.5, 0.0)).norm() < 1e-12);
        assert!((c.vel[0] - Vec2::new(1.0, 0.0)).norm() < 1e-12);
        for _ in 0..4 {
            c.step(0.5, &[]);
        }
        // 2.5 m walked: 2 m along x, then 0.5 m up
        assert!((c.pos[0] - Vec2::new(2.0, 0.5)).norm() < 1e-12, "{:?}", c.pos[0]);
    }

    #[test]
    fn walker_dwells_at_waypoints() {
        let p = walker(&[[0.0, 0.0], [1.0, 0.0]], 1.0, 2.0);
        let mut rng = ChaCha8Rng::seed_from_u64(0);
        let mut c = Crowd::spawn(&[p], &fixed(), &mut rng);
        c.step(1.0, &[]); // arrives at (1, 0)
        c.step(1.0, &[]); // dwelling
        assert!((c.pos[0] - Vec2::new(1.0, 0.0)).norm() < 1e-12);
        assert_eq!(c.vel[0], Vec2::zeros());
        c.step(1.5, &[]); // 1 s more dwell, then 0.5 m back
        assert!((c.pos[0] - Vec2::new(0.5, 0.0)).norm() < 1e-12, "{:?}", c.pos[0]);
    }

    #[test]
    fn heading_turns_at_bounded_rate() {
        let p = walker(&[[0.0, 0.0], [1.0, 0.0], [1.0, 5.0]], 1.0, 0.0);
        let mut rng = ChaCha8Rng::seed_from_u64(0);
        let mut c = Crowd::spawn(&[p], &fixed(), &mut rng);
        c.step(1.0, &[]);
        let before = c.heading[0];
        c.step(0.1, &[]);
        assert!((wrap_angle(c.heading[0] - before)).abs() <= TURN_RATE * 0.1 + 1e-12);
    }

    #[test]
    fn aware_walker_yields_to_a_robot_and_oblivious_does_not() {
        let mut p = walker(&[[0.0, 0.0], [4.0, 0.0]], 1.0, 0.0);
        let robot = [(Vec2::new(1.0, 0.0), 0.24)];
        let mut rng = ChaCha8Rng::seed_from_u64(0);
        let mut c = Crowd::spawn(std::slice::from_ref(&p), &fixed(), &mut rng);
        for _ in 0..20 {
            c.step(0.1, &robot);
        }
        let gap = (c.pos[0] - robot[0].0).norm() - 0.2 - 0.24;
        assert!(gap >= YIELD_GAP - 1e-9, "gap {gap}");
        p.aware = false;
        let mut c = Crowd::spawn(&[p], &fixed(), &mut rng);
        for _ in 0..20 {
            c.step(0.1, &robot);
        }
        assert!(c.pos[0].x > 1.5);
    }

    #[test]
    fn random_phase_is_on_the_route_and_seeded() {
        let p = walker(&[[0.0, 0.0], [4.0, 0.0], [4.0, 3.0]], 1.0, 0.0);
        let r = Randomize::default();
        let a = Crowd::spawn(std::slice::from_ref(&p), &r, &mut ChaCha8Rng::seed_from_u64(7));
        let b = Crowd::spawn(std::slice::from_ref(&p), &r, &mut ChaCha8Rng::seed_from_u64(7));
        let c = Crowd::spawn(std::slice::from_ref(&p), &r, &mut ChaCha8Rng::seed_from_u64(8));
        assert_eq!(a.pos, b.pos);
        assert_ne!(a.pos, c.pos);
        // on one of the three segments
        let q = a.pos[0];
        let on = (q.y.abs() < 1e-9 && (0.0..=4.0).contains(&q.x))
            || ((q.x - 4.0).abs() < 1e-9 && (0.0..=3.0).contains(&q.y))
            || ((q.y - 0.75 * q.x).abs() < 1e-9);
        assert!(on, "{q:?}");
    }

    #[test]
    fn standing_person_stays() {
        let p = Person {
            name: "s".into(),
            behaviour: Behaviour::Standing,
            pose: [3.0, 2.0, 1.0],
            route: vec![],
            speed: 1.0,
            dwell: 0.0,
            radius: 0.2,
            height: 1.7,
            group: None,
            aware: true,
        };
        let mut c = Crowd::spawn(&[p], &Randomize::default(), &mut ChaCha8Rng::seed_from_u64(0));
        c.step(1.0, &[]);
        assert_eq!(c.pos[0], Vec2::new(3.0, 2.0));
        assert_eq!(c.heading[0], 1.0);
    }
}
