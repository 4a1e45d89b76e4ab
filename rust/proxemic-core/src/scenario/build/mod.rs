//! From the raw file tables to the validated [`Scenario`]: every value checked (errors name the
//! file and the dotted field), defaults filled in, names resolved to indices, world-frame polygons
//! computed. [`build`] runs the steps in file order, each in its own file; the first failing check
//! is the error reported.

mod objects;
pub(super) mod people;
pub(super) mod polygons;
mod proxemics;
pub(super) mod replay;
mod robots;
mod scene;

use super::check::{Checker, err};
use super::model::{Episode, Scenario};
use super::raw::{RawEpisode, RawScenario};
use super::{RewardWeights, Sensors};
use crate::error::Result;

/// Checks the raw scenario read from `file` and builds the validated one.
pub(super) fn build(raw: RawScenario, file: &str) -> Result<Scenario> {
    let ck = Checker { file };
    let scene = scene::build_scene(&ck, &raw.scene)?;
    let b = scene.bounds;
    let walls = scene::build_walls(&ck, &raw.wall, scene.wall_height, scene.bounds)?;
    let objects = objects::build_objects(&ck, &raw.object, b)?;
    let mut persons = people::build_people(&ck, &raw.person, &objects, scene.start_time, b)?;

    let proxemics = proxemics::build_proxemics(&ck, &raw.proxemics)?;
    for (i, (person, rp)) in persons.iter_mut().zip(&raw.person).enumerate() {
        person.features = proxemics::person_features(&ck, i, rp, &proxemics.features)?;
    }
    let replayed =
        replay::build_replays(&ck, &raw.replay, file, b, &proxemics::default_features(&proxemics.features))?;
    persons.extend(replayed);
    people::assign_reactions(&ck, &raw.person, &raw.group, raw.scene.reaction, &mut persons)?;
    let (agenda, activities) = objects::build_agenda(&ck, &raw.agenda, &raw.activity, &objects)?;

    let robots = robots::build_robots(&ck, &raw.robot, &persons, &proxemics, b)?;
    people::link_robot_guides(&ck, &raw.person, &mut persons, &robots)?;
    robots::check_robot_starts(file, &robots)?;

    check_settings(&ck, &raw.episode, &raw.sensors, &raw.reward)?;
    let e = &raw.episode;
    robots::check_start_clearances(
        file,
        &robots,
        &persons,
        e.randomize.robot_start_jitter,
        e.success_radius,
        b,
    )?;
    robots::check_people_apart(file, &persons)?;
    objects::check_spaces_face_the_room(file, &objects, &walls, b)?;
    scene::check_rates(file, &scene, &robots)?;
    Ok(Scenario {
        source: file.to_string(),
        scene,
        walls,
        objects,
        persons,
        robots,
        episode: Episode {
            max_time: e.max_time,
            success_radius: e.success_radius,
            randomize: e.randomize.clone(),
        },
        sensors: raw.sensors,
        reward: raw.reward,
        proxemics,
        agenda,
        activities,
    })
}

/// Checks `[episode]`, `[sensors]` and `[reward]`.
fn check_settings(ck: &Checker<'_>, e: &RawEpisode, sn: &Sensors, rw: &RewardWeights) -> Result<()> {
    let file = ck.file;
    ck.range("episode.max_time", e.max_time, 0.0, 86400.0, true)?;
    ck.range("episode.success_radius", e.success_radius, 0.0, 10.0, true)?;
    ck.range("episode.randomize.speed_jitter", e.randomize.speed_jitter, 0.0, 0.5, false)?;
    ck.range("episode.randomize.robot_start_jitter", e.randomize.robot_start_jitter, 0.0, 5.0, false)?;
    if !(4..=1440).contains(&sn.lidar_rays) {
        return Err(err(file, "sensors.lidar_rays", "an integer in [4, 1440]", sn.lidar_rays.to_string()));
    }
    ck.range("sensors.lidar_range", sn.lidar_range, 0.0, 50.0, true)?;
    if !(1..=64).contains(&sn.k_nearest) {
        return Err(err(file, "sensors.k_nearest", "an integer in [1, 64]", sn.k_nearest.to_string()));
    }
    ck.range("sensors.subgoal", sn.subgoal, 0.0, 10.0, false)?;
    for (name, v) in [
        ("progress", rw.progress),
        ("success", rw.success),
        ("collision", rw.collision),
        ("time", rw.time),
        ("personal_space", rw.personal_space),
    ] {
        ck.range(&format!("reward.{name}"), v, -1e6, 1e6, false)?;
    }
    Ok(())
}
