"""The plain A* baseline: a good planner that avoids walls and furniture (not people)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from proxemic.env import ProxemicEnv
from proxemic.runner import run_episode
from proxemic.scenarios import resolve


@pytest.fixture
def empty_museum(write_scenario):
    """The museum with its people removed: plain A* must always reach the goal."""
    text = resolve("museum").read_text()
    text = re.sub(r"\n\[\[person\]\]\n(?:(?!\n\[).)*", "\n", text, flags=re.S)
    assert "[[person]]" not in text
    return write_scenario(text, "empty_museum.toml")


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_astar_reaches_the_goal_in_an_empty_museum(empty_museum, seed):
    rec = run_episode(empty_museum, seed)
    m = rec.metrics
    assert m["outcome"] == "success", m
    assert not m["wc"]
    env = ProxemicEnv(empty_museum)
    geodesic = env.world.geodesic_start_distance(0)
    env.close()
    # close to the shortest collision-free path (start jitter and the success radius aside)
    assert m["path_length"] < 1.1 * geodesic + 0.6
    # Pepper's limits hold on the executed trajectory (10 Hz positions)
    v = np.linalg.norm(np.diff(rec.robot[:, :2], axis=0), axis=1) / 0.1
    assert v.max() <= 0.55 * 1.05


def test_rust_metrics_match_the_recorded_trajectory():
    rec = run_episode("museum", 5)
    steps = rec.metrics["steps"]
    assert len(rec.robot) == steps + 1
    length = float(np.sum(np.linalg.norm(np.diff(rec.robot[:, :2], axis=0), axis=1)))
    assert abs(length - rec.metrics["path_length"]) < 1e-9
    d = np.linalg.norm(rec.people - rec.robot[:, None, :2], axis=2).min()
    assert abs(d - rec.metrics["dist_person_min"]) < 1e-9


def test_astar_ignores_people_and_collides_in_some_episodes():
    """The baseline does not see people: over seeds it runs into some (which is why it is a baseline)."""
    env = ProxemicEnv("museum", autopilot=True)
    outcomes = [run_episode("museum", s, env=env).metrics["outcome"] for s in range(12)]
    env.close()
    assert "collision" in outcomes
    assert set(outcomes) <= {"success", "collision", "timeout"}
