"""The built-in ``learned`` planner: the shipped PPO policy, run in the core with no ML framework.

The reference is an independent NumPy forward pass of the shipped array file: driving the env
with its actions must give the episode the core's ``learned`` planner drives.
"""

from __future__ import annotations

from importlib import resources

import numpy as np
import pytest

import proxemic
from proxemic._core import PLANNERS
from proxemic.env import ProxemicEnv

SHIPPED = resources.files("proxemic") / "data" / "models" / "learned_policy.npz"


def _numpy_policy():
    with resources.as_file(SHIPPED) as path, np.load(path) as f:
        arrays = {k: f[k] for k in f.files}
    layers = []
    k = 0
    while f"w{k}" in arrays:
        layers.append((arrays[f"w{k}"], arrays[f"b{k}"]))
        k += 1
    scale = arrays["input_scale"]

    def act(obs):
        x = np.concatenate([np.asarray(obs[key], np.float32).ravel() for key in sorted(obs)]) / scale
        for j, (w, b) in enumerate(layers):
            # Each output's products summed in input order, in float32, as the core sums them
            # (a BLAS matmul's order rounds differently, and an episode's dynamics amplify it).
            z = np.zeros(w.shape[0], np.float32)
            for i in range(w.shape[1]):
                z += w[:, i] * x[i]
            x = z + b
            if j < len(layers) - 1:
                x = np.tanh(x)
        return np.clip(x, -1.0, 1.0).astype(np.float32)

    return act, arrays


def test_shipped_file_is_a_small_plain_array_file():
    _, arrays = _numpy_policy()
    assert SHIPPED.is_file()
    assert len(SHIPPED.read_bytes()) < 300_000
    assert all(a.dtype == np.float32 for a in arrays.values())
    subgoal = 2 if float(arrays.get("subgoal", [0.0])[0]) > 0.0 else 0
    assert arrays["input_scale"].shape == (72 + 8 * 5 + 8 + 5 + subgoal,)
    assert "learned" in PLANNERS


@pytest.mark.parametrize("scenario", ["generated/7?width=12&height=12", "museum"])
def test_core_learned_planner_drives_as_the_numpy_forward_pass(scenario):
    act, arrays = _numpy_policy()
    auto = ProxemicEnv(scenario, planner="learned", autopilot=True)
    # The driven env observes the subgoal the policy was trained with (the core's planner
    # computes it for itself: the autopilot env's observation has no such key).
    driven = ProxemicEnv(scenario, subgoal=float(arrays.get("subgoal", [0.0])[0]))
    obs_a, _ = auto.reset(seed=3)
    obs_d, _ = driven.reset(seed=3)
    for step in range(120):
        obs_a, r_a, term_a, trunc_a, _ = auto.step(np.zeros(3, np.float32))
        obs_d, r_d, term_d, trunc_d, _ = driven.step(act(obs_d))
        assert abs(r_a - r_d) < 1e-4, f"{scenario} step {step}: reward {r_a} vs {r_d}"
        for key in obs_a:
            np.testing.assert_allclose(obs_a[key], obs_d[key], atol=1e-4, err_msg=f"{scenario} step {step} {key}")
        assert (term_a, trunc_a) == (term_d, trunc_d)
        if term_a or trunc_a:
            break


def test_learned_is_evaluated_like_any_planner():
    result = proxemic.evaluate(None, scenario="daza2021_path3", episodes=1, planners=["learned", "astar"])
    assert [r["planner"] for r in result.records][:2] == ["learned", "learned"]
    assert {r["planner"] for r in result.records} == {"learned", "astar"}


def test_learned_planner_with_other_sensors_is_refused_by_name(tmp_path):
    from proxemic.scenarios import generate_toml

    text = generate_toml(7, width=12, height=12).replace("[sensors]", "[sensors]\nk_nearest = 4", 1)
    if "k_nearest = 4" not in text:
        text += "\n[sensors]\nk_nearest = 4\n"
    path = tmp_path / "four.toml"
    path.write_text(text)
    with pytest.raises(proxemic.InputError, match="planner learned: sensors"):
        env = ProxemicEnv(str(path), planner="learned", autopilot=True)
        env.reset(seed=0)
