"""How summarised metrics are labelled, bounded, formatted and grouped into plot panels."""

from __future__ import annotations

import math
from dataclasses import dataclass

from proxemic import reference, snqi

#: Metrics summarised as rates (0/1 per episode), with Wilson intervals: success, collisions with
#: people (HC) and with walls or furniture (WC), timeout.
RATE_METRICS = ("success", "hc", "wc", "timeout")

#: Metrics summarised as means with t intervals (None values are left out): efficiency (time to
#: goal, path length, path length ratio to the geodesic, SPL, Daza 2021's L_ratio and Smooth),
#: motion (CHC), distance to people (closest centre distance), and time shares (%) in people's
#: intimate and personal zones, inside groups' o-spaces and inside object spaces while their
#: activity is on (ours) or whatever their state (Calderita's Psi(Objects)), plus interaction
#: crossings (person-person and person-object) per episode. Smooth is the root of Daza's eq. 2
#: (rad, the unit of their Table 2); the records also hold eq. 2 itself (``smooth_rad2``).
MEAN_METRICS = (
    "time_to_goal",
    "path_length",
    "path_length_ratio",
    "spl",
    "l_ratio",
    "smooth_rad",
    "chc",
    "dist_person_min",
    "psi_intimate",
    "psi_personal",
    "ospace_pct",
    "interaction_crossings",
    "psi_objects_active",
    "psi_objects_any",
    "recoveries",
    "monitor_stalled_time",
    "reward",
    "snqi",
    # Who hit whom (contact events by fault) and the robot's cost to people (robot-free replay).
    "collisions_robot_fault",
    "collisions_person_fault",
    "collisions_static",
    "ped_delay_s_mean",
    "ped_delay_s_max",
    "ped_extra_distance_m_mean",
    "ped_path_deviation_m_mean",
)


@dataclass(frozen=True)
class MetricInfo:
    """How a summarised metric is labelled and bounded (intervals are clipped to the bounds)."""

    label: str
    unit: str = ""
    low: float = -math.inf
    high: float = math.inf
    fmt: str = ".2f"


#: Display formats of the summarised means (default ``.2f``).
_FORMATS = {
    "time_to_goal": ".1f",
    "path_length": ".1f",
    "smooth_rad": ".3f",
    "smooth_rad2": ".3f",
    "chc": ".1f",
    "interaction_crossings": ".1f",
    "psi_intimate": ".1f",
    "psi_personal": ".1f",
    "ospace_pct": ".1f",
    "psi_objects_active": ".1f",
    "psi_objects_any": ".1f",
    "reward": ".1f",
}


def _metric_info(key: str) -> MetricInfo:
    """Label, unit and bounds of a summarised metric, from the core's metric registry.

    Rates are shown as shares of episodes (0-1, formatted as %). ``reward`` (the return) is the
    env's, not a metric of the registry.
    """
    if key == "reward":
        return MetricInfo("return", "", fmt=_FORMATS["reward"])
    if key == "snqi":  # over the records of an evaluation, not a metric of one episode (proxemic.snqi)
        return MetricInfo("SNQI", "", high=snqi.WEIGHTS["w_success"], fmt=".3f")
    m = reference.metric_info(key)
    if key in (*RATE_METRICS, "collision"):
        return MetricInfo(m["label"], "% of episodes", 0.0, 1.0, ".0%")
    low = -math.inf if m["low"] is None else m["low"]
    high = math.inf if m["high"] is None else m["high"]
    return MetricInfo(m["label"], m["unit"], low, high, _FORMATS.get(key, ".2f"))


#: Label, unit and bounds of every summarised metric (from the metric registry of the core).
METRICS: dict[str, MetricInfo] = {k: _metric_info(k) for k in (*RATE_METRICS, "collision", *MEAN_METRICS)}

#: The panels of ``metrics.png``, in rows: outcome, efficiency, social, the papers' own metrics.
METRIC_GROUPS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("outcome", ("success", "hc", "wc", "timeout")),
    ("efficiency", ("time_to_goal", "path_length", "path_length_ratio", "spl", "reward")),
    ("social", ("dist_person_min", "psi_intimate", "psi_personal", "ospace_pct", "interaction_crossings")),
    (
        "papers' metrics (Daza 2021: L_ratio, Smooth; Calderita et al.: CHC, object-space time Psi)",
        ("l_ratio", "smooth_rad", "chc", "psi_objects_any", "psi_objects_active"),
    ),
)

#: The columns of the headline table (terminal and top of ``summary.md``); "collision" is a collision
#: that ends the episode (walls, furniture, a robot, or a person by the robot's fault).
#: "o-space crossings" are the robot's crossings of the segments joining people in interaction
#: (person-person, i.e. through a group's o-space, and person-object).
HEADLINE = (
    "success",
    "collision",
    "time_to_goal",
    "path_length_ratio",
    "psi_personal",
    "interaction_crossings",
    "psi_objects_active",
    "snqi",
)
