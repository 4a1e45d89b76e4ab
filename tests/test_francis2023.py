"""The Francis et al. 2023 suite from Python: names, gym.make, parallel_env, both planners on every
archetype, ``proxemic eval --suite francis2023`` and the docs' pictures.

How each archetype is laid out (people and robot where the archetype puts them, passages as narrow
as drawn) is tested in the core (``scenario/generate/francis2023/tests.rs``), over many seeds.
"""

from __future__ import annotations

import csv
import re
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import proxemic
from proxemic import cli, francis2023, scenarios
from proxemic.env import ProxemicEnv
from proxemic.errors import ScenarioError, UnknownNameError

ROOT = Path(__file__).resolve().parents[1]

#: The archetypes the issues ask for (at least), by our names: every panel (a)-(y) of Francis et al.'s Fig. 7
#: (panel (f), Intersection No Gesture, is crossing_90 and crossing_45).
REQUIRED = {
    "down_path",
    "intersection_wait",
    "intersection_proceed",
    "entering_elevator",
    "exiting_elevator",
    "leading_person",
    "parallel_traffic",
    "perpendicular_traffic",
    "circular_crossing",
    "frontal_approach",
    "pedestrian_obstruction",
    "robot_overtaking",
    "pedestrian_overtaking",
    "crossing_90",
    "crossing_45",
    "narrow_hallway",
    "narrow_doorway",
    "blind_corner",
    "entering_room",
    "exiting_room",
    "joining_group",
    "leaving_group",
    "following_person",
    "accompanying_person",
    "dense_crowd",
    "robot_crowding",
}


def test_every_required_archetype_exists() -> None:
    assert REQUIRED <= set(francis2023.ARCHETYPES)
    assert len(REQUIRED) == 26 and len(francis2023.ARCHETYPES) == 26


@pytest.mark.parametrize("archetype", francis2023.ARCHETYPES)
def test_every_robot_s_goal_is_reachable(archetype: str) -> None:
    """The robot's A* path from its start to its goal exists, for 12 scene seeds."""
    for seed in range(12):
        env = ProxemicEnv(francis2023.scenario_name(archetype, seed), planner="astar")
        try:
            env.reset(seed=seed)
            for i in range(env.world.num_robots):
                path = env.world.astar_path(i)
                assert path is not None and len(path) >= 2, f"{archetype} seed {seed}: robot {i} has no path"
        finally:
            env.close()


def test_leading_person_follows_the_robot() -> None:
    """The person of leading_person walks behind the robot, on its line, as it drives."""
    env = ProxemicEnv(francis2023.scenario_name("leading_person", 3), autopilot=True, planner="astar")
    try:
        env.reset(seed=3)
        start = np.asarray(env.world.trajectory(0))[0, :2]
        for _ in range(80):
            env.step(env.action_space.sample() * 0.0)
        robot = np.asarray(env.world.trajectory(0))[-1, :2]
        person = np.asarray(env.world.people())[0, :2]
        assert robot[0] - start[0] > 2.0, f"the robot moved {robot[0] - start[0]:.2f} m"
        # Behind the robot, within 2 m, and past where the robot started: it followed.
        assert 0.5 < robot[0] - person[0] < 2.0 and abs(person[1] - robot[1]) < 0.5, (robot, person)
        assert person[0] > start[0], (start, person)
    finally:
        env.close()


def test_names_and_errors() -> None:
    assert francis2023.scenario_name("crossing_90") == "francis2023/crossing_90"
    assert francis2023.scenario_name("crossing_90", 3, 12) == "francis2023/crossing_90?seed=3&max_time=12"
    _, d = scenarios.load("francis2023/crossing_90?seed=3&max_time=12")
    assert d["episode"]["max_time"] == 12.0 and d["scene"]["name"] == "francis2023_crossing_90"
    with pytest.raises(UnknownNameError, match="crossing_90"):
        francis2023.scenario_name("crossing90")
    with pytest.raises(ScenarioError, match="archetype"):
        scenarios.load("francis2023/crossing90")
    with pytest.raises(ScenarioError, match="max_time"):
        scenarios.load("francis2023/crossing_90?max_time=0")
    # Another seed, other parameters; the same seed, the same scene.
    a = scenarios.load("francis2023/narrow_doorway?seed=1")[0].to_json()
    assert a == scenarios.load("francis2023/narrow_doorway?seed=1")[0].to_json()
    assert a != scenarios.load("francis2023/narrow_doorway?seed=2")[0].to_json()


@pytest.mark.parametrize("archetype", francis2023.ARCHETYPES)
@pytest.mark.parametrize("planner", ["astar", "social"])
def test_astar_and_social_drive_every_archetype(archetype: str, planner: str) -> None:
    env = ProxemicEnv(francis2023.scenario_name(archetype), autopilot=True, planner=planner)
    try:
        env.reset(seed=0)
        start = np.asarray(env.world.trajectory(0))[0, :2]
        for _ in range(40):
            _, _, terminated, truncated, info = env.step(env.action_space.sample() * 0.0)
            assert not terminated or info["metrics"]["outcome"] != "collision", f"{archetype}: {info['metrics']}"
            if terminated or truncated:
                break
        moved = float(np.linalg.norm(np.asarray(env.world.trajectory(0))[-1, :2] - start))
        assert moved > 0.3, f"{archetype} with {planner}: the robot moved {moved:.2f} m in 40 steps"
    finally:
        env.close()


def test_gym_make_francis2023_env_id() -> None:
    env = gym.make("proxemic/Francis2023-v7", archetype="blind_corner", scene_seed=2)
    obs, _ = env.reset(seed=0)
    assert env.observation_space.contains(obs)
    assert env.unwrapped.scenario["scene"]["name"] == "francis2023_blind_corner"
    env.close()
    env = gym.make("proxemic/Generated-v5", scenario="francis2023/frontal_approach?seed=4")
    obs, _ = env.reset(seed=0)
    assert env.observation_space.contains(obs)
    env.close()


def test_eval_suite_runs_every_archetype_with_both_planners(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "suite"
    argv = ["eval", "--suite", "francis2023", "--planner", "social", "--planner", "astar"]
    argv += ["--episodes", "1", "--max-time", "5", "--workers", "1", "--out", str(out)]
    assert cli.main(argv) == 0
    with (out / "episodes.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert {r["archetype"] for r in rows} == set(francis2023.ARCHETYPES)
    for a in francis2023.ARCHETYPES:
        for p in ("social", "astar"):
            mine = [r for r in rows if r["archetype"] == a and r["planner"] == p]
            robots = scenarios.load(francis2023.scenario_name(a))[0].num_robots
            assert len(mine) == robots, f"{a} {p}: {len(mine)} records"
            assert all(r["outcome"] for r in mine)
    printed = capsys.readouterr().out
    summary = (out / "summary.md").read_text()
    with (out / "archetypes.csv").open() as fh:
        table = list(csv.DictReader(fh))
    assert {(r["archetype"], r["planner"]) for r in table} == {
        (a, p) for a in francis2023.ARCHETYPES for p in ("social", "astar")
    }
    # Every registry metric with a value in the records is a column of the per-archetype table.
    metric_keys = [m["key"] for m in proxemic.reference.metric_registry()]
    numeric = {k for k in metric_keys if any(re.fullmatch(r"-?[\d.]+(e-?\d+)?", r.get(k) or "") for r in rows)}
    assert numeric and numeric <= set(table[0])
    assert {"success", "collision", "hc"} <= set(table[0])  # rates: booleans averaged
    for a in francis2023.ARCHETYPES:
        assert a in printed and f"| {a} |" in summary


def test_docs_show_every_archetype() -> None:
    page = (ROOT / "docs" / "francis2023.md").read_text()
    for a in francis2023.ARCHETYPES:
        picture = f"images/francis2023/{a}.png"
        assert picture in page, f"docs/francis2023.md does not show {a}"
        assert (ROOT / "docs" / picture).is_file(), f"{picture} missing: python -m proxemic.francis2023 pictures"
