"""One episode in this process: cached envs and policies, a single- or multi-robot run, its records."""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import Any

import numpy as np

from proxemic import _core
from proxemic.errors import input_error
from proxemic.evaluation.config import EpisodeResult, EvalConfig
from proxemic.policy import PolicyActor, PolicyRef, build_policy

_ENV_CACHE: dict[tuple[Any, ...], Any] = {}
#: Envs kept per process (a tune run makes one per gain point: the oldest are closed).
_ENV_CACHE_SIZE = 8


def cached_env(
    scenario: str | _core.Scenario,
    planner: str,
    eband: Mapping[str, float] | None = None,
    goal: tuple[float, float] | None = None,
    drive: str | None = None,
) -> Any:
    """An autopilot env of (scenario, planner, eband gains, goal, drive), cached per process."""
    from proxemic.env import ProxemicEnv

    key = (scenario, planner, tuple(sorted((eband or {}).items())), goal, drive)
    env = _ENV_CACHE.get(key)
    if env is None:
        while len(_ENV_CACHE) >= _ENV_CACHE_SIZE:
            _ENV_CACHE.pop(next(iter(_ENV_CACHE))).close()
        env = ProxemicEnv(scenario, autopilot=True, planner=planner, eband=eband, goal=goal, drive=drive)
        _ENV_CACHE[key] = env
    return env


#: Policy objects given to :func:`evaluate` (not import paths), by label: read in this process and
#: in worker processes forked after they were put here.
_LOCAL_POLICIES: dict[str, Any] = {}
#: (scenario, policy label, import path, drive) -> (env, actor), per process, for the run under way.
_POLICY_CACHE: dict[tuple[str | _core.Scenario, str, str, str | None], tuple[Any, PolicyActor]] = {}


def policy_env(scenario: str | _core.Scenario, ref: PolicyRef, drive: str | None = None) -> tuple[Any, PolicyActor]:
    """An action-driven env of `scenario` and the policy of `ref` built for it, cached per process.

    `drive` is every robot's drive (None: the scenario's); the policy is built for its action space.
    An import-path policy is built here from its factory (so every worker has its own); a policy
    object is taken from those given to :func:`evaluate`.
    """
    from proxemic.env import ProxemicEnv

    key = (scenario, ref.name, ref.target, drive)
    cached = _POLICY_CACHE.get(key)
    if cached is None:
        env = ProxemicEnv(scenario, autopilot=False, drive=drive)
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
        cached = (env, PolicyActor(policy, ref.name, scene=env.scenario["scene"]["name"]))
        _POLICY_CACHE[key] = cached
    return cached


#: One episode: (scenario, planner or policy, seed), optionally with every robot's drive last.
Task = tuple[str | _core.Scenario, str | PolicyRef, int] | tuple[str | _core.Scenario, str | PolicyRef, int, str | None]


def run_task(task: Task, keep: bool = False) -> EpisodeResult:
    """Runs one (scenario, planner or policy, seed[, drive]) episode in this process (envs cached per process).

    The result is robot 0's record (column ``robot`` = 0). On a scene with several robots, a
    built-in planner drives every robot and the episode runs until every robot's episode ended;
    the other robots' records are in ``others`` (a user policy drives robot 0 only and is refused
    there by :func:`check_policies`).
    """
    from proxemic.env import flatten_metrics
    from proxemic.runner import run_episode

    scenario, planner, seed = task[0], task[1], task[2]
    drive = task[3] if len(task) > 3 else None
    if isinstance(planner, PolicyRef):
        env, actor = policy_env(scenario, planner, drive)
        rec = run_episode(scenario, seed, env=env, policy=actor)
        label = planner.name
    else:
        env = cached_env(scenario, planner, drive=drive)
        if env.ws.num_robots > 1:
            return _run_team(env, seed, planner, keep)
        rec = run_episode(scenario, seed, env=env)
        label = planner
    record = {
        "scenario": env.scenario["scene"]["name"],
        "planner": label,
        "seed": seed,
        "robot": 0,
        "drive": env.scenario["robots"][0].get("drive", "holonomic"),
        "reward": rec.total_reward,
        "max_time": float(env.scenario["episode"]["max_time"]),
    }
    record.update(flatten_metrics(rec.metrics, env.scenario))
    if keep:
        return EpisodeResult(
            record, rec.robot, rec.people, rec.path, people_heading=rec.people_heading, modes=rec.modes
        )
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
    robots = list(range(ws.num_robots))
    modes: list[list[str]] = [[] for _ in robots]
    running = [True] * ws.num_robots
    first_running = True
    while True:
        ws.step()
        outcome = ws.step_outcome()
        totals += [r for r, _, _ in outcome]
        if keep and first_running:  # the people while robot 0 runs, as the single-robot env gives
            people.append(env.people()[:, :2])
        if keep:  # each robot's planner mode while its episode runs
            for i, info in zip(robots, ws.infos(robots), strict=True):
                if running[i] and "planner_mode" in info:
                    modes[i].append(info["planner_mode"])
        running = [not (t or u) for _, t, u in outcome]
        first_running = running[0]
        if all(t or u for _, t, u in outcome):
            break
    results = []
    for i, metrics in enumerate(env.world.episode_metrics()):
        record = {
            "scenario": env.scenario["scene"]["name"],
            "planner": planner,
            "seed": seed,
            "robot": i,
            "drive": env.scenario["robots"][i].get("drive", "holonomic"),
            "reward": float(totals[i]),
            "max_time": float(env.scenario["episode"]["max_time"]),
        }
        record.update(flatten_metrics(metrics, env.scenario))
        results.append(EpisodeResult(record))
    first = results[0]
    if keep:
        first.robot, first.people, first.path = np.asarray(env.world.trajectory(0)), np.array(people), path
        for result, robot_modes in zip(results, modes, strict=True):
            result.modes = robot_modes or None
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
        env, actor = policy_env(cfg.scenario, ref, cfg.drive)
        obs, _ = env.reset(seed=cfg.seed)
        actor.reset(cfg.seed)
        actor(obs)
        if cfg.workers > 1 or cfg.backend == "ray":
            _POLICY_CACHE.pop((cfg.scenario, ref.name, ref.target, cfg.drive))[0].close()  # the workers build their own


def _run_task_kw(args: tuple[Task, bool]) -> EpisodeResult:
    return run_task(args[0], args[1])
