//! Planning and sensing benchmarks on a synthetic 36 x 24 m museum at 0.1 m (360 x 240 cells), and
//! social A* across a crowded 100 x 60 m hall (1000 x 600 cells, the size of `crowd_bench.py`).
//!
//! Run with `cargo bench --bench planning` (add `-- --quick` for a short run).

#![allow(missing_docs)]

use criterion::{Criterion, criterion_group, criterion_main};
use proxemic_core::map::{Bounds, DistanceField, GridSpec, OccupancyGrid, StaticGeometry, scan};
use proxemic_core::map::{CostGrid, INSCRIBED};
use proxemic_core::math::Vec2;
use proxemic_core::plan::{PathPlanner, SearchMode, nearest_passable, smooth_path};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::time::Duration;

const RES: f64 = 0.1;
const ROBOT_RADIUS: f64 = 0.3;

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Vec2> {
    vec![Vec2::new(x0, y0), Vec2::new(x1, y0), Vec2::new(x1, y1), Vec2::new(x0, y1)]
}

fn disc_polygon(c: Vec2, r: f64, n: usize) -> Vec<Vec2> {
    (0..n)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / n as f64;
            c + Vec2::new(a.cos(), a.sin()) * r
        })
        .collect()
}

/// Outer walls, two interior walls with doorways splitting the hall into rooms, 15 display cases
/// and 4 round tables (24-gons): 44 polygons.
fn museum() -> StaticGeometry {
    let (w, h, t) = (36.0, 24.0, 0.2);
    let mut p =
        vec![rect(0.0, 0.0, w, t), rect(0.0, h - t, w, h), rect(0.0, 0.0, t, h), rect(w - t, 0.0, w, h)];
    // Vertical walls at x = 12 and x = 24, each with two 1.2 m doorways.
    for x in [12.0, 24.0] {
        p.push(rect(x, t, x + t, 5.0));
        p.push(rect(x, 6.2, x + t, 16.0));
        p.push(rect(x, 17.2, x + t, h - t));
    }
    // A horizontal wall in the middle room with one doorway.
    p.push(rect(12.0 + t, 12.0, 17.0, 12.0 + t));
    p.push(rect(18.4, 12.0, 24.0, 12.0 + t));
    // Display cases.
    let cases = [
        (2.0, 2.0),
        (6.0, 2.5),
        (2.5, 8.0),
        (7.0, 9.0),
        (3.0, 15.0),
        (8.0, 19.0),
        (14.0, 3.0),
        (19.0, 7.0),
        (15.0, 15.0),
        (20.0, 19.0),
        (27.0, 3.0),
        (31.0, 6.0),
        (26.0, 11.0),
        (30.0, 15.0),
        (27.5, 20.0),
    ];
    for (i, &(x, y)) in cases.iter().enumerate() {
        let (dx, dy) = if i % 2 == 0 { (2.0, 0.8) } else { (0.8, 1.6) };
        p.push(rect(x, y, x + dx, y + dy));
    }
    for c in [(5.0, 12.0), (10.0, 14.0), (33.0, 10.0), (21.0, 10.0)] {
        p.push(disc_polygon(Vec2::new(c.0, c.1), 0.6, 24));
    }
    let bounds = Bounds { min: Vec2::new(0.0, 0.0), max: Vec2::new(w, h) };
    StaticGeometry::new(p, bounds).expect("valid museum")
}

fn cost_grid(geom: &StaticGeometry) -> CostGrid {
    let spec = GridSpec::covering(geom.bounds(), RES).expect("valid grid");
    let occ = OccupancyGrid::rasterize(geom, spec);
    let df = DistanceField::from_occupancy(&occ);
    CostGrid::inflated(&df, ROBOT_RADIUS)
}

/// A 100 x 60 m hall: its four walls and nothing else.
fn hall() -> StaticGeometry {
    let (w, h, t) = (100.0, 60.0, 0.2);
    let p = vec![rect(0.0, 0.0, w, t), rect(0.0, h - t, w, h), rect(0.0, 0.0, t, h), rect(w - t, 0.0, w, h)];
    let bounds = Bounds { min: Vec2::new(0.0, 0.0), max: Vec2::new(w, h) };
    StaticGeometry::new(p, bounds).expect("valid hall")
}

/// Adds `count` Gaussian personal-space blobs (peak 252, `sigma` metres, cut at 3 sigma) centred
/// at random places at least 1 m inside the grid.
fn with_social_blobs(base: &CostGrid, rng: &mut ChaCha8Rng, count: usize, sigma: f64) -> CostGrid {
    let mut g = base.clone();
    let spec = g.spec;
    let (w, h) = (spec.width as f64 * spec.resolution, spec.height as f64 * spec.resolution);
    for _ in 0..count {
        let c = spec.origin + Vec2::new(rng.random_range(1.0..w - 1.0), rng.random_range(1.0..h - 1.0));
        let reach = 3.0 * sigma;
        let lo = spec.cell_of(c - Vec2::new(reach, reach)).unwrap_or((0, 0));
        let hi = spec.cell_of(c + Vec2::new(reach, reach)).unwrap_or((spec.width - 1, spec.height - 1));
        for iy in lo.1..=hi.1 {
            for ix in lo.0..=hi.0 {
                let i = spec.index(ix, iy);
                if g.cost[i] >= INSCRIBED {
                    continue;
                }
                let d2 = (spec.center(ix, iy) - c).norm_squared();
                let v = (252.0 * (-d2 / (2.0 * sigma * sigma)).exp()).floor() as u8;
                g.cost[i] = g.cost[i].max(v);
            }
        }
    }
    g
}

/// Uniform random cost 0..=252 on every passable cell (a stress case for the heuristic).
fn with_noise(base: &CostGrid, rng: &mut ChaCha8Rng) -> CostGrid {
    let mut g = base.clone();
    for c in g.cost.iter_mut().filter(|c| **c < INSCRIBED) {
        *c = rng.random_range(0..=252);
    }
    g
}

fn benches(c: &mut Criterion) {
    let geom = museum();
    let grid = cost_grid(&geom);
    let spec = grid.spec;
    let start =
        nearest_passable(&grid, spec.cell_of(Vec2::new(0.8, 0.8)).expect("in grid"), 20).expect("start");
    let goal =
        nearest_passable(&grid, spec.cell_of(Vec2::new(35.2, 23.2)).expect("in grid"), 20).expect("goal");
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let social = with_social_blobs(&grid, &mut rng, 25, 0.8);
    let noise = with_noise(&grid, &mut rng);
    let mut planner = PathPlanner::new();

    // One-off report of path costs and expansions.
    for (name, g, mode) in [
        ("plain A*", &grid, SearchMode::PLAIN),
        ("weighted A* (blobs)", &social, SearchMode::weighted(2.0)),
        ("Dijkstra (blobs)", &social, SearchMode::dijkstra(2.0)),
        ("weighted A* (noise)", &noise, SearchMode::weighted(2.0)),
        ("Dijkstra (noise)", &noise, SearchMode::dijkstra(2.0)),
    ] {
        let p = planner.plan(g, start, goal, mode).expect("museum is connected");
        let s = smooth_path(g, &p, mode.weight);
        eprintln!(
            "{name}: cost {:.3} m, {} cells, {} expansions, {} smoothed waypoints",
            p.cost,
            p.cells.len(),
            p.expansions,
            s.len()
        );
    }

    c.bench_function("map/rasterize+edt+inflate", |b| b.iter(|| black_box(cost_grid(black_box(&geom)))));
    c.bench_function("plan/astar_plain", |b| {
        b.iter(|| black_box(planner.plan(&grid, start, goal, SearchMode::PLAIN)))
    });
    c.bench_function("plan/astar_w2_blobs", |b| {
        b.iter(|| black_box(planner.plan(&social, start, goal, SearchMode::weighted(2.0))))
    });
    c.bench_function("plan/dijkstra_w2_blobs", |b| {
        b.iter(|| black_box(planner.plan(&social, start, goal, SearchMode::dijkstra(2.0))))
    });
    c.bench_function("plan/astar_w2_noise", |b| {
        b.iter(|| black_box(planner.plan(&noise, start, goal, SearchMode::weighted(2.0))))
    });
    // Across the hall through 1000 people's blobs: the social planner's re-plan in the crowd bench.
    let hall_grid = with_social_blobs(&cost_grid(&hall()), &mut ChaCha8Rng::seed_from_u64(1), 1000, 1.0);
    let (hall_start, hall_goal) = (
        nearest_passable(&hall_grid, (20, 300), 20).expect("start"),
        nearest_passable(&hall_grid, (980, 300), 20).expect("goal"),
    );
    let p = planner.plan(&hall_grid, hall_start, hall_goal, SearchMode::weighted(2.0)).expect("connected");
    eprintln!("weighted A* (hall): cost {:.3} m, {} expansions", p.cost, p.expansions);
    c.bench_function("plan/astar_w2_hall", |b| {
        b.iter(|| black_box(planner.plan(&hall_grid, hall_start, hall_goal, SearchMode::weighted(2.0))))
    });
    let plain_path = planner.plan(&grid, start, goal, SearchMode::PLAIN).expect("connected");
    let social_path = planner.plan(&social, start, goal, SearchMode::weighted(2.0)).expect("connected");
    c.bench_function("plan/smooth_plain", |b| b.iter(|| black_box(smooth_path(&grid, &plain_path, 0.0))));
    c.bench_function("plan/smooth_w2_blobs", |b| {
        b.iter(|| black_box(smooth_path(&social, &social_path, 2.0)))
    });

    let discs: Vec<(Vec2, f64)> = (0..20)
        .map(|_| (Vec2::new(rng.random_range(1.0..35.0), rng.random_range(1.0..23.0)), 0.25))
        .collect();
    let origin = Vec2::new(18.0, 9.0);
    let mut out = vec![0.0; 72];
    c.bench_function("lidar/scan_72_rays_20_discs", |b| {
        b.iter(|| {
            scan(&geom, &discs, black_box(origin), 0.3, 10.0, &mut out).expect("valid scan");
            black_box(out[0])
        })
    });
}

criterion_group! {
    name = planning;
    config = Criterion::default()
        .sample_size(30)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    targets = benches
}
criterion_main!(planning);
