"""Seeded evaluation of planners: episodes spread over processes (or Ray), records, summaries, plots.

Every planner runs the same episode seeds. Each episode yields one record (its metrics); the
records are written as CSV (row by row, so an interrupted run keeps what it finished) and as
Parquet at the end, and summarised per planner as means with 95% confidence intervals (Student t)
and rates with Wilson score intervals.

The package, by concern: :mod:`~proxemic.evaluation.config` (what to run),
:mod:`~proxemic.evaluation.episodes` (one episode in this process),
:mod:`~proxemic.evaluation.backend` (where episodes run), :mod:`~proxemic.evaluation.stats`
(intervals), :mod:`~proxemic.evaluation.metrics` (how summarised metrics are shown),
:mod:`~proxemic.evaluation.summary` (per-planner rows and tables),
:mod:`~proxemic.evaluation.verdicts` (pairs of planners in words),
:mod:`~proxemic.evaluation.output` (files and plots) and :mod:`~proxemic.evaluation.run` (the
whole run). Everything public is importable from ``proxemic.evaluation``.
"""

from __future__ import annotations

from proxemic.evaluation.backend import Backend, iter_results
from proxemic.evaluation.config import BASELINE_PLANNERS, EpisodeResult, EvalConfig
from proxemic.evaluation.episodes import cached_env, check_policies, policy_env, run_task
from proxemic.evaluation.metrics import HEADLINE, METRIC_GROUPS, METRICS, VERDICT_METRICS
from proxemic.evaluation.output import RecordWriter, check_out_dir, plot_planners_on_social_map
from proxemic.evaluation.run import EvalResult, evaluate, run_eval, run_evaluation
from proxemic.evaluation.stats import mean_ci, paired_ratio, t95, wilson
from proxemic.evaluation.summary import (
    headline_markdown,
    headline_text,
    policy_robot_note,
    robots_note,
    summarise,
    summary_markdown,
    summary_report,
)
from proxemic.evaluation.verdicts import verdict, verdicts

__all__ = [
    "BASELINE_PLANNERS",
    "HEADLINE",
    "METRICS",
    "METRIC_GROUPS",
    "VERDICT_METRICS",
    "Backend",
    "EpisodeResult",
    "EvalConfig",
    "EvalResult",
    "RecordWriter",
    "cached_env",
    "check_out_dir",
    "check_policies",
    "evaluate",
    "headline_markdown",
    "headline_text",
    "iter_results",
    "mean_ci",
    "paired_ratio",
    "plot_planners_on_social_map",
    "policy_env",
    "policy_robot_note",
    "robots_note",
    "run_eval",
    "run_evaluation",
    "run_task",
    "summarise",
    "summary_markdown",
    "summary_report",
    "t95",
    "verdict",
    "verdicts",
    "wilson",
]
