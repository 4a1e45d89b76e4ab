"""The PPO example trains, saves and evaluates (only with the ``rl`` extra: stable-baselines3)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

import proxemic

pytest.importorskip("stable_baselines3", reason="the PPO example needs the rl extra: pip install 'proxemic[rl]'")

ROOT = Path(__file__).resolve().parent.parent


def _example():
    spec = importlib.util.spec_from_file_location("train_ppo", ROOT / "examples" / "train_ppo.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_ppo_trains_a_few_hundred_steps_and_is_evaluated_like_a_planner(tmp_path, monkeypatch):
    example = _example()
    model = example.train("daza2021_path3", 256, tmp_path, seed=0, n_envs=1, n_steps=128)
    assert model.is_file()
    monkeypatch.setenv("PROXEMIC_PPO_MODEL", str(model))
    monkeypatch.chdir(ROOT)
    result = proxemic.evaluate(
        "examples/train_ppo.py:make", name="ppo", scenario="daza2021_path3", episodes=1, planners=["astar"]
    )
    assert [r["planner"] for r in result.records] == ["ppo", "astar"]
    assert result.records[0]["steps"] > 0
