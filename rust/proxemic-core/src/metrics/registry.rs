//! The metric reference: one [`MetricInfo`] per key of a serialised [`super::EpisodeReport`]
//! (name, unit, which direction is better, definition, formula, source paper).
//!
//! It is the one source of truth for what a metric means: the Python bindings expose it
//! (`proxemic._core.metric_registry()`), and from it come the metric tables of `docs/metrics.md`,
//! the `metrics.json` column descriptions that `proxemic eval` writes beside its records, the
//! plot and summary labels with their units, and what the evaluation summarises and shows: each
//! metric's summary (rate or mean, and its digits), its panel of the metrics plot, whether it is a
//! headline column and how verdicts compare it. The serialised report lists its keys in this
//! table's order ([`super::EpisodeReport`]'s `Serialize`); tests check that the registry and the
//! serialised report have the same keys in the same order.
//!
//! The file is over 800 lines by design, the one exception to the core's file size: it is a data
//! table, one entry per metric in the order of the reference and of the records (definitions,
//! formulas and sources), and
//! splitting it would split that one ordered list; the code around the table is about 110 lines.

use serde::Serialize;

/// Which direction of a metric is better for a socially-aware robot, all else equal.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Better {
    /// Larger values are better.
    Higher,
    /// Smaller values are better.
    Lower,
    /// A descriptive value: neither direction is better.
    Neither,
}

/// What one value of a metric describes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Per {
    /// One value per robot episode.
    Episode,
    /// A list with one value per person (scenario order); flat records have one column
    /// `<key>_<person name>` per person.
    Person,
    /// A list with one value per object with an interaction space (scenario order); flat records
    /// have one column `<key>_<object name>` per object.
    Object,
}

/// The reference entry of one metric.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MetricInfo {
    /// Key in the serialised report (and column of the records, or column prefix when
    /// [`MetricInfo::per`] is not [`Per::Episode`]).
    pub key: &'static str,
    /// Section of the reference it belongs to (e.g. `"Efficiency"`).
    pub family: &'static str,
    /// Short label for tables and plots (e.g. `"personal-zone time"`).
    pub label: &'static str,
    /// Unit (`"m"`, `"s"`, `"%"` ...); `""` for a dimensionless number, `"bool"` for a flag.
    pub unit: &'static str,
    /// Which direction is better.
    pub better: Better,
    /// Lowest possible value, when bounded (e.g. 0 for a length).
    pub low: Option<f64>,
    /// Highest possible value, when bounded (e.g. 100 for a percentage).
    pub high: Option<f64>,
    /// One value per episode, person or object.
    pub per: Per,
    /// What it measures, in words, and when it is undefined (`None`).
    pub definition: &'static str,
    /// How it is computed (notation of `docs/metrics.md`); `""` when the definition says it all.
    pub formula: &'static str,
    /// Where it comes from (paper, benchmark); `""` for the project's own.
    pub source: &'static str,
    /// How `proxemic eval` summarises it over episodes, if it does.
    pub summary: Option<Summary>,
    /// Whether a summarised mean is taken over the successful episodes only (a value measured on
    /// an episode that a collision or the time limit cut short is left out of it).
    pub over_successes: bool,
    /// Digits after the decimal point of a summarised mean (its value and interval); rates are
    /// shown as whole percentages. Default 2.
    pub decimals: u8,
    /// The panel of the evaluation's metrics plot (`metrics.png`) showing it, if any.
    pub panel: Option<Panel>,
    /// Whether it is a column of the evaluation's headline table (terminal and `summary.md`).
    pub headline: bool,
    /// How the evaluation's verdicts compare two planners on it, if they do.
    pub verdict: Option<Verdict>,
}

/// How `proxemic eval` summarises a metric over a planner's episodes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Summary {
    /// A 0/1 flag per episode, summarised as the share of episodes with a 95% Wilson interval.
    Rate,
    /// A number per episode, summarised as the mean of the defined values with a 95% Student t
    /// interval (clipped to the metric's bounds).
    Mean,
}

/// The panels of the evaluation's metrics plot, in its rows' order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Panel {
    /// Episode outcomes (rates).
    Outcome,
    /// Time, length and efficiency.
    Efficiency,
    /// Distances to people, zone time shares and interaction crossings.
    Social,
    /// The source papers' own metrics (Daza 2021's L_ratio and Smooth; Calderita et al.'s CHC and
    /// object-space time).
    Papers,
}

/// How a verdict says the ratio of two planners' means of a metric.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// As a factor (`1.20x time to goal`).
    Times,
    /// As a relative change (`55% less personal-zone time`).
    Share,
}

#[allow(clippy::too_many_arguments, reason = "one argument per column of the reference, in its order")]
const fn m(
    key: &'static str,
    family: &'static str,
    label: &'static str,
    unit: &'static str,
    better: Better,
    bounds: (Option<f64>, Option<f64>),
    definition: &'static str,
    formula: &'static str,
    source: &'static str,
) -> MetricInfo {
    MetricInfo {
        key,
        family,
        label,
        unit,
        better,
        low: bounds.0,
        high: bounds.1,
        per: Per::Episode,
        definition,
        formula,
        source,
        summary: None,
        over_successes: false,
        decimals: 2,
        panel: None,
        headline: false,
        verdict: None,
    }
}

const fn per(info: MetricInfo, per: Per) -> MetricInfo {
    MetricInfo { per, ..info }
}

impl MetricInfo {
    /// Summarised as a rate (a 0/1 flag per episode).
    const fn rate(self) -> Self {
        MetricInfo { summary: Some(Summary::Rate), ..self }
    }

    /// Summarised as a mean shown with `decimals` digits after the point.
    const fn mean(self, decimals: u8) -> Self {
        MetricInfo { summary: Some(Summary::Mean), decimals, ..self }
    }

    /// Its summarised mean taken over the successful episodes only.
    const fn over_successes(self) -> Self {
        MetricInfo { over_successes: true, ..self }
    }

    /// Shown on `panel` of the metrics plot.
    const fn panel(self, panel: Panel) -> Self {
        MetricInfo { panel: Some(panel), ..self }
    }

    /// A column of the headline table.
    const fn headline(self) -> Self {
        MetricInfo { headline: true, ..self }
    }

    /// Compared in the verdicts, said as `verdict`.
    const fn verdict(self, verdict: Verdict) -> Self {
        MetricInfo { verdict: Some(verdict), ..self }
    }
}

use Better::{Higher, Lower, Neither};
use Panel::{Efficiency, Outcome, Papers, Social};
use Verdict::{Share, Times};

const OUTCOME: &str = "Outcome and collisions";
const EFFICIENCY: &str = "Efficiency";
const MOTION: &str = "Motion quality";
const PEOPLE: &str = "Distance to people";
const GROUPS: &str = "Groups and interactions";
const OBJECTS: &str = "Objects (time-dependent spaces)";
const STATIC: &str = "Static geometry";
const SNQI: &str = "SNQI inputs";
const RECOVERY: &str = "Progress monitor";

/// The sources of the who-approached-whom zone metrics.
const SRC_APPROACH: &str =
    "Hall 1966 (zones); SEAN 2.0, HuNavSim (robot- and person-caused); ours (body gaps, per step)";

const NONE: (Option<f64>, Option<f64>) = (None, None);
const POS: (Option<f64>, Option<f64>) = (Some(0.0), None);
const FLAG: (Option<f64>, Option<f64>) = (Some(0.0), Some(1.0));
const PCT: (Option<f64>, Option<f64>) = (Some(0.0), Some(100.0));

/// Every metric of a robot's episode report, in the reference's order.
pub const METRICS: &[MetricInfo] = &[
    // Outcome
    m(
        "outcome",
        OUTCOME,
        "outcome",
        "",
        Neither,
        NONE,
        "How the episode ended: `success`, `collision` or `timeout` (`running` before the end). A \
         collision (a contact with walls, furniture or another robot, or with a person while the \
         robot moved toward them: physics contact, or a negative surface gap anywhere on the \
         relative motion swept over a step) ends the episode before the goal does; reaching the \
         goal ends it before the time limit. A person walking into a robot that is stopped or \
         moving away does not end it (`collisions_person_fault`).",
        "",
        "Francis et al. 2023; CrowdNav's swept test",
    ),
    m(
        "success",
        OUTCOME,
        "success",
        "bool",
        Higher,
        FLAG,
        "The robot centre came within the success radius of the goal with no collision in a step \
         ending at or before that instant: no contact with walls, furniture or another robot, and \
         no person contact that is the robot's fault. Person-at-fault contacts (a person walking \
         into a stopped robot) do not fail it.",
        "",
        "Francis et al. 2023 (S)",
    )
    .rate()
    .panel(Outcome)
    .headline(),
    m(
        "collision",
        OUTCOME,
        "collision",
        "bool",
        Lower,
        FLAG,
        "A collision that ends the episode: with walls, furniture or another robot, or with a \
         person by the robot's fault (`collisions_robot_fault`).",
        "",
        "Francis et al. 2023 (C)",
    )
    .rate()
    .headline(),
    m(
        "timeout",
        OUTCOME,
        "timeout",
        "bool",
        Lower,
        FLAG,
        "Neither success nor collision.",
        "",
        "Francis et al. 2023 (TO)",
    )
    .rate()
    .panel(Outcome),
    m(
        "hc_count",
        OUTCOME,
        "person-collision steps",
        "steps",
        Lower,
        POS,
        "Steps with a person collision: the physics' person contact, or a negative surface gap on \
         the swept relative motion, with a person present over the step (a physics contact with a \
         replayed person leaving in the step is none); whoever's fault (`collisions_robot_fault`, \
         `collisions_person_fault`).",
        "",
        "Francis et al. 2023 (HC)",
    ),
    m(
        "hc",
        OUTCOME,
        "collision with a person",
        "bool",
        Lower,
        FLAG,
        "Some step had a person collision.",
        "`hc_count > 0`",
        "Francis et al. 2023 (HC)",
    )
    .rate()
    .panel(Outcome),
    m(
        "wc_count",
        OUTCOME,
        "wall-collision steps",
        "steps",
        Lower,
        POS,
        "Steps with a contact with walls or furniture.",
        "",
        "Francis et al. 2023 (WC)",
    ),
    m(
        "wc",
        OUTCOME,
        "collision with walls/furniture",
        "bool",
        Lower,
        FLAG,
        "Some step had a contact with walls or furniture.",
        "`wc_count > 0`",
        "Francis et al. 2023 (WC)",
    )
    .rate()
    .panel(Outcome),
    m(
        "ac_count",
        OUTCOME,
        "robot-collision steps",
        "steps",
        Lower,
        POS,
        "Steps with a contact with another robot.",
        "",
        "Francis et al. 2023 (AC)",
    ),
    m(
        "ac",
        OUTCOME,
        "collision with a robot",
        "bool",
        Lower,
        FLAG,
        "Some step had a contact with another robot.",
        "`ac_count > 0`",
        "Francis et al. 2023 (AC)",
    ),
    m(
        "min_robot_gap",
        OUTCOME,
        "closest robot",
        "m (surface)",
        Higher,
        NONE,
        "Smallest surface gap to another robot over the instants (negative: overlap); `None` for a \
         robot alone.",
        "",
        "",
    ),
    m("steps", OUTCOME, "steps", "steps", Neither, POS, "Control steps of the episode.", "`T`", ""),
    m("duration", OUTCOME, "duration", "s", Neither, POS, "Episode duration.", "`T · dt`", ""),
    // Efficiency
    m(
        "time_to_goal",
        EFFICIENCY,
        "time to goal",
        "s",
        Lower,
        POS,
        "First instant within the success radius, in seconds; `None` without success.",
        "",
        "CrowdNav \"navigation time\"",
    )
    .mean(1)
    .panel(Efficiency)
    .headline()
    .verdict(Times),
    m(
        "path_length",
        EFFICIENCY,
        "path length",
        "m",
        Lower,
        POS,
        "Length of the executed path.",
        "`Σ_t |p_t+1 − p_t|`",
        "Francis et al. 2023 (PL)",
    )
    .mean(1)
    .panel(Efficiency)
    .verdict(Times),
    m(
        "d_t",
        EFFICIENCY,
        "distance travelled",
        "m",
        Lower,
        POS,
        "Calderita et al.'s distance travelled; equal to `path_length`.",
        "",
        "Calderita et al., Tables 1–2",
    ),
    m(
        "tau",
        EFFICIENCY,
        "navigation time",
        "s",
        Lower,
        POS,
        "Calderita et al.'s navigation time.",
        "`T · dt`",
        "Calderita et al., Tables 1–2",
    ),
    m(
        "geodesic_length",
        EFFICIENCY,
        "geodesic length",
        "m",
        Neither,
        POS,
        "`ℓ*`, the shortest collision-free start–goal length on the robot's inflated grid; `None` \
         when unreachable.",
        "",
        "",
    ),
    m(
        "path_length_ratio",
        EFFICIENCY,
        "path length ratio",
        "x geodesic",
        Lower,
        POS,
        "Executed path length over the geodesic length (≥ 1 up to grid effects); `None` when `ℓ*` \
         is not finite or ≈ 0. `proxemic eval` averages it over the successful episodes only: a \
         collision or the time limit cuts the path short, which would make the ratio look better.",
        "`path_length / ℓ*`",
        "SocNavBench (with a geodesic `ℓ*` because of walls)",
    )
    .mean(2)
    .over_successes()
    .panel(Efficiency)
    .headline(),
    m(
        "spl",
        EFFICIENCY,
        "SPL",
        "",
        Higher,
        FLAG,
        "Success weighted by path length: 0 on failure, 1 for a success along the geodesic.",
        "`S · ℓ* / max(PL, ℓ*)`",
        "Anderson et al. 2018",
    )
    .mean(2)
    .panel(Efficiency),
    m(
        "failure_to_progress",
        EFFICIENCY,
        "failures to progress",
        "windows",
        Lower,
        POS,
        "Non-overlapping 5 s windows in which the straight-line distance to the goal fell by less \
         than 0.1 m.",
        "",
        "Francis et al. 2023 (FP)",
    ),
    m(
        "stalled_time",
        EFFICIENCY,
        "stalled time",
        "s",
        Lower,
        POS,
        "Time spent nearly still: steps with speed below 0.001 m/s and yaw rate below 0.01 rad/s, \
         times `dt`.",
        "",
        "HuNavSim, SEAN 2.0",
    ),
    m(
        "astar_length",
        EFFICIENCY,
        "A* length",
        "m",
        Neither,
        POS,
        "Daza et al.'s `D_A*`: length of the plain A* path from the episode's start to the goal.",
        "",
        "Daza et al. 2021",
    ),
    m(
        "l_ratio",
        EFFICIENCY,
        "L_ratio",
        "",
        Higher,
        POS,
        "The A* length over the social path's length to the goal: the executed path plus the straight rest from its last point (inside the success radius) to the goal, so both run to the goal as in the paper (≤ 1 against a shortest reference; success only, else `None`).",
        "`D_A* / (path_length + |p_T − goal|)`",
        "Daza et al. 2021, eq. 1",
    )
    .mean(2)
    .panel(Papers)
    .verdict(Times),
    // Motion quality
    m(
        "vel_min",
        MOTION,
        "min speed",
        "m/s",
        Neither,
        POS,
        "Smallest speed over the steps.",
        "`min_t |v_t|`, `v_t = (p_t+1 − p_t)/dt`",
        "Francis et al. 2023 (V)",
    ),
    m(
        "vel_avg",
        MOTION,
        "mean speed",
        "m/s",
        Neither,
        POS,
        "Mean speed over the steps.",
        "`mean_t |v_t|`",
        "Francis et al. 2023 (V)",
    ),
    m(
        "vel_max",
        MOTION,
        "max speed",
        "m/s",
        Neither,
        POS,
        "Largest speed over the steps.",
        "`max_t |v_t|`",
        "Francis et al. 2023 (V)",
    ),
    m(
        "acc_min",
        MOTION,
        "min acceleration",
        "m/s²",
        Lower,
        POS,
        "Smallest acceleration magnitude.",
        "`min_t |p_t+1 − 2p_t + p_t−1| / dt²`",
        "Francis et al. 2023 (A)",
    ),
    m(
        "acc_avg",
        MOTION,
        "mean acceleration",
        "m/s²",
        Lower,
        POS,
        "Mean acceleration magnitude.",
        "`mean_t |p_t+1 − 2p_t + p_t−1| / dt²`",
        "Francis et al. 2023 (A)",
    ),
    m(
        "acc_max",
        MOTION,
        "max acceleration",
        "m/s²",
        Lower,
        POS,
        "Largest acceleration magnitude.",
        "`max_t |p_t+1 − 2p_t + p_t−1| / dt²`",
        "Francis et al. 2023 (A)",
    ),
    m(
        "jerk_min",
        MOTION,
        "min jerk",
        "m/s³",
        Lower,
        POS,
        "Smallest jerk magnitude (third finite difference).",
        "`min_t |p_t+2 − 3p_t+1 + 3p_t − p_t−1| / dt³`",
        "Francis et al. 2023 (J); SocNavBench",
    ),
    m(
        "jerk_avg",
        MOTION,
        "mean jerk",
        "m/s³",
        Lower,
        POS,
        "Mean jerk magnitude (third finite difference).",
        "`mean_t |p_t+2 − 3p_t+1 + 3p_t − p_t−1| / dt³`",
        "Francis et al. 2023 (J); SocNavBench",
    ),
    m(
        "jerk_max",
        MOTION,
        "max jerk",
        "m/s³",
        Lower,
        POS,
        "Largest jerk magnitude (third finite difference).",
        "`max_t |p_t+2 − 3p_t+1 + 3p_t − p_t−1| / dt³`",
        "Francis et al. 2023 (J); SocNavBench",
    ),
    m(
        "chc",
        MOTION,
        "CHC",
        "rad",
        Lower,
        POS,
        "Cumulative heading change of the body yaw: Calderita et al.'s CHC and the `H` of their \
         tuning cost (eq. 18).",
        "`Σ_t |wrap(θ_t+1 − θ_t)|`",
        "Pérez-Higueras et al. 2018; HuNavSim; Calderita et al.",
    )
    .mean(1)
    .panel(Papers),
    m(
        "chc_motion",
        MOTION,
        "CHC of motion",
        "rad",
        Lower,
        POS,
        "The same over the direction of motion `atan2(v_t)`, skipping steps slower than 0.01 m/s \
         (a holonomic robot can move without turning).",
        "",
        "",
    ),
    m(
        "path_irregularity",
        MOTION,
        "path irregularity",
        "rad/m",
        Lower,
        NONE,
        "Turning beyond the one needed to face the goal, per metre (may be negative); `None` for a \
         path of length 0.",
        "`(chc − |wrap(atan2(g − p_0) − θ_0)|) / path_length`",
        "Guzzi et al. 2013",
    ),
    m(
        "smooth_rad2",
        MOTION,
        "Smooth (eq. 2, rad²)",
        "rad²",
        Lower,
        POS,
        "Daza et al.'s Smooth as eq. 2 is written: mean squared angle between the executed \
         direction and the A* path's where the path leaves and rejoins it (within 0.2 m counts as \
         on it). A robot that follows the plain A* path never leaves it, so `astar` scores 0 by \
         construction.",
        "`1/(k−1) Σ_i θ_i²` over the `k` angles; `θ_1²` for `k = 1`, 0 for `k = 0`",
        "Daza et al. 2021, eq. 2",
    ),
    m(
        "smooth_rad",
        MOTION,
        "Smooth",
        "rad",
        Lower,
        POS,
        "The root of eq. 2, a root-mean-square leave/rejoin angle: the value Daza et al.'s Table 2 \
         prints (its text reads 0.08 as 4.6°), so the one `proxemic reproduce daza2021` compares. \
         0 for `astar` by construction.",
        "`√smooth_rad2`",
        "Daza et al. 2021, eq. 2 and Table 2",
    )
    .mean(3)
    .panel(Papers),
    m(
        "smooth_k",
        MOTION,
        "Smooth angles",
        "count",
        Neither,
        POS,
        "Number `k` of leave and rejoin angles in `smooth_rad2` and `smooth_rad`.",
        "",
        "Daza et al. 2021, eq. 2",
    ),
    // Distance to people
    m(
        "dist_person_min",
        PEOPLE,
        "closest person",
        "m (centre)",
        Higher,
        POS,
        "Smallest centre distance to a person; `None` without people.",
        "`min_t,i d_i,t`",
        "SocNavGym; HuNavSim",
    )
    .mean(2)
    .panel(Social),
    m(
        "gap_person_min",
        PEOPLE,
        "closest person gap",
        "m (surface)",
        Higher,
        NONE,
        "Smallest surface gap to a person (negative: overlap); `None` without people.",
        "`min_t,i s_i,t`",
        "CrowdNav",
    ),
    m(
        "cp_avg",
        PEOPLE,
        "mean closest person",
        "m (centre)",
        Higher,
        POS,
        "Mean over instants of the closest person's centre distance; `None` without people. The \
         `P` of Calderita et al.'s tuning cost (eq. 20), here over every person rather than the \
         visible ones.",
        "`mean_t min_i d_i,t`",
        "HuNavSim (CP_avg); Calderita et al.",
    ),
    per(
        m(
            "d_min",
            PEOPLE,
            "closest approach",
            "m (centre)",
            Higher,
            POS,
            "Calderita et al.'s `d_min`, per person: the smallest centre distance to that person.",
            "`min_t d_i,t`",
            "Calderita et al., Tables 1–2",
        ),
        Per::Person,
    ),
    m(
        "discomfort_frequency",
        PEOPLE,
        "discomfort frequency",
        "fraction",
        Lower,
        FLAG,
        "Share of instants whose closest surface gap is under the discomfort gap (0.2 m).",
        "instants with `0 ≤ min_i s_i,t < 0.2 m`, over `T + 1`",
        "CrowdNav",
    ),
    m(
        "discomfort_gap_avg",
        PEOPLE,
        "discomfort gap",
        "m (surface)",
        Higher,
        POS,
        "Mean closest surface gap over the discomfort instants; `None` without one.",
        "",
        "CrowdNav",
    ),
    m(
        "personal_space_compliance",
        PEOPLE,
        "personal-space compliance",
        "fraction",
        Higher,
        FLAG,
        "Share of instants with everybody at least τ = 0.45 m from the robot's surface (1 without \
         people).",
        "instants with `min_i (d_i,t − r_R) ≥ 0.45 m`, over `T + 1`",
        "SocNavGym; SEAN 2.0",
    ),
    m(
        "psi_intimate",
        PEOPLE,
        "intimate-zone time, centres",
        "%",
        Lower,
        PCT,
        "Share of instants whose closest person (centre distance) is in the intimate zone: \
         Calderita et al.'s Ψ(intimate). Read on centres, 0.45 m is reached only by bodies that \
         overlap (robot 0.3 m and person 0.22 m radii): `intimate_gap_time` reads the zone on body \
         gaps.",
        "`100 · #{t : min_i d_i,t < r_intimate} / (T + 1)`",
        "Hall 1966; HuNavSim; Calderita et al.",
    )
    .mean(1)
    .panel(Social)
    .headline(),
    m(
        "psi_personal",
        PEOPLE,
        "personal-zone time, centres",
        "%",
        Lower,
        PCT,
        "Share of instants whose closest person is in the personal zone: Calderita et al.'s \
         Ψ(personal).",
        "`100 · #{t : r_intimate ≤ min_i d_i,t < r_personal} / (T + 1)`",
        "Hall 1966; HuNavSim; Calderita et al.",
    )
    .mean(1)
    .panel(Social)
    .headline()
    .verdict(Share),
    m(
        "psi_social",
        PEOPLE,
        "social-zone time",
        "%",
        Neither,
        PCT,
        "Share of instants whose closest person is in the social zone.",
        "`100 · #{t : r_personal ≤ min_i d_i,t < r_social} / (T + 1)`",
        "Hall 1966; HuNavSim; Calderita et al.",
    ),
    m(
        "psi_public",
        PEOPLE,
        "public-zone time",
        "%",
        Neither,
        PCT,
        "Share of instants whose closest person is in the public zone, or with nobody present.",
        "`100 · #{t : min_i d_i,t ≥ r_social} / (T + 1)`",
        "Hall 1966; HuNavSim; Calderita et al.",
    ),
    // Who approached whom (rust/proxemic-core/src/metrics/approach.rs; the fault rule of fault.rs)
    m(
        "intimate_gap_time",
        PEOPLE,
        "intimate-zone time, body gaps",
        "s",
        Lower,
        POS,
        "Seconds with the closest present person's body gap (surface to surface) in the intimate \
         zone, counted per step at the step's end; 0 without people. The reading of the claims \
         (`tests/test_social_vs_astar.py`), beside `psi_intimate`'s centre reading.",
        "`dt · #{k < T : min_i s_i,k+1 < r_intimate}`",
        SRC_APPROACH,
    )
    .mean(2)
    .panel(Social)
    .headline(),
    m(
        "intimate_gap_time_robot_caused",
        PEOPLE,
        "intimate-zone time, body gaps, robot-caused",
        "s",
        Lower,
        POS,
        "The part of `intimate_gap_time` in steps over which the robot moved toward that closest \
         person: its velocity along the direction robot → person above 0.05 m/s (the rule of \
         `collisions_robot_fault`).",
        "steps of `intimate_gap_time` with `v_R,k · (q_i,k − p_k)/|q_i,k − p_k| > 0.05 m/s`, times `dt`",
        SRC_APPROACH,
    )
    .mean(2),
    m(
        "intimate_gap_time_person_caused",
        PEOPLE,
        "intimate-zone time, body gaps, person-caused",
        "s",
        Neither,
        POS,
        "The rest of `intimate_gap_time`: the robot stopped, moving away or passing slower than \
         0.05 m/s toward the person.",
        "`intimate_gap_time − intimate_gap_time_robot_caused`",
        SRC_APPROACH,
    )
    .mean(2),
    m(
        "intimate_gap_entries",
        PEOPLE,
        "intimate-zone entries, body gaps",
        "count",
        Lower,
        POS,
        "Entries into a person's intimate zone: steps over which a present person's body gap falls \
         below the intimate radius from at or above it, counted per person.",
        "`#{(k, i) : s_i,k ≥ r_intimate > s_i,k+1}`",
        SRC_APPROACH,
    )
    .mean(2),
    m(
        "intimate_gap_entries_robot_caused",
        PEOPLE,
        "intimate-zone entries, robot-caused",
        "count",
        Lower,
        POS,
        "The entries of `intimate_gap_entries` made while the robot moved toward the person above \
         0.05 m/s over the step of the entry.",
        "",
        SRC_APPROACH,
    )
    .mean(2)
    .headline(),
    m(
        "intimate_gap_entries_person_caused",
        PEOPLE,
        "intimate-zone entries, person-caused",
        "count",
        Neither,
        POS,
        "The other entries of `intimate_gap_entries`: the person came to a robot stopped, moving \
         away or slower than 0.05 m/s toward them.",
        "",
        SRC_APPROACH,
    )
    .mean(2)
    .headline(),
    m(
        "personal_gap_time",
        PEOPLE,
        "personal-zone time, body gaps",
        "s",
        Lower,
        POS,
        "Seconds with the closest present person's body gap in the personal zone (at or above the \
         intimate radius, below the personal one), per step like `intimate_gap_time`.",
        "`dt · #{k < T : r_intimate ≤ min_i s_i,k+1 < r_personal}`",
        SRC_APPROACH,
    )
    .mean(1)
    .panel(Social),
    m(
        "personal_gap_time_robot_caused",
        PEOPLE,
        "personal-zone time, body gaps, robot-caused",
        "s",
        Lower,
        POS,
        "The part of `personal_gap_time` in steps over which the robot moved toward that closest \
         person above 0.05 m/s.",
        "",
        SRC_APPROACH,
    )
    .mean(1)
    .headline(),
    m(
        "personal_gap_time_person_caused",
        PEOPLE,
        "personal-zone time, body gaps, person-caused",
        "s",
        Neither,
        POS,
        "The rest of `personal_gap_time`: the person came to a robot stopped, moving away or \
         slower than 0.05 m/s toward them.",
        "",
        SRC_APPROACH,
    )
    .mean(1)
    .headline(),
    m(
        "personal_gap_entries",
        PEOPLE,
        "personal-zone entries, body gaps",
        "count",
        Lower,
        POS,
        "Entries into a person's personal zone: steps over which a present person's body gap falls \
         below the personal radius from at or above it, per person (straight into the intimate \
         zone included).",
        "`#{(k, i) : s_i,k ≥ r_personal > s_i,k+1}`",
        SRC_APPROACH,
    )
    .mean(2),
    m(
        "personal_gap_entries_robot_caused",
        PEOPLE,
        "personal-zone entries, robot-caused",
        "count",
        Lower,
        POS,
        "The entries of `personal_gap_entries` made while the robot moved toward the person above \
         0.05 m/s.",
        "",
        SRC_APPROACH,
    )
    .mean(2),
    m(
        "personal_gap_entries_person_caused",
        PEOPLE,
        "personal-zone entries, person-caused",
        "count",
        Neither,
        POS,
        "The other entries of `personal_gap_entries`: the person came to the robot.",
        "",
        SRC_APPROACH,
    )
    .mean(2),
    // Groups and interactions
    m(
        "group_psi_intimate",
        GROUPS,
        "o-space intimate time",
        "%",
        Lower,
        PCT,
        "As `psi_intimate`, with the distance to the closest o-space centre (the scenario's \
         ground-truth groups).",
        "",
        "HuNavSim (IS_prox); Okal & Arras",
    ),
    m(
        "group_psi_personal",
        GROUPS,
        "o-space personal time",
        "%",
        Lower,
        PCT,
        "As `psi_personal`, with the distance to the closest o-space centre.",
        "",
        "HuNavSim (IS_prox); Okal & Arras",
    ),
    m(
        "group_psi_social",
        GROUPS,
        "o-space social time",
        "%",
        Neither,
        PCT,
        "As `psi_social`, with the distance to the closest o-space centre.",
        "",
        "HuNavSim (IS_prox); Okal & Arras",
    ),
    m(
        "group_psi_public",
        GROUPS,
        "o-space public time",
        "%",
        Neither,
        PCT,
        "As `psi_public`, with the distance to the closest o-space centre (public also without \
         any o-space).",
        "",
        "HuNavSim (IS_prox); Okal & Arras",
    ),
    m(
        "ospace_pct",
        GROUPS,
        "o-space time",
        "%",
        Lower,
        PCT,
        "Share of instants with the robot centre inside some o-space circle.",
        "",
        "Kendon's F-formations; Sousa et al. 2022",
    )
    .mean(1)
    .panel(Social)
    .verdict(Share),
    m(
        "ospace_time",
        GROUPS,
        "o-space time",
        "s",
        Lower,
        POS,
        "The steps starting at an instant inside, times `dt` (at most the episode's duration).",
        "",
        "",
    ),
    m(
        "ospace_entries",
        GROUPS,
        "o-space entries",
        "count",
        Lower,
        POS,
        "Entries into o-spaces (an instant inside after one outside).",
        "",
        "",
    ),
    m(
        "interaction_crossings",
        GROUPS,
        "interaction crossings",
        "steps",
        Lower,
        POS,
        "Steps whose segment `[p_t, p_t+1)` crosses an interaction segment (person ↔ partner or \
         person ↔ attended object) present at instant `t`.",
        "",
        "Daza et al. 2021 §4.3; Sousa et al. 2022",
    )
    .mean(1)
    .panel(Social)
    .headline()
    .verdict(Share),
    m(
        "interaction_crossings_person_person",
        GROUPS,
        "person-person crossings",
        "steps",
        Lower,
        POS,
        "The crossings of a segment between two members of a gathered group.",
        "",
        "",
    ),
    m(
        "interaction_crossings_person_object",
        GROUPS,
        "person-object crossings",
        "steps",
        Lower,
        POS,
        "The crossings of a segment between a person and the object they attend.",
        "",
        "",
    ),
    // Objects
    per(
        m(
            "psi_object_active",
            OBJECTS,
            "active object-space time",
            "%",
            Lower,
            PCT,
            "Per object: share of instants with the robot centre inside the object's interaction \
             polygon while its activity is on.",
            "",
            "ours (Calderita et al.'s Ψ per object, counted while active)",
        ),
        Per::Object,
    ),
    per(
        m(
            "psi_object_any",
            OBJECTS,
            "object-space time (any activity)",
            "%",
            Lower,
            PCT,
            "Per object: share of instants inside the object's interaction polygon whatever the \
             activity state.",
            "",
            "Calderita et al., Tables 1–2 (Ψ per object)",
        ),
        Per::Object,
    ),
    m(
        "psi_objects_any",
        OBJECTS,
        "object-space time (any activity)",
        "%",
        Lower,
        PCT,
        "Share of instants inside at least one object space, active or not: Calderita et al.'s \
         Ψ(Objects) as their Tables 1–2 count it (their Table 1 Path 1, the social path, scores \
         34.98% by crossing the idle TV space).",
        "",
        "Calderita et al., Tables 1–2",
    )
    .mean(1)
    .panel(Papers),
    m(
        "psi_objects_active",
        OBJECTS,
        "active object-space time",
        "%",
        Lower,
        PCT,
        "Share of instants inside at least one object space whose activity is on (an idle TV's \
         space bothers nobody); never more than `psi_objects_any`.",
        "",
        "ours",
    )
    .mean(1)
    .panel(Papers)
    .headline()
    .verdict(Share),
    // Time to collision and social force (with the people)
    m(
        "ttc_min",
        PEOPLE,
        "min time to collision",
        "s",
        Higher,
        POS,
        "Smallest time to collision over steps and people, both moving at constant velocity from \
         the instant (0 when already overlapping); `None` when no finite TTC occurred.",
        "",
        "Francis et al. 2023 (TTC)",
    ),
    m(
        "ttc_below_fraction",
        PEOPLE,
        "TTC below 2 s",
        "fraction",
        Lower,
        FLAG,
        "Share of steps whose smallest time to collision is below 2 s.",
        "",
        "Francis et al. 2023",
    ),
    m(
        "social_force_on_people",
        PEOPLE,
        "social force on people",
        "m/s² summed over instants",
        Lower,
        POS,
        "The robot's social force on the people, summed over people and instants; `φ` is the \
         angle between the person's heading and the direction person → robot (A = 2.1, \
         B = 0.3 m, λ = 0.5).",
        "`Σ_t Σ_i |F_R→i|`, `F = A exp((r_R + r_i − d)/B) (λ + (1 − λ)(1 + cos φ)/2)`",
        "Helbing & Molnár 1995; HuNavSim",
    ),
    m(
        "social_force_on_robot",
        PEOPLE,
        "social force on the robot",
        "m/s² summed over instants",
        Lower,
        POS,
        "The people's social force on the robot, the same law with the robot's yaw as its \
         heading.",
        "`Σ_t |Σ_i F_i→R|`",
        "HuNavSim",
    ),
    m(
        "social_work",
        PEOPLE,
        "social work",
        "m/s² summed over instants",
        Lower,
        POS,
        "The sum of the two social forces.",
        "`social_force_on_people + social_force_on_robot`",
        "HuNavSim",
    ),
    // Static geometry
    m(
        "clearance_min",
        STATIC,
        "min clearance",
        "m (surface)",
        Higher,
        NONE,
        "Smallest distance from the robot surface to walls and furniture over the instants.",
        "",
        "Francis et al. 2023 (CD)",
    ),
    m(
        "clearance_avg",
        STATIC,
        "mean clearance",
        "m (surface)",
        Higher,
        NONE,
        "Mean distance from the robot surface to walls and furniture over the instants.",
        "",
        "Francis et al. 2023",
    ),
    // SNQI inputs
    m(
        "near_misses",
        SNQI,
        "near misses",
        "instants",
        Lower,
        POS,
        "Instants at which the closest person's surface gap is at least 0 and under 0.5 m (an \
         instant in contact is a collision, not a near miss). An input of the SNQI composite of \
         `proxemic eval` summaries.",
        "instants with `0 ≤ min_i s_i,t < 0.5 m`",
        "robot-sf (SNQI)",
    ),
    m(
        "force_exceed_events",
        SNQI,
        "force-exceed events",
        "instant-person pairs",
        Lower,
        POS,
        "(instant, person) pairs at which the robot's social force on the person (the force of \
         `social_force_on_people`) is above 2.0 m/s². robot-sf takes the total social force of its \
         pedestrian simulator on the person; we take the robot's own, so that it measures the \
         robot's effect (docs: choices.md).",
        "pairs `(t, i)` with `|F_R→i,t| > 2.0 m/s²`",
        "robot-sf (SNQI)",
    ),
    m(
        "comfort_exposure",
        SNQI,
        "comfort exposure",
        "fraction",
        Lower,
        FLAG,
        "Share of (instant, person) pairs that are force-exceed events; 0 without people.",
        "`force_exceed_events / (K (T + 1))` over the `K` people",
        "robot-sf (SNQI)",
    ),
    // Who hit whom (the fault rule: rust/proxemic-core/src/metrics/fault.rs)
    m(
        "collisions_robot_fault",
        OUTCOME,
        "robot-at-fault person contacts",
        "events",
        Lower,
        POS,
        "Contact events with a person (a run of consecutive steps touching them, counted once) in \
         which the robot moved toward the person: its velocity along the direction robot → person \
         above 0.05 m/s in some step of the run. Such a contact ends the episode and fails success.",
        "`v_R · (p_i − p_R)/|p_i − p_R| > 0.05 m/s`",
        "SEAN 2.0 (robot on person collision); HuNavSim",
    )
    .mean(2),
    m(
        "collisions_person_fault",
        OUTCOME,
        "person-at-fault contacts",
        "events",
        Neither,
        POS,
        "Contact events with a person who moved into the robot while it was stopped or moving \
         away (its velocity toward the person at most 0.05 m/s in every step of the run). Counted \
         in `hc_count` but not a collision: it neither ends the episode nor fails success.",
        "",
        "SEAN 2.0 (person on robot collision); HuNavSim",
    )
    .mean(2),
    m(
        "collisions_static",
        OUTCOME,
        "wall/furniture contacts",
        "events",
        Lower,
        POS,
        "Contact events with walls or furniture (runs of steps with the physics' static contact, \
         counted once each).",
        "",
        "SEAN 2.0 (static obstacle collision)",
    )
    .mean(2),
    // The robot's cost to people (counterfactual: rust/proxemic-core/src/metrics/people_cost.rs)
    m(
        "ped_delay_s_mean",
        PEOPLE,
        "people's mean delay",
        "s",
        Lower,
        POS,
        "Mean over the scene's people of each person's delay against the same episode replayed \
         without the robots (same seed, people only): the largest lateness of a stage change of \
         their script (way-point reached, walk leg done, task finished) that the robot-free run \
         makes within the episode, one not yet made counting until the episode's end; 0 for a \
         person whose robot-free run makes none (standing, talking). `None` without people.",
        "`mean_i max(0, max_k (r_ik − c_ik) dt)`",
        "ours (a robot-free replay; after Katyal et al. 2022's pedestrian velocity)",
    )
    .mean(2),
    m(
        "ped_delay_s_max",
        PEOPLE,
        "people's max delay",
        "s",
        Lower,
        POS,
        "The largest person's delay (see `ped_delay_s_mean`).",
        "`max_i max(0, max_k (r_ik − c_ik) dt)`",
        "ours",
    )
    .mean(2),
    m(
        "ped_extra_distance_m_mean",
        PEOPLE,
        "people's mean extra distance",
        "m",
        Lower,
        POS,
        "Mean over people of the extra distance walked to the last stage change both the episode \
         and its robot-free replay made (episode minus robot-free, floored at 0; 0 without one).",
        "`mean_i max(0, L_i(0..r_ik*) − L^free_i(0..c_ik*))`",
        "ours",
    )
    .mean(2),
    m(
        "ped_extra_distance_m_max",
        PEOPLE,
        "people's max extra distance",
        "m",
        Lower,
        POS,
        "The largest person's extra distance (see `ped_extra_distance_m_mean`).",
        "",
        "ours",
    ),
    m(
        "ped_path_deviation_m_mean",
        PEOPLE,
        "people's mean path deviation",
        "m",
        Lower,
        POS,
        "Mean over people of each person's path deviation: the largest distance from where they \
         are at an instant of the episode to their robot-free path (the polyline of their \
         robot-free positions over the episode); 0 when the two tracks are identical.",
        "`mean_i max_t dist(p_i(t), path^free_i)`",
        "ours",
    )
    .mean(2),
    m(
        "ped_path_deviation_m_max",
        PEOPLE,
        "people's max path deviation",
        "m",
        Lower,
        POS,
        "The largest person's path deviation (see `ped_path_deviation_m_mean`).",
        "",
        "ours",
    ),
    // Progress monitor
    m(
        "recoveries",
        RECOVERY,
        "recoveries",
        "count",
        Lower,
        POS,
        "Recoveries of the built-in planner's progress monitor: each time the geodesic distance to \
         the current target had not fallen by `progress.distance` (default 0.5 m) within \
         `progress.window` (default 15 s), the robot backed out and re-planned round the people \
         blocking it. 0 when the built-in planner does not run or its monitor is off.",
        "",
        "ours",
    )
    .mean(2),
    m(
        "monitor_stalled_time",
        RECOVERY,
        "stalled time (monitor)",
        "s",
        Lower,
        POS,
        "Seconds the progress monitor considered the robot stalled: from the start of each window \
         without progress that ended in a recovery to the progress that ended the stall (or the \
         episode's end). Unlike `stalled_time`, it counts a robot that moves without getting closer.",
        "",
        "ours",
    )
    .mean(2),
    m(
        "recovery_time",
        RECOVERY,
        "time in recovery",
        "s",
        Lower,
        POS,
        "Seconds of steps whose command followed a held recovery path (the path the monitor's \
         recovery planned, held for 8 s), those steps times `dt`. 0 when the built-in \
         planner does not run or never recovered.",
        "",
        "ours",
    )
    .mean(2),
    m(
        "recovery_ospace_entries",
        RECOVERY,
        "o-space entries in recovery",
        "count",
        Lower,
        POS,
        "Entries into groups' o-spaces while following a recovery path: recovery steps that end \
         with the robot centre inside an o-space present then, having started outside every \
         o-space present at the step's start (the o-spaces of `ospace_entries`).",
        "",
        "ours",
    )
    .mean(2),
    m(
        "recovery_object_entries",
        RECOVERY,
        "active object-space entries in recovery",
        "count",
        Lower,
        POS,
        "Entries into active object spaces while following a recovery path: recovery steps that \
         end with the robot centre inside the interaction polygon of an object whose activity is \
         on, having started outside every active one (the spaces of `psi_objects_active`).",
        "",
        "ours",
    )
    .mean(2),
];

/// The sections of the reference, in order.
pub const FAMILIES: [&str; 9] =
    [OUTCOME, EFFICIENCY, MOTION, PEOPLE, GROUPS, OBJECTS, STATIC, SNQI, RECOVERY];

/// The reference entry of `key`, if it is a metric.
pub fn metric_info(key: &str) -> Option<&'static MetricInfo> {
    METRICS.iter().find(|m| m.key == key)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::{EpisodeReport, Groups, ObjectSpaces, Outcome, PeopleTracks, Trajectory, evaluate};

    /// The report of a 4 m straight run to the goal without people.
    fn report() -> EpisodeReport {
        let robot: Vec<[f64; 3]> = (0..=4).map(|x| [x as f64, 0.0, 0.0]).collect();
        let traj = Trajectory {
            dt: 0.1,
            robot: &robot,
            robot_radius: 0.3,
            goal: crate::math::Vec2::new(4.0, 0.0),
            success_radius: 0.1,
        };
        let none = |_: crate::math::Vec2| f64::INFINITY;
        let ctx = crate::metrics::EvalContext {
            geodesic_length: 4.0,
            astar_path: &[],
            clearance: &none,
            zones: crate::metrics::DEFAULT_ZONES,
            collision_steps: &[],
            params: crate::metrics::MetricParams::default(),
            robot_free: None,
        };
        let metrics = evaluate(&traj, &PeopleTracks::none(), &Groups::none(), &ObjectSpaces::none(), &ctx)
            .expect("valid input");
        EpisodeReport {
            outcome: Outcome::Success,
            duration: 0.4,
            astar_length: 4.0,
            geodesic_length: Some(4.0),
            min_robot_gap: None,
            metrics,
            recovery: crate::metrics::RecoveryMetrics::default(),
        }
    }

    #[test]
    fn every_reported_key_is_in_the_registry_and_back() {
        let report = report();
        let value = serde_json::to_value(&report).expect("serialisable");
        let keys: Vec<&str> = value.as_object().expect("an object").keys().map(String::as_str).collect();
        let missing: Vec<&str> = keys.iter().copied().filter(|k| metric_info(k).is_none()).collect();
        assert!(missing.is_empty(), "reported but not in the registry: {missing:?}");
        let extra: Vec<&str> = METRICS.iter().map(|m| m.key).filter(|k| !keys.contains(k)).collect();
        assert!(extra.is_empty(), "in the registry but not reported: {extra:?}");
        // List-valued keys are exactly the per-person and per-object ones.
        for info in METRICS {
            let is_list = value[info.key].is_array();
            assert_eq!(is_list, info.per != Per::Episode, "{}", info.key);
        }
    }

    /// The record's columns in the order Python receives them (the JSON text's order, which
    /// `json.loads` keeps; the binding's dicts are built in the same order) are the registry's
    /// keys in the registry's order: no column that is not a metric, no metric left out.
    #[test]
    fn the_report_lists_the_registry_keys_in_the_registry_order() {
        let text = serde_json::to_string(&report()).expect("serialisable");
        // Every other quoted token is a string; a key is one followed by a colon.
        let parts: Vec<&str> = text.split('"').collect();
        let keys: Vec<&str> = (1..parts.len())
            .step_by(2)
            .filter(|&i| parts[i + 1].starts_with(':'))
            .map(|i| parts[i])
            .collect();
        let registry: Vec<&str> = METRICS.iter().map(|m| m.key).collect();
        assert_eq!(keys, registry);
    }

    #[test]
    fn keys_are_unique_and_entries_complete() {
        for (i, a) in METRICS.iter().enumerate() {
            assert!(METRICS[i + 1..].iter().all(|b| b.key != a.key), "duplicate {}", a.key);
            assert!(FAMILIES.contains(&a.family), "{}: unknown family {}", a.key, a.family);
            assert!(!a.label.is_empty() && !a.definition.is_empty(), "{}", a.key);
            if let (Some(lo), Some(hi)) = (a.low, a.high) {
                assert!(lo < hi, "{}", a.key);
            }
        }
    }

    #[test]
    fn what_the_evaluation_shows_is_summarised_per_episode() {
        for a in METRICS {
            let shown = a.panel.is_some() || a.headline || a.verdict.is_some();
            assert!(!shown || a.summary.is_some(), "{}: shown but not summarised", a.key);
            assert!(a.summary.is_none() || a.per == Per::Episode, "{}: a list summarised", a.key);
            if a.summary == Some(Summary::Rate) {
                assert_eq!(a.unit, "bool", "{}: a rate of a value that is not a flag", a.key);
            }
            if a.verdict.is_some() {
                assert_eq!(a.summary, Some(Summary::Mean), "{}: a verdict on a rate", a.key);
            }
            assert!(a.decimals <= 6, "{}", a.key);
        }
    }
}
