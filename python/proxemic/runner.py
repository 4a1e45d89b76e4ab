"""Run seeded episodes with a built-in planner and collect trajectories and metrics."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from proxemic import _core
from proxemic.env import ProxemicEnv
from proxemic.policy import PolicyActor


@dataclass
class EpisodeRecord:
    """What one episode produced: the trajectories and the metrics."""

    seed: int
    scenario: str
    planner: str
    metrics: dict[str, Any]
    robot: np.ndarray = field(repr=False)
    """(T + 1, 3) robot poses x, y, theta at every control instant, start included (the core's
    recorded trajectory, the one its metrics are computed from)."""
    people: np.ndarray = field(repr=False)
    """(T + 1, P, 2) people positions."""
    path: np.ndarray = field(repr=False)
    """(K, 2) the global path planned at the start."""
    total_reward: float = 0.0
    people_heading: np.ndarray | None = field(default=None, repr=False)
    """(T + 1, P) people headings (rad), beside ``people``."""
    modes: list[str] | None = field(default=None, repr=False)
    """The built-in planner's mode at each of the T control steps (``info["planner_mode"]``, e.g.
    ``"follow_path"``, ``"social_momentum"``, ``"orca"``, ``"wait"``); None when the env skips
    the planner (``planner_actions=False``)."""

    def row(self) -> dict[str, Any]:
        """A flat row for tables: seed, planner, outcome and the scalar metrics."""
        out: dict[str, Any] = {"seed": self.seed, "planner": self.planner, "reward": self.total_reward}
        out.update(self.metrics)
        return out


def run_episode(
    scenario: str | Path | _core.Scenario,
    seed: int,
    *,
    env: ProxemicEnv | None = None,
    policy: Callable[[dict[str, np.ndarray]], np.ndarray] | None = None,
) -> EpisodeRecord:
    """Runs one episode of `scenario` from `seed` with the robot's built-in planner driving.

    Pass an existing `env` (made with ``autopilot=True``) to reuse its compiled model. With a
    `policy` (see :mod:`proxemic.policy`; its ``reset(seed)`` is called first if it has one) the
    policy drives instead, in an env made with ``autopilot=False``, through a
    :class:`proxemic.policy.PolicyActor` (unless it is one already).

    Raises:
        PolicyError: The policy raised or called ``sys.exit`` (naming it, the seed and the step).
        InputError: The policy returned an action that is not 3 finite real numbers.
    """
    own = env is None
    if env is None:
        env = ProxemicEnv(scenario, autopilot=policy is None)
    try:
        obs, _ = env.reset(seed=seed)
        if policy is not None and not isinstance(policy, PolicyActor):
            name = getattr(policy, "__name__", None) or type(policy).__name__
            policy = PolicyActor(policy, name, scene=env.scenario["scene"]["name"])
        if policy is not None:
            policy.reset(seed)
        now = env.people()
        people, headings = [now[:, :2]], [now[:, 2]]
        path = env.planned_path()
        total = 0.0
        modes: list[str] | None = []
        while True:
            action = env.action_space.sample() * 0.0 if policy is None else policy(obs)
            obs, reward, terminated, truncated, info = env.step(action)
            total += reward
            mode = info.get("planner_mode")
            if mode is None:
                modes = None
            elif modes is not None:
                modes.append(mode)
            now = env.people()
            people.append(now[:, :2])
            headings.append(now[:, 2])
            if terminated or truncated:
                break
        planner = env.scenario["robots"][0]["planner"]
        return EpisodeRecord(
            seed=seed,
            scenario=env.scenario["scene"]["name"],
            planner=planner,
            metrics=info["metrics"],
            robot=np.asarray(env.world.trajectory(0)),
            people=np.array(people),
            path=path,
            total_reward=total,
            people_heading=np.array(headings),
            modes=modes,
        )
    finally:
        if own:
            env.close()
