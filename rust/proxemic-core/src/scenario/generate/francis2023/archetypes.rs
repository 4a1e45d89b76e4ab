//! One function per archetype of Francis et al. 2023 (the scenario names are the paper's; the
//! ranges are ours, chosen so every draw is a feasible instance of the archetype for a Pepper-like
//! robot of 0.24 m radius and 0.55 m/s). Every drawn value carries its range and unit beside it.
//!
//! Frame: the robot's main direction of travel is +x; y grows to its left.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

use super::{Draft, Goal, H, Ped, ROBOT_SPEED, WALL, round2};

/// Lays out archetype `name` (one of [`super::ARCHETYPES`]).
pub(super) fn lay_out(name: &str, d: &mut Draft) {
    match name {
        "frontal_approach" => frontal_approach(d),
        "pedestrian_obstruction" => pedestrian_obstruction(d),
        "robot_overtaking" => robot_overtaking(d),
        "pedestrian_overtaking" => pedestrian_overtaking(d),
        "crossing_90" => crossing(d, FRAC_PI_2),
        "crossing_45" => crossing(d, FRAC_PI_4),
        "narrow_hallway" => narrow_hallway(d),
        "narrow_doorway" => narrow_doorway(d),
        "blind_corner" => blind_corner(d),
        "entering_room" => room_and_corridor(d, true),
        "exiting_room" => room_and_corridor(d, false),
        "joining_group" => group(d, true),
        "leaving_group" => group(d, false),
        "following_person" => following_person(d),
        "accompanying_person" => accompanying_person(d),
        "dense_crowd" => dense_crowd(d),
        "down_path" => down_path(d),
        "intersection_wait" => intersection(d, true),
        "intersection_proceed" => intersection(d, false),
        "entering_elevator" => elevator(d, true),
        "exiting_elevator" => elevator(d, false),
        "leading_person" => leading_person(d),
        "parallel_traffic" => parallel_traffic(d),
        "perpendicular_traffic" => perpendicular_traffic(d),
        "circular_crossing" => circular_crossing(d),
        _ => robot_crowding(d),
    }
}

/// Francis et al. 2023, "Frontal Approach": the robot and a person walk toward each other on the
/// same line in an open space and must pass.
fn frontal_approach(d: &mut Draft) {
    let w = d.draw("hall_width", 4.0, 6.0, "m"); // a wide hall: room to pass on either side
    let l = d.draw("hall_length", 10.0, 14.0, "m");
    let ahead = d.draw("person_ahead", 6.0, 9.0, "m"); // where the person starts, ahead of the robot
    let off = d.draw("person_offset", -0.2, 0.2, "m"); // lateral offset from the robot's line
    let v = d.draw("person_speed", 0.8, 1.3, "m/s"); // ordinary walking speeds
    d.room(0.0, 0.0, l, w);
    let y = round2(w / 2.0); // on the centimetre grid, as every drawn value
    let x0 = (1.0 + ahead).min(l - 0.6);
    d.person(Ped::Walk { route: vec![[x0, y + off], [0.5, y + off]], speed: v });
    d.robot_to([1.0, y], [l - 1.0, y]);
    d.time_for(l - 2.0);
    d.what = format!("a person {ahead} m ahead on the robot's line walks toward it in a hall {w} m wide");
}

/// Francis et al. 2023, "Pedestrian Obstruction": a person stands in the robot's way in a hallway,
/// and the robot has to go round them.
fn pedestrian_obstruction(d: &mut Draft) {
    let w = d.draw("hall_width", 2.4, 3.2, "m"); // room to pass the person on either side
    let l = d.draw("hall_length", 10.0, 13.0, "m");
    let ahead = d.draw("person_ahead", 4.0, 6.0, "m");
    let off = d.draw("person_offset", -0.3, 0.3, "m"); // from the hall's centre line
    let facing = d.draw("person_heading", -PI, PI, "rad");
    d.room(0.0, 0.0, l, w);
    let y = round2(w / 2.0); // on the centimetre grid, as every drawn value
    d.person(Ped::Stand { pose: [1.0 + ahead, y + off, facing], group: None });
    d.robot_to([1.0, y], [l - 1.0, y]);
    d.time_for(l - 2.0);
    d.what = format!("a person stands {ahead} m ahead in the robot's way in a hallway {w} m wide");
}

/// Francis et al. 2023, "Robot Overtaking": the robot overtakes a slower person walking ahead of
/// it in the same direction along a hallway.
fn robot_overtaking(d: &mut Draft) {
    let w = d.draw("hall_width", 2.0, 3.0, "m");
    let l = d.draw("hall_length", 16.0, 20.0, "m");
    let ahead = d.draw("person_ahead", 2.0, 3.5, "m");
    let off = d.draw("person_offset", -0.2, 0.2, "m");
    let v = d.draw("person_speed", 0.25, 0.4, "m/s"); // slower than the robot's 0.55 m/s
    d.room(0.0, 0.0, l, w);
    let y = round2(w / 2.0); // on the centimetre grid, as every drawn value
    // The person stops 4 m short of the hall's end: the robot has caught up long before.
    d.person(Ped::Walk { route: vec![[1.0 + ahead, y + off], [l - 4.0, y + off]], speed: v });
    d.robot_to([1.0, y], [l - 1.0, y]);
    d.time_for(l - 2.0);
    d.what = format!(
        "the robot overtakes a person walking at {v} m/s {ahead} m ahead of it in a hallway {w} m wide"
    );
}

/// Francis et al. 2023, "Pedestrian Overtaking": a faster person coming from behind overtakes the
/// robot in a hallway.
fn pedestrian_overtaking(d: &mut Draft) {
    let w = d.draw("hall_width", 2.0, 3.0, "m");
    let l = d.draw("hall_length", 14.0, 18.0, "m");
    let behind = d.draw("person_behind", 1.5, 3.0, "m"); // the person starts this far behind the robot
    let off = d.draw("person_offset", -0.2, 0.2, "m");
    let v = d.draw("person_speed", 1.0, 1.4, "m/s"); // brisk walking, faster than the robot
    d.room(0.0, 0.0, l, w);
    let y = round2(w / 2.0); // on the centimetre grid, as every drawn value
    d.person(Ped::Walk { route: vec![[0.6, y + off], [l - 0.6, y + off]], speed: v });
    d.robot_to([0.6 + behind, y], [l - 3.0, y]);
    d.time_for(l - 3.6 - behind);
    d.what = format!("a person {behind} m behind the robot overtakes it at {v} m/s in a hallway {w} m wide");
}

/// Francis et al. 2023, "Intersection" (a person crossing the robot's path): the person's straight
/// path crosses the robot's at `angle` (90 deg: perpendicular; 45 deg: oblique, coming from ahead),
/// timed so both reach the crossing point at about the same time.
fn crossing(d: &mut Draft, angle: f64) {
    let to_cross = d.draw("robot_to_crossing", 3.5, 5.5, "m"); // robot start to the crossing point
    let beyond = d.draw("robot_beyond_crossing", 4.0, 6.0, "m"); // crossing point to the robot's goal
    let v = d.draw("person_speed", 0.8, 1.2, "m/s");
    let timing = d.draw("timing", 0.9, 1.2, ""); // person's time to the crossing / robot's
    let side = d.side("person_side"); // +1: the person comes from the robot's left
    // The person's heading: at `angle` to the robot's path, from the robot's `side`; at 45 deg
    // it comes from ahead (heading pi - 45 deg from the robot's +x), crossing obliquely.
    let heading = if angle >= FRAC_PI_2 - 1e-9 { -side * FRAC_PI_2 } else { -side * (PI - angle) };
    let dir = [heading.cos(), heading.sin()];
    let walk = v * timing * to_cross / ROBOT_SPEED;
    let (yc, xc) = (0.0, 1.0 + to_cross);
    let p0 = [xc - dir[0] * walk, yc - dir[1] * walk];
    let p1 = [xc + dir[0] * 3.0, yc + dir[1] * 3.0];
    let (r0, r1) = ([1.0, yc], [xc + beyond, yc]);
    let xs = [p0[0], p1[0], r0[0], r1[0]];
    let ys = [p0[1], p1[1], r0[1], r1[1]];
    let lo = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min) - 1.0;
    let hi = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max) + 1.0;
    let (x0, y0, x1, y1) = (lo(&xs), lo(&ys), hi(&xs), hi(&ys));
    d.room(x0, y0, x1, y1);
    d.person(Ped::Walk { route: vec![p0, p1], speed: v });
    d.robot_to(r0, r1);
    d.time_for(to_cross + beyond);
    d.what = format!(
        "a person's path crosses the robot's at {:.0} deg, {to_cross} m ahead of the robot, in an open room",
        angle.to_degrees()
    );
}

/// Francis et al. 2023, "Narrow Hallway": the robot and a person pass each other, in opposite
/// directions, in a hallway barely wide enough for both.
fn narrow_hallway(d: &mut Draft) {
    let w = d.draw("hall_width", 1.2, 1.6, "m"); // 0.48 m of robot and 0.4 m of person, and a little
    let l = d.draw("hall_length", 8.0, 12.0, "m");
    let v = d.draw("person_speed", 0.8, 1.2, "m/s");
    d.room(0.0, 0.0, l, w);
    let y = round2(w / 2.0); // on the centimetre grid, as every drawn value
    d.person(Ped::Walk { route: vec![[l - 0.6, y], [0.5, y]], speed: v });
    d.robot_to([0.8, y], [l - 0.8, y]);
    d.time_for(l - 1.6);
    d.what = format!("the robot and a person pass each other in a hallway {w} m wide");
}

/// Francis et al. 2023, "Narrow Doorway": the robot and a person go through a doorway wide enough
/// for one, in opposite directions.
fn narrow_doorway(d: &mut Draft) {
    let door = d.draw("door_width", 0.9, 1.2, "m"); // a single door leaf
    let depth = d.draw("room_depth", 5.0, 6.0, "m"); // each room's extent along x
    let span = d.draw("room_width", 4.0, 6.0, "m"); // the rooms' extent along y (the wall's length)
    let door_off = d.draw("door_offset", -0.5, 0.5, "m"); // the doorway's centre off the wall's middle
    let r_before = d.draw("robot_before_door", 2.5, 3.5, "m");
    let p_after = d.draw("person_beyond_door", 1.5, 3.0, "m");
    let v = d.draw("person_speed", 0.8, 1.2, "m/s");
    let xw = depth; // the dividing wall's west face
    let yd = span / 2.0 + door_off;
    d.room(0.0, 0.0, 2.0 * depth + WALL, span);
    d.wall([xw + H, 0.0], [xw + H, yd - door / 2.0 - H]);
    d.wall([xw + H, yd + door / 2.0 + H], [xw + H, span]);
    let east = xw + WALL;
    d.person(Ped::Walk {
        route: vec![[east + p_after, yd], [east + 0.5, yd], [xw - 0.5, yd], [xw - 2.5, yd]],
        speed: v,
    });
    d.robot_to([xw - r_before, yd], [east + 2.5, yd]);
    d.time_for(r_before + 2.7);
    d.what = format!("the robot and a person cross a doorway {door} m wide in opposite directions");
}

/// Francis et al. 2023, "Blind Corner": the robot and a person meet at the corner of an L-shaped
/// corridor; the walls hide each from the other until the corner.
fn blind_corner(d: &mut Draft) {
    let w = d.draw("corridor_width", 1.6, 2.4, "m");
    let leg1 = d.draw("robot_leg", 5.0, 7.0, "m"); // the robot's leg (west-east), to the corner
    let leg2 = d.draw("person_leg", 5.0, 7.0, "m"); // the other leg (south-north), from the corner
    let p_from = d.draw("person_from_corner", 2.5, 4.5, "m"); // the person's start up the other leg
    let v = d.draw("person_speed", 0.8, 1.2, "m/s");
    // Clear floor: [0, leg1 + w] x [0, w] and [leg1, leg1 + w] x [0, w + leg2].
    let (x1, y1) = (leg1 + w, w + leg2);
    d.wall([0.0, -H], [x1, -H]); // south
    d.wall([x1 + H, 0.0], [x1 + H, y1]); // east
    d.wall([leg1, y1 + H], [x1, y1 + H]); // north end of the person's leg
    d.wall([-H, 0.0], [-H, w]); // west end of the robot's leg
    // The inner corner, convex seen from the floor: faces without overhang.
    d.face([0.0 - H, w], [leg1, w], [0.0, 1.0]);
    d.face([leg1, w], [leg1, y1 + H], [-1.0, 0.0]);
    let xm = leg1 + w / 2.0;
    d.person(Ped::Walk { route: vec![[xm, w / 2.0 + p_from], [xm, w / 2.0], [0.5, w / 2.0]], speed: v });
    d.robot_to([0.8, w / 2.0], [xm, y1 - 0.8]);
    d.robots[0].0[2] = 0.0; // facing down its leg, toward the corner
    d.time_for(leg1 + leg2);
    d.what = format!("the robot and a person meet at the blind corner of an L-shaped corridor {w} m wide");
}

/// Francis et al. 2023, "Entering Room" / "Exiting Room": a corridor along x with a room to its
/// north through a doorway. Entering: the robot goes from the corridor into the room while a
/// person comes out. Exiting: the robot comes out of the room into the corridor while a person
/// walks along the corridor past the doorway, toward the side the robot turns to.
fn room_and_corridor(d: &mut Draft, entering: bool) {
    let cw = d.draw("corridor_width", 1.8, 2.4, "m");
    let door = d.draw("door_width", 0.9, 1.2, "m");
    let rw = d.draw("room_width", 4.0, 6.0, "m");
    let rd = d.draw("room_depth", 5.0, 6.0, "m");
    let side = d.side("corridor_side"); // +1: the robot's corridor end of the trip is east of the door
    let along = d.draw("corridor_distance", 3.0, 4.5, "m"); // robot's corridor end to the door, along x
    let inside = d.draw("room_distance", 2.0, 3.0, "m"); // robot's room end, into the room from the door
    let v = d.draw("person_speed", 0.6, 1.0, "m/s");
    let l = 12.0;
    let dx = l / 2.0;
    let ry = cw + WALL; // the room's south face
    // The corridor [0, l] x [0, cw]; its north wall has the doorway.
    d.wall([0.0, -H], [l, -H]);
    d.wall([-H, 0.0], [-H, cw]);
    d.wall([l + H, 0.0], [l + H, cw]);
    d.wall([0.0, cw + H], [dx - door / 2.0 - H, cw + H]);
    d.wall([dx + door / 2.0 + H, cw + H], [l, cw + H]);
    let (rx0, rx1) = (dx - rw / 2.0, dx + rw / 2.0);
    d.wall([rx0 - H, ry], [rx0 - H, ry + rd]);
    d.wall([rx1 + H, ry], [rx1 + H, ry + rd]);
    d.wall([rx0, ry + rd + H], [rx1, ry + rd + H]);
    let corridor_end = [dx + side * along, cw / 2.0];
    let room_end = [dx, ry + inside];
    if entering {
        let from = d.draw("person_in_room", 2.5, rd - 0.6, "m"); // the person's start, into the room
        let p0 = [dx, ry + from];
        d.person(Ped::Walk {
            route: vec![p0, [dx, ry + 0.5], [dx, cw / 2.0], [dx + side * (along + 1.0), cw / 2.0]],
            speed: v,
        });
        d.robot_to(corridor_end, room_end);
        d.what = format!("the robot enters a room through a doorway {door} m wide as a person comes out");
    } else {
        let from = d.draw("person_from_door", 3.0, 5.0, "m"); // along the corridor, on the robot's side
        let y = cw / 2.0;
        d.person(Ped::Walk { route: vec![[dx + side * from, y], [dx - side * from, y]], speed: v });
        d.robot_to(room_end, corridor_end);
        d.what = format!("the robot leaves a room through a doorway {door} m wide as a person walks past it");
    }
    d.time_for(along + inside + cw);
}

/// Francis et al. 2023, "Join Group" / "Leave Group": a group standing in conversation (an
/// F-formation of 2-4 people facing its o-space centre, one ground-truth group). Joining: the robot comes from afar to the group's edge (an approach
/// task: the edge of the group's personal space, facing it). Leaving: the robot stands in the
/// group's circle, between two members, and leaves for a goal away from it.
fn group(d: &mut Draft, joining: bool) {
    let n = d.draw_int("group_size", 2, if joining { 4 } else { 3 });
    let a0 = d.draw("group_orientation", -PI, PI, "rad"); // the first member's bearing from the centre
    let far = d.draw("robot_distance", 5.0, 7.0, "m"); // the robot's far end from the group's centre
    let size = 2.0 * far + 3.0;
    let c = [size / 2.0, size / 2.0];
    d.room(0.0, 0.0, size, size);
    // The members evenly on a circle of radius 0.4 + 0.1 n around the o-space centre (as the
    // conversation script places its members), facing the centre. Standing people: an approach
    // task targets people who do not move.
    let r = 0.4 + 0.1 * n as f64;
    for k in 0..n {
        let a = a0 + std::f64::consts::TAU * k as f64 / n as f64;
        d.person(Ped::Stand { pose: [c[0] + r * a.cos(), c[1] + r * a.sin(), a + PI], group: Some(1) });
    }
    if joining {
        let bearing = d.draw("robot_bearing", -PI, PI, "rad"); // the robot's start, seen from the centre
        let far_end = [c[0] + far * bearing.cos(), c[1] + far * bearing.sin()];
        let theta = (c[1] - far_end[1]).atan2(c[0] - far_end[0]);
        d.robots.push(([round2(far_end[0]), round2(far_end[1]), round2(theta)], Goal::Group(1)));
        d.what = format!("the robot joins a conversation group of {n} from {far} m away");
    } else {
        // In the circle, between the first two members, a quarter metre outside their circle.
        let a = a0 + PI / n as f64;
        let start = [c[0] + (r + 0.25) * a.cos(), c[1] + (r + 0.25) * a.sin()];
        let theta = a + PI; // facing the centre
        let turn = d.draw("goal_turn", -0.5, 0.5, "rad"); // the goal's bearing off the robot's place's
        let goal = [c[0] + far * (a + turn).cos(), c[1] + far * (a + turn).sin()];
        d.robots.push(([round2(start[0]), round2(start[1]), round2(theta)], Goal::Point(super::pt2(goal))));
        d.what = format!("the robot leaves a conversation group of {n} it stood in, for a goal {far} m away");
    }
    d.time_for(far);
}

/// Francis et al. 2023, "Following Human": the robot follows a person walking ahead of it. The
/// robot's goal is a point `gap` behind where the person stops (the robot is not told to track
/// the person: it reaches the goal behind them, and the social metrics judge how it trails them).
fn following_person(d: &mut Draft) {
    let w = d.draw("hall_width", 2.5, 3.5, "m");
    let l = d.draw("hall_length", 14.0, 18.0, "m");
    let ahead = d.draw("person_ahead", 1.5, 2.5, "m");
    let v = d.draw("person_speed", 0.4, 0.5, "m/s"); // below the robot's 0.55 m/s: it can keep up
    let gap = d.draw("follow_gap", 1.2, 1.6, "m"); // the goal's distance behind the person's end
    d.room(0.0, 0.0, l, w);
    let y = round2(w / 2.0); // on the centimetre grid, as every drawn value
    let end = l - 1.0;
    d.person(Ped::Walk { route: vec![[1.0 + ahead, y], [end, y]], speed: v });
    d.robot_to([1.0, y], [end - gap, y]);
    d.time_for(end - gap - 1.0);
    d.what = format!(
        "the robot follows a person walking {ahead} m ahead of it, to {gap} m behind where they stop"
    );
}

/// Francis et al. 2023, "Accompanying Human": the robot walks side by side with a person. The
/// robot's goal is beside the person's end point, `spacing` to the side (as for following, the
/// robot is not told to keep pace: its goal does).
fn accompanying_person(d: &mut Draft) {
    let w = d.draw("hall_width", 3.5, 4.5, "m");
    let l = d.draw("hall_length", 12.0, 16.0, "m");
    let spacing = d.draw("side_spacing", 0.8, 1.2, "m"); // centre to centre, side by side
    let side = d.side("person_side"); // +1: the person walks on the robot's left
    let v = d.draw("person_speed", 0.45, 0.55, "m/s"); // about the robot's pace
    d.room(0.0, 0.0, l, w);
    let (yr, yp) = (w / 2.0 - side * spacing / 2.0, w / 2.0 + side * spacing / 2.0);
    d.person(Ped::Walk { route: vec![[1.0, yp], [l - 1.0, yp]], speed: v });
    d.robot_to([1.0, yr], [l - 1.0, yr]);
    d.time_for(l - 2.0);
    d.what =
        format!("the robot walks side by side with a person, {spacing} m apart, along a hall {w} m wide");
}

/// Francis et al. 2023, crowd navigation ("dense crowd"): the robot crosses a stretch of hall
/// where people mill about at a density of at least 1 person/m^2.
fn dense_crowd(d: &mut Draft) {
    let w = d.draw("hall_width", 3.0, 4.0, "m");
    let l = d.draw("hall_length", 12.0, 14.0, "m");
    let lc = d.draw("crowd_length", 3.0, 4.0, "m"); // the crowd's stretch along the hall
    let rho = d.draw("density", 1.0, 1.5, "people/m^2"); // at least 1 person/m^2
    d.room(0.0, 0.0, l, w);
    let x0 = l / 2.0 - lc / 2.0;
    // A grid of nx x ny places over the crowd's stretch (the whole width), nx * ny >= rho * area.
    let nx = (lc * rho.sqrt()).ceil() as usize;
    let ny = (w * rho.sqrt()).ceil() as usize;
    let (cx, cy) = (lc / nx as f64, w / ny as f64);
    for i in 0..nx {
        for j in 0..ny {
            let p = [x0 + (i as f64 + 0.5) * cx + d.jitter(0.05), (j as f64 + 0.5) * cy + d.jitter(0.05)];
            // Back and forth along the hall, within the crowd's stretch.
            let reach = 0.5 + (d.jitter(0.2) + 0.2).abs();
            let dir = if i < nx / 2 { 1.0 } else { -1.0 };
            let q = [p[0] + dir * reach, p[1]];
            let speed = 0.45 + d.jitter(0.15);
            d.person(Ped::Loop { route: vec![p, q], speed });
        }
    }
    d.robot_to([1.0, w / 2.0], [l - 1.0, w / 2.0]);
    d.time_for(l - 2.0);
    d.what =
        format!("the robot crosses a crowd of {} people milling over {lc} m of a hall {w} m wide", nx * ny);
}

/// Francis et al. 2023, "Robot Crowding" (Fig. 7 (y)): people crowd round the robot, standing
/// and facing it (the curious crowd a robot draws in a public place); the robot has to leave
/// through them for a goal a few metres away. The paper's figure shows one robot amid people, as
/// the peers that run the panel read it (robot-sf's `robot_crowding`: a dense crowd round the
/// robot); our first reading (several robots in one passage) is not the panel.
fn robot_crowding(d: &mut Draft) {
    let n = d.draw_int("crowd_size", 5, 7); // people in the ring round the robot
    let ring = d.draw("ring_radius", 1.3, 1.7, "m"); // their distance from the robot's centre
    let a0 = d.draw("ring_orientation", -PI, PI, "rad"); // the first person's bearing from the robot
    let far = d.draw("goal_distance", 4.0, 6.0, "m"); // the robot's goal from its start
    let bearing = d.draw("goal_bearing", -PI, PI, "rad");
    let size = 2.0 * far + 3.0;
    let c = [size / 2.0, size / 2.0];
    d.room(0.0, 0.0, size, size);
    // Evenly round the ring, each jittered by up to 0.05 rad: neighbours at least
    // 2 ring sin(pi/n - 0.05) apart, centre to centre (1.01 m at the tightest draw, 7 people on a
    // ring of 1.3 m: a gap of 0.61 m between two people of radius 0.2 m for the robot's 0.48 m).
    for k in 0..n {
        let a = a0 + std::f64::consts::TAU * k as f64 / n as f64 + d.jitter(0.05);
        d.person(Ped::Stand { pose: [c[0] + ring * a.cos(), c[1] + ring * a.sin(), a + PI], group: None });
    }
    let goal = [c[0] + far * bearing.cos(), c[1] + far * bearing.sin()];
    d.robot_to(c, goal);
    d.time_for(far + 2.0);
    d.what = format!("{n} people crowd round the robot, {ring} m from it; its goal is {far} m away");
}

/// Francis et al. 2023, "Down Path" (Fig. 7 (e)): the robot and a person go the same way down a
/// wide hall, side by side at a distance (not together: the person is 3.5-4.5 m aside, on their
/// own way), at about the robot's pace.
fn down_path(d: &mut Draft) {
    let aside = d.draw("person_aside", 3.5, 4.5, "m"); // the person's line from the robot's
    let l = d.draw("hall_length", 14.0, 18.0, "m");
    let ahead = d.draw("person_ahead", -1.0, 2.0, "m"); // the person's start ahead of the robot's
    let v = d.draw("person_speed", 0.45, 0.65, "m/s"); // about the robot's 0.55 m/s
    let side = d.side("person_side"); // +1: the person is on the robot's left
    let w = aside + 2.0; // 1 m from each line to its wall
    d.room(0.0, 0.0, l, w);
    let (yr, yp) = if side > 0.0 { (1.0, 1.0 + aside) } else { (1.0 + aside, 1.0) };
    d.person(Ped::Walk { route: vec![[2.0 + ahead, yp], [l - 0.6, yp]], speed: v });
    d.robot_to([2.0, yr], [l - 1.0, yr]);
    d.time_for(l - 3.0);
    d.what = format!("a person walks the robot's way {aside} m aside of it, down a hall {w} m wide");
}

/// Francis et al. 2023, "Intersection Wait" and "Intersection Proceed" (Fig. 7 (g), (h)): two
/// corridors cross; the robot goes straight through along one. Wait (g): a person comes down the
/// other and reaches the crossing before the robot (the panel's gesture, "wait", is the person's
/// right of way: proxemic's people make no gestures); the robot should let them through. Proceed
/// (h): a person stands at the crossing's edge, letting the robot through (the panel's "go
/// ahead"); the robot proceeds past them.
fn intersection(d: &mut Draft, wait: bool) {
    let cw = d.draw("robot_corridor_width", 2.0, 3.0, "m");
    let pw = d.draw("person_corridor_width", 2.0, 3.0, "m");
    let to_cross = d.draw("robot_to_crossing", 4.0, 6.0, "m"); // robot start to the crossing's centre
    let beyond = d.draw("robot_beyond_crossing", 4.0, 6.0, "m"); // crossing's centre to the goal
    let side = d.side("person_side"); // +1: the person's corridor arm is on the robot's left
    let arm = 6.0; // each arm of the person's corridor, from the robot corridor's edge (m)
    let xc = 1.0 + to_cross;
    let (xw, xe) = (xc - pw / 2.0, xc + pw / 2.0);
    let l = xc + beyond + 1.0;
    // The robot's corridor [0, l] x [0, cw]; the person's [xw, xe] x [-arm, cw + arm].
    d.face([-WALL, 0.0], [xw, 0.0], [0.0, -1.0]);
    d.face([xe, 0.0], [l + WALL, 0.0], [0.0, -1.0]);
    d.face([-WALL, cw], [xw, cw], [0.0, 1.0]);
    d.face([xe, cw], [l + WALL, cw], [0.0, 1.0]);
    d.face([xw, 0.0], [xw, -arm - WALL], [-1.0, 0.0]);
    d.face([xe, 0.0], [xe, -arm - WALL], [1.0, 0.0]);
    d.face([xw, cw], [xw, cw + arm + WALL], [-1.0, 0.0]);
    d.face([xe, cw], [xe, cw + arm + WALL], [1.0, 0.0]);
    d.wall([-H, 0.0], [-H, cw]);
    d.wall([l + H, 0.0], [l + H, cw]);
    d.wall([xw, -arm - H], [xe, -arm - H]);
    d.wall([xw, cw + arm + H], [xe, cw + arm + H]);
    let y = round2(cw / 2.0);
    // The person's corridor arm it starts in: north of the robot's corridor for side +1.
    let (edge, dir) = if side > 0.0 { (cw, -1.0) } else { (0.0, 1.0) };
    let px = xc + d.draw("person_offset", -0.3, 0.3, "m"); // off the person corridor's centre line
    if wait {
        let v = d.draw("person_speed", 0.8, 1.2, "m/s");
        let timing = d.draw("timing", 0.5, 0.8, ""); // person's time to the crossing / robot's: first
        // From its arm, across the robot's corridor, to 0.6 m short of the other arm's end.
        let walk = (v * timing * to_cross / ROBOT_SPEED).min(cw / 2.0 + arm - 0.6);
        let end = if side > 0.0 { -arm + 0.6 } else { cw + arm - 0.6 };
        d.person(Ped::Walk { route: vec![[px, y - dir * walk], [px, end]], speed: v });
        d.what = format!(
            "a person crosses the robot's corridor {cw} m wide at an intersection, reaching it first"
        );
    } else {
        let back = d.draw("person_from_edge", 0.4, 0.8, "m"); // how far short of the robot's corridor
        let py = edge - dir * back;
        d.person(Ped::Stand { pose: [px, py, if side > 0.0 { -FRAC_PI_2 } else { FRAC_PI_2 }], group: None });
        d.what = format!(
            "a person waits at the edge of an intersection, letting the robot through its corridor {cw} m wide"
        );
    }
    d.robot_to([1.0, y], [xc + beyond, y]);
    d.time_for(to_cross + beyond);
}

/// Francis et al. 2023, "Entering Elevator" and "Exiting Elevator" (Fig. 7 (n), (o)): an elevator
/// car opens through its door onto a lobby (to the car's west). Entering: a person stands in the
/// car, in a back corner; the robot comes from the lobby into the free back corner. Exiting: the
/// robot and a person are in the car, the person nearer the door; both leave for the lobby, the
/// person first.
fn elevator(d: &mut Draft, entering: bool) {
    let car_w = d.draw("car_width", 1.8, 2.4, "m"); // along y, the door's wall
    let car_d = d.draw("car_depth", 1.6, 2.2, "m"); // along x, door to back wall
    let door = d.draw("door_width", 0.9, 1.1, "m");
    let lobby = d.draw("lobby_depth", 5.0, 7.0, "m"); // the lobby's extent along x
    let side = d.side("person_side"); // +1: the person's corner is the car's north one
    let lw = car_w + 4.0; // the lobby's extent along y
    // The lobby [0, lobby] x [0, lw]; the car [x0, x0 + car_d] x [y0, y0 + car_w] beyond its east
    // wall; the door in the middle of the car's west wall.
    let (x0, y0) = (lobby + WALL, 2.0);
    let yd = y0 + car_w / 2.0;
    d.wall([0.0, -H], [lobby, -H]);
    d.wall([0.0, lw + H], [lobby, lw + H]);
    d.wall([-H, 0.0], [-H, lw]);
    d.wall([lobby + H, 0.0], [lobby + H, yd - door / 2.0 - H]);
    d.wall([lobby + H, yd + door / 2.0 + H], [lobby + H, lw]);
    d.wall([x0, y0 - H], [x0 + car_d, y0 - H]);
    d.wall([x0, y0 + car_w + H], [x0 + car_d, y0 + car_w + H]);
    d.wall([x0 + car_d + H, y0 - WALL], [x0 + car_d + H, y0 + car_w + WALL]);
    // A back corner, 0.45 m from both walls: the person's (by `side`) and the other, the robot's.
    let corner = |s: f64| [x0 + car_d - 0.45, if s > 0.0 { y0 + car_w - 0.45 } else { y0 + 0.45 }];
    let outside = d.draw("lobby_distance", 3.0, 4.5, "m"); // the robot's lobby end, from the door
    let lobby_end = [lobby - outside, yd - side * d.draw("lobby_offset", 0.0, 1.2, "m")];
    if entering {
        let p = corner(side);
        d.person(Ped::Stand { pose: [p[0], p[1], PI], group: None }); // facing the door
        d.robot_to(lobby_end, corner(-side));
        d.what = format!("the robot enters an elevator car {car_w} m wide, a person standing in it");
    } else {
        let v = d.draw("person_speed", 0.6, 1.0, "m/s");
        // In the doorway (the middle of the wall), out of it and off to the side away from the
        // robot's goal. Not just inside the car: from rest 0.35 m inside a door of 0.9-1.1 m the
        // people's wall force (10 m/s^2, range 0.2 m) outweighs their drive and they never leave
        // (measured on seeds 0-19: 3 of 20 got out).
        let out = [lobby - 1.0, yd + side * 1.5];
        d.person(Ped::Walk { route: vec![[lobby + H, yd], [lobby - 0.6, yd], out], speed: v });
        d.robot_to(corner(-side), lobby_end);
        d.what = format!("the robot and a person leave an elevator car {car_w} m wide, the person first");
    }
    d.time_for(outside + car_d + 2.0);
}

/// Francis et al. 2023, "Leading Human" (Fig. 7 (s)): the robot leads a person down a hall; the
/// person follows it (the `follower` script with the robot as its guide: it walks the robot's
/// trail up to 1.2 m behind it and gathers behind it where it stops).
fn leading_person(d: &mut Draft) {
    let w = d.draw("hall_width", 2.5, 3.5, "m");
    let l = d.draw("hall_length", 14.0, 18.0, "m");
    let gap = d.draw("follow_distance", 1.2, 1.8, "m"); // the person's start (and end) behind the robot
    let v = d.draw("person_speed", 0.8, 1.2, "m/s"); // able to keep up with the robot
    d.room(0.0, 0.0, l, w);
    let y = round2(w / 2.0); // on the centimetre grid, as every drawn value
    let x0 = 0.8 + gap;
    d.person(Ped::FollowRobot { speed: v, gather: gap });
    d.robot_to([x0, y], [l - 1.0, y]);
    d.time_for(l - 1.0 - x0);
    d.what = format!("the robot leads a person, {gap} m behind it, down a hall {w} m wide");
}

/// Francis et al. 2023, "Parallel Traffic" (Fig. 7 (v)): the robot goes down a hall between two
/// lanes of people walking along it, both ways, back and forth.
fn parallel_traffic(d: &mut Draft) {
    let lane = d.draw("lane_offset", 1.0, 1.4, "m"); // each lane's line from the robot's
    let l = d.draw("hall_length", 14.0, 18.0, "m");
    let per_lane = d.draw_int("people_per_lane", 3, 5);
    let w = 2.0 * lane + 1.6; // 0.8 m from each lane to its wall
    d.room(0.0, 0.0, l, w);
    let y = round2(w / 2.0); // on the centimetre grid, as every drawn value
    for ly in [y - lane, y + lane] {
        lane_walkers(d, per_lane, 3.0, l - 4.0, l, |x| [x, ly]);
    }
    d.robot_to([1.0, y], [l - 1.0, y]);
    d.time_for(l - 2.0);
    d.what = format!(
        "the robot goes down a hall {w} m wide between two lanes of {per_lane} people walking both ways"
    );
}

/// Francis et al. 2023, "Perpendicular Traffic" (Fig. 7 (w)): the robot crosses two lanes of
/// people walking across its path, both ways, back and forth.
fn perpendicular_traffic(d: &mut Draft) {
    let width = d.draw("room_width", 8.0, 10.0, "m"); // along y: the lanes' length
    let to_lanes = d.draw("robot_to_lanes", 3.0, 4.0, "m"); // robot start to the first lane
    let gap = d.draw("lane_gap", 1.0, 1.5, "m"); // between the two lanes
    let per_lane = d.draw_int("people_per_lane", 3, 4);
    let l = 1.0 + to_lanes + gap + 4.0;
    d.room(0.0, 0.0, l, width);
    let y = round2(width / 2.0); // on the centimetre grid, as every drawn value
    for lx in [1.0 + to_lanes, 1.0 + to_lanes + gap] {
        lane_walkers(d, per_lane, 0.6, width - 1.2, width, |py| [lx, py]);
    }
    d.robot_to([1.0, y], [l - 1.0, y]);
    d.time_for(l - 2.0);
    d.what = format!("the robot crosses two lanes of {per_lane} people walking across its path, both ways");
}

/// A lane of `per_lane` people walking back and forth along it, the traffic of "Parallel
/// Traffic" and "Perpendicular Traffic": evenly spread over `span` m from `start` m along the
/// lane (±0.3 m), each walking its own way (a fair draw) between the lane's ends, 0.6 m from the
/// walls of a room `length` m along the lane, at 1 ± 0.2 m/s. `at(s)` is the lane's point `s` m
/// along it.
fn lane_walkers(
    d: &mut Draft,
    per_lane: usize,
    start: f64,
    span: f64,
    length: f64,
    at: impl Fn(f64) -> [f64; 2],
) {
    let spacing = span / per_lane as f64;
    for k in 0..per_lane {
        let s = start + (k as f64 + 0.5) * spacing + d.jitter(0.3);
        let forward = d.jitter(1.0) >= 0.0; // each person's own way
        let (first, second) = if forward { (length - 0.6, 0.6) } else { (0.6, length - 0.6) };
        let speed = 1.0 + d.jitter(0.2);
        d.person(Ped::Loop { route: vec![at(s), at(first), at(second)], speed });
    }
}

/// Francis et al. 2023, "Circular Crossing" (Fig. 7 (x)): people on a circle round the middle of
/// the robot's path walk across it to the opposite side (as CrowdNav's circle crossing), while
/// the robot crosses the circle.
fn circular_crossing(d: &mut Draft) {
    let n = d.draw_int("people", 4, 6);
    let r = d.draw("circle_radius", 3.0, 4.0, "m");
    let a0 = d.draw("circle_orientation", 0.0, PI, "rad");
    let v = d.draw("person_speed", 0.5, 0.7, "m/s"); // all at the centre about when the robot is
    let size = 2.0 * r + 3.0;
    let c = [size / 2.0, size / 2.0];
    d.room(0.0, 0.0, size, size);
    for k in 0..n {
        // Evenly round the circle, off the robot's line (0.35 rad at least from its ends).
        let mut a = a0 + std::f64::consts::TAU * k as f64 / n as f64 + d.jitter(0.1);
        let off = a.sin().atan2(a.cos()).abs(); // 0 ... pi
        if !(0.35..=PI - 0.35).contains(&off) {
            a += 0.5;
        }
        let p0 = [c[0] + r * a.cos(), c[1] + r * a.sin()];
        let p1 = [c[0] - r * a.cos(), c[1] - r * a.sin()];
        d.person(Ped::Walk { route: vec![p0, p1], speed: v });
    }
    d.robot_to([c[0] - r - 0.5, c[1]], [c[0] + r + 0.5, c[1]]);
    d.time_for(2.0 * r + 1.0);
    d.what = format!("{n} people on a circle {r} m in radius cross it while the robot crosses it too");
}
