"""Summaries of an evaluation's records: per-planner rows with intervals, and their tables."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from proxemic import markdown, scenarios, snqi
from proxemic.evaluation.config import EvalConfig
from proxemic.evaluation.metrics import HEADLINE, MEAN_METRICS, METRICS, OVER_SUCCESSES, RATE_METRICS
from proxemic.evaluation.stats import mean_ci, wilson


def collided(record: Mapping[str, Any]) -> bool:
    """A collision (walls or furniture, another robot, or a person by the robot's fault).

    A person walking into a stopped robot (``collisions_person_fault``) is not one: it is in
    ``hc`` but neither ends the episode nor counts here.
    """
    return record.get("outcome") == "collision" or bool(record.get("collision"))


def summarise(records: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """One row per planner: rates with Wilson intervals, means with t intervals.

    Rates ``m`` have ``m_lo``/``m_hi``; means have ``m_ci`` (half-width), ``m_n`` (episodes with
    a value) and ``m_lo``/``m_hi``: the interval clipped to the metric's bounds (:data:`METRICS`);
    the means of :data:`OVER_SUCCESSES` (``path_length_ratio``) are over the successful episodes.
    ``collision`` is the rate of episodes with any collision. ``snqi`` is robot-sf's composite
    (:mod:`proxemic.snqi`), normalised on the plain ``astar`` episodes among `records` (all of
    them when ``astar`` did not run). ``episodes`` counts the seeds and
    ``robots`` the robots per episode: on a multi-robot scene every robot of every episode is one
    sample (records with a ``robot`` column), so rates and means are over all robots.
    """
    stats = snqi.baseline_stats(records)
    records = [{**r, "snqi": snqi.episode_snqi(r, stats)} for r in records]
    rows = []
    planners = list(dict.fromkeys(r["planner"] for r in records))
    for planner in planners:
        recs = [r for r in records if r["planner"] == planner]
        robots = len({r.get("robot", 0) for r in recs})
        episodes = sum(1 for r in recs if r.get("robot", 0) == 0)
        row: dict[str, Any] = {"planner": planner, "episodes": episodes, "robots": robots}
        for m in RATE_METRICS:
            k = sum(collided(r) if m == "collision" else bool(r.get(m)) for r in recs)
            p, lo, hi = wilson(k, len(recs))
            row[m] = p
            row[f"{m}_lo"] = lo
            row[f"{m}_hi"] = hi
        for m in MEAN_METRICS:
            over = [r for r in recs if r.get("success")] if m in OVER_SUCCESSES else recs
            mean, half, n = mean_ci(r.get(m) for r in over)
            info = METRICS[m]
            row[m] = mean
            row[f"{m}_ci"] = half
            row[f"{m}_n"] = n
            row[f"{m}_lo"] = max(mean - half, info.low) if math.isfinite(half) else math.nan
            row[f"{m}_hi"] = min(mean + half, info.high) if math.isfinite(half) else math.nan
        rows.append(row)
    return rows


def is_rate(m: str) -> bool:
    """Whether `m` is summarised as a rate (a share of episodes, Wilson interval)."""
    return m in RATE_METRICS


def cell(row: Mapping[str, Any], m: str) -> str:
    """One summary cell: a rate or a mean and its 95% interval within the metric's bounds, as m [lo, hi]."""
    info = METRICS[m]
    if is_rate(m):
        return f"{row[m]:.0%} [{row[m + '_lo']:.0%}, {row[m + '_hi']:.0%}]"
    mean, lo, hi, n = row[m], row[m + "_lo"], row[m + "_hi"], row[m + "_n"]
    if math.isnan(mean):
        return "n/a"
    if math.isnan(lo):
        return f"{mean:{info.fmt}} (n={n})"
    partial = f" (n={n})" if n < row["episodes"] else ""
    return f"{mean:{info.fmt}} [{lo:{info.fmt}}, {hi:{info.fmt}}]{partial}"


def header(m: str) -> str:
    """A table column's header: the metric's label and unit."""
    info = METRICS[m]
    unit = "%" if is_rate(m) else info.unit.split(" (")[0]
    return f"{info.label} ({unit})" if unit else info.label


def _table(rows: Sequence[Mapping[str, Any]], metrics: Sequence[str]) -> str:
    cols = ["planner", "episodes", *(header(m) for m in metrics)]
    lines = []
    for r in rows:
        n = f"{r['episodes']} x {r['robots']} robots" if r.get("robots", 1) > 1 else str(r["episodes"])
        cells = [str(r["planner"]), n, *(cell(r, m) for m in metrics)]
        lines.append(cells)
    return markdown.table(cols, lines)


def robots_note(rows: Sequence[Mapping[str, Any]]) -> str:
    """What a summary of a multi-robot scene averages over (empty for single-robot scenes)."""
    robots = max((int(r.get("robots", 1)) for r in rows), default=1)
    if robots <= 1:
        return ""
    return (
        f"Every robot scored: the planner drives all {robots} robots of each episode and every robot is one "
        f"sample (the `robot` column of the records); rates and means are over episodes x {robots} robots "
        "(robots of one episode are not independent: the intervals are narrower than for as many episodes)."
    )


def policy_robot_note(cfg: EvalConfig) -> str:
    """What an evaluation with user policies on a multi-robot scene scores (empty otherwise)."""
    if not cfg.policies:
        return ""
    core, _ = scenarios.load(cfg.scenario, drive=cfg.drive)
    if core.num_robots <= 1:
        return ""
    return (
        f"Robot 0 scored only: the scene has {core.num_robots} robots and a policy drives robot 0 "
        "(the others keep their built-in planners), so every planner is scored on robot 0 as well."
    )


def headline_markdown(rows: Sequence[dict[str, Any]]) -> str:
    """The headline table with units and 95% intervals.

    Success, collisions, time to goal, path length ratio, intimate- and personal-zone time on
    centre distances, intimate-zone time on body gaps with the robot-caused and person-caused
    intimate entries and personal-zone seconds, o-space crossings and active object-space time
    (:data:`HEADLINE`).
    """
    return _table(rows, HEADLINE)


def headline_text(rows: Sequence[dict[str, Any]]) -> str:
    """The headline table for a terminal: one line per metric (label and unit), one column per planner.

    Transposed from :func:`headline_markdown` so that it stays narrow (about 40 characters plus
    20 per planner) however long the labels are; cells are ``mean [95% interval]``.
    """
    labels = [header(m) for m in HEADLINE]
    names = [str(r["planner"]) for r in rows]
    cells = [[cell(r, m) for r in rows] for m in HEADLINE]
    episodes = [str(r["episodes"]) for r in rows]
    w0 = max(len(x) for x in [*labels, "episodes"])
    widths = [
        max(len(x) for x in [name, ep, *(c[i] for c in cells)])
        for i, (name, ep) in enumerate(zip(names, episodes, strict=True))
    ]

    def line(first: str, values: Sequence[str]) -> str:
        return "  ".join([first.ljust(w0), *(v.rjust(w) for v, w in zip(values, widths, strict=True))]).rstrip()

    out = [line("", names), line("episodes", episodes)]
    out += [line(label, row) for label, row in zip(labels, cells, strict=True)]
    return "\n".join(out)


def summary_markdown(rows: Sequence[dict[str, Any]]) -> str:
    """The full summary as a markdown table: rates and means as m [lo, hi] (Wilson, Student t)."""
    return _table(rows, [*RATE_METRICS, *MEAN_METRICS])


def summary_report(rows: Sequence[dict[str, Any]], verdict_lines: Sequence[str], snqi_line: str = "") -> str:
    """The markdown summary: headline table, the SNQI ranking and its sensitivity, verdicts, then the full table."""
    note = robots_note(rows)
    parts = [
        headline_markdown(rows),
        *([note] if note else []),
        *([snqi_line] if snqi_line else []),
        "Rates: % of episodes [95% Wilson interval]; means [95% Student t interval, clipped to the metric's "
        "range]; (n=) when only n episodes have a value (time to goal: successes only).",
    ]
    if verdict_lines:
        parts += [
            "Verdicts (ratios of means over the seeds both reached the goal, [95% paired bootstrap interval]):",
            "\n".join(f"- {v}" for v in verdict_lines),
        ]
    parts += ["## All metrics", summary_markdown(rows)]
    return "\n\n".join(parts)
