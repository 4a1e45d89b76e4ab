//! The social model (`[proxemics]`): Hall's zones, the personal-space sigmas, the cost map's
//! factors, group detection, and each person's socialization features.

use crate::error::{CoreError, Result};
use crate::scenario::check::{Checker, err};
use crate::scenario::model::Proxemics;
use crate::scenario::raw::{RawPerson, RawProxemics};

/// Validates `[proxemics]` by building the social model it describes.
pub(super) fn build_proxemics(ck: &Checker<'_>, r: &RawProxemics) -> Result<Proxemics> {
    let file = ck.file;
    let zones = zone_radii(ck, r)?;
    let sigmas = base_sigmas(ck, r)?;
    if !matches!(r.cost_mode.as_str(), "zones" | "continuous") {
        return Err(err(
            file,
            "proxemics.cost_mode",
            "\"zones\" or \"continuous\"",
            format!("{:?}", r.cost_mode),
        ));
    }
    ck.range("proxemics.public_cost", r.public_cost, 1.0, 5.0, false)?;
    ck.range("proxemics.social_cost", r.social_cost, r.public_cost, 5.0, false)?;
    ck.range("proxemics.personal_cost", r.personal_cost, r.social_cost, 5.0, false)?;
    ck.range("proxemics.continuous_gain", r.continuous_gain, 0.0, 4.0, false)?;
    if !matches!(r.groups.as_str(), "delaunay" | "density" | "fformation" | "none") {
        return Err(err(
            file,
            "proxemics.groups",
            "\"delaunay\", \"density\", \"fformation\" or \"none\"",
            format!("{:?}", r.groups),
        ));
    }
    let d_max = r.d_max.unwrap_or(1.5);
    ck.range("proxemics.d_max", d_max, 0.0, 20.0, true)?;
    if !matches!(r.aggregate.as_str(), "mean" | "min" | "mode") {
        return Err(err(
            file,
            "proxemics.aggregate",
            "\"mean\", \"min\" or \"mode\"",
            format!("{:?}", r.aggregate),
        ));
    }
    let influence = influence_vectors(ck, r)?;
    Ok(Proxemics {
        zones,
        space: r.space.clone(),
        sigmas,
        cost_mode: r.cost_mode.clone(),
        personal_cost: r.personal_cost,
        social_cost: r.social_cost,
        public_cost: r.public_cost,
        continuous_gain: r.continuous_gain,
        groups: r.groups.clone(),
        d_max,
        orientation_rule: r.orientation_rule.unwrap_or(true),
        aggregate: r.aggregate.clone(),
        features: r.features.clone(),
        influence,
    })
}

/// Hall's zone radii `[intimate, personal, social]`: a named preset or `zone_radii`.
fn zone_radii(ck: &Checker<'_>, r: &RawProxemics) -> Result<[f64; 3]> {
    let file = ck.file;
    let zones = match (r.zones.as_str(), r.zone_radii) {
        (_, Some(radii)) => radii,
        ("evaluation", None) => [0.45, 1.2, 3.6],
        ("daza2021", None) => [0.5, 1.0, 4.0],
        (other, None) => {
            return Err(err(
                file,
                "proxemics.zones",
                "\"evaluation\" or \"daza2021\" (or zone_radii = [i, p, s])",
                format!("{other:?}"),
            ));
        }
    };
    crate::proxemics::HallZones::new(zones[0], zones[1], zones[2])
        .map_err(|e| prefix_input(file, "proxemics.zone_radii", e))?;
    Ok(zones)
}

/// The personal-space sigmas `[front, rear, right, left]`: the `space` preset's, then `sigma`,
/// then each side's override.
fn base_sigmas(ck: &Checker<'_>, r: &RawProxemics) -> Result<[f64; 4]> {
    let file = ck.file;
    let mut sigmas = match r.space.as_str() {
        "calderita" => [2.0, 1.0, 4.0 / 3.0, 4.0 / 3.0],
        "daza2021" => [1.0; 4],
        "sousa2022" => [1.0; 4],
        other => {
            return Err(err(
                file,
                "proxemics.space",
                "\"calderita\", \"daza2021\" or \"sousa2022\"",
                format!("{other:?}"),
            ));
        }
    };
    if let Some(sg) = r.sigma {
        ck.range("proxemics.sigma", sg, 0.0, 20.0, true)?;
        sigmas = [sg; 4];
    }
    for (k, (name, v)) in [
        ("sigma_front", r.sigma_front),
        ("sigma_rear", r.sigma_rear),
        ("sigma_right", r.sigma_right),
        ("sigma_left", r.sigma_left),
    ]
    .into_iter()
    .enumerate()
    {
        if let Some(v) = v {
            ck.range(&format!("proxemics.{name}"), v, 0.0, 20.0, true)?;
            sigmas[k] = v;
        }
    }
    Ok(sigmas)
}

/// The influence vectors `[front, rear, right, left]`, one value in [-1, 1] per feature each
/// (zeros when a side is not given).
fn influence_vectors(ck: &Checker<'_>, r: &RawProxemics) -> Result<[Vec<f64>; 4]> {
    let file = ck.file;
    let nf = r.features.len();
    let inf = &r.influence;
    let mut influence: [Vec<f64>; 4] =
        [inf.front.clone(), inf.rear.clone(), inf.right.clone(), inf.left.clone()];
    for (side, v) in ["front", "rear", "right", "left"].iter().zip(influence.iter_mut()) {
        if v.is_empty() {
            *v = vec![0.0; nf];
        }
        if v.len() != nf {
            return Err(err(
                file,
                format!("proxemics.influence.{side}"),
                format!("{nf} value(s), one per feature in proxemics.features"),
                format!("{} value(s)", v.len()),
            ));
        }
        for (k, x) in v.iter().enumerate() {
            ck.range(&format!("proxemics.influence.{side}[{k}]"), *x, -1.0, 1.0, false)?;
        }
    }
    Ok(influence)
}

/// The features of a person who gives none: 0.5 each, 0.70 for `emotional_state`.
pub(super) fn default_features(names: &[String]) -> Vec<f64> {
    names.iter().map(|n| if n == "emotional_state" { 0.70 } else { 0.5 }).collect()
}

/// A person's feature vector: explicit `features`, or the emotional state looked up in Sousa
/// 2022 Table 1; features not given default to their neutral value (0.70 for the emotional
/// state, 0.5 otherwise).
pub(super) fn person_features(
    ck: &Checker<'_>,
    i: usize,
    raw: &RawPerson,
    names: &[String],
) -> Result<Vec<f64>> {
    let file = ck.file;
    let f = format!("person[{i}]");
    let mut fv = default_features(names);
    if !raw.features.is_empty() {
        if raw.features.len() != names.len() {
            return Err(err(
                file,
                format!("{f}.features"),
                format!("{} value(s), one per name in proxemics.features {names:?}", names.len()),
                format!("{} value(s)", raw.features.len()),
            ));
        }
        for (k, v) in raw.features.iter().enumerate() {
            ck.range(&format!("{f}.features[{k}]"), *v, 0.0, 1.0, true)?;
        }
        fv.clone_from(&raw.features);
    }
    if let Some(state) = &raw.emotional_state {
        let k = names.iter().position(|n| n == "emotional_state").ok_or_else(|| {
            err(
                file,
                format!("{f}.emotional_state"),
                "\"emotional_state\" listed in proxemics.features",
                "a scenario without it",
            )
        })?;
        fv[k] = crate::proxemics::emotional_state_value(state).ok_or_else(|| {
            err(
                file,
                format!("{f}.emotional_state"),
                format!("one of {:?}", crate::proxemics::EMOTIONAL_STATES),
                format!("{state:?}"),
            )
        })?;
    }
    Ok(fv)
}
/// Re-labels a core input error as a scenario error under `field`.
fn prefix_input(file: &str, field: &str, e: CoreError) -> CoreError {
    match e {
        CoreError::Input { field: inner, expected, found } => {
            err(file, format!("{field} ({inner})"), expected, found)
        }
        other => other,
    }
}
