//! Shared by the speed examples, the pedestrian criterion bench and the batch-step test (included
//! there by path): the crowd world they time, the robots' kinematics without MuJoCo, and the
//! thread-CPU clock and median they report with.
#![allow(dead_code)] // each includer uses its part

use proxemic_core::map::geometry::{Bounds, StaticGeometry};
use proxemic_core::math::Vec2;
use proxemic_core::scenario::{Behaviour, Person, Reaction};
use proxemic_core::world::World;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Square metres per person in the first museum (864 m^2, 29 people): the crowd's density.
pub const AREA_PER_PERSON: f64 = 864.0 / 29.0;

/// A square hall of `side` metres with 0.2 m walls and a 0.6 m pillar every 8 m.
pub fn hall(side: f64) -> Result<StaticGeometry, String> {
    let rect = |x0: f64, y0: f64, x1: f64, y1: f64| {
        vec![Vec2::new(x0, y0), Vec2::new(x1, y0), Vec2::new(x1, y1), Vec2::new(x0, y1)]
    };
    let mut polys = vec![
        rect(-0.2, -0.2, side + 0.2, 0.0),
        rect(-0.2, side, side + 0.2, side + 0.2),
        rect(-0.2, 0.0, 0.0, side),
        rect(side, 0.0, side + 0.2, side),
    ];
    let mut x = 8.0;
    while x < side - 4.0 {
        let mut y = 8.0;
        while y < side - 4.0 {
            polys.push(rect(x - 0.3, y - 0.3, x + 0.3, y + 0.3));
            y += 8.0;
        }
        x += 8.0;
    }
    StaticGeometry::new(polys, Bounds { min: Vec2::new(-1.0, -1.0), max: Vec2::new(side + 1.0, side + 1.0) })
        .map_err(|e| e.to_string())
}

/// `n` walkers, each on a route through three random points of the hall at 1.2 m/s, one in five
/// in a group of two.
pub fn walkers(n: usize, side: f64, rng: &mut ChaCha8Rng) -> Vec<Person> {
    let mut pt = || Vec2::new(rng.random_range(1.0..side - 1.0), rng.random_range(1.0..side - 1.0));
    (0..n)
        .map(|k| {
            let (a, b, c) = (pt(), pt(), pt());
            Person {
                name: format!("p{k}"),
                behaviour: Behaviour::Walker,
                pose: [a.x, a.y, 0.0],
                route: vec![[a.x, a.y], [b.x, b.y], [c.x, c.y]],
                speed: 1.2,
                dwell: 2.0,
                radius: 0.2,
                height: 1.7,
                group: if k % 10 < 2 { Some((k / 10) as u32) } else { None },
                reaction: Reaction::Aware,
                features: vec![],
                ..Person::default()
            }
        })
        .collect()
}

/// Nanoseconds this thread has spent on a CPU (Linux `schedstat`), if available.
pub fn thread_cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

/// The median (NaN for no values).
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.is_empty() {
        f64::NAN
    } else if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

/// Integrates each robot's command (robot frame, from `out`, the world's output rows) over one
/// control period of `dt` seconds into `state` (x, y, yaw, vx, vy, wz per robot): the robots
/// simulated kinematically, no MuJoCo, no contacts.
pub fn kinematics(world: &World, out: &[f64], state: &mut [f64], dt: f64) {
    let lay = world.layout();
    for i in 0..world.num_robots() {
        let row = &out[i * lay.stride..(i + 1) * lay.stride];
        let pose = &row[lay.pose.offset..lay.pose.offset + 3];
        let c = &row[lay.command.offset..lay.command.offset + 3];
        let (s, co) = pose[2].sin_cos();
        let (vx, vy) = (co * c[0] - s * c[1], s * c[0] + co * c[1]);
        state[6 * i..6 * i + 6].copy_from_slice(&[
            pose[0] + vx * dt,
            pose[1] + vy * dt,
            pose[2] + c[2] * dt,
            vx,
            vy,
            c[2],
        ]);
    }
}
