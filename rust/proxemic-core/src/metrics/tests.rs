//! Tests of [`super::evaluate`]: hand-computed episodes per family, bad inputs, a property test.

use super::proximity::time_to_collision;
use super::*;
use crate::error::CoreError;
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
        robot_free: None,
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
    assert_eq!(m.collisions.steps, 10);
    assert!(m.collisions.success && !m.collisions.collision && !m.collisions.timeout);
    assert_close(m.collisions.time_to_goal, 5.0);
    assert!(close(m.efficiency.path_length, 10.0) && close(m.papers.d_t, 10.0) && close(m.papers.tau, 5.0));
    assert_close(m.efficiency.path_length_ratio, 1.0);
    assert_close(m.efficiency.spl, 1.0);
    for v in [m.motion.vel_min, m.motion.vel_avg, m.motion.vel_max] {
        assert_close(v, 2.0);
    }
    for v in [
        m.motion.acc_min,
        m.motion.acc_avg,
        m.motion.acc_max,
        m.motion.jerk_min,
        m.motion.jerk_avg,
        m.motion.jerk_max,
    ] {
        assert_close(v, 0.0);
    }
    assert!(close(m.motion.chc, 0.0) && close(m.motion.chc_motion, 0.0));
    assert_close(m.motion.path_irregularity, 0.0);
    assert_eq!(m.efficiency.failure_to_progress, 0);
    assert!(close(m.motion.stalled_time, 0.0));
    assert_close(m.clearance.clearance_min, 1.7);
    assert_close(m.clearance.clearance_avg, 1.7);
    // No people: all public, compliant, nothing else defined.
    assert_close(m.proximity.psi_public, 100.0);
    assert_close(m.proximity.psi_intimate, 0.0);
    assert_close(m.proximity.personal_space_compliance, 1.0);
    assert_close(m.proximity.discomfort_frequency, 0.0);
    assert_eq!((m.proximity.dist_person_min, m.proximity.cp_avg, m.clearance.ttc_min), (None, None, None));
    assert_close(m.clearance.ttc_below_fraction, 0.0);
    assert!(m.proximity.d_min.is_empty() && m.objects.psi_object_active.is_empty());
}

#[test]
fn detour_lowers_spl_and_raises_plr() {
    let robot = line(10);
    let t = traj(&robot, 0.5, Vec2::new(10.0, 0.0));
    let m = run(&t, &PeopleTracks::none(), &ctx(8.0));
    // l* = 8 < PL = 10: SPL = 8 / 10.
    assert_close(m.efficiency.path_length_ratio, 1.25);
    assert_close(m.efficiency.spl, 0.8);
    let m = run(&t, &PeopleTracks::none(), &ctx(12.5));
    assert_close(m.efficiency.path_length_ratio, 0.8);
    assert_close(m.efficiency.spl, 1.0);
    let short = traj(&robot[..5], 0.5, Vec2::new(10.0, 0.0));
    let m = run(&short, &PeopleTracks::none(), &ctx(10.0));
    assert!(!m.collisions.success && m.collisions.timeout);
    assert_close(m.efficiency.spl, 0.0);
    assert_eq!(m.collisions.time_to_goal, None);
    let m = run(&t, &PeopleTracks::none(), &ctx(f64::INFINITY));
    assert_eq!((m.efficiency.path_length_ratio, m.efficiency.spl), (None, None));
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
    assert!(close(m.motion.chc, FRAC_PI_2));
    assert!(close(m.motion.chc_motion, FRAC_PI_2));
    // (pi/2 - |atan2(2, 2) - 0|) / 4
    assert_close(m.motion.path_irregularity, PI / 16.0);
    let s2 = 2f64.sqrt();
    assert_close(m.motion.acc_min, 0.0);
    assert_close(m.motion.acc_avg, s2 / 3.0);
    assert_close(m.motion.acc_max, s2);
    for v in [m.motion.jerk_min, m.motion.jerk_avg, m.motion.jerk_max] {
        assert_close(v, s2);
    }
    assert_close(m.efficiency.path_length_ratio, 1.0);
    assert_close(m.collisions.time_to_goal, 4.0);
}

#[test]
fn heading_change_wraps_and_motion_direction_skips_stops() {
    // Yaw 3.1 -> -3.1 is a 2 pi - 6.2 turn, not 6.2.
    let robot = [[0.0, 0.0, 3.1], [1.0, 0.0, -3.1], [1.0, 0.0, -3.1], [1.0, 1.0, -3.1]];
    let t = traj(&robot, 1.0, Vec2::new(5.0, 5.0));
    let m = run(&t, &PeopleTracks::none(), &ctx(1.0));
    assert!(close(m.motion.chc, 2.0 * PI - 6.2));
    // The stop at step 1 is skipped: east then north.
    assert!(close(m.motion.chc_motion, FRAC_PI_2));
    assert_close(m.motion.vel_min, 0.0);
    assert!(close(m.motion.stalled_time, 1.0));
}

#[test]
fn stalled_robot_fails_to_progress() {
    let robot = vec![[0.0, 0.0, 0.0]; 12];
    let t = traj(&robot, 1.0, Vec2::new(5.0, 0.0));
    let m = run(&t, &PeopleTracks::none(), &ctx(5.0));
    // 11 steps, windows of 5 s = 5 steps: two complete windows.
    assert_eq!(m.efficiency.failure_to_progress, 2);
    assert!(close(m.motion.stalled_time, 11.0));
    assert!(m.collisions.timeout);
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
    let people = PeopleTracks {
        positions: &pos,
        velocities: &vel,
        headings: &head,
        radii: &[0.25],
        count: 1,
        present: &[],
    };
    let t = traj(&robot, 1.0, Vec2::new(9.0, 0.0));
    let m = run(&t, &people, &ctx(9.0));
    let d: Vec<f64> = (0..10).map(|x| ((x as f64 - 5.0).powi(2) + 0.49).sqrt()).collect();
    // Closest 0.7 at x = 5: personal; x = 2..4, 6..8 social; x = 0, 1, 9 public.
    assert_close(m.proximity.psi_intimate, 0.0);
    assert_close(m.proximity.psi_personal, 10.0);
    assert_close(m.proximity.psi_social, 60.0);
    assert_close(m.proximity.psi_public, 30.0);
    assert_close(m.proximity.d_min[0], 0.7);
    assert_close(m.proximity.dist_person_min, 0.7);
    assert_close(m.proximity.gap_person_min, 0.15);
    assert_close(m.proximity.cp_avg, d.iter().sum::<f64>() / 10.0);
    // Gap 0.15 < 0.2 only at x = 5.
    assert_close(m.proximity.discomfort_frequency, 0.1);
    assert_close(m.proximity.discomfort_gap_avg, 0.15);
    // d - r_R = 0.4 < 0.45 only at x = 5.
    assert_close(m.proximity.personal_space_compliance, 0.9);
    // Lateral offset 0.7 > 0.55: never on a collision course, no contact.
    assert_eq!(m.clearance.ttc_min, None);
    assert_close(m.clearance.ttc_below_fraction, 0.0);
    assert!(!m.collisions.hc && m.collisions.success);
}

#[test]
fn custom_zones_move_the_boundaries() {
    let (robot, pos, vel, head) = passing_person();
    let people = PeopleTracks {
        positions: &pos,
        velocities: &vel,
        headings: &head,
        radii: &[0.25],
        count: 1,
        present: &[],
    };
    let t = traj(&robot, 1.0, Vec2::new(9.0, 0.0));
    let mut c = ctx(9.0);
    c.zones = [1.0, 2.0, 3.0];
    let m = run(&t, &people, &c);
    // 0.7 | 1.22 x2 | 2.12 x2 | 3.08 x2, 4.06 x2, 5.05
    assert_close(m.proximity.psi_intimate, 10.0);
    assert_close(m.proximity.psi_personal, 20.0);
    assert_close(m.proximity.psi_social, 20.0);
    assert_close(m.proximity.psi_public, 50.0);
}

#[test]
fn head_on_time_to_collision() {
    let robot = line(2);
    let pos = [Vec2::new(10.0, 0.0), Vec2::new(9.0, 0.0), Vec2::new(8.0, 0.0)];
    let vel = [Vec2::new(-1.0, 0.0); 3];
    let people = PeopleTracks {
        positions: &pos,
        velocities: &vel,
        headings: &[PI; 3],
        radii: &[0.3],
        count: 1,
        present: &[],
    };
    let t = traj(&robot, 1.0, Vec2::new(20.0, 0.0));
    let mut c = ctx(20.0);
    c.params.ttc_threshold = 4.0;
    let m = run(&t, &people, &c);
    // Step 0: (10 - 0.6) / 2 = 4.7 s; step 1: (8 - 0.6) / 2 = 3.7 s.
    assert_close(m.clearance.ttc_min, 3.7);
    assert_close(m.clearance.ttc_below_fraction, 0.5);
    assert!(close(time_to_collision(Vec2::new(0.5, 0.0), Vec2::zeros(), 0.6), 0.0));
    assert!(time_to_collision(Vec2::new(5.0, 0.0), Vec2::new(1.0, 0.0), 0.6).is_infinite());
}

#[test]
fn swept_test_catches_tunnelling() {
    let robot = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
    let pos = [Vec2::zeros(); 2];
    let vel = [Vec2::zeros(); 2];
    let people = PeopleTracks {
        positions: &pos,
        velocities: &vel,
        headings: &[0.0; 2],
        radii: &[0.25],
        count: 1,
        present: &[],
    };
    let t = traj(&robot, 1.0, Vec2::new(1.0, 0.0));
    let m = run(&t, &people, &ctx(2.0));
    // Both samples have a gap of 0.45 m, the swept motion passes through the person.
    assert_close(m.proximity.gap_person_min, 0.45);
    assert_eq!(m.collisions.hc_count, 1);
    assert!(m.collisions.hc && m.collisions.collision && !m.collisions.success && !m.collisions.timeout);
    // Moved 1 m sideways, the swept distance is 1 m: no contact.
    let pos = [Vec2::new(0.0, 1.0); 2];
    let people = PeopleTracks { positions: &pos, ..people };
    let m = run(&t, &people, &ctx(2.0));
    assert_eq!(m.collisions.hc_count, 0);
    assert!(m.collisions.success);
}

#[test]
fn contact_bits_by_kind_and_success_before_collision() {
    let robot = line(3);
    let t = traj(&robot, 1.0, Vec2::new(3.0, 0.0));
    let mut c = ctx(3.0);
    c.collision_steps = &[0, CONTACT_STATIC, CONTACT_ROBOT | CONTACT_PERSON];
    let m = run(&t, &PeopleTracks::none(), &c);
    assert_eq!((m.collisions.hc_count, m.collisions.wc_count, m.collisions.ac_count), (1, 1, 1));
    assert!(
        m.collisions.hc
            && m.collisions.wc
            && m.collisions.ac
            && m.collisions.collision
            && !m.collisions.success
            && !m.collisions.timeout
    );
    // Goal at instant 1, collision in step 2 (instant 3): success.
    let t = traj(&robot, 1.0, Vec2::new(1.0, 0.0));
    c.collision_steps = &[0, 0, CONTACT_STATIC];
    let m = run(&t, &PeopleTracks::none(), &c);
    assert!(m.collisions.success && m.collisions.collision);
    assert_close(m.collisions.time_to_goal, 1.0);
    // Collision in the step that reaches the goal: not a success.
    c.collision_steps = &[CONTACT_STATIC, 0, 0];
    let m = run(&t, &PeopleTracks::none(), &c);
    assert!(!m.collisions.success && m.collisions.collision);
}

#[test]
fn social_force_on_a_single_pair() {
    let robot = [[0.0, 0.0, 0.0]];
    let pos = [Vec2::new(1.0, 0.0)];
    let vel = [Vec2::zeros()];
    let t = Trajectory { robot_radius: 0.3, ..traj(&robot, 1.0, Vec2::new(5.0, 0.0)) };
    let facing = PeopleTracks {
        positions: &pos,
        velocities: &vel,
        headings: &[PI],
        radii: &[0.2],
        count: 1,
        present: &[],
    };
    let m = run(&t, &facing, &ctx(5.0));
    let f = 2.1 * ((0.5f64 - 1.0) / 0.3).exp();
    assert!(close(m.clearance.social_force_on_people, f));
    assert!(close(m.clearance.social_force_on_robot, f));
    assert!(close(m.clearance.social_work, 2.0 * f));
    // The person faces away: the robot is behind them, weight lambda = 0.5.
    let away = PeopleTracks { headings: &[0.0], ..facing };
    let m = run(&t, &away, &ctx(5.0));
    assert!(close(m.clearance.social_force_on_people, 0.5 * f));
    assert!(close(m.clearance.social_force_on_robot, f));
}

#[test]
fn object_space_entered_while_active() {
    let robot = line(9);
    let n = robot.len();
    let square = vec![Vec2::new(3.5, -1.0), Vec2::new(6.5, -1.0), Vec2::new(6.5, 1.0), Vec2::new(3.5, 1.0)];
    let degenerate = vec![Vec2::new(0.0, -1.0), Vec2::new(0.0, 1.0)];
    let polygons = [square, degenerate];
    // Object 0 active from t = 5, object 1 always active.
    let active: Vec<bool> = (0..n).flat_map(|t| [t >= 5, true]).collect();
    let objects = ObjectSpaces { polygons: &polygons, active: &active };
    let t = traj(&robot, 1.0, Vec2::new(9.0, 0.0));
    let m = evaluate(&t, &PeopleTracks::none(), &Groups::none(), &objects, &ctx(9.0)).expect("valid");
    // Inside at x = 4, 5, 6; active at 5 and 6.
    assert_close(m.objects.psi_object_active[0], 20.0);
    assert_close(m.objects.psi_object_any[0], 30.0);
    assert_close(m.objects.psi_object_active[1], 0.0);
    assert_close(m.objects.psi_objects_active, 20.0);
    // Calderita's reading: any time inside, the idle instant x = 4 included.
    assert_close(m.objects.psi_objects_any, 30.0);
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
    let m = evaluate(&t, &PeopleTracks::none(), &groups, &ObjectSpaces::none(), &ctx(9.0)).expect("valid");
    // x = 5 is a sample point: counted once (half-open steps).
    assert_eq!(m.groups.interaction_crossings_person_object, 1);
    assert_eq!(m.groups.interaction_crossings_person_person, 1);
    assert_eq!(m.groups.interaction_crossings, 2);
    // Inside the o-space at x = 1, 2, 3 (distances 1.118, 0.5, 1.118).
    assert_close(m.groups.ospace_pct, 30.0);
    assert!(close(m.groups.ospace_time, 1.5));
    assert_eq!(m.groups.ospace_entries, 1);
    assert_close(m.groups.group_psi_intimate, 0.0);
    assert_close(m.groups.group_psi_personal, 30.0);
    assert_close(m.groups.group_psi_social, 30.0);
    assert_close(m.groups.group_psi_public, 40.0);
}

#[test]
fn ospace_time_of_an_episode_spent_inside_is_its_duration() {
    // Every one of the 10 instants (9 steps of 0.5 s) inside the o-space: 4.5 s, the episode's
    // duration (each step counted by its start), not 10 instants times dt = 5 s.
    let robot = line(9);
    let n = robot.len();
    let ospaces = vec![OSpace { centre: Vec2::new(4.5, 0.0), radius: 10.0 }; n];
    let ospace_offsets: Vec<usize> = (0..=n).collect();
    let groups = Groups { ospace_offsets: &ospace_offsets, ospaces: &ospaces, link_offsets: &[], links: &[] };
    let t = traj(&robot, 0.5, Vec2::new(9.0, 0.0));
    let m = evaluate(&t, &PeopleTracks::none(), &groups, &ObjectSpaces::none(), &ctx(9.0)).expect("valid");
    assert_close(m.groups.ospace_pct, 100.0);
    assert_eq!(m.groups.ospace_time, 4.5);
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
    assert!(close(m.efficiency.path_length, pl));
    assert_close(m.papers.l_ratio, 10.0 / pl);
    assert_eq!(m.papers.smooth_k, 2);
    // 1/(k - 1) * (2 (pi/4)^2)
    assert_close(m.papers.smooth_rad2, 2.0 * FRAC_PI_4 * FRAC_PI_4);
    // Its root, in rad: sqrt(2) * pi/4.
    assert_close(m.papers.smooth_rad, 2f64.sqrt() * FRAC_PI_4);
    // Staying on the A* path: L_ratio 1, Smooth 0.
    let robot = line(10);
    let t = traj(&robot, 1.0, Vec2::new(10.0, 0.0));
    let m = run(&t, &PeopleTracks::none(), &c);
    assert_close(m.papers.l_ratio, 1.0);
    assert_close(m.papers.smooth_rad2, 0.0);
    assert_eq!(m.papers.smooth_k, 0);
    // Ending 0.3 m short of the goal (inside the success radius) on the A* path: D_SN is the
    // executed 9.7 m plus the 0.3 m rest to the goal, so L_ratio is 1, never above it.
    let short: Vec<[f64; 3]> = (0..=97).map(|k| [k as f64 * 0.1, 0.0, 0.0]).collect();
    let t_short = Trajectory { success_radius: 0.5, ..traj(&short, 1.0, Vec2::new(10.0, 0.0)) };
    let m = run(&t_short, &PeopleTracks::none(), &c);
    assert!(close(m.efficiency.path_length, 9.7));
    assert_close(m.papers.l_ratio, 1.0);
    // Without an A* path, both undefined.
    let m = run(&t, &PeopleTracks::none(), &ctx(10.0));
    assert_eq!((m.papers.l_ratio, m.papers.smooth_rad2, m.papers.smooth_rad), (None, None, None));
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
    assert_eq!(m.papers.smooth_k, 1);
    assert_close(m.papers.smooth_rad2, FRAC_PI_4 * FRAC_PI_4);
    assert_close(m.papers.smooth_rad, FRAC_PI_4);
    assert_eq!(m.papers.l_ratio, None);
}

#[test]
fn empty_and_single_point_trajectories() {
    let polygons = [vec![Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)]];
    let objects = ObjectSpaces { polygons: &polygons, active: &[] };
    let people = PeopleTracks {
        positions: &[],
        velocities: &[],
        headings: &[],
        radii: &[0.2, 0.3],
        count: 2,
        present: &[],
    };
    let t = traj(&[], 0.1, Vec2::zeros());
    let m = evaluate(&t, &people, &Groups::none(), &objects, &ctx(1.0)).expect("empty is valid");
    assert_eq!(m.collisions.steps, 0);
    assert!(!m.collisions.success && !m.collisions.collision && !m.collisions.timeout);
    assert!(close(m.efficiency.path_length, 0.0) && close(m.papers.tau, 0.0));
    assert_eq!(m.proximity.d_min, vec![None, None]);
    assert_eq!(m.objects.psi_object_active, vec![None]);
    assert_eq!(
        (m.proximity.psi_public, m.motion.vel_avg, m.clearance.ttc_below_fraction, m.papers.smooth_rad2),
        (None, None, None, None)
    );
    assert_close(m.efficiency.spl, 0.0);

    let robot = [[0.0, 0.0, 0.0]];
    let t = traj(&robot, 0.1, Vec2::zeros());
    let m = run(&t, &PeopleTracks::none(), &ctx(0.0));
    assert!(m.collisions.success);
    assert_close(m.collisions.time_to_goal, 0.0);
    assert_eq!(m.efficiency.path_length_ratio, None);
    assert_close(m.efficiency.spl, 1.0);
    assert_eq!(
        (m.motion.vel_min, m.motion.acc_min, m.motion.jerk_min, m.motion.path_irregularity),
        (None, None, None, None)
    );
    assert_eq!((m.clearance.ttc_min, m.clearance.ttc_below_fraction), (None, None));
    assert_close(m.proximity.psi_public, 100.0);
}

#[test]
fn clearance_skips_non_finite_samples() {
    let robot = line(2);
    let t = traj(&robot, 1.0, Vec2::new(2.0, 0.0));
    let f = |p: Vec2| if p.x > 0.5 { f64::NAN } else { 1.0 };
    let mut c = ctx(2.0);
    c.clearance = &f;
    let m = run(&t, &PeopleTracks::none(), &c);
    assert_close(m.clearance.clearance_min, 0.7);
    assert_close(m.clearance.clearance_avg, 0.7);
    let nan = |_: Vec2| f64::NAN;
    c.clearance = &nan;
    let m = run(&t, &PeopleTracks::none(), &c);
    assert_eq!((m.clearance.clearance_min, m.clearance.clearance_avg), (None, None));
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
    let short = PeopleTracks {
        positions: &pos,
        velocities: &vel,
        headings: &[0.0; 3],
        radii: &[0.2],
        count: 1,
        present: &[],
    };
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
        "smooth_rad2",
        "smooth_rad",
        "d_t",
        "tau",
        "chc",
        "d_min",
        "psi_intimate",
        "psi_object_active",
        "psi_objects_any",
        "psi_objects_active",
        "spl",
        "ttc_min",
    ] {
        assert!(v.get(key).is_some(), "{key}");
    }
    assert_eq!(v["time_to_goal"], serde_json::json!(3.0));
    assert_eq!(v["ttc_min"], serde_json::Value::Null);
}

/// The metrics of one episode, as the serialised record (every value to the last bit: ryu's
/// shortest round-trip form).
fn passing_record() -> String {
    let (robot, pos, vel, head) = passing_person();
    let people = PeopleTracks {
        positions: &pos,
        velocities: &vel,
        headings: &head,
        radii: &[0.25],
        count: 1,
        present: &[],
    };
    let t = traj(&robot, 1.0, Vec2::new(9.0, 0.0));
    serde_json::to_string(&run(&t, &people, &ctx(9.0))).expect("serialisable")
}

/// The same episode evaluated on several threads at once gives this thread's record bit for bit:
/// no state shared between evaluations, no thread-dependent order of a reduction (the vector
/// envs and `step_worlds` evaluate episodes on worker threads).
#[test]
fn the_same_episode_gives_the_same_record_on_every_thread() {
    let here = passing_record();
    let there: Vec<String> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..4).map(|_| s.spawn(passing_record)).collect();
        handles.into_iter().map(|h| h.join().expect("no panic")).collect()
    });
    assert!(here.contains("\"dist_person_min\":"), "{here}");
    for record in there {
        assert_eq!(record, here);
    }
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
        let people = PeopleTracks { positions: &positions, velocities: &velocities, headings: &headings, radii: &radii, count: np, present: &[] };
        let astar = [Vec2::new(-5.0, 0.0), Vec2::new(5.0, 3.0)];
        let mut c = ctx(7.0);
        c.astar_path = &astar;
        let t = Trajectory { dt, robot: &robot, robot_radius: 0.3, goal: Vec2::new(1.0, 1.0), success_radius: 0.5 };
        match evaluate(&t, &people, &groups, &objects, &c) {
            Err(_) => proptest::prop_assert!(corrupted),
            Ok(m) => {
                proptest::prop_assert!(!corrupted);
                proptest::prop_assert_eq!(m.collisions.steps, n.saturating_sub(1));
                proptest::prop_assert!(!(m.collisions.timeout && (m.collisions.success || m.collisions.collision)));
                proptest::prop_assert!(m.efficiency.path_length >= 0.0 && m.motion.chc >= 0.0 && m.motion.chc_motion >= 0.0);
                if n > 0 {
                    let zones = [m.proximity.psi_intimate, m.proximity.psi_personal, m.proximity.psi_social, m.proximity.psi_public];
                    let total: f64 = zones.iter().map(|z| z.unwrap_or(f64::NAN)).sum();
                    proptest::prop_assert!((total - 100.0).abs() < 1e-9, "{}", total);
                    for f in [m.proximity.discomfort_frequency, m.proximity.personal_space_compliance, m.objects.psi_objects_active.map(|p| p / 100.0)] {
                        let f = f.unwrap_or(f64::NAN);
                        proptest::prop_assert!((0.0..=1.0).contains(&f), "{}", f);
                    }
                    proptest::prop_assert!(m.objects.psi_object_active[0] <= m.objects.psi_object_any[0]);
                    proptest::prop_assert!(m.objects.psi_objects_active <= m.objects.psi_objects_any);
                }
                if let Some(r) = m.papers.l_ratio {
                    proptest::prop_assert!(r > 0.0);
                }
                proptest::prop_assert!(m.groups.interaction_crossings <= m.collisions.steps * links.len());
                proptest::prop_assert!(serde_json::to_string(&m).is_ok());
            }
        }
    }
}

#[test]
fn snqi_near_misses_and_force_exceed_events() {
    // The passing person: closest gap 0.15 m at x = 5 (a near miss), 0.67 m at x = 4 and 6; the
    // robot's force on them peaks at 2.1 exp(-0.5) * 0.75 = 0.96 m/s², under 2.0.
    let (robot, pos, vel, head) = passing_person();
    let people = PeopleTracks {
        positions: &pos,
        velocities: &vel,
        headings: &head,
        radii: &[0.25],
        present: &[],
        count: 1,
    };
    let t = traj(&robot, 1.0, Vec2::new(9.0, 0.0));
    let m = run(&t, &people, &ctx(9.0));
    assert_eq!(m.snqi.near_misses, 1);
    assert_eq!(m.snqi.force_exceed_events, 0);
    assert_close(m.snqi.comfort_exposure, 0.0);
    // A person at (5, 0.5) facing the robot's line: gap -0.05 m at x = 5 is a contact, not a near
    // miss, and the force there is 2.1 exp(0.05 / 0.3) * 1 = 2.48 m/s² > 2.0: one event of 10.
    let pos = vec![Vec2::new(5.0, 0.5); robot.len()];
    let head = vec![-std::f64::consts::FRAC_PI_2; robot.len()];
    let people = PeopleTracks {
        positions: &pos,
        velocities: &vel,
        headings: &head,
        radii: &[0.25],
        present: &[],
        count: 1,
    };
    let m = run(&t, &people, &ctx(9.0));
    assert_eq!(m.snqi.near_misses, 0);
    assert_eq!(m.snqi.force_exceed_events, 1);
    assert_close(m.snqi.comfort_exposure, 0.1);
    // Without people: no events, exposure 0.
    let m = run(&t, &PeopleTracks::none(), &ctx(9.0));
    assert_eq!((m.snqi.near_misses, m.snqi.force_exceed_events), (0, 0));
    assert_close(m.snqi.comfort_exposure, 0.0);
}
