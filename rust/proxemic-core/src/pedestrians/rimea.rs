//! Known-answer tests of the RiMEA guideline (Richtlinie fuer Mikroskopische
//! Entfluchtungsanalysen, version 3.0, 2016) run on the core's [`Crowd`]: test 1 (one person
//! crosses a corridor), test 4 (speed against density, compared with Weidmann's fundamental
//! diagram) and test 6 (twenty people round a corner without passing through a wall). The
//! geometries are the guideline's; where it leaves a choice (start layout, speed spread, the
//! periodic corridor's shape) the choice is documented on each function and in
//! `docs/people-validation.md`.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::scripts::Script;
use super::{Crowd, SocialForceParams};
use crate::error::{CoreError, Result};
use crate::map::geometry::{Bounds, StaticGeometry};
use crate::map::grid::{DistanceField, GridSpec, OccupancyGrid};
use crate::math::Vec2;
use crate::scenario::{Person, Randomize};

/// Free walking speed of Weidmann's fundamental diagram (m/s; Weidmann 1993).
pub const WEIDMANN_FREE_SPEED: f64 = 1.34;
/// Shape constant gamma of Weidmann's fundamental diagram (1/m^2).
pub const WEIDMANN_GAMMA: f64 = 1.913;
/// Jam density of Weidmann's fundamental diagram (people per m^2).
pub const WEIDMANN_JAM_DENSITY: f64 = 5.4;

/// Weidmann's walking speed (m/s) at `density` (people per m^2):
/// `v0 (1 - exp(-gamma (1/rho - 1/rho_max)))`, 0 at and above the jam density.
pub fn weidmann_speed(density: f64) -> f64 {
    if density >= WEIDMANN_JAM_DENSITY {
        return 0.0;
    }
    if density <= 0.0 {
        return WEIDMANN_FREE_SPEED;
    }
    WEIDMANN_FREE_SPEED * (1.0 - (-WEIDMANN_GAMMA * (1.0 / density - 1.0 / WEIDMANN_JAM_DENSITY)).exp())
}

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Vec2> {
    vec![Vec2::new(x0, y0), Vec2::new(x1, y0), Vec2::new(x1, y1), Vec2::new(x0, y1)]
}

struct Room {
    geometry: StaticGeometry,
    field: DistanceField,
}

impl Room {
    fn new(polygons: Vec<Vec<Vec2>>, bounds: Bounds) -> Result<Self> {
        let geometry = StaticGeometry::new(polygons, bounds)?;
        let spec = GridSpec::covering(bounds, 0.05)?;
        let field = DistanceField::from_occupancy(&OccupancyGrid::rasterize(&geometry, spec));
        Ok(Room { geometry, field })
    }

    fn step(&self, c: &mut Crowd, h: f64) {
        c.step(h, &[], &self.geometry, &self.field);
    }
}

fn walkers(people: &[(Vec<Vec2>, f64)], radius: f64, params: SocialForceParams) -> Crowd {
    let persons: Vec<Person> = people
        .iter()
        .map(|(route, speed)| {
            let mut stops = vec![false; route.len()];
            if let Some(s) = stops.last_mut() {
                *s = true;
            }
            Person {
                pose: [route[0].x, route[0].y, 0.0],
                route: route.iter().map(|p| [p.x, p.y]).collect(),
                speed: *speed,
                // At its last waypoint the person stays.
                dwell: f64::INFINITY,
                stops,
                radius,
                ..Person::default()
            }
        })
        .collect();
    let scripts = vec![Script::Walker; persons.len()];
    let fixed = Randomize { person_phase: false, speed_jitter: 0.0, robot_start_jitter: 0.0 };
    let mut rng = ChaCha8Rng::seed_from_u64(0);
    Crowd::spawn_scripted(&persons, &scripts, &fixed, params, &[], &mut rng)
}

fn check_radius(radius: f64) -> Result<()> {
    if radius > 0.0 && radius <= 0.5 {
        Ok(())
    } else {
        Err(CoreError::input("radius", "a body radius in (0, 0.5] metres", format!("{radius}")))
    }
}

/// RiMEA test 1: one person (body `radius`, metres) walks a corridor 40 m long and 2 m wide at a
/// desired 1.33 m/s, starting at rest at its entrance (x = 0, on the centre line). Returns the
/// time (s) at which its centre crosses the far end (x = 40 m); the guideline expects 26 to 34 s.
/// Errors if it has not crossed within 120 s.
pub fn rimea1(params: SocialForceParams, radius: f64) -> Result<f64> {
    check_radius(radius)?;
    let room = Room::new(
        vec![rect(-1.0, -0.2, 42.0, 0.0), rect(-1.0, 2.0, 42.0, 2.2), rect(-1.2, -0.2, -1.0, 2.2)],
        Bounds { min: Vec2::new(-2.0, -1.0), max: Vec2::new(43.0, 3.0) },
    )?;
    let mut c = walkers(&[(vec![Vec2::new(0.0, 1.0), Vec2::new(41.5, 1.0)], 1.33)], radius, params);
    let h = params.dt;
    let mut t = 0.0;
    while t < 120.0 {
        let before = c.pos[0].x;
        room.step(&mut c, h);
        t += h;
        let after = c.pos[0].x;
        if after >= 40.0 {
            // The crossing within the step, by linear interpolation.
            return Ok(t - h * (after - 40.0) / (after - before).max(1e-12));
        }
    }
    Err(CoreError::input(
        "rimea1",
        "the person to cross the corridor within 120 s",
        format!("x = {:.2} m", c.pos[0].x),
    ))
}

/// What RiMEA test 6 found ([`rimea6`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Corner {
    /// People who left through the exit of the second leg within the time allowed.
    pub arrived: usize,
    /// Substeps in which some person's centre was inside a wall or its step crossed one
    /// (the guideline: none).
    pub wall_crossings: usize,
    /// When the last person left (s), if all did.
    pub time: Option<f64>,
    /// Every person's path, one point per substep (metres), for the card's plot.
    pub paths: Vec<Vec<Vec2>>,
}

/// RiMEA test 6: twenty people (body `radius`) start in the first 6 m of a corridor 2 m wide
/// that runs 12 m and turns left into a second leg of 12 m (walls 0.2 m thick), and walk round the
/// corner to its exit. The guideline fixes the geometry and the count; the start layout (a
/// 5 x 4 grid, 1.1 m by 0.45 m), the desired speeds (uniform in 0.89 to 1.79 m/s, Weidmann's
/// mean 1.34 and standard deviation 0.26, drawn from `seed`) and the route (the corner's
/// centre, then the exit) are this project's choices. Simulates at most `duration` seconds.
pub fn rimea6(params: SocialForceParams, radius: f64, seed: u64, duration: f64) -> Result<Corner> {
    check_radius(radius)?;
    // First leg x in [0, 12], y in [0, 2]; second leg x in [10, 12], y in [0, 12] (exit at y = 12).
    let polygons = vec![
        rect(-0.2, -0.2, 12.2, 0.0),
        rect(12.0, 0.0, 12.2, 12.0),
        rect(-0.2, 0.0, 0.0, 2.0),
        rect(-0.2, 2.0, 10.0, 12.0),
    ];
    let room = Room::new(polygons, Bounds { min: Vec2::new(-1.0, -1.0), max: Vec2::new(13.0, 14.0) })?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut people = Vec::new();
    for ix in 0..5 {
        for iy in 0..4 {
            let start = Vec2::new(0.5 + 1.1 * ix as f64, 0.3 + 0.4667 * iy as f64);
            let speed = rng.random_range(0.89..=1.79);
            people.push((vec![start, Vec2::new(11.0, 1.0), Vec2::new(11.0, 13.5)], speed));
        }
    }
    let mut c = walkers(&people, radius, params);
    let h = params.dt;
    let (mut t, mut wall_crossings, mut time) = (0.0, 0, None);
    let mut paths: Vec<Vec<Vec2>> = c.pos.iter().map(|p| vec![*p]).collect();
    while t < duration {
        let before = c.pos.clone();
        room.step(&mut c, h);
        t += h;
        let crossed = before
            .iter()
            .zip(&c.pos)
            .any(|(a, b)| room.geometry.contains(*b) || room.geometry.segment_hits(*a, *b));
        wall_crossings += usize::from(crossed);
        for (path, p) in paths.iter_mut().zip(&c.pos) {
            path.push(*p);
        }
        if c.pos.iter().all(|p| p.y > 12.0) {
            time = Some(t);
            break;
        }
    }
    let arrived = c.pos.iter().filter(|p| p.y > 12.0).count();
    Ok(Corner { arrived, wall_crossings, time, paths })
}

/// RiMEA test 4 (speed against density) in a periodic corridor 2 m wide: a ring between radii
/// 7 and 9 m (area 100.5 m^2; a ring is periodic without a seam, where a straight corridor whose
/// people jump from its end to its start would hide each side's people from the other). For
/// each of `densities` (people per m^2, at most 6) the ring is filled in lanes 1/sqrt(density)
/// apart, everyone walking counterclockwise at a desired speed uniform in 0.89 to 1.79 m/s
/// (Weidmann's mean and spread, from `seed`), heading 2 m ahead along its own circle. After
/// `warmup` seconds the mean speed along the ring is averaged over everyone for `measure`
/// seconds. Returns that speed (m/s) per density, to be read against [`weidmann_speed`].
pub fn rimea4(
    params: SocialForceParams,
    radius: f64,
    densities: &[f64],
    seed: u64,
    warmup: f64,
    measure: f64,
) -> Result<Vec<f64>> {
    check_radius(radius)?;
    const R_IN: f64 = 7.0;
    const R_OUT: f64 = 9.0;
    const SIDES: usize = 90;
    let polar = |r: f64, a: f64| Vec2::new(r * a.cos(), r * a.sin());
    let step = std::f64::consts::TAU / SIDES as f64;
    // The inner wall: a disc; the outer wall: quadrilaterals round the ring (chords outside
    // the circle of radius R_OUT).
    let mut polygons = vec![(0..SIDES).map(|k| polar(R_IN, k as f64 * step)).collect::<Vec<_>>()];
    let r_chord = R_OUT / (step / 2.0).cos();
    for k in 0..SIDES {
        let (a, b) = (k as f64 * step, (k + 1) as f64 * step);
        polygons.push(vec![
            polar(r_chord, a),
            polar(r_chord + 0.3, a),
            polar(r_chord + 0.3, b),
            polar(r_chord, b),
        ]);
    }
    let room = Room::new(polygons, Bounds { min: Vec2::new(-10.0, -10.0), max: Vec2::new(10.0, 10.0) })?;
    let area = std::f64::consts::PI * (R_OUT * R_OUT - R_IN * R_IN);
    let mut out = Vec::with_capacity(densities.len());
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for (k, &rho) in densities.iter().enumerate() {
        if !(rho > 0.0 && rho <= 6.0) {
            return Err(CoreError::input(
                format!("densities[{k}]"),
                "a density in (0, 6] people per m^2",
                format!("{rho}"),
            ));
        }
        let n = (rho * area).round() as usize;
        let spacing = 1.0 / rho.sqrt();
        let lanes = ((1.6 / spacing).floor() as usize + 1).min(n.max(1));
        let mut people = Vec::with_capacity(n);
        for i in 0..n {
            let lane = i % lanes;
            let r = if lanes == 1 { 8.0 } else { R_IN + 0.2 + 1.6 * lane as f64 / (lanes - 1) as f64 };
            let per_lane = n.div_ceil(lanes);
            let a = (i / lanes) as f64 * std::f64::consts::TAU / per_lane as f64
                + 0.5 * lane as f64 / per_lane as f64;
            let p = polar(r, a);
            people.push((vec![p, p], rng.random_range(0.89..=1.79)));
        }
        let mut c = walkers(&people, radius, params);
        for i in 0..c.len() {
            // Never dwelling: the heading point is moved ahead every substep.
            c.stops[i] = vec![false, false];
        }
        let h = params.dt;
        let (mut t, mut sum, mut count) = (0.0, 0.0, 0usize);
        while t < warmup + measure - 1e-9 {
            for i in 0..c.len() {
                let p = c.pos[i];
                let r = p.norm().max(1e-6);
                let a = p.y.atan2(p.x) + 2.0 / r;
                c.routes[i][1] = polar(r, a);
                c.target[i] = 1;
            }
            room.step(&mut c, h);
            t += h;
            if t > warmup {
                for i in 0..c.len() {
                    let p = c.pos[i];
                    let tangent = Vec2::new(-p.y, p.x) / p.norm().max(1e-6);
                    sum += c.vel[i].dot(&tangent);
                    count += 1;
                }
            }
        }
        out.push(if count > 0 { sum / count as f64 } else { 0.0 });
    }
    Ok(out)
}
