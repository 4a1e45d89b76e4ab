"""PPO (stable-baselines3, the ``rl`` extra) learns on a proxemic scene, saves, and is evaluated like a planner.

``make test`` installs the ``rl`` extra and sets ``PROXEMIC_REQUIRE_RL=1``, so these tests run in
CI and fail (rather than skip) if stable-baselines3 is missing; elsewhere they skip without it.
"""

from __future__ import annotations

import importlib.util
import os
from pathlib import Path

import numpy as np
import pytest

import proxemic
from proxemic.splits import TUNING_EPISODE_SEEDS, TUNING_SCENE_SEEDS

if os.environ.get("PROXEMIC_REQUIRE_RL") != "1":
    pytest.importorskip("stable_baselines3", reason="the PPO example needs the rl extra: pip install 'proxemic[rl]'")

ROOT = Path(__file__).resolve().parent.parent
SCENE = "daza2021_path3"
#: Episode seeds the three policies are scored on (tuning split: nothing is asserted on the test split here).
SEEDS = TUNING_EPISODE_SEEDS[500:510]


def _example():
    spec = importlib.util.spec_from_file_location("train_ppo", ROOT / "examples" / "train_ppo.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_ppo_learns_in_a_tiny_budget(tmp_path):
    """32,768 env steps (about 20 s on two cores) raise the return above the untrained net's and a random policy's.

    On these seeds the untrained deterministic policy and a uniform random one both lose about 7
    (time, collisions, no progress); the trained one comes close to 0 (it crosses most of the
    room). The learning curve and the saved model are written.
    """
    example = _example()
    model = example.build_model(SCENE, seed=0, n_envs=2, n_steps=512)
    rng = np.random.default_rng(0)
    space = model.action_space

    def untrained_or_trained(obs):
        return model.predict(obs, deterministic=True)[0]

    def random_policy(obs):
        return rng.uniform(space.low, space.high).astype(np.float32)

    before = example.mean_return(untrained_or_trained, SCENE, SEEDS)
    random_return = example.mean_return(random_policy, SCENE, SEEDS)
    path = example.train(SCENE, 32_768, tmp_path, model=model)
    after = example.mean_return(untrained_or_trained, SCENE, SEEDS)
    print(f"mean return: untrained {before:.2f}, random {random_return:.2f}, trained {after:.2f}")
    assert path.is_file()
    assert after > before + 2.0, f"PPO did not learn: return {before:.2f} untrained, {after:.2f} trained"
    assert after > random_return + 2.0, f"trained return {after:.2f} not above a random policy's {random_return:.2f}"
    curve = (tmp_path / f"curve_{SCENE}.csv").read_text().splitlines()
    assert curve[0] == "env_steps,success,collision,personal_gap_time" and len(curve) > 1


def test_ppo_model_is_evaluated_like_a_planner(tmp_path, monkeypatch):
    example = _example()
    model = example.train(SCENE, 256, tmp_path, seed=0, n_envs=1, n_steps=128)
    assert model.is_file()
    monkeypatch.setenv("PROXEMIC_PPO_MODEL", str(model))
    monkeypatch.chdir(ROOT)
    result = proxemic.evaluate("examples/train_ppo.py:make", name="ppo", scenario=SCENE, episodes=1, planners=["astar"])
    assert [r["planner"] for r in result.records] == ["ppo", "astar"]
    assert result.records[0]["steps"] > 0


def test_scene_cycle_draws_tuning_scenes_with_one_observation_space():
    example = _example()
    env = example.SceneCycle()
    drawn = set()
    for seed in range(3):
        obs, _ = env.reset(seed=seed)
        assert env.observation_space.contains(obs)
        drawn.add(env.scene_seed)
        assert env.scene_seed in TUNING_SCENE_SEEDS
    again = example.SceneCycle()
    again.reset(seed=2)
    assert again.scene_seed == env.scene_seed  # the draw follows the reset seed
    assert len(drawn) > 1


def test_mixed_set_draws_generated_and_bundled_scenes_on_one_scale():
    example = _example()
    env = example.make_env(example.MIXED_SET, 1.5)
    drawn = set()
    for seed in range(12):
        obs, _ = env.reset(seed=seed)
        assert env.observation_space.contains(obs), env.scene
        drawn.add(env.scene if env.scene in example.MIXED_BUNDLED else "generated")
        obs, *_ = env.step(np.zeros(3, np.float32))
        assert env.observation_space.contains(obs), env.scene
    assert drawn == {"generated", *example.MIXED_BUNDLED}
    # One scale for every scene: the museum's goal offsets (its diagonal) bound the robot key's.
    scale = example.input_scale(example.MIXED_SET, 1.5)
    assert scale.shape == (72 + 8 * 5 + 8 + 5 + 2,)
    assert scale[-2:].tolist() == [1.5, 1.5]  # the subgoal key, last in sorted order
    env.close()


def test_export_writes_the_subgoal_look_ahead_for_the_core(tmp_path):
    example = _example()
    model = example.build_model(SCENE, seed=0, n_envs=1, n_steps=64, subgoal=1.0)
    path = example.export_policy(model, SCENE, tmp_path / "p.npz", subgoal=1.0)
    with np.load(path) as f:
        assert f["subgoal"].tolist() == [1.0]
        assert f["input_scale"].shape == (72 + 8 * 5 + 8 + 5 + 2,)
        assert f["w0"].shape[1] == f["input_scale"].shape[0]


def test_a_model_and_an_env_that_disagree_on_the_subgoal_key_are_refused_by_name(tmp_path):
    from proxemic.env import ProxemicEnv

    example = _example()
    path = example.train(SCENE, 256, tmp_path, seed=0, n_envs=1, n_steps=128, subgoal=1.0)
    with pytest.raises(ValueError, match="subgoal"):
        example.PPOPolicy(path, ProxemicEnv(SCENE).observation_space)
    policy = example.PPOPolicy(path, ProxemicEnv(SCENE, subgoal=1.0).observation_space)
    obs, _ = ProxemicEnv(SCENE, subgoal=1.0).reset(seed=0)
    assert policy(obs).shape == (3,)
