"""Who hit whom (contact events by fault) and the robot's cost to people (robot-free replay).

End-to-end env episodes with MuJoCo contacts: a person walking into a parked robot is the
person's fault and does not end the episode; a robot driving into a standing person is the
robot's fault and does; a wall contact is static. The counterfactual metrics reach the env's
episode metrics, ``episodes.csv`` and the summary.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Any

import numpy as np

from proxemic.env import ProxemicEnv
from proxemic.evaluation import EvalConfig, run_evaluation

ROOM = """
[scene]
name = "fault_room"
bounds = [0, 0, 10, 8]

[[wall]]
from = [0, 0]
to = [10, 0]
[[wall]]
from = [10, 0]
to = [10, 8]
[[wall]]
from = [10, 8]
to = [0, 8]
[[wall]]
from = [0, 8]
to = [0, 0]

{person}

[[robot]]
start = [{rx}, 4, 0]
goal = [{rx}, 7]

[episode]
max_time = 12

[episode.randomize]
person_phase = false
speed_jitter = 0.0
"""

#: A walker that ignores robots (``aware = false``), back and forth across the room along y = 4.
WALKER = '[[person]]\nname = "walker"\nroute = [[1, 4], [9, 4]]\nspeed = 1.0\naware = false'
#: A person standing at (5, 4).
STANDING = '[[person]]\nname = "stander"\nbehaviour = "standing"\npose = [5, 4, 0]'


def drive(path: Path, action: tuple[float, float, float], steps: int) -> tuple[dict[str, Any], int, bool]:
    """Runs `steps` steps of the scenario at `path` with a fixed normalised action; (metrics, steps run, terminated)."""
    env = ProxemicEnv(str(path))
    env.reset(seed=0)
    act = np.array(action, dtype=np.float32)
    terminated = False
    for k in range(steps):
        _, _, terminated, truncated, info = env.step(act)
        if terminated or truncated:
            env.close()
            return dict(info["metrics"]), k + 1, terminated
    metrics = dict(env.metrics())
    env.close()
    return metrics, steps, terminated


def test_a_person_walking_into_a_parked_robot_is_the_persons_fault(tmp_path: Path) -> None:
    path = tmp_path / "parked.toml"
    path.write_text(ROOM.format(person=WALKER, rx=5))
    m, steps, terminated = drive(path, (0.0, 0.0, 0.0), 100)
    assert m["hc_count"] > 0, m
    assert m["collisions_person_fault"] >= 1 and m["collisions_robot_fault"] == 0, m
    # not a collision: the episode runs on
    assert not terminated and steps == 100 and not m["collision"] and m["outcome"] == "running", m


def test_a_robot_driving_into_a_standing_person_is_the_robots_fault(tmp_path: Path) -> None:
    path = tmp_path / "drive.toml"
    # A person who does not make way (`ignore`): one who sees the robot shifts aside and is missed.
    path.write_text(ROOM.format(person=STANDING + '\nreaction = "ignore"', rx=2))
    m, _, terminated = drive(path, (1.0, 0.0, 0.0), 100)
    assert terminated and m["outcome"] == "collision" and not m["success"], m
    assert (m["collisions_robot_fault"], m["collisions_person_fault"], m["collisions_static"]) == (1, 0, 0), m


def test_a_wall_contact_is_static(tmp_path: Path) -> None:
    path = tmp_path / "wall.toml"
    path.write_text(ROOM.format(person=STANDING.replace("[5, 4, 0]", "[2, 2, 0]"), rx=8.5))
    m, _, terminated = drive(path, (1.0, 0.0, 0.0), 100)
    assert terminated and m["outcome"] == "collision" and m["wc"], m
    assert (m["collisions_robot_fault"], m["collisions_person_fault"], m["collisions_static"]) == (0, 0, 1), m


def test_people_cost_reaches_the_records_and_the_summary(tmp_path: Path) -> None:
    res = run_evaluation(EvalConfig(scenario="museum", planners=["astar"], episodes=1, out=tmp_path), progress=False)
    keys = ("ped_delay_s_mean", "ped_delay_s_max", "ped_extra_distance_m_mean", "ped_path_deviation_m_max")
    with (tmp_path / "episodes.csv").open() as f:
        row = next(csv.DictReader(f))
    for k in (*keys, "collisions_robot_fault", "collisions_person_fault", "collisions_static"):
        assert k in row and row[k] != "", k
        assert float(row[k]) >= 0.0, (k, row[k])
    assert "ped_delay_s_mean" in res.summary[0]
    assert "people's mean delay" in res.summary_markdown()
