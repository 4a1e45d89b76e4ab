"""Gymnasium conformance, observation bounds, reward terms, determinism."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import proxemic
from proxemic.env import ProxemicEnv


def test_check_env_passes_for_every_registered_env():
    for env_id in proxemic.ENV_IDS:
        env = gym.make(env_id)
        check_env(env.unwrapped, skip_render_check=True)
        env.close()


def test_spaces_and_observation_shapes():
    env = gym.make("proxemic/Museum-v5")
    obs, _info = env.reset(seed=0)
    assert set(obs) == {"robot", "people", "people_mask", "lidar"}
    k = env.unwrapped.scenario["sensors"]["k_nearest"]
    assert obs["people"].shape == (k, 5)
    assert obs["lidar"].shape == (env.unwrapped.scenario["sensors"]["lidar_rays"],)
    assert env.action_space.shape == (3,)
    assert all(v.dtype == np.float32 for v in obs.values())
    env.close()


#: A room split by a wall with one doorway at its north end: the straight way to the goal runs
#: into the wall.
WALLED_ROOM = """
[scene]
name = "walled_room"
bounds = [0, 0, 10, 6]

[[wall]]
from = [0, 0]
to = [10, 0]
[[wall]]
from = [10, 0]
to = [10, 6]
[[wall]]
from = [10, 6]
to = [0, 6]
[[wall]]
from = [0, 6]
to = [0, 0]
[[wall]]
from = [5, 0]
to = [5, 4.6]

[[robot]]
start = [2, 1.5, 0]
goal = [8, 1.5]
"""


def test_subgoal_observation_leads_round_walls(write_scenario):
    path = write_scenario(WALLED_ROOM, "walled_room.toml")
    env = ProxemicEnv(str(path), subgoal=0.5)
    obs, _ = env.reset(seed=0)
    assert env.observation_space["subgoal"].shape == (2,)
    assert env.observation_space.contains(obs)
    # The goal is straight ahead (+x); the way goes north first, to the doorway.
    assert obs["robot"][0] > 5.0 and abs(obs["robot"][1]) < 0.5
    assert obs["subgoal"][1] > 0.45 > abs(obs["subgoal"][0]), obs["subgoal"]
    # Driving at the subgoal (robot frame, the robot never turns) reaches the goal round the wall.
    # (The shortest path hugs the inflated wall end, so a look-ahead much longer than the robot's
    # radius cuts the corner: 0.7 m and more collide here; a policy reads the lidar too.)
    for _ in range(600):
        direction = obs["subgoal"] / max(float(np.linalg.norm(obs["subgoal"])), 1e-9)
        obs, _, terminated, truncated, info = env.step(np.array([direction[0], direction[1], 0.0], np.float32))
        if terminated or truncated:
            break
    assert info["metrics"]["outcome"] == "success", info["metrics"]["outcome"]
    # Off by default, and its look-ahead is checked.
    assert "subgoal" not in ProxemicEnv(str(path)).observation_space.spaces
    with pytest.raises(proxemic.ScenarioError, match=r"sensors\.subgoal"):
        ProxemicEnv(str(path), subgoal=-1.0)


def _rollout(seed: int, steps: int, *, random_actions: bool):
    env = ProxemicEnv("museum", autopilot=not random_actions)
    env.action_space.seed(seed)
    obs, info = env.reset(seed=seed)
    trace = [(obs, 0.0, False, False, info)]
    for _ in range(steps):
        out = env.step(env.action_space.sample())
        trace.append(out)
        if out[2] or out[3]:
            break
    env.close()
    return trace


def _assert_same(a, b):
    assert len(a) == len(b)
    for (o1, r1, te1, tr1, i1), (o2, r2, te2, tr2, i2) in zip(a, b, strict=True):
        for k in o1:
            np.testing.assert_array_equal(o1[k], o2[k])
        assert r1 == r2 and te1 == te2 and tr1 == tr2
        assert i1.keys() == i2.keys()
        for k in i1:
            if isinstance(i1[k], np.ndarray):
                np.testing.assert_array_equal(i1[k], i2[k])
            else:
                assert i1[k] == i2[k], k


@pytest.mark.parametrize("random_actions", [False, True])
def test_same_seed_same_episode_bit_for_bit(random_actions):
    a = _rollout(7, 3000, random_actions=random_actions)
    b = _rollout(7, 3000, random_actions=random_actions)
    assert a[-1][2] or a[-1][3], "the episode should run to its end"
    _assert_same(a, b)


def test_different_seeds_differ():
    a = _rollout(1, 5, random_actions=False)
    b = _rollout(2, 5, random_actions=False)
    assert not np.array_equal(a[-1][0]["people"], b[-1][0]["people"])


@pytest.mark.parametrize("random_actions", [False, True])
def test_observations_stay_in_space_and_reward_terms_sum_exactly(random_actions):
    env = ProxemicEnv("museum", autopilot=not random_actions)
    terms = [f"reward_{t}" for t in proxemic._core.REWARD_TERMS]
    for seed in (3, 4):
        env.action_space.seed(seed)
        obs, _ = env.reset(seed=seed)
        assert env.observation_space.contains(obs)
        for _ in range(3000):
            action = env.action_space.sample() * 4.0 - 2.0  # also out of range: clipped
            obs, reward, terminated, truncated, info = env.step(action)
            assert env.observation_space.contains(obs), obs
            total = 0.0
            for t in terms:
                total += info[t]
            assert total == reward
            if terminated or truncated:
                assert "metrics" in info
                break
    env.close()


def test_planner_action_reproduces_the_autopilot():
    """Feeding info['planner_action'] back as the action drives the robot as the autopilot does."""
    auto = ProxemicEnv("museum", autopilot=True)
    manual = ProxemicEnv("museum")
    _, _ = auto.reset(seed=11)
    _, info = manual.reset(seed=11)
    for _ in range(150):
        a = auto.step(np.zeros(3, np.float32))
        m = manual.step(info["planner_action"].astype(np.float64))
        info = m[4]
        np.testing.assert_allclose(m[0]["robot"], a[0]["robot"], atol=1e-4)
        if a[2] or a[3]:
            break
    auto.close()
    manual.close()


def test_time_limit_truncates(write_scenario, small_room):
    path = write_scenario(small_room.replace("max_time = 40", "max_time = 2"))
    env = ProxemicEnv(str(path))
    env.reset(seed=0)
    steps = 0
    while True:
        _, _, terminated, truncated, info = env.step(np.zeros(3, np.float32))
        steps += 1
        if terminated or truncated:
            break
    assert truncated and not terminated
    assert steps == 20
    assert info["metrics"]["outcome"] == "timeout"
    env.close()


def test_planner_actions_off_skips_the_planner_and_keeps_the_episode() -> None:
    import gymnasium as gym
    import numpy as np

    rng = np.random.default_rng(3)
    actions = rng.uniform(-1, 1, (120, 3)).astype(np.float32)
    runs = []
    for planner_actions in (True, False):
        env = gym.make("proxemic/Museum-v5", planner_actions=planner_actions)
        obs, info = env.reset(seed=4)
        trace = [obs["robot"].copy()]
        for a in actions:
            obs, reward, terminated, truncated, info = env.step(a)
            trace.append(np.append(obs["robot"], [reward]))
            assert ("planner_action" in info) is planner_actions
            if terminated or truncated:
                break
        runs.append(np.concatenate(trace))
        env.close()
    np.testing.assert_array_equal(runs[0], runs[1])


def test_env_pickles_as_its_arguments() -> None:
    import pickle

    import gymnasium as gym
    import numpy as np

    env = gym.make("proxemic/Museum-v5", planner="social", width=320, height=240)
    copy = pickle.loads(pickle.dumps(env))
    a, _ = env.reset(seed=2)
    b, _ = copy.reset(seed=2)
    for key in a:
        np.testing.assert_array_equal(a[key], b[key])
    assert copy.unwrapped.width == 320
    step_a = env.step(np.array([0.5, 0.0, 0.1], np.float32))
    step_b = copy.step(np.array([0.5, 0.0, 0.1], np.float32))
    assert step_a[1] == step_b[1]


def test_env_steps_from_another_thread() -> None:
    # The compiled World was "unsendable": a step from another thread raised a PanicException
    # (not an Exception). Vector envs and thread pools move envs between threads.
    import threading

    import gymnasium as gym
    import numpy as np

    env = gym.make("proxemic/Museum-v5")
    env.reset(seed=0)
    errors: list[BaseException] = []
    rewards: list[float] = []

    def run() -> None:
        try:
            for _ in range(5):
                _, reward, *_ = env.step(np.zeros(3, np.float32))
                rewards.append(float(reward))
        except BaseException as e:
            errors.append(e)

    t = threading.Thread(target=run)
    t.start()
    t.join()
    assert not errors, errors
    assert len(rewards) == 5
