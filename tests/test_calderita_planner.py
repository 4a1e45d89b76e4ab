"""The ``calderita`` planner (Calderita et al.'s system as published) on the paper's scenes.

Dijkstra on the time-dependent social map with the people's zones as contours of the summed
density, the elastic band on that path, re-planned on the agenda. The claims are the paper's
(§6.1): it reaches its goal in both experiments, and in the first experiment the path avoids the
TV's interaction space while the TV therapy runs (Test 2, 10:05) and uses it while the TV is idle
(Test 1, 09:05, its own scene calderita_exp1_test1). A claim our reconstruction misses is a
strict xfail stating the measured figure.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from proxemic import scenarios
from proxemic.env import ProxemicEnv, flatten_metrics

#: The scene of every published Calderita path (Tables 1, 2), each at its own start time.
CALDERITA_RUNS = [
    "calderita_exp1_test1",  # Table 1 Path 1: 09:05, table therapy on, TV idle
    "calderita_exp1",  # Table 1 Path 2: 10:05, table and TV therapies on
    "calderita_exp2_path1",  # Table 2 Path 1: 11:05, the table's therapy on
    "calderita_exp2_path2",  # Table 2 Path 2: the table's cost rises during the trip
    "calderita_exp2",  # the original second-experiment scene
]


def run(scene: str, planner: str = "calderita", seed: int = 0) -> tuple[dict[str, Any], Any]:
    """One episode of `scene` with the built-in `planner`: (flattened metrics, trajectory)."""
    core, _ = scenarios.load(scene)
    env = ProxemicEnv(core, autopilot=True, planner=planner)
    _, info = env.reset(seed=seed)
    done = False
    while not done:
        _, _, terminated, truncated, info = env.step(info["planner_action"])
        done = terminated or truncated
    metrics = flatten_metrics(env.metrics(), env.scenario)
    traj = np.asarray(env.world.trajectory(0)).copy()
    env.close()
    return metrics, traj


@pytest.mark.parametrize("scene", CALDERITA_RUNS)
def test_calderita_reaches_the_goal_on_the_papers_scenes(scene: str) -> None:
    metrics, _ = run(scene)
    assert metrics["success"], metrics
    assert metrics["psi_intimate"] == 0.0


def test_calderita_is_deterministic() -> None:
    a, ta = run("calderita_exp2_path2", seed=3)
    b, tb = run("calderita_exp2_path2", seed=3)
    assert np.array_equal(ta, tb)
    assert a == b


def test_calderita_test2_avoids_the_tv_space_while_its_therapy_runs() -> None:
    # Calderita Table 1 Path 2 (Test 2, both therapies on at 10:05): no time in the TV's space.
    metrics, _ = run("calderita_exp1")
    assert metrics["success"]
    assert metrics["psi_object_any_tv"] == 0.0


def test_calderita_test1_uses_the_idle_tv_space() -> None:
    # Calderita Table 1 Path 1 (Test 1, 09:05: the TV idle, no TV therapy scheduled): "in Path 1,
    # the robot uses the TV's time-dependent social interaction spaces in its trajectory since it
    # is not in use" (Psi(Objects) 34.98%). Test 1 is its own scene, calderita_exp1_test1: with no
    # TV therapy senior_2 is not seated in front of the TV (calderita_exp1 run at 09:05 would keep
    # her there, which the paper's test 1 does not have).
    test1, _ = run("calderita_exp1_test1")
    test2, _ = run("calderita_exp1")
    assert test1["success"] and test2["success"]
    assert test1["psi_object_any_tv"] > 0.0
    assert test2["psi_object_any_tv"] == 0.0


@pytest.mark.xfail(
    strict=True,
    reason="test 1 travels 15.729 m, test 2 15.672 m (seed 0; the paper: 14.03 m against 17.40 m): the route "
    "through the idle TV space saves nothing here. Test 2 took 15.778 m only while senior_1, standing by a wall or "
    "furniture, was pushed 0.40 m off it as the robot passed (standing people near an obstacle now stay put)",
)
def test_calderita_test1_travels_less_than_test2() -> None:
    # Calderita Table 1: "in Path 1, the robot travels a shorter distance" than in Path 2 (d_t
    # 14.03 m against 17.40 m).
    test1, _ = run("calderita_exp1_test1")
    test2, _ = run("calderita_exp1")
    assert test1["d_t"] < test2["d_t"], (test1["d_t"], test2["d_t"])


def test_calderita_keeps_out_of_the_table_space_during_the_therapy() -> None:
    # Calderita Table 2 Path 2 (the table's therapy starts during the trip): Psi(Objects) 0 in the
    # paper; plain A* on the same scene crosses the table's space while its therapy is on. (The
    # band on the Dijkstra path grazing door D3's post once bisected until its bubble cap and was
    # dropped, and the follower cut a corner into the table's space: 2.7% of the trip.)
    social, _ = run("calderita_exp2_path2")
    plain, _ = run("calderita_exp2_path2", planner="astar")
    assert social["psi_object_active_ot_table"] == 0.0
    assert plain["psi_object_active_ot_table"] > 0.0
