"""SNQI, the Social Navigation Quality Index of the robot-sf benchmark, over an evaluation's records.

Definition (robot-sf, ``robot_sf.benchmark.snqi.compute``: repository ``ll7/robot_sf_ll7``, file
``robot_sf/benchmark/snqi/compute.py``, read at commit ``af4b7c2c8b04576289b529c30c1367b16f3f7c3b``),
per episode, higher is better::

    SNQI = w_success * success
           - w_time * time_norm
           - w_collisions * norm(collisions)
           - w_near * norm(near_misses)
           - w_comfort * comfort_exposure
           - w_force_exceed * norm(force_exceed_events)
           - w_jerk * norm(jerk_mean)

with ``time_norm`` the time to goal over the episode's time limit on success and 1 otherwise, and
``norm(v) = (v - median) / (p95 - median)`` clamped to [0, 1], the median and 95th percentile
taken over a baseline's episodes (a denominator under 1e-9 is replaced by 1, as published). The
published canonical weights are :data:`WEIGHTS`.

Our inputs (``docs/metrics.md``): ``collisions`` is ``hc_count`` (instants of robot-person contact),
``near_misses``, ``force_exceed_events`` and ``comfort_exposure`` are the core's SNQI family
(robot-sf's thresholds, 0.5 m and 2.0 m/s²; the force is the robot's social force on each person),
``jerk_mean`` is ``jerk_avg``. Our choice where robot-sf leaves it to the user: the baseline of
the normalisation is the plain ``astar`` planner's episodes in the same evaluation when it ran,
otherwise every episode of the evaluation (docs: choices.md). A missing value (``None``, e.g. no
jerk in a 2-sample episode) contributes 0, as robot-sf does for a metric without baseline.

The sensitivity analysis moves each weight alone by -50% and +50% and reports whether the
planners' ranking by mean SNQI changes.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

#: robot-sf's canonical SNQI weights, as published in ``recompute_snqi_weights`` (its
#: ``canonical_weights``, ``method="canonical"``) of ``robot_sf/benchmark/snqi/compute.py`` in the
#: repository ``ll7/robot_sf_ll7`` (read at commit ``af4b7c2c8b04576289b529c30c1367b16f3f7c3b``);
#: its ``WEIGHT_NAMES`` are these keys in this order.
WEIGHTS: dict[str, float] = {
    "w_success": 1.0,
    "w_time": 0.8,
    "w_collisions": 2.0,
    "w_near": 1.0,
    "w_comfort": 0.5,
    "w_force_exceed": 1.5,
    "w_jerk": 0.3,
}

#: The weights whose metric is normalised by the baseline's median and 95th percentile, and the
#: record column each reads.
NORMALISED: dict[str, str] = {
    "w_collisions": "hc_count",
    "w_near": "near_misses",
    "w_force_exceed": "force_exceed_events",
    "w_jerk": "jerk_avg",
}

#: The planner whose episodes set the normalisation, when it ran.
BASELINE = "astar"

#: The factors of the sensitivity analysis (each weight alone).
SENSITIVITY_FACTORS = (0.5, 1.5)

Stats = dict[str, tuple[float, float]]


def _value(record: Mapping[str, Any], key: str) -> float | None:
    v = record.get(key)
    if v is None:
        return None
    x = float(v)
    return x if math.isfinite(x) else None


def baseline_stats(records: Sequence[Mapping[str, Any]], baseline: str = BASELINE) -> Stats:
    """Median and 95th percentile of each normalised metric over the baseline's records.

    The baseline is the records of planner `baseline` when there are any, else all `records`.
    A metric with no value in them is left out (its term then contributes 0).
    """
    base = [r for r in records if r.get("planner") == baseline] or list(records)
    stats: Stats = {}
    for column in NORMALISED.values():
        values = [v for r in base if (v := _value(r, column)) is not None]
        if values:
            stats[column] = (float(np.median(values)), float(np.percentile(values, 95)))
    return stats


def normalise(value: float, med: float, p95: float) -> float:
    """``(value - med) / (p95 - med)`` clamped to [0, 1]; a denominator under 1e-9 counts as 1."""
    denom = p95 - med
    if abs(denom) < 1e-9:
        denom = 1.0
    return min(1.0, max(0.0, (value - med) / denom))


def time_norm(record: Mapping[str, Any]) -> float:
    """Time to goal over the episode's time limit (``max_time``) on success; 1 otherwise."""
    t, horizon = _value(record, "time_to_goal"), _value(record, "max_time")
    if not record.get("success") or t is None or horizon is None or horizon <= 0:
        return 1.0
    return min(1.0, t / horizon)


def episode_snqi(record: Mapping[str, Any], stats: Stats, weights: Mapping[str, float] = WEIGHTS) -> float:
    """The SNQI of one episode's record (higher is better; at most ``w_success``)."""
    score = weights["w_success"] * float(bool(record.get("success")))
    score -= weights["w_time"] * time_norm(record)
    score -= weights["w_comfort"] * (_value(record, "comfort_exposure") or 0.0)
    for weight, column in NORMALISED.items():
        v = _value(record, column)
        if v is not None and column in stats:
            score -= weights[weight] * normalise(v, *stats[column])
    return score


def planner_means(
    records: Sequence[Mapping[str, Any]], stats: Stats, weights: Mapping[str, float] = WEIGHTS
) -> dict[str, float]:
    """Mean SNQI per planner (record order), over every record (episodes x robots)."""
    sums: dict[str, list[float]] = {}
    for r in records:
        sums.setdefault(str(r["planner"]), []).append(episode_snqi(r, stats, weights))
    return {p: float(np.mean(v)) for p, v in sums.items()}


def ranking(means: Mapping[str, float]) -> list[str]:
    """Planners from the best mean SNQI to the worst (ties keep record order)."""
    return sorted(means, key=lambda p: -means[p])


def sensitivity(
    records: Sequence[Mapping[str, Any]], stats: Stats, weights: Mapping[str, float] = WEIGHTS
) -> list[tuple[str, float, list[str]]]:
    """The ranking with each weight alone scaled by each of :data:`SENSITIVITY_FACTORS`.

    Returns ``(weight, factor, ranking)`` for every weight and factor, in :data:`WEIGHTS` order.
    """
    out = []
    for w in weights:
        for f in SENSITIVITY_FACTORS:
            moved = dict(weights)
            moved[w] = weights[w] * f
            out.append((w, f, ranking(planner_means(records, stats, moved))))
    return out


def sensitivity_line(records: Sequence[Mapping[str, Any]], baseline: str = BASELINE) -> str:
    """One line: the SNQI ranking and how it changes when each weight moves by ±50%."""
    stats = baseline_stats(records, baseline)
    means = planner_means(records, stats)
    base = ranking(means)
    order = " > ".join(f"{p} ({means[p]:+.3f})" for p in base)
    if len(base) < 2:
        return f"SNQI (robot-sf, canonical weights): {order}."
    changes = [f"{w} x{f:g}: {' > '.join(r)}" for w, f, r in sensitivity(records, stats) if r != base]
    moved = "; ".join(changes) if changes else "unchanged when any one weight moves by -50% or +50%"
    return f"SNQI ranking (robot-sf, canonical weights): {order}. Sensitivity: {moved}."


def add_snqi(records: Sequence[dict[str, Any]], baseline: str = BASELINE) -> None:
    """Sets each record's ``snqi`` (normalised on the baseline of these `records`), in place."""
    stats = baseline_stats(records, baseline)
    for r in records:
        r["snqi"] = episode_snqi(r, stats)
