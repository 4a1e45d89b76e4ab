"""Soak test: long runs that must neither grow the process nor produce a bad observation.

1. The museum env (``proxemic/Museum-v5``), random actions, auto-reset, for ``--steps`` env steps
   (default 1,000,000); the built-in planner runs every step to fill ``info["planner_action"]``.
2. The parallel museum (``museum_multi``, 4 robots), random actions, reset when every agent is
   done, for ``--parallel-steps`` steps (default 200,000).

The resident set size (RSS, from ``/proc/self/statm``) is printed every 100,000 steps. The run
fails (exit code 1) if RSS grows by more than 5% from the first 100,000 steps (the warm-up) to
the end, or if any observation (of every step and every reset) is non-finite or outside its space.

Run: ``make soak`` (``python tests/soak.py [--steps N] [--parallel-steps N]``).
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import Any

import gymnasium as gym
import numpy as np

import proxemic

CHECKPOINT = 100_000
GROWTH_LIMIT = 0.05


def rss_mb() -> float:
    """The process's resident set size in MiB."""
    with open("/proc/self/statm") as f:
        pages = int(f.read().split()[1])
    return pages * os.sysconf("SC_PAGE_SIZE") / 2**20


def check_obs(obs: dict[str, np.ndarray], space: gym.spaces.Dict, where: str) -> str | None:
    """A description of what is wrong with `obs`, or None."""
    for key, value in obs.items():
        if not np.isfinite(value).all():
            return f"{where}: observation {key!r} is not finite"
    if not space.contains(obs):
        bad = [k for k, v in obs.items() if not space[k].contains(v)]
        return f"{where}: observation {bad} outside its space"
    return None


class Tracker:
    """RSS at each checkpoint and the growth verdict."""

    def __init__(self, name: str) -> None:
        self.name = name
        self.samples: list[tuple[int, float]] = []

    def maybe_sample(self, step: int) -> None:
        if step % CHECKPOINT == 0:
            self.samples.append((step, rss_mb()))
            print(f"{self.name}: {step:>9} steps  RSS {self.samples[-1][1]:8.1f} MiB", flush=True)

    def verdict(self) -> str | None:
        if len(self.samples) < 2:
            return None
        base, last = self.samples[0][1], self.samples[-1][1]
        growth = last / base - 1.0
        print(f"{self.name}: RSS {base:.1f} -> {last:.1f} MiB after warm-up ({growth:+.1%}, limit +{GROWTH_LIMIT:.0%})")
        return f"{self.name}: RSS grew {growth:+.1%}" if growth > GROWTH_LIMIT else None


def soak_single(steps: int) -> list[str]:
    """The single-robot museum with random actions."""
    env = gym.make("proxemic/Museum-v5")
    space: Any = env.observation_space
    env.action_space.seed(0)
    obs, _ = env.reset(seed=0)
    tracker, failures = Tracker("museum"), []
    for step in range(1, steps + 1):
        obs, _, terminated, truncated, _ = env.step(env.action_space.sample())
        if bad := check_obs(obs, space, f"museum step {step}"):
            failures.append(bad)
            break
        if terminated or truncated:
            obs, _ = env.reset()
            if bad := check_obs(obs, space, f"museum reset after step {step}"):
                failures.append(bad)
                break
        tracker.maybe_sample(step)
    env.close()
    if verdict := tracker.verdict():
        failures.append(verdict)
    return failures


def soak_parallel(steps: int) -> list[str]:
    """The parallel museum, 4 robots, random actions."""
    env = proxemic.parallel_env("museum_multi", robots=4)
    rng = np.random.default_rng(0)
    obs, _ = env.reset(seed=0)
    tracker, failures = Tracker("museum_multi x4"), []
    for step in range(1, steps + 1):
        if not env.agents:
            obs, _ = env.reset()
            for agent, o in obs.items():
                if bad := check_obs(o, env.observation_space(agent), f"parallel reset after step {step} {agent}"):
                    failures.append(bad)
        actions = {a: rng.uniform(-1, 1, 3).astype(np.float32) for a in env.agents}
        obs, _, _, _, _ = env.step(actions)
        for agent, o in obs.items():
            if bad := check_obs(o, env.observation_space(agent), f"parallel step {step} {agent}"):
                failures.append(bad)
        if failures:
            break
        tracker.maybe_sample(step)
    env.close()
    if verdict := tracker.verdict():
        failures.append(verdict)
    return failures


def main() -> int:
    """Runs both soaks; returns the exit code."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=1_000_000)
    parser.add_argument("--parallel-steps", type=int, default=200_000)
    args = parser.parse_args()
    failures = soak_single(args.steps) + soak_parallel(args.parallel_steps)
    for f in failures:
        print("FAILED:", f)
    print("soak:", "FAILED" if failures else "passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
