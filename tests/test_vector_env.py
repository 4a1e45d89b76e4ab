"""gymnasium.make_vec of a proxemic env: sync and async give the same steps as plain envs."""

from __future__ import annotations

import gymnasium as gym
import numpy as np

import proxemic  # noqa: F401  (registers the environments)

ENV_ID = "proxemic/Museum-v0"
STEPS = 25


def _actions(num_envs: int) -> np.ndarray:
    return np.random.default_rng(11).uniform(-1.0, 1.0, size=(STEPS, num_envs, 3)).astype(np.float32)


def _run_vec(mode: str, num_envs: int) -> list[tuple[np.ndarray, ...]]:
    envs = gym.make_vec(ENV_ID, num_envs=num_envs, vectorization_mode=mode)
    try:
        obs, _ = envs.reset(seed=7)  # sub-env k is seeded 7 + k
        out = [(obs["robot"].copy(), obs["lidar"].copy(), obs["people"].copy())]
        for action in _actions(num_envs):
            obs, reward, terminated, truncated, _ = envs.step(action)
            out.append((obs["robot"].copy(), obs["lidar"].copy(), reward.copy(), terminated.copy(), truncated.copy()))
        return out
    finally:
        envs.close()


def test_make_vec_sync_and_async_step_identically_and_match_plain_envs():
    sync, async_ = _run_vec("sync", 2), _run_vec("async", 2)
    assert len(sync) == len(async_) == STEPS + 1
    for a, b in zip(sync, async_, strict=True):
        for x, y in zip(a, b, strict=True):
            np.testing.assert_array_equal(x, y)
    # sub-env 1 is the plain env reset with seed 8, given the same actions
    env = gym.make(ENV_ID)
    obs, _ = env.reset(seed=8)
    np.testing.assert_array_equal(obs["robot"], sync[0][0][1])
    for t, action in enumerate(_actions(2)[:, 1]):
        obs, reward, terminated, truncated, _ = env.step(action)
        np.testing.assert_array_equal(obs["lidar"], sync[t + 1][1][1])
        assert reward == sync[t + 1][2][1]
        if terminated or truncated:
            break
    env.close()
    moved = np.abs(sync[-1][0] - sync[0][0]).max()
    assert moved > 0.01  # the robots did move
