"""Seeded evaluation of planners: episodes spread over processes (or Ray), records, summaries, plots.

Every planner runs the same episode seeds. Each episode yields one record (its metrics); the
records are written as CSV (row by row, so an interrupted run keeps what it finished) and as
Parquet at the end, and summarised per planner as means with 95% confidence intervals (Student t)
and rates with Wilson score intervals.
"""

from __future__ import annotations

import csv
import math
import os
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from proxemic import _core, scenarios
from proxemic.errors import EpisodeError, ProxemicError, input_error

T = TypeVar("T")
R = TypeVar("R")

#: Metrics summarised as rates (0/1 per episode), with Wilson intervals: success, collisions with
#: people (HC) and with walls or furniture (WC), timeout.
RATE_METRICS = ("success", "hc", "wc", "timeout")

#: Metrics summarised as means with t intervals (None values are left out): efficiency (time to
#: goal, path length, SPL, Daza 2021's L_ratio and Smooth), motion (CHC), distance to people
#: (closest centre distance), and time shares (%) in people's intimate and personal zones, inside
#: groups' o-spaces and inside object spaces while their activity is on (Calderita's Psi), plus
#: interaction crossings (person-person and person-object) per episode.
MEAN_METRICS = (
    "time_to_goal",
    "path_length",
    "spl",
    "l_ratio",
    "smooth",
    "chc",
    "dist_person_min",
    "psi_intimate",
    "psi_personal",
    "ospace_pct",
    "interaction_crossings",
    "psi_objects",
    "reward",
)

# Two-sided 95% Student t quantiles for 1..30 degrees of freedom (Fisher & Yates tables).
_T95 = (
    12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
    2.201, 2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
    2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042,
)  # fmt: skip


@dataclass(frozen=True)
class EvalConfig:
    """What to evaluate and where to write it."""

    scenario: str
    planners: Sequence[str]
    episodes: int = 20
    seed: int = 0
    out: Path = Path("out/eval")
    workers: int = 2
    backend: str = "process"
    ray_address: str | None = None
    keep_trajectories: int = 5
    """Episodes per planner whose trajectories are kept for the trajectory plot."""

    def tasks(self) -> list[tuple[str, str, int]]:
        """(scenario, planner, seed) of every episode, planner-major."""
        return [(self.scenario, p, self.seed + k) for p in self.planners for k in range(self.episodes)]


@dataclass
class EpisodeResult:
    """One episode's record and, optionally, its trajectories."""

    record: dict[str, Any]
    robot: np.ndarray | None = field(default=None, repr=False)
    people: np.ndarray | None = field(default=None, repr=False)
    path: np.ndarray | None = field(default=None, repr=False)


_ENV_CACHE: dict[tuple[Any, ...], Any] = {}
#: Envs kept per process (a tune run makes one per gain point: the oldest are closed).
_ENV_CACHE_SIZE = 8


def cached_env(
    scenario: str | _core.Scenario,
    planner: str,
    eband: Mapping[str, float] | None = None,
    goal: tuple[float, float] | None = None,
) -> Any:
    """An autopilot env of (scenario, planner, eband gains, goal), cached per process."""
    from proxemic.env import ProxemicEnv

    key = (scenario, planner, tuple(sorted((eband or {}).items())), goal)
    env = _ENV_CACHE.get(key)
    if env is None:
        while len(_ENV_CACHE) >= _ENV_CACHE_SIZE:
            _ENV_CACHE.pop(next(iter(_ENV_CACHE))).close()
        env = ProxemicEnv(scenario, autopilot=True, planner=planner, eband=eband, goal=goal)
        _ENV_CACHE[key] = env
    return env


def run_task(task: tuple[str | _core.Scenario, str, int], keep: bool = False) -> EpisodeResult:
    """Runs one (scenario, planner, seed) episode in this process (envs are cached per process)."""
    from proxemic.env import flatten_metrics
    from proxemic.runner import run_episode

    scenario, planner, seed = task
    env = cached_env(scenario, planner)
    rec = run_episode(scenario, seed, env=env)
    record = {"scenario": env.scenario["scene"]["name"], "planner": planner, "seed": seed, "reward": rec.total_reward}
    record.update(flatten_metrics(rec.metrics, env.scenario))
    if keep:
        return EpisodeResult(record, rec.robot, rec.people, rec.path)
    return EpisodeResult(record)


def _run_task_kw(args: tuple[tuple[str, str, int], bool]) -> EpisodeResult:
    return run_task(args[0], args[1])


def _check_ray_address(address: str) -> None:
    """Fails fast, with a clear message, when a ``host:port`` Ray address does not answer."""
    import socket

    hostport = address.removeprefix("ray://")
    host, sep, port = hostport.rpartition(":")
    if not sep or not port.isdigit():
        return  # "auto" and other forms are left to ray.init
    try:
        socket.create_connection((host or "127.0.0.1", int(port)), timeout=5.0).close()
    except OSError as e:
        raise input_error(
            "ray_address",
            "the address of a running Ray cluster (host:port)",
            address,
            note=f"no Ray cluster answers there: {e.strerror or e}",
        ) from e


class Backend:
    """Where episodes run: a process pool or Ray tasks (a local Ray, or a cluster's address).

    Use as a context manager; :meth:`imap` yields results in task order, so the same tasks give
    the same results on any backend and any number of workers. The pool (or the Ray connection)
    lives until the ``with`` block ends, so per-process env caches survive between calls.
    """

    def __init__(self, kind: str = "process", workers: int = 1, ray_address: str | None = None) -> None:
        """Checks the backend name; nothing starts before ``with``."""
        if kind not in ("process", "ray"):
            raise input_error("backend", "'process' or 'ray'", kind)
        self.kind, self.workers, self.ray_address = kind, max(1, workers), ray_address
        self._pool: Any = None
        self._ray: Any = None

    def __enter__(self) -> Backend:
        if self.kind == "ray":
            self._ray = self._start_ray()
        elif self.workers > 1:
            import multiprocessing as mp

            ctx = mp.get_context("fork") if hasattr(os, "fork") else mp.get_context("spawn")
            self._pool = ctx.Pool(self.workers)
        return self

    def __exit__(self, *exc: object) -> None:
        if self._pool is not None:
            self._pool.terminate()
            self._pool.join()
            self._pool = None
        if self._ray is not None:
            self._ray.shutdown()
            self._ray = None

    def _start_ray(self) -> Any:
        if self.ray_address:
            _check_ray_address(self.ray_address)
        try:
            import ray
        except ImportError as e:
            raise input_error(
                "backend",
                "the ray package installed",
                "ray not importable",
                note="backend 'ray' needs the ray package: pip install 'proxemic[ray]' (or pip install ray)",
            ) from e
        try:
            if self.ray_address:
                ray.init(address=self.ray_address, ignore_reinit_error=True, log_to_driver=False)
            else:
                ray.init(num_cpus=self.workers, ignore_reinit_error=True, log_to_driver=False, include_dashboard=False)
        except Exception as e:  # ray raises ConnectionError, RuntimeError, ... for a dead address
            raise input_error(
                "ray_address",
                "the address of a running Ray cluster",
                str(self.ray_address or "a local cluster"),
                note=f"could not connect: {e}",
            ) from e
        return ray

    def imap(self, fn: Callable[[T], R], items: Sequence[T]) -> Iterator[R]:
        """``fn`` over `items` (``fn`` a module-level function), results in order."""
        if self._ray is not None:
            remote = self._ray.remote(fn)
            refs = [remote.remote(item) for item in items]
            for ref in refs:
                yield self._ray.get(ref)
        elif self._pool is not None:
            yield from self._pool.imap(fn, items, chunksize=max(1, len(items) // (8 * self.workers)))
        else:
            for item in items:
                yield fn(item)


def iter_results(cfg: EvalConfig) -> Iterator[EpisodeResult]:
    """Runs every episode of `cfg` on its backend, yielding results in task order."""
    keep = [(t, (t[2] - cfg.seed) < cfg.keep_trajectories) for t in cfg.tasks()]
    with Backend(cfg.backend, cfg.workers, cfg.ray_address) as backend:
        yield from backend.imap(_run_task_kw, keep)


def t95(n: int) -> float:
    """Two-sided 95% Student t quantile for n samples (normal beyond 31)."""
    if n < 2:
        return math.nan
    return _T95[n - 2] if n - 1 <= len(_T95) else 1.96


def mean_ci(values: Iterable[float | None]) -> tuple[float, float, int]:
    """Mean, 95% half-width (Student t) and count of the finite values."""
    x = np.array([v for v in values if v is not None and math.isfinite(v)], dtype=np.float64)
    n = int(x.size)
    if n == 0:
        return math.nan, math.nan, 0
    if n == 1:
        return float(x[0]), math.nan, 1
    return float(x.mean()), t95(n) * float(x.std(ddof=1)) / math.sqrt(n), n


def wilson(successes: int, n: int, z: float = 1.959964) -> tuple[float, float, float]:
    """Rate and 95% Wilson score interval (low, high)."""
    if n == 0:
        return math.nan, math.nan, math.nan
    p = successes / n
    denom = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / denom
    return p, centre - half, centre + half


def summarise(records: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """One row per planner: rates with Wilson intervals, means with t intervals."""
    rows = []
    planners = list(dict.fromkeys(r["planner"] for r in records))
    for planner in planners:
        recs = [r for r in records if r["planner"] == planner]
        row: dict[str, Any] = {"planner": planner, "episodes": len(recs)}
        for m in RATE_METRICS:
            k = sum(bool(r.get(m)) for r in recs)
            p, lo, hi = wilson(k, len(recs))
            row[m] = p
            row[f"{m}_lo"] = lo
            row[f"{m}_hi"] = hi
        for m in MEAN_METRICS:
            mean, half, n = mean_ci(r.get(m) for r in recs)
            row[m] = mean
            row[f"{m}_ci"] = half
            row[f"{m}_n"] = n
        rows.append(row)
    return rows


def summary_markdown(rows: Sequence[dict[str, Any]]) -> str:
    """The summary as a markdown table: rates as p [lo, hi], means as m ± ci."""
    cols = ["planner", "episodes", *RATE_METRICS, *MEAN_METRICS]
    lines = ["| " + " | ".join(cols) + " |", "| " + " | ".join("---" for _ in cols) + " |"]
    for r in rows:
        cells = [str(r["planner"]), str(r["episodes"])]
        for m in RATE_METRICS:
            cells.append(f"{r[m]:.2f} [{r[m + '_lo']:.2f}, {r[m + '_hi']:.2f}]")
        for m in MEAN_METRICS:
            mean, ci = r[m], r[m + "_ci"]
            if math.isnan(mean):
                cells.append("n/a")
            elif math.isnan(ci):
                cells.append(f"{mean:.2f} (n={r[m + '_n']})")
            else:
                cells.append(f"{mean:.2f} ± {ci:.2f} (n={r[m + '_n']})")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def check_out_dir(out: Path) -> None:
    """Creates `out` if needed and checks that it can be written (InputError naming it if not)."""
    try:
        out.mkdir(parents=True, exist_ok=True)
        probe = out / ".write-test"
        probe.write_text("")
        probe.unlink()
    except OSError as e:
        raise input_error(
            "out", "a writable folder", str(out), note=f"the output folder cannot be written: {e.strerror}"
        ) from e


class RecordWriter:
    """Per-episode records written as they arrive: CSV rows flushed one by one, Parquet at the end.

    Used as a context manager around a run. If the run fails or is interrupted, the records that
    finished stay in the CSV, the Parquet file is written with them, and the error is re-raised as
    an :class:`EpisodeError` naming the episode that failed (an interrupt stays a
    ``KeyboardInterrupt``). `tasks` (in result order) names the failed episode.
    """

    def __init__(self, csv_path: Path, parquet_path: Path, tasks: Sequence[Any] = ()) -> None:
        """Opens the CSV file for writing (and removes an earlier run's Parquet file)."""
        self.csv_path, self.parquet_path, self.tasks = csv_path, parquet_path, tasks
        parquet_path.unlink(missing_ok=True)
        self.rows: list[dict[str, Any]] = []
        self._fh = csv_path.open("w", newline="")
        self._writer: csv.DictWriter[str] | None = None

    def write(self, record: dict[str, Any]) -> None:
        """Appends one record (the first fixes the columns) and flushes it to disk."""
        if self._writer is None:
            self._writer = csv.DictWriter(self._fh, fieldnames=list(record.keys()))
            self._writer.writeheader()
        self._writer.writerow(record)
        self._fh.flush()
        self.rows.append(record)

    def __enter__(self) -> RecordWriter:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: object) -> None:
        self._fh.close()
        if self.rows:
            _write_parquet(self.rows, self.parquet_path)
        if not isinstance(exc, Exception) or isinstance(exc, EpisodeError):
            return  # success, or an interrupt: the records stay, the exception goes on as it is
        if isinstance(exc, ProxemicError) and exc.field in ("backend", "ray_address"):
            return  # the backend did not start: no episode ran
        n = len(self.rows)
        task = f" {self.tasks[n]}" if n < len(self.tasks) else ""
        raise EpisodeError(
            f"episode {n + 1}{task} failed ({type(exc).__name__}: {exc}); the {n} finished episodes are kept "
            f"in {self.csv_path} and {self.parquet_path.name}",
            field="episode",
            expected="an episode that runs to its end",
            found=f"{type(exc).__name__}: {exc}",
        ) from exc


def run_eval(cfg: EvalConfig, *, progress: bool = True) -> list[dict[str, Any]]:
    """Runs the evaluation and writes records, summary and plots into `cfg.out`; returns the summary."""
    from tqdm import tqdm

    from proxemic.viz.plots import plot_episodes, plot_metrics_bars

    core, _ = scenarios.load(cfg.scenario)
    for p in cfg.planners:
        core.with_planner(p)  # an unknown name raises the core's ScenarioError
    if cfg.episodes < 1:
        raise input_error("episodes", "at least 1", cfg.episodes)
    out = Path(cfg.out)
    check_out_dir(out)
    _, scenario = scenarios.load(cfg.scenario)
    kept: dict[str, list[EpisodeResult]] = {p: [] for p in cfg.planners}
    tasks = cfg.tasks()
    bar = tqdm(total=len(tasks), desc=f"{cfg.scenario}: {', '.join(cfg.planners)}", unit="ep", disable=not progress)
    with RecordWriter(out / "episodes.csv", out / "episodes.parquet", tasks) as records:
        for res in iter_results(cfg):
            records.write(res.record)
            if res.robot is not None:
                kept[res.record["planner"]].append(res)
            bar.update(1)
    bar.close()
    rows = summarise(records.rows)
    (out / "summary.md").write_text(summary_markdown(rows) + "\n")
    plot_metrics_bars(rows, list(RATE_METRICS[:2] + MEAN_METRICS[:-1]), out / "metrics.png")
    for planner, results in kept.items():
        episodes = [
            {
                "label": f"seed {r.record['seed']}",
                "robot": r.robot,
                "people": r.people,
                "path": r.path if i == 0 else None,
                "outcome": r.record["outcome"],
            }
            for i, r in enumerate(results)
        ]
        if episodes:
            plot_episodes(scenario, episodes, out / f"trajectories_{planner}.png", title=f"{cfg.scenario}: {planner}")
    plot_planners_on_social_map(cfg.scenario, cfg.seed, kept, out / "trajectories_social_map.png")
    return rows


def plot_planners_on_social_map(
    scenario: str, seed: int, kept: dict[str, list[EpisodeResult]], out_png: Path
) -> Path | None:
    """Each planner's executed trajectory of episode `seed` over the social cost map at its start."""
    from proxemic.social import SocialMap

    paths = {
        planner: results[0].robot[:, :2]
        for planner, results in kept.items()
        if results and results[0].record["seed"] == seed and results[0].robot is not None
    }
    if not paths:
        return None
    sm = SocialMap(scenario, seed=seed)
    return sm.plot(out_png, paths=paths, title=f"{scenario}, seed {seed}: executed trajectories over the social map")


def _write_parquet(records: Sequence[dict[str, Any]], path: Path) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    pq.write_table(pa.Table.from_pylist(list(records)), path)
