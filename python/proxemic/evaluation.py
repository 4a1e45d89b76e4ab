"""Seeded evaluation of planners: episodes spread over processes (or Ray), records, summaries, plots.

Every planner runs the same episode seeds. Each episode yields one record (its metrics); the
records are written as CSV (row by row, so an interrupted run keeps what it finished) and as
Parquet at the end, and summarised per planner as means with 95% confidence intervals (Student t)
and rates with Wilson score intervals.
"""

from __future__ import annotations

import contextlib
import csv
import math
import os
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from proxemic import _core, reference, scenarios, snqi
from proxemic.errors import EpisodeError, MissingExtraError, ProxemicError, input_error, require_extra
from proxemic.policy import PolicyActor, PolicyRef, build_policy, check_policy

T = TypeVar("T")
R = TypeVar("R")

#: The non-social baselines, the default planners of ``proxemic eval`` (without ``--policy``) and of
#: :func:`evaluate`: plain A* blind to people, plain A* followed with ORCA (people do not
#: reciprocate), plain A* that stops for whoever is in its way and re-plans around them after 2 s.
BASELINE_PLANNERS: tuple[str, ...] = ("astar", "astar_orca", "astar_stop")

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

# Two-sided 95% Student t quantiles for 1..30 degrees of freedom (Fisher & Yates tables).
_T95 = (
    12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
    2.201, 2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
    2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042,
)  # fmt: skip


@dataclass(frozen=True)
class EvalConfig:
    """What to evaluate and where to write it.

    `policies` are user policies (:class:`proxemic.policy.PolicyRef`) evaluated beside the
    built-in `planners`, on the same seeds; both are "planners" in the records' ``planner`` column.
    With ``out=None`` nothing is written.
    """

    scenario: str
    planners: Sequence[str]
    episodes: int = 20
    seed: int = 0
    out: Path | None = Path("out/eval")
    workers: int = 2
    backend: str = "process"
    ray_address: str | None = None
    keep_trajectories: int = 5
    """Episodes per planner whose trajectories are kept for the trajectory plot."""
    policies: Sequence[PolicyRef] = ()

    @property
    def labels(self) -> list[str]:
        """The label of every evaluated policy and planner, in task order."""
        return [p.name for p in self.policies] + list(self.planners)

    def tasks(self) -> list[tuple[str, str | PolicyRef, int]]:
        """(scenario, planner or policy, seed) of every episode, policies then planners, planner-major."""
        who: list[str | PolicyRef] = [*self.policies, *self.planners]
        return [(self.scenario, p, self.seed + k) for p in who for k in range(self.episodes)]


@dataclass
class EpisodeResult:
    """One episode's record and, optionally, its trajectories."""

    record: dict[str, Any]
    robot: np.ndarray | None = field(default=None, repr=False)
    people: np.ndarray | None = field(default=None, repr=False)
    path: np.ndarray | None = field(default=None, repr=False)
    others: list[EpisodeResult] = field(default_factory=list, repr=False)
    """On a multi-robot scene, the other robots' records of the same episode (robot 1, 2, ...)."""


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


#: Policy objects given to :func:`evaluate` (not import paths), by label: read in this process and
#: in worker processes forked after they were put here.
_LOCAL_POLICIES: dict[str, Any] = {}
#: (scenario, policy label, import path) -> (env, actor), per process, for the run under way.
_POLICY_CACHE: dict[tuple[str | _core.Scenario, str, str], tuple[Any, PolicyActor]] = {}


def policy_env(scenario: str | _core.Scenario, ref: PolicyRef) -> tuple[Any, PolicyActor]:
    """An action-driven env of `scenario` and the policy of `ref` built for it, cached per process.

    An import-path policy is built here from its factory (so every worker has its own); a policy
    object is taken from those given to :func:`evaluate`.
    """
    from proxemic.env import ProxemicEnv

    key = (scenario, ref.name, ref.target)
    cached = _POLICY_CACHE.get(key)
    if cached is None:
        env = ProxemicEnv(scenario, autopilot=False)
        if ref.target:
            policy = build_policy(ref.target, env.observation_space, env.action_space, ref.search_path)
        elif ref.name in _LOCAL_POLICIES:
            policy = _LOCAL_POLICIES[ref.name]
        else:
            env.close()
            raise input_error(
                "policy",
                "an import path 'module:factory'",
                "a policy object",
                note=f"policy {ref.name!r} runs only in this process and in forked worker processes; "
                "an import path runs anywhere (e.g. on Ray)",
            )
        cached = (env, PolicyActor(policy, tuple(env.action_space.shape or (3,)), ref.name))
        _POLICY_CACHE[key] = cached
    return cached


def run_task(task: tuple[str | _core.Scenario, str | PolicyRef, int], keep: bool = False) -> EpisodeResult:
    """Runs one (scenario, planner or policy, seed) episode in this process (envs cached per process).

    The result is robot 0's record (column ``robot`` = 0). On a scene with several robots, a
    built-in planner drives every robot and the episode runs until every robot's episode ended;
    the other robots' records are in ``others`` (a user policy drives robot 0 only and is refused
    there by :func:`check_policies`).
    """
    from proxemic.env import flatten_metrics
    from proxemic.runner import run_episode

    scenario, planner, seed = task
    if isinstance(planner, PolicyRef):
        env, actor = policy_env(scenario, planner)
        rec = run_episode(scenario, seed, env=env, policy=actor)
        label = planner.name
    else:
        env = cached_env(scenario, planner)
        if env.ws.num_robots > 1:
            return _run_team(env, seed, planner, keep)
        rec = run_episode(scenario, seed, env=env)
        label = planner
    record = {
        "scenario": env.scenario["scene"]["name"],
        "planner": label,
        "seed": seed,
        "robot": 0,
        "reward": rec.total_reward,
        "max_time": float(env.scenario["episode"]["max_time"]),
    }
    record.update(flatten_metrics(rec.metrics, env.scenario))
    if keep:
        return EpisodeResult(record, rec.robot, rec.people, rec.path)
    return EpisodeResult(record)


def _run_team(env: Any, seed: int, planner: str, keep: bool) -> EpisodeResult:
    """One episode of a multi-robot scene with every robot on its built-in planner, to the last robot's end.

    Robot 0's record is the one the single-robot env gives (a robot's metrics and reward stop at
    its own episode's end); robot k's record has ``robot`` = k.
    """
    from proxemic.env import flatten_metrics

    env.reset(seed=seed)
    ws = env.ws
    path = env.planned_path() if keep else None
    people = [env.people()[:, :2]] if keep else []
    totals = np.zeros(ws.num_robots)
    first_running = True
    while True:
        ws.step()
        outcome = ws.step_outcome()
        totals += [r for r, _, _ in outcome]
        if keep and first_running:  # the people while robot 0 runs, as the single-robot env gives
            people.append(env.people()[:, :2])
        first_running = not (outcome[0][1] or outcome[0][2])
        if all(t or u for _, t, u in outcome):
            break
    results = []
    for i, metrics in enumerate(env.world.episode_metrics()):
        record = {
            "scenario": env.scenario["scene"]["name"],
            "planner": planner,
            "seed": seed,
            "robot": i,
            "reward": float(totals[i]),
            "max_time": float(env.scenario["episode"]["max_time"]),
        }
        record.update(flatten_metrics(metrics, env.scenario))
        results.append(EpisodeResult(record))
    first = results[0]
    if keep:
        first.robot, first.people, first.path = np.asarray(env.world.trajectory(0)), np.array(people), path
    first.others = results[1:]
    return first


def check_policies(cfg: EvalConfig) -> None:
    """Builds each user policy here and asks it for one action, so a bad one fails before any episode.

    Raises:
        InputError: A factory that does not load, a policy that is not callable, an action of the
            wrong shape, a duplicated label, or a policy object on a backend that cannot run it.
    """
    labels = cfg.labels
    for ref in cfg.policies:
        if labels.count(ref.name) > 1:
            raise input_error("policy_name", f"a label no other policy or planner has (taken: {labels})", ref.name)
        if not ref.target and (cfg.backend == "ray" or (cfg.workers > 1 and not hasattr(os, "fork"))):
            raise input_error(
                "policy",
                "an import path 'module:factory' (built in each worker)",
                "a policy object",
                note=f"policy {ref.name!r} cannot be sent to backend {cfg.backend!r}",
            )
        env, actor = policy_env(cfg.scenario, ref)
        obs, _ = env.reset(seed=cfg.seed)
        actor.reset(cfg.seed)
        actor(obs)
        if cfg.workers > 1 or cfg.backend == "ray":
            _POLICY_CACHE.pop((cfg.scenario, ref.name, ref.target))[0].close()  # the workers build their own


def _run_task_kw(args: tuple[tuple[str, str | PolicyRef, int], bool]) -> EpisodeResult:
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
        ray: Any = require_extra("ray", "ray", "backend 'ray'")
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
    """Runs every episode of `cfg` on its backend, yielding results in task order.

    On a multi-robot scene an episode yields one result per robot (robot 0 first), unless user
    policies are evaluated: a policy drives robot 0 only, so then every planner is scored on robot 0
    too (like for like; see :func:`policy_robot_note`).
    """
    keep = [(t, (t[2] - cfg.seed) < cfg.keep_trajectories) for t in cfg.tasks()]
    with Backend(cfg.backend, cfg.workers, cfg.ray_address) as backend:
        for res in backend.imap(_run_task_kw, keep):
            yield res
            if not cfg.policies:  # a policy drives robot 0 only: everyone is scored on robot 0
                yield from res.others


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


def _collided(record: Mapping[str, Any]) -> bool:
    """A collision (walls or furniture, another robot, or a person by the robot's fault).

    A person walking into a stopped robot (``collisions_person_fault``) is not one: it is in
    ``hc`` but neither ends the episode nor counts here.
    """
    return record.get("outcome") == "collision" or bool(record.get("collision"))


def summarise(records: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """One row per planner: rates with Wilson intervals, means with t intervals.

    Rates ``m`` have ``m_lo``/``m_hi``; means have ``m_ci`` (half-width), ``m_n`` (episodes with
    a value) and ``m_lo``/``m_hi``: the interval clipped to the metric's bounds (:data:`METRICS`).
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
        for m in (*RATE_METRICS, "collision"):
            k = sum(_collided(r) if m == "collision" else bool(r.get(m)) for r in recs)
            p, lo, hi = wilson(k, len(recs))
            row[m] = p
            row[f"{m}_lo"] = lo
            row[f"{m}_hi"] = hi
        for m in MEAN_METRICS:
            mean, half, n = mean_ci(r.get(m) for r in recs)
            info = METRICS[m]
            row[m] = mean
            row[f"{m}_ci"] = half
            row[f"{m}_n"] = n
            row[f"{m}_lo"] = max(mean - half, info.low) if math.isfinite(half) else math.nan
            row[f"{m}_hi"] = min(mean + half, info.high) if math.isfinite(half) else math.nan
        rows.append(row)
    return rows


def _is_rate(m: str) -> bool:
    return m in (*RATE_METRICS, "collision")


def _cell(row: Mapping[str, Any], m: str) -> str:
    """One summary cell: a rate or a mean and its 95% interval within the metric's bounds, as m [lo, hi]."""
    info = METRICS[m]
    if _is_rate(m):
        return f"{row[m]:.0%} [{row[m + '_lo']:.0%}, {row[m + '_hi']:.0%}]"
    mean, lo, hi, n = row[m], row[m + "_lo"], row[m + "_hi"], row[m + "_n"]
    if math.isnan(mean):
        return "n/a"
    if math.isnan(lo):
        return f"{mean:{info.fmt}} (n={n})"
    partial = f" (n={n})" if n < row["episodes"] else ""
    return f"{mean:{info.fmt}} [{lo:{info.fmt}}, {hi:{info.fmt}}]{partial}"


def _header(m: str) -> str:
    info = METRICS[m]
    unit = "%" if _is_rate(m) else info.unit.split(" (")[0]
    return f"{info.label} ({unit})" if unit else info.label


def _table(rows: Sequence[Mapping[str, Any]], metrics: Sequence[str]) -> str:
    cols = ["planner", "episodes", *(_header(m) for m in metrics)]
    lines = ["| " + " | ".join(cols) + " |", "| " + " | ".join("---" for _ in cols) + " |"]
    for r in rows:
        n = f"{r['episodes']} x {r['robots']} robots" if r.get("robots", 1) > 1 else str(r["episodes"])
        cells = [str(r["planner"]), n, *(_cell(r, m) for m in metrics)]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


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
    core, _ = scenarios.load(cfg.scenario)
    if core.num_robots <= 1:
        return ""
    return (
        f"Robot 0 scored only: the scene has {core.num_robots} robots and a policy drives robot 0 "
        "(the others keep their built-in planners), so every planner is scored on robot 0 as well."
    )


def headline_markdown(rows: Sequence[dict[str, Any]]) -> str:
    """The headline table with units and 95% intervals.

    Success, collisions, time to goal, path length ratio, personal-zone time, o-space crossings
    and active object-space time (:data:`HEADLINE`).
    """
    return _table(rows, HEADLINE)


def headline_text(rows: Sequence[dict[str, Any]]) -> str:
    """The headline table for a terminal: one line per metric (label and unit), one column per planner.

    Transposed from :func:`headline_markdown` so that it stays narrow (about 40 characters plus
    20 per planner) however long the labels are; cells are ``mean [95% interval]``.
    """
    labels = [_header(m) for m in HEADLINE]
    names = [str(r["planner"]) for r in rows]
    cells = [[_cell(r, m) for r in rows] for m in HEADLINE]
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
    return _table(rows, [*RATE_METRICS, "collision", *MEAN_METRICS])


#: The metrics of a verdict: (metric, how a ratio is said: "times" as 1.2x, "share" as 55% less).
VERDICT_METRICS: tuple[tuple[str, str], ...] = (
    ("time_to_goal", "times"),
    ("path_length", "times"),
    ("l_ratio", "times"),
    ("psi_personal", "share"),
    ("ospace_pct", "share"),
    ("interaction_crossings", "share"),
    ("psi_objects_active", "share"),
)
BOOTSTRAP_SAMPLES = 2000


def paired_ratio(a: Sequence[float], b: Sequence[float], seed: int = 0) -> tuple[float, float, float]:
    """mean(a) / mean(b) over paired samples and its 95% percentile bootstrap interval (pairs resampled).

    Returns NaNs when b's mean is 0 (or a resample's is: those resamples are left out).
    """
    x, y = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    if x.size == 0 or y.mean() == 0:
        return math.nan, math.nan, math.nan
    idx = np.random.default_rng(seed).integers(0, x.size, size=(BOOTSTRAP_SAMPLES, x.size))
    num, den = x[idx].mean(axis=1), y[idx].mean(axis=1)
    ok = den > 0
    ratios = num[ok] / den[ok]
    lo, hi = np.percentile(ratios, [2.5, 97.5]) if ratios.size else (math.nan, math.nan)
    return float(x.mean() / y.mean()), float(lo), float(hi)


def _change(r: float, lo: float, hi: float) -> str:
    """A ratio of means and its interval in words: ``55% less X [33-73% less]``."""

    def pct(x: float) -> str:
        return f"{abs(x - 1):.0%}"

    said = f"{pct(r)} {'less' if r < 1 else 'more'}"
    if hi < 1 or lo > 1:
        a, b = sorted((pct(lo), pct(hi)), key=lambda t: float(t[:-1]))
        word = "less" if hi < 1 else "more"
        return f"{said} [{a} {word}]" if a == b else f"{said} [{a[:-1]}-{b} {word}]"
    return f"{said} [{pct(lo)} less to {pct(hi)} more]"


def verdict(records: Sequence[Mapping[str, Any]], a: str, b: str) -> str:
    """One plain-language paragraph comparing planner `a` with `b` on the seeds both ran.

    Success and collision counts over all shared seeds; then, over the seeds where both reached the
    goal, ratios of means of time to goal, path length and the social time shares with 95%
    bootstrap intervals (pairs of episodes resampled).
    """
    # Episodes pair by (seed, robot): on a multi-robot scene every robot is paired with itself.
    by = {p: {(r["seed"], r.get("robot", 0)): r for r in records if r["planner"] == p} for p in (a, b)}
    seeds = sorted(set(by[a]) & set(by[b]))
    if not seeds:
        return f"{a} vs {b}: no seed in common."
    unit = "seeds" if all(robot == 0 for _, robot in seeds) else "robot-episodes (seed, robot)"

    def count(p: str, pred: Callable[[Mapping[str, Any]], bool]) -> int:
        return sum(pred(by[p][s]) for s in seeds)

    ok = [s for s in seeds if by[a][s].get("success") and by[b][s].get("success")]
    parts = [
        f"{a} vs {b} on {len(seeds)} {unit}: success {count(a, lambda r: bool(r.get('success')))} vs "
        f"{count(b, lambda r: bool(r.get('success')))}, collisions {count(a, _collided)} vs {count(b, _collided)}"
    ]
    if len(ok) < 2:
        what = "seed(s)" if unit == "seeds" else "robot-episode(s)"
        parts.append(f"only {len(ok)} {what} where both reached the goal, too few to compare further.")
        return "; ".join(parts)
    said = []
    for m, how in VERDICT_METRICS:
        raw = [(by[a][s].get(m), by[b][s].get(m)) for s in ok]
        pairs = [(float(x), float(y)) for x, y in raw if x is not None and y is not None]
        if len(pairs) < 2:
            continue
        xs, ys = [p[0] for p in pairs], [p[1] for p in pairs]
        label = METRICS[m].label
        r, lo, hi = paired_ratio(xs, ys)
        if math.isnan(r):
            if np.mean(xs) == 0:
                said.append(f"no {label} for either")
            else:
                said.append(f"{label} {np.mean(xs):{METRICS[m].fmt}} {METRICS[m].unit} vs none")
        elif how == "times":
            said.append(f"{r:.2f}x {label} [{lo:.2f}x, {hi:.2f}x]")
        else:
            words = _change(r, lo, hi)
            said.append(words.replace(" [", f" {label} [", 1))
    parts.append(f"over the {len(ok)} {unit} both reached the goal: " + ", ".join(said) + ".")
    return "; ".join(parts)


def verdicts(records: Sequence[Mapping[str, Any]], labels: Sequence[str], policies: int = 0) -> list[str]:
    """A :func:`verdict` for every pair of `labels`.

    The first `policies` labels (user policies) come first against every later label, then each
    later planner against each earlier one (``social vs astar``).
    """
    out = []
    for i in range(len(labels)):
        for j in range(i + 1, len(labels)):
            a, b = (labels[i], labels[j]) if i < policies else (labels[j], labels[i])
            out.append(verdict(records, a, b))
    return out


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
        if isinstance(exc, MissingExtraError) or (
            isinstance(exc, ProxemicError) and exc.field in ("backend", "ray_address")
        ):
            return  # the backend did not start: no episode ran
        n = sum(1 for r in self.rows if r.get("robot", 0) == 0)  # episodes (a record per robot)
        task = f" {self.tasks[n]}" if n < len(self.tasks) else ""
        raise EpisodeError(
            f"episode {n + 1}{task} failed ({type(exc).__name__}: {exc}); the {n} finished episodes are kept "
            f"in {self.csv_path} and {self.parquet_path.name}",
            field="episode",
            expected="an episode that runs to its end",
            found=f"{type(exc).__name__}: {exc}",
        ) from exc


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
    core, _ = scenarios.load(cfg.scenario)
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
    _, scenario = scenarios.load(cfg.scenario)
    kept: dict[str, list[EpisodeResult]] = {p: [] for p in cfg.labels}
    tasks = cfg.tasks()
    bar = tqdm(total=len(tasks), desc=f"{cfg.scenario}: {', '.join(cfg.labels)}", unit="ep", disable=not progress)
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
            cached = _POLICY_CACHE.pop((cfg.scenario, ref.name, ref.target), None)
            if cached is not None:
                cached[0].close()
    rows = summarise(records)
    result = EvalResult(records, rows, verdicts(records, cfg.labels, len(cfg.policies)), out)
    if out is not None:
        _write_outputs(cfg, result, scenario, kept)
    return result


def _write_outputs(cfg: EvalConfig, result: EvalResult, scenario: Any, kept: dict[str, list[EpisodeResult]]) -> None:
    from proxemic.viz.plots import plot_episodes, plot_metrics_grid

    out = Path(cfg.out or ".")
    (out / "summary.md").write_text(result.summary_markdown() + "\n")
    plot_metrics_grid(
        result.summary,
        [
            (name, [(m, METRICS[m].label, "rate" if _is_rate(m) else METRICS[m].unit) for m in ms])
            for name, ms in METRIC_GROUPS
        ],
        out / "metrics.png",
        title=f"{cfg.scenario}: {cfg.episodes} seeded episodes each (seeds {cfg.seed}-{cfg.seed + cfg.episodes - 1}); "
        "bars: rate or mean, whiskers: 95% interval (Wilson for rates, Student t for means),\n"
        "clipped to each metric's range (0-100% for rates and time shares, >= 0 for lengths and times)",
    )
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
    outcomes = {planner: str(results[0].record["outcome"]) for planner, results in kept.items() if planner in paths}
    sm = SocialMap(scenario, seed=seed)
    return sm.plot(
        out_png,
        paths=paths,
        outcomes=outcomes,
        title=f"{scenario}, seed {seed}: executed trajectories over the social map",
    )


def _write_parquet(records: Sequence[dict[str, Any]], path: Path) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    pq.write_table(pa.Table.from_pylist(list(records)), path)
