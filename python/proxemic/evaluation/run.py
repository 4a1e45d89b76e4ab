"""Running an evaluation: checks, episodes on the backend, records, summary, verdicts and outputs."""

from __future__ import annotations

import contextlib
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from proxemic import reference, scenarios, snqi
from proxemic.errors import input_error
from proxemic.evaluation.backend import iter_results
from proxemic.evaluation.config import BASELINE_PLANNERS, EpisodeResult, EvalConfig
from proxemic.evaluation.episodes import _LOCAL_POLICIES, _POLICY_CACHE, check_policies
from proxemic.evaluation.output import RecordWriter, _write_outputs, check_out_dir
from proxemic.evaluation.summary import summarise, summary_report
from proxemic.evaluation.verdicts import verdicts
from proxemic.policy import PolicyRef, check_policy


@dataclass
class EvalResult:
    """What an evaluation produced: the per-episode records, the summary and the verdicts."""

    records: list[dict[str, Any]]
    """One dict per episode (the columns of ``episodes.csv``)."""
    summary: list[dict[str, Any]]
    """One row per planner or policy (:func:`summarise`)."""
    verdicts: list[str]
    """One paragraph per pair (:func:`verdicts`)."""
    out: Path | None = None
    """Where records, summary and plots were written (None: nowhere)."""

    def table(self) -> Any:
        """The records as a ``pyarrow.Table`` (``.to_pandas()`` gives a DataFrame if pandas is installed)."""
        import pyarrow as pa

        return pa.Table.from_pylist(self.records)

    def summary_markdown(self) -> str:
        """Headline table, verdicts and full table, as written to ``summary.md``."""
        return summary_report(self.summary, self.verdicts, self.snqi_line)

    @property
    def snqi_line(self) -> str:
        """The planners' ranking by mean SNQI and how it moves with each weight at -50% / +50%."""
        return snqi.sensitivity_line(self.records)


def _check_config(cfg: EvalConfig) -> None:
    core, _ = scenarios.load(cfg.scenario, drive=cfg.drive)
    for p in cfg.planners:
        scenarios.check_planner(p)  # an unknown name: a ScenarioError with "did you mean"
        core.with_planner(p)
    if cfg.episodes < 1:
        raise input_error("episodes", "at least 1", cfg.episodes)
    if not cfg.labels:
        raise input_error("planners", "at least one planner or policy", "none", note="nothing to evaluate")


def run_evaluation(cfg: EvalConfig, *, progress: bool = True) -> EvalResult:
    """Runs the evaluation of `cfg`; with ``cfg.out`` writes records, summary and plots there.

    Raises:
        InputError: A bad scenario, planner, policy (checked on one action before any episode),
            episode count, backend or output folder.
        EpisodeError: An episode failed (the finished ones are kept in ``episodes.csv``).
    """
    from tqdm import tqdm

    _check_config(cfg)
    out = None if cfg.out is None else Path(cfg.out)
    if out is not None:
        check_out_dir(out)
    check_policies(cfg)
    _, scenario = scenarios.load(cfg.scenario, drive=cfg.drive)
    kept: dict[str, list[EpisodeResult]] = {p: [] for p in cfg.labels}
    tasks = cfg.tasks()
    bar = tqdm(total=len(tasks), desc=f"{cfg.scene_label}: {', '.join(cfg.labels)}", unit="ep", disable=not progress)
    records: list[dict[str, Any]] = []
    if out is not None:
        reference.write_metrics_json(out / "metrics.json", scenario)
    writer = RecordWriter(out / "episodes.csv", out / "episodes.parquet", tasks) if out is not None else None
    try:
        with writer if writer is not None else contextlib.nullcontext():
            for res in iter_results(cfg):
                records.append(res.record)
                if writer is not None:
                    writer.write(res.record)
                if res.robot is not None:
                    kept[res.record["planner"]].append(res)
                if res.record.get("robot", 0) == 0:
                    bar.update(1)  # an episode (its other robots' records follow)
    finally:
        bar.close()
        for ref in cfg.policies:  # a later run builds its policies afresh
            cached = _POLICY_CACHE.pop((cfg.scenario, ref.name, ref.target, cfg.drive), None)
            if cached is not None:
                cached[0].close()
    rows = summarise(records)
    result = EvalResult(records, rows, verdicts(records, cfg.labels, len(cfg.policies)), out)
    if out is not None:
        _write_outputs(cfg, result, scenario, kept)
    return result


def run_eval(cfg: EvalConfig, *, progress: bool = True) -> list[dict[str, Any]]:
    """Runs the evaluation and writes records, summary and plots into `cfg.out`; returns the summary."""
    return run_evaluation(cfg, progress=progress).summary


def evaluate(
    policy: Any = None,
    *,
    scenario: str = "museum",
    episodes: int = 20,
    seed: int = 0,
    planners: Sequence[str] = BASELINE_PLANNERS,
    name: str | None = None,
    out: str | Path | None = None,
    workers: int = 1,
    backend: str = "process",
    ray_address: str | None = None,
    progress: bool = False,
) -> EvalResult:
    """Evaluates a policy beside built-in planners on the same seeds.

    Args:
        policy: A policy (see :mod:`proxemic.policy`: a callable ``obs -> action`` or an object with
            ``predict``), or the import path ``"module:factory"`` of a factory
            ``make(observation_space, action_space)`` (needed for the Ray backend), or None for
            planners only.
        scenario: Bundled scenario name or TOML path.
        episodes: Episodes per policy and planner; seeds ``seed .. seed + episodes - 1``.
        seed: First seed.
        planners: Built-in planners run on the same seeds.
        name: The policy's label (default: the factory's module, or the policy's class or function name).
        out: Folder for ``episodes.csv``/``.parquet``, ``summary.md`` and plots (default: write nothing).
        workers: Processes (policy objects reach them by fork).
        backend: ``"process"`` or ``"ray"``.
        ray_address: An existing Ray cluster.
        progress: Show a progress bar.

    Returns:
        The records (``result.table()`` is a pyarrow Table, ``.to_pandas()`` a DataFrame), the summary
        rows and the verdicts.
    """
    refs: list[PolicyRef] = []
    label = name
    if isinstance(policy, str):
        label = label or policy.partition(":")[0].rpartition(".")[2].removesuffix(".py").rpartition("/")[2]
        refs.append(PolicyRef(label, policy, os.getcwd()))
    elif policy is not None:
        check_policy(policy)
        label = label or getattr(policy, "__name__", None) or type(policy).__name__
        refs.append(PolicyRef(label, ""))
        _LOCAL_POLICIES[label] = policy
    cfg = EvalConfig(
        scenario=scenario,
        planners=list(planners),
        episodes=episodes,
        seed=seed,
        out=None if out is None else Path(out),
        workers=workers,
        backend=backend,
        ray_address=ray_address,
        policies=refs,
    )
    try:
        return run_evaluation(cfg, progress=progress)
    finally:
        for ref in refs:
            if not ref.target:
                _LOCAL_POLICIES.pop(ref.name, None)
