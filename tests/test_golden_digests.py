"""Golden digests: an episode of every registered env id may not change unnoticed.

Each digest is a SHA-256 of 200 control steps of observations, rewards, the planners' commands
and the end flags, under seed 0, with the scenario's built-in planner driving (and again with the
``social`` planner), followed by the episode metrics at the last step: a change in a planner, the
people, the reward terms, the observations or a metric changes the digest. Changing an episode on
purpose means bumping the env's ``-vN`` and its digest together, with a line in ``CHANGELOG.md``.

Regenerate after a deliberate change with ``python tests/test_golden_digests.py --update``.
"""

from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import pytest

import proxemic

GOLDEN = Path(__file__).with_name("golden_digests.json")
STEPS = 200
SEED = 0


def _feed(h: Any, value: Any) -> None:
    arr = np.ascontiguousarray(np.asarray(value, dtype=np.float64))
    h.update(arr.tobytes())


def env_digest(env_id: str, planner: str | None = None) -> str:
    """The digest of ``STEPS`` steps of ``env_id`` driven by its built-in planner (``planner`` if given)."""
    env = gym.make(env_id) if planner is None else gym.make(env_id, planner=planner)
    h = hashlib.sha256()
    obs, info = env.reset(seed=SEED)
    for _ in range(STEPS):
        for key in sorted(obs):
            _feed(h, obs[key])
        action = info["planner_action"]
        _feed(h, action)
        obs, reward, terminated, truncated, info = env.step(action)
        _feed(h, [reward, float(terminated), float(truncated)])
        if terminated or truncated:
            obs, info = env.reset()
    h.update(json.dumps(env.unwrapped.metrics(), sort_keys=True).encode())  # type: ignore[attr-defined]
    env.close()
    return h.hexdigest()


def parallel_digest(scenario: str, robots: int) -> str:
    """The digest of ``STEPS`` steps of a parallel env on the social planner."""
    env = proxemic.parallel_env(scenario, robots=robots, planners="social")
    h = hashlib.sha256()
    obs, infos = env.reset(seed=SEED)
    for _ in range(STEPS):
        if not env.agents:
            break
        for agent in sorted(obs):
            for key in sorted(obs[agent]):
                _feed(h, obs[agent][key])
        actions = {a: infos[a]["planner_action"] for a in env.agents}
        obs, rewards, terms, truncs, infos = env.step(actions)
        for agent in sorted(rewards):
            _feed(h, [rewards[agent], float(terms[agent]), float(truncs[agent])])
    h.update(json.dumps(env.episode_metrics(), sort_keys=True).encode())
    env.close()
    return h.hexdigest()


#: Every env id with its own planner, and again with the ``social`` planner driving.
SINGLE_CASES: dict[str, tuple[str, str | None]] = {
    **{env_id: (env_id, None) for env_id in proxemic.ENV_IDS},
    **{f"{env_id}:social": (env_id, "social") for env_id in proxemic.ENV_IDS},
}
PARALLEL_CASES = {"parallel:museum_multi:4": ("museum_multi", 4), "parallel:daza2021_fig15:4": ("daza2021_fig15", 4)}


def compute_all() -> dict[str, str]:
    """Every digest, keyed by env id (and ``parallel:<scenario>:<robots>`` for parallel envs)."""
    out = {key: env_digest(*case) for key, case in SINGLE_CASES.items()}
    out.update({key: parallel_digest(*case) for key, case in PARALLEL_CASES.items()})
    return out


def _golden() -> dict[str, str]:
    return json.loads(GOLDEN.read_text())


def test_every_env_id_has_a_digest() -> None:
    expected = set(SINGLE_CASES) | set(PARALLEL_CASES)
    assert set(proxemic.ENV_IDS) <= expected
    assert set(_golden()) == expected


@pytest.mark.parametrize("key", sorted(SINGLE_CASES))
def test_env_digest(key: str) -> None:
    assert env_digest(*SINGLE_CASES[key]) == _golden()[key], (
        f"{key}: the episode changed; bump the env's -vN, its digest and CHANGELOG.md together"
    )


@pytest.mark.parametrize("key", sorted(PARALLEL_CASES))
def test_parallel_digest(key: str) -> None:
    assert parallel_digest(*PARALLEL_CASES[key]) == _golden()[key]


if __name__ == "__main__":
    if "--update" not in sys.argv:
        sys.exit("usage: python tests/test_golden_digests.py --update")
    GOLDEN.write_text(json.dumps(compute_all(), indent=2, sort_keys=True) + "\n")
    print(f"wrote {GOLDEN}")
