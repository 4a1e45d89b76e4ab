"""gymnasium.make_vec of a proxemic env: sync and async give the same steps as plain envs."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import proxemic

ENV_ID = "proxemic/Museum-v5"
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


# ---------------------------------------------------------------- proxemic.vector_env (one core call)


def _short_scene(tmp_path, max_time: float = 3.0):
    """daza2021_path1 with episodes of `max_time` seconds: autoresets within a short test."""
    from proxemic import scenarios

    text = (scenarios.envs_dir() / "daza2021_path1.toml").read_text()
    assert "max_time = 60.0" in text
    path = tmp_path / "short.toml"
    path.write_text(text.replace("max_time = 60.0", f"max_time = {max_time}"))
    return path


def test_vector_env_is_a_gymnasium_vector_env_with_batched_spaces():
    envs = proxemic.vector_env("museum", num_envs=3)
    try:
        assert isinstance(envs, gym.vector.VectorEnv)
        assert envs.num_envs == 3
        assert envs.metadata["autoreset_mode"] == gym.vector.AutoresetMode.NEXT_STEP
        single = gym.make(ENV_ID)
        assert envs.single_observation_space == single.observation_space
        assert envs.single_action_space == single.action_space
        assert envs.action_space.shape == (3, 3)
        obs, infos = envs.reset(seed=0)
        assert obs in envs.observation_space
        assert infos["_reward_progress"].all() and infos["planner_mode"].shape == (3,)
        obs, *_ = envs.step(envs.action_space.sample())
        assert obs in envs.observation_space
        single.close()
    finally:
        envs.close()


@pytest.mark.parametrize("threads", [1, 2])
def test_vector_env_world_k_is_the_plain_env_seeded_seed_plus_k(threads):
    """Bit for bit, also with the worlds stepped in groups on two threads (groups [0, 1] and [2])."""
    actions = _actions(3)
    envs = proxemic.vector_env("museum", num_envs=3, threads=threads)
    obs, _ = envs.reset(seed=7)
    vec = [(obs, None, None, None)]
    for a in actions:
        o, r, te, tr, _ = envs.step(a)
        vec.append((o, r, te, tr))
    envs.close()
    for k in range(3):
        env = gym.make(ENV_ID)
        o, _ = env.reset(seed=7 + k)
        for key in o:
            np.testing.assert_array_equal(o[key], vec[0][0][key][k])
        for t, a in enumerate(actions[:, k]):
            o, r, te, tr, _ = env.step(a)
            vo, vr, vte, vtr = vec[t + 1]
            for key in o:
                np.testing.assert_array_equal(o[key], vo[key][k], err_msg=f"world {k}, step {t}, {key}")
            assert (r, te, tr) == (vr[k], vte[k], vtr[k])
        env.close()
    assert not np.array_equal(vec[-1][0]["robot"][0], vec[-1][0]["robot"][1])  # distinct episodes


def _same(a, b, where):
    if isinstance(a, tuple):
        assert len(a) == len(b), where
        for k, (x, y) in enumerate(zip(a, b, strict=True)):
            _same(x, y, f"{where}[{k}]")
    elif isinstance(a, dict):
        assert set(a) == set(b), where
        for key in a:
            _same(a[key], b[key], f"{where}.{key}")
    else:
        a, b = np.asarray(a), np.asarray(b)
        assert a.shape == b.shape, where
        if a.dtype == object:
            assert a.tolist() == b.tolist(), where
        else:
            np.testing.assert_array_equal(a, b, err_msg=where)


@pytest.mark.parametrize(("num_envs", "threads"), [(2, 1), (2, 2), (4, 2)])
def test_vector_env_autoresets_as_the_sync_vector_env(tmp_path, num_envs, threads):
    """Episodes of 3 s (30 steps) end within 70 steps: the NEXT_STEP autoreset, rewards, flags,
    observations and infos (metrics included) equal gymnasium's sync vector env's.

    With 4 worlds on 2 threads, world 1 is reset alone at step 10 (``reset_mask``), so that its
    episode ends after the others' and the autoreset leaves a thread a group of worlds that are
    not consecutive (0 and 2), stepped on copies of their rows.
    """
    from proxemic.env import ProxemicEnv

    path = _short_scene(tmp_path)
    ours = proxemic.vector_env(path, num_envs=num_envs, threads=threads)
    groups: list[list[int]] = []
    step_group = ours._step_group
    ours._step_group = lambda idx: (groups.append(list(idx)), step_group(idx))[1]  # type: ignore[method-assign]
    sync = gym.vector.SyncVectorEnv([lambda: ProxemicEnv(path)] * num_envs)
    actions = np.random.default_rng(3).uniform(-1, 1, size=(70, num_envs, 3)).astype(np.float32)
    try:
        a, b = ours.reset(seed=5), sync.reset(seed=5)
        _same(a, b, "reset")
        ends = 0
        for t, act in enumerate(actions):
            if num_envs == 4 and t == 10:
                mask = np.array([False, True, False, False])
                _same(ours.reset(options={"reset_mask": mask}), sync.reset(options={"reset_mask": mask}), "mask")
            a, b = ours.step(act), sync.step(act)
            _same(a, b, f"step {t}")
            ends += int(np.sum(a[2] | a[3]))
        assert ends >= 2  # episodes did end (and the worlds were reset on the next step)
        if num_envs == 4:
            assert any(g != list(range(g[0], g[-1] + 1)) for g in groups), "no group of scattered worlds"
        # reset(seed=None) continues each world's stream, as the sync env's sub-envs do
        _same(ours.reset(), sync.reset(), "reset without seed")
    finally:
        ours.close()
        sync.close()


def test_vector_env_reset_mask_and_seed_lists():
    envs = proxemic.vector_env("daza2021_path1", num_envs=2)
    try:
        first, _ = envs.reset(seed=[4, 9])
        single = gym.make("proxemic/Daza2021Path1-v4")
        o, _ = single.reset(seed=9)
        np.testing.assert_array_equal(first["lidar"][1], o["lidar"])
        envs.step(np.zeros((2, 3)))
        moved, *_ = envs.step(np.ones((2, 3)))
        obs, infos = envs.reset(seed=[4, None], options={"reset_mask": np.array([True, False])})
        np.testing.assert_array_equal(obs["lidar"][0], first["lidar"][0])  # world 0 reset with seed 4
        np.testing.assert_array_equal(obs["lidar"][1], moved["lidar"][1])  # world 1 untouched
        assert infos["_is_success"].tolist() == [True, False]
        single.close()
    finally:
        envs.close()


def test_vector_env_bad_input_is_a_clear_error():
    from proxemic.errors import InputError, NeedsResetError

    with pytest.raises(InputError, match="num_envs: expected an integer from 1 to 1024, got 0"):
        proxemic.vector_env("museum", num_envs=0)
    with pytest.raises(InputError, match="num_envs: expected an integer from 1 to 1024, got 5000"):
        proxemic.vector_env("museum", num_envs=5000)
    with pytest.raises(InputError, match="threads: expected an integer of at least 1"):
        proxemic.vector_env("museum", num_envs=2, threads=0)
    envs = proxemic.vector_env("daza2021_path1", num_envs=2)
    try:
        with pytest.raises(NeedsResetError):
            envs.step(np.zeros((2, 3)))
        envs.reset(seed=0)
        with pytest.raises(InputError, match=r"actions: expected a \(2, 3\) array"):
            envs.step(np.zeros(3))
        with pytest.raises(InputError, match=r"actions\[1\]: expected 3 finite"):
            envs.step(np.array([[0, 0, 0], [np.nan, 0, 0]]))
        with pytest.raises(InputError, match="seed"):
            envs.reset(seed=[1, 2, 3])
        envs.step(np.zeros((2, 3)))  # still usable after refused input
    finally:
        envs.close()


def test_a_differential_robot_s_vector_env_has_its_action_space_and_steps_like_its_plain_env():
    """The batched action space is the differential robot's (v, 0, wz); world k is the plain env."""
    name = "francis2023/frontal_approach?seed=3&drive=differential"
    envs = proxemic.vector_env(name, num_envs=2)
    single = proxemic.ProxemicEnv(name)
    try:
        assert envs.single_action_space == single.action_space
        assert envs.single_action_space.high[1] == 0.0 and envs.action_space.shape == (2, 3)
        actions = np.stack([envs.action_space.sample() for _ in range(10)])
        assert (actions[:, :, 1] == 0.0).all()
        obs, _ = envs.reset(seed=5)
        o, _ = single.reset(seed=6)
        for a in actions:
            obs, *_ = envs.step(a)
            o, *_ = single.step(a[1])
        np.testing.assert_array_equal(obs["robot"][1], o["robot"])
        with pytest.raises(proxemic.InputError, match=r"action"):
            envs.step(np.array([[0.5, 0.5, 0.0], [0.5, 0.0, 0.0]], np.float32))
    finally:
        envs.close()
        single.close()


def test_vector_env_batches_the_subgoal_key_as_the_plain_env_gives_it():
    from proxemic.env import ProxemicEnv

    vec = proxemic.vector_env("museum", num_envs=2, subgoal=1.5)
    assert vec.single_observation_space["subgoal"].shape == (2,)
    obs, _ = vec.reset(seed=3)
    plain = ProxemicEnv("museum", subgoal=1.5)
    one, _ = plain.reset(seed=4)  # world 1 is reset with seed 3 + 1
    np.testing.assert_array_equal(obs["subgoal"][1], one["subgoal"])
    actions = _actions(2)
    for action in actions[:5]:
        obs, *_ = vec.step(action)
        one, *_ = plain.step(action[1])
        np.testing.assert_array_equal(obs["subgoal"][1], one["subgoal"])
    vec.close()
    plain.close()
