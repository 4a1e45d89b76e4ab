//! Social map and social planner costs on the museum at 0.1 m (issue targets in brackets):
//! full rebuild with 50 people and 10 object spaces (2 ms), incremental update when 5 of the 50
//! move (0.5 ms), the same two for the `calderita` planner's map (the contours of the summed
//! density `G_d` of the people, Calderita et al. §4.1/§5.2.1), social A* across the museum (5 ms)
//! beside plain A* on the same map, and group detection for 200 people (200 us).
//! `benches/criterion_targets.py` checks the medians against the targets.
#![allow(missing_docs)] // criterion_group! generates an undocumented public function

use criterion::{Criterion, criterion_group, criterion_main};
use proxemic_core::groups::{DensityParams, GroupMethod, PersonState, detect};
use proxemic_core::map::CostGrid;
use proxemic_core::map::geometry::{Bounds, StaticGeometry};
use proxemic_core::map::grid::{DistanceField, GridSpec, OccupancyGrid};
use proxemic_core::math::Vec2;
use proxemic_core::perception::{ProxemicsConfig, perceive};
use proxemic_core::plan::{PathPlanner, SearchMode, nearest_passable};
use proxemic_core::proxemics::DensityZones;
use proxemic_core::scenario::Scenario;
use proxemic_core::social_cost_map::{DensityLayer, SocialMap};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const MUSEUM: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../python/proxemic/data/envs/museum.toml");

fn people(n: usize, geom: &StaticGeometry, rng: &mut ChaCha8Rng) -> Vec<PersonState> {
    let b = geom.bounds();
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let p = Vec2::new(rng.random_range(b.min.x..b.max.x), rng.random_range(b.min.y..b.max.y));
        if !geom.contains(p) && geom.distance(p) > 0.4 {
            let th: f64 = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
            let moving = out.len() % 2 == 0;
            let vel = if moving { Vec2::new(th.cos(), th.sin()) } else { Vec2::zeros() };
            out.push(PersonState { pos: p, heading: th, vel });
        }
    }
    out
}

fn bench(c: &mut Criterion) {
    let scenario = Scenario::from_file(MUSEUM).expect("museum parses");
    let b = scenario.scene.bounds;
    let polys: Vec<Vec<Vec2>> = scenario
        .static_polygons()
        .into_iter()
        .map(|p| p.into_iter().map(|q| Vec2::new(q[0], q[1])).collect())
        .collect();
    let bounds = Bounds { min: Vec2::new(b[0], b[1]), max: Vec2::new(b[2], b[3]) };
    let geom = StaticGeometry::new(polys, bounds).expect("valid museum");
    let spec = GridSpec::covering(bounds, 0.1).expect("grid");
    let field = DistanceField::from_occupancy(&OccupancyGrid::rasterize(&geom, spec));
    let grid = CostGrid::inflated(&field, 0.3);
    let objects: Vec<Vec<Vec2>> = scenario
        .objects
        .iter()
        .filter_map(|o| o.interaction.as_ref())
        .take(10)
        .map(|s| s.polygon.iter().map(|q| Vec2::new(q[0], q[1])).collect())
        .collect();
    let factors = vec![3.5; objects.len()];
    let cfg = ProxemicsConfig::default();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let crowd = people(50, &geom, &mut rng);
    let features = vec![Vec::new(); crowd.len()];
    let perception = perceive(&cfg, &crowd, &features, &[]).expect("perception");
    let mut map = SocialMap::new(grid.clone(), &objects, cfg.costs);

    let mut g = c.benchmark_group("socialmap");
    g.bench_function("full_rebuild_50_people_10_objects", |bch| {
        bch.iter(|| map.rebuild(&perception.individuals, &factors).expect("one factor per object"))
    });
    // Incremental: 5 of the 50 people move by 10 cm.
    let mut moved = crowd.clone();
    for p in moved.iter_mut().take(5) {
        p.pos.x += 0.1;
    }
    let after = perceive(&cfg, &moved, &features, &[]).expect("perception");
    map.rebuild(&perception.individuals, &factors).expect("one factor per object");
    let mut flip = false;
    g.bench_function("incremental_5_of_50_move", |bch| {
        bch.iter(|| {
            flip = !flip;
            map.update_people(if flip { &after.individuals } else { &perception.individuals });
        })
    });
    // Calderita's map: the people layer from the density contours of the 50 people, rebuilt
    // whole, then updated when 5 of them move by 10 cm as `SocialPlanning` does
    // before each calderita plan (the layer keeps its reference people between updates).
    let zones = DensityZones::new(DensityParams::default(), cfg.zones).expect("density zones");
    let mut density_map = SocialMap::new(grid.clone(), &objects, cfg.costs);
    let mut layer = DensityLayer::new(spec, zones, density_map.costs());
    g.bench_function("calderita_full_rebuild_50_people_10_objects", |bch| {
        bch.iter(|| {
            density_map
                .rebuild::<proxemic_core::perception::Individual>(&[], &factors)
                .expect("one factor per object");
            layer.rebuild(&crowd);
            layer.write_to(&mut density_map).expect("the layer is made for this map");
        })
    });
    // Every iteration is a real update: the layer's reference stays the 50 people as rebuilt,
    // and each update brings it to the 5 moved ones (going back to the reference would cost
    // nothing, so the row does not alternate as the counted map's row does).
    layer.rebuild(&crowd);
    g.bench_function("calderita_update_5_of_50_move", |bch| {
        bch.iter(|| {
            density_map.set_object_factors(&factors).expect("one factor per object");
            layer.update(&moved);
            layer.write_to(&mut density_map).expect("the layer is made for this map");
        })
    });
    g.bench_function("perceive_50_people", |bch| {
        bch.iter(|| perceive(&cfg, &crowd, &features, &[]).expect("ok"))
    });

    // Social A* across the museum, and plain A* between the same cells on the static grid (no
    // people, no object spaces): what the social map adds to a search.
    map.rebuild(&perception.individuals, &factors).expect("one factor per object");
    let start =
        nearest_passable(&grid, spec.cell_of(Vec2::new(2.5, 15.0)).expect("inside"), 10).expect("free");
    let goal =
        nearest_passable(&grid, spec.cell_of(Vec2::new(33.0, 8.5)).expect("inside"), 10).expect("free");
    let mut planner = PathPlanner::new();
    let w = cfg.costs.weight();
    g.bench_function("social_astar_across_museum", |bch| {
        bch.iter(|| {
            planner.plan(map.grid(), start, goal, SearchMode { weight: w, heuristic: true }).expect("path")
        })
    });
    g.bench_function("plain_astar_static_grid_same_endpoints", |bch| {
        bch.iter(|| planner.plan(&grid, start, goal, SearchMode::PLAIN).expect("path"))
    });
    let two_hundred = people(200, &geom, &mut rng);
    let method = GroupMethod::default();
    g.bench_function("group_detection_200_people", |bch| {
        bch.iter(|| detect(&two_hundred, &method).expect("ok"))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
