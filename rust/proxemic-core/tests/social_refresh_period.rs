//! The `social` planner's refresh (a re-plan without a trigger, kept only when it is worth a
//! change of way) runs every 2 s on maps whose searches are small, and less often after a search
//! that expanded more than 100,000 cells, so that refreshes cost about 5,000 expanded cells per
//! control step on average: a hall of 100 x 60 m full of people is refreshed far less often.
//!
//! The robot drives on its built-in planner, simulated kinematically (its commands integrated
//! exactly); the people stand still, so nothing triggers a re-plan and every search after the
//! first is a refresh.

use proxemic_core::scenario::Scenario;

mod common;
use common::Drive;

/// A hall of `width` x `height` m with people standing on a 2.2 m lattice (none within 3 m of
/// the robot's start or goal, on the hall's middle line) and one `social` robot crossing it.
fn hall(width: f64, height: f64) -> String {
    let mid = height / 2.0;
    let mut s = format!(
        "[scene]\nname = \"lattice\"\nbounds = [0, 0, {width}, {height}]\n\
         [[wall]]\nfrom = [0, 0]\nto = [{width}, 0]\n[[wall]]\nfrom = [{width}, 0]\nto = [{width}, {height}]\n\
         [[wall]]\nfrom = [{width}, {height}]\nto = [0, {height}]\n[[wall]]\nfrom = [0, {height}]\nto = [0, 0]\n\
         [[robot]]\nstart = [2, {mid}, 0]\ngoal = [{}, {mid}]\nplanner = \"social\"\n\
         [episode]\nmax_time = 300\n",
        width - 2.0
    );
    let (mut x, mut k) = (5.0, 0);
    while x < width - 4.0 {
        let mut y = 3.0 + if k % 2 == 1 { 1.1 } else { 0.0 };
        while y < height - 2.0 {
            s += &format!(
                "[[person]]\nbehaviour = \"standing\"\npose = [{x:.2}, {y:.2}, {:.2}]\n",
                0.7 * f64::from(k)
            );
            y += 2.2;
        }
        x += 2.2;
        k += 1;
    }
    s
}

/// Social searches of the robot in the first `steps` control steps of an episode.
fn searches(scene: &str, steps: usize) -> usize {
    let s = Scenario::from_toml_str(scene, "lattice").expect("the lattice hall is a valid scenario");
    let mut d = Drive::start(s, 0);
    for _ in 0..steps {
        d.drive();
    }
    d.world.social_searches(0)
}

#[test]
fn a_small_hall_is_refreshed_every_two_seconds() {
    // The first plan at the reset, then refreshes at the first checks 2 s later: steps 21, 42, 63, 84.
    assert_eq!(searches(&hall(24.0, 16.0), 100), 5);
}

#[test]
fn a_large_crowded_hall_is_refreshed_less_often() {
    // The first plan expands over 100,000 cells: one refresh in 10 s (five at the 2 s period).
    assert_eq!(searches(&hall(100.0, 60.0), 100), 2);
}
