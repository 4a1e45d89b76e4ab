"""Typed records returned by the compiled core (``proxemic._core``): episode metrics, social layers, perception.

These ``TypedDict`` classes describe the dicts of ``World.episode_metrics``, ``World.social_layers``
and ``World.perception`` (``ProxemicEnv.metrics``, ``SocialMap.layers`` and ``SocialMap.perception``
return them too). Each metric is defined in ``docs/metrics.md``; undefined values are None.
"""

from __future__ import annotations

from typing import Literal, TypedDict

import numpy as np
import numpy.typing as npt

Outcome = Literal["running", "success", "collision", "timeout"]
"""How a robot's episode ended (``running`` before the end)."""


class EpisodeMetrics(TypedDict):
    """One robot's episode: the outcome and one key per metric (see ``docs/metrics.md``).

    ``d_min`` holds one value per person and ``psi_object_active`` / ``psi_object_any`` one per object
    with an interaction space, in scenario order.
    """

    outcome: Outcome
    duration: float
    astar_length: float
    geodesic_length: float | None
    min_robot_gap: float | None
    steps: int
    success: bool
    collision: bool
    timeout: bool
    time_to_goal: float | None
    hc_count: int
    wc_count: int
    ac_count: int
    hc: bool
    wc: bool
    ac: bool
    path_length: float
    path_length_ratio: float | None
    spl: float | None
    failure_to_progress: int
    stalled_time: float
    vel_min: float | None
    vel_avg: float | None
    vel_max: float | None
    acc_min: float | None
    acc_avg: float | None
    acc_max: float | None
    jerk_min: float | None
    jerk_avg: float | None
    jerk_max: float | None
    chc: float
    chc_motion: float
    path_irregularity: float | None
    dist_person_min: float | None
    gap_person_min: float | None
    cp_avg: float | None
    d_min: list[float | None]
    discomfort_frequency: float | None
    discomfort_gap_avg: float | None
    personal_space_compliance: float | None
    psi_intimate: float | None
    psi_personal: float | None
    psi_social: float | None
    psi_public: float | None
    intimate_gap_time: float
    intimate_gap_time_robot_caused: float
    intimate_gap_time_person_caused: float
    intimate_gap_entries: int
    intimate_gap_entries_robot_caused: int
    intimate_gap_entries_person_caused: int
    personal_gap_time: float
    personal_gap_time_robot_caused: float
    personal_gap_time_person_caused: float
    personal_gap_entries: int
    personal_gap_entries_robot_caused: int
    personal_gap_entries_person_caused: int
    group_psi_intimate: float | None
    group_psi_personal: float | None
    group_psi_social: float | None
    group_psi_public: float | None
    ospace_pct: float | None
    ospace_time: float
    ospace_entries: int
    interaction_crossings: int
    interaction_crossings_person_person: int
    interaction_crossings_person_object: int
    psi_object_active: list[float | None]
    psi_object_any: list[float | None]
    psi_objects_any: float | None
    psi_objects_active: float | None
    ttc_min: float | None
    ttc_below_fraction: float | None
    clearance_min: float | None
    clearance_avg: float | None
    social_force_on_people: float
    social_force_on_robot: float
    social_work: float
    l_ratio: float | None
    smooth_rad2: float | None
    smooth_rad: float | None
    smooth_k: int
    d_t: float
    tau: float
    near_misses: int
    force_exceed_events: int
    comfort_exposure: float | None
    collisions_robot_fault: int
    collisions_person_fault: int
    collisions_static: int
    ped_delay_s_mean: float | None
    ped_delay_s_max: float | None
    ped_extra_distance_m_mean: float | None
    ped_extra_distance_m_max: float | None
    ped_path_deviation_m_mean: float | None
    ped_path_deviation_m_max: float | None
    recoveries: int
    monitor_stalled_time: float
    recovery_time: float
    recovery_ospace_entries: int
    recovery_object_entries: int


class MetricInfo(TypedDict):
    """The reference entry of one metric (``_core.metric_registry()``; see ``docs/metrics.md``)."""

    key: str
    """Key in :class:`EpisodeMetrics` (a column prefix when ``per`` is not ``episode``)."""
    family: str
    """Section of the reference (e.g. ``Efficiency``)."""
    label: str
    """Short label for tables and plots."""
    unit: str
    """Unit (``m``, ``s``, ``%`` ...); empty for a dimensionless number, ``bool`` for a flag."""
    better: Literal["higher", "lower", "neither"]
    """Which direction is better for a socially-aware robot, all else equal."""
    low: float | None
    """Lowest possible value, when bounded."""
    high: float | None
    """Highest possible value, when bounded."""
    per: Literal["episode", "person", "object"]
    """One value per episode, or a list with one per person or per object with an interaction space."""
    definition: str
    """What it measures, and when it is undefined (None)."""
    formula: str
    """How it is computed (empty when the definition says it all)."""
    source: str
    """Where it comes from (empty for the project's own)."""
    summary: Literal["rate", "mean"] | None
    """How ``proxemic eval`` summarises it over episodes (None: it does not)."""
    over_successes: bool
    """Whether a summarised mean is over the successful episodes only."""
    decimals: int
    """Digits after the decimal point of a summarised mean (rates are whole percentages)."""
    panel: Literal["outcome", "efficiency", "social", "papers"] | None
    """The panel of the evaluation's ``metrics.png`` showing it, if any."""
    headline: bool
    """Whether it is a column of the evaluation's headline table."""
    verdict: Literal["times", "share"] | None
    """How verdicts say the ratio of two planners' means (None: not compared)."""


class SocialLayers(TypedDict):
    """A robot's social cost map (``World.social_layers``): (H, W) arrays, row 0 the lowest y."""

    static: npt.NDArray[np.uint8]
    """The inflated static map: 254 obstacles, 253 the inflation band."""
    people: npt.NDArray[np.float64]
    """Traversal factors of the people's zones (1 free, inf forbidden)."""
    objects: npt.NDArray[np.float64]
    """Traversal factors of the objects' interaction spaces at R(t)."""
    combined: npt.NDArray[np.uint8]
    """What social A* searches (0 free .. 252, 253 and 254 impassable)."""
    grid: tuple[float, float, float]
    """(origin_x, origin_y, resolution) in metres."""
    weight: float
    """The A* cost weight."""


class Individual(TypedDict):
    """A person alone or a group treated as one individual (Sousa et al. 2022 §3.3.4)."""

    centre: tuple[float, float]
    heading: float
    sides: tuple[float, float, float, float]
    """Gaussian sigmas (m): front, rear, right, left."""
    zone_scale: float
    """The length (m) that turns sqrt(2 q) into a zone distance (``_core.zone_distances``)."""
    members: list[int]
    """Person indices."""
    robots: list[int]
    """Robots that joined the interaction."""


class DetectionAccuracy(TypedDict):
    """Precision, recall and F1 of the detected groups against the scenario's ground truth."""

    precision: float
    recall: float
    f1: float
    true_positives: int
    detected: int
    truth: int


class _PerceptionBase(TypedDict):
    labels: list[int]
    """Group index per person."""
    groups: list[list[int]]
    """Members of each group."""
    robot_joins: list[int | None]
    """Group joined per robot, or None."""
    individuals: list[Individual]
    truth: list[int | None]
    """The scenario's group id per person, or None."""


class Perception(_PerceptionBase, total=False):
    """What the robots perceive of the people now (``World.perception``)."""

    accuracy: DetectionAccuracy
    """Absent when the detection cannot be scored against the truth."""


__all__ = ["DetectionAccuracy", "EpisodeMetrics", "Individual", "MetricInfo", "Outcome", "Perception", "SocialLayers"]
