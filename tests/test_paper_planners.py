"""The papers' own planners, ``daza2021`` and ``sousa2022``, against their papers' claims.

Daza et al. 2021 (Micromachines 12, 193): Algorithm 1 (plain A*, ORCA among robots, Social
Momentum near people and groups); Fig. 15 (four robots cross with ORCA) and Paths 1-5 (Table 2).
Sousa et al. 2022 (Sensors 22, 4602) §4.5, Fig. 16: Delaunay groups (triangles 3 + 4 form one
group) and a Social Momentum path that respects the groups' asymmetric Gaussians.
"""

from __future__ import annotations

import math
from collections import Counter

import numpy as np
import pytest

import proxemic
from proxemic import ScenarioError
from proxemic.cli import main
from proxemic.env import ProxemicEnv
from proxemic.records import Individual

PAPER_PLANNERS = ("daza2021", "sousa2022")

#: Sousa 2022 Fig. 16: the people of triangles 3 + 4 (``g3_1`` ... ``g3_4`` in the scene file,
#: the 7th to 10th people).
FIG16_GROUP_3_4 = [6, 7, 8, 9]
#: Daza 2021's intimate radius (m): the keep-out level of Social Momentum in both papers.
INTIMATE = 0.5


def _run(scene: str, planner: str, seed: int) -> tuple[ProxemicEnv, dict, Counter, list[np.ndarray]]:
    """One episode of robot_0 on its built-in ``planner``: env, last info, modes, per-step outputs."""
    env = ProxemicEnv(scene, planner=planner)
    obs, info = env.reset(seed=seed)
    modes: Counter = Counter()
    steps: list[np.ndarray] = []
    terminated = truncated = False
    while not (terminated or truncated):
        obs, reward, terminated, truncated, info = env.step(info["planner_action"])
        modes[info["planner_mode"]] += 1
        steps.append(np.concatenate([obs["robot"].ravel(), np.asarray(info["planner_action"]), [reward]]))
    return env, info, modes, steps


def _team_run(scene: str, seed: int) -> tuple[dict[str, str], Counter, dict]:
    """Every robot of ``scene`` on ``daza2021`` autopilot: outcomes, (robot, mode) counts, team metrics."""
    env = proxemic.parallel_env(scene, autopilot=True, planners="daza2021")
    env.reset(seed=seed)
    outcomes: dict[str, str] = {}
    modes: Counter = Counter()
    team: dict = {}
    while env.agents:
        _, _, term, trunc, infos = env.step({})
        for a, info in infos.items():
            if "planner_mode" in info:
                modes[(a, info["planner_mode"])] += 1
            if term.get(a) or trunc.get(a):
                outcomes[a] = info["metrics"]["outcome"]
                team = info.get("team", team)
    return outcomes, modes, team


def test_the_paper_planners_are_selectable_everywhere(tmp_path, write_scenario, capsys):
    assert set(PAPER_PLANNERS) <= set(proxemic.PLANNERS)
    for planner in PAPER_PLANNERS:
        # a scenario file's planner
        text = proxemic.scenarios.resolve("daza2021_path1").read_text()
        assert text.count("[[robot]]") == 1
        path = write_scenario(text.replace("[[robot]]", f'[[robot]]\nplanner = "{planner}"'))
        assert [r["planner"] for r in proxemic.scenarios.load(path)[1]["robots"]] == [planner]
        env = ProxemicEnv(path)
        _, info = env.reset(seed=0)
        assert "planner_mode" in info
        # the CLI's eval
        out = tmp_path / planner
        assert (
            main(["eval", "--scenario", "daza2021_path1", "--planner", planner, "--episodes", "1", "--out", str(out)])
            == 0
        )
    capsys.readouterr()


def test_an_unknown_planner_is_a_typed_error_listing_the_paper_planners(write_scenario):
    with pytest.raises(ScenarioError) as e:
        ProxemicEnv("daza2021_path1", planner="daza2020")
    assert e.value.field == "planner"
    assert all(f'"{p}"' in str(e.value) for p in PAPER_PLANNERS), str(e.value)
    with pytest.raises(ScenarioError) as e:
        proxemic.parallel_env("daza2021_fig15", planners={"robot_1": "sousa"})
    assert e.value.field == "robot[1].planner" and all(p in str(e.value) for p in PAPER_PLANNERS)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_daza_fig15_four_robots_cross_with_orca_and_no_collision(seed):
    outcomes, modes, team = _team_run("daza2021_fig15", seed)
    assert outcomes == {f"robot_{k}": "success" for k in range(4)}, outcomes
    # Every robot ran ORCA (Algorithm 1 line 8) at some step: only robots are around.
    assert all(modes[(f"robot_{k}", "orca")] > 0 for k in range(4)), modes
    assert not any(m in ("social_momentum", "wait") for _, m in modes), modes
    assert team["agent_collisions"] == 0 and team["robot_collision_steps"] == 0
    assert team["min_robot_gap"] > 0.0


@pytest.mark.parametrize("path", [1, 2, 3, 4, 5])
def test_daza_paths_reach_the_goal_with_social_momentum_near_people(path):
    _, info, modes, _ = _run(f"daza2021_path{path}", "daza2021", seed=0)
    assert info["metrics"]["outcome"] == "success", (path, info["metrics"]["outcome"])
    assert modes["social_momentum"] > 0, modes


@pytest.mark.xfail(
    strict=True,
    reason=(
        "measured: 0 ORCA steps on Paths 4 and 5 (robot_0: 7 follow / 223 Social Momentum steps on "
        "Path 4, 1 / 256 on Path 5; robot_1: Social Momentum then success). Algorithm 1 runs ORCA "
        "only when every detected mobile object is a robot (lines 5-8), and the scenes' second "
        "robot stands in a human group, so people are always detected with it"
    ),
)
@pytest.mark.parametrize("path", [4, 5])
def test_daza_paths_4_and_5_use_orca_at_some_step(path):
    outcomes, modes, _ = _team_run(f"daza2021_path{path}", seed=0)
    assert outcomes["robot_0"] == "success"
    assert any(m == "orca" for _, m in modes), modes


def _zone_distance(ind: Individual, p: np.ndarray, zone_scale: float = 1.0) -> float:
    """Sousa 2022 eq. 5: the zone distance ``z sqrt(2 q)`` of ``p`` in the individual's Gaussian.

    ``zone_scale`` is 1 m for the ``sousa2022`` space (every base sigma is 1 m).
    """
    dx, dy = p[0] - ind["centre"][0], p[1] - ind["centre"][1]
    c, s = math.cos(ind["heading"]), math.sin(ind["heading"])
    sag, fro = c * dx + s * dy, s * dx - c * dy
    front, rear, right, left = ind["sides"]
    sa, sf = (front if sag >= 0 else rear), (right if fro >= 0 else left)
    return zone_scale * math.sqrt(sag * sag / (sa * sa) + fro * fro / (sf * sf))


def _fig16_group(planner: str) -> tuple[list[list[int]], float, float, str]:
    """Sousa Fig. 16 on ``planner``: the detected groups, the robot's least centre distance to
    triangles 3 + 4's o-space edge (m), its least zone distance in their Gaussian, the outcome."""
    env, info, _, _ = _run("sousa2022_fig16", planner, seed=0)
    per = env.world.perception()
    groups = [sorted(g) for g in per["groups"] if len(g) > 1]
    ind = next(i for i in per["individuals"] if sorted(i["members"]) == FIG16_GROUP_3_4)
    members = np.asarray(env.world.people())[FIG16_GROUP_3_4, :2]
    centre = members.mean(axis=0)
    ospace = float(np.linalg.norm(members - centre, axis=1).mean())
    traj = np.asarray(env.world.trajectory(0))[:, :2]
    gap = float(np.linalg.norm(traj - centre, axis=1).min()) - ospace
    zone = min(_zone_distance(ind, p) for p in traj)
    return groups, gap, zone, info["metrics"]["outcome"]


def test_sousa_fig16_triangles_3_and_4_form_one_group_and_the_sousa_path_avoids_it():
    groups, gap, zone, outcome = _fig16_group("sousa2022")
    assert FIG16_GROUP_3_4 in groups, groups
    assert outcome == "success"
    assert gap > 0.0, f"the robot entered the o-space of triangles 3 + 4 ({gap:.2f} m)"
    assert zone > INTIMATE, f"the robot entered the group's Gaussian intimate level (zone distance {zone:.2f} m)"


@pytest.mark.xfail(
    strict=True,
    reason=(
        "measured: plain A*'s least zone distance in the Gaussian of triangles 3 + 4 is 3.02 m "
        "(4.26 m from their centre): the scene's diagonal to the Fig. 16 target passes groups 1 "
        "and 2 and the angry and happy individuals, not group 3 + 4"
    ),
)
def test_sousa_fig16_plain_astar_crosses_the_group_of_triangles_3_and_4():
    _, gap, zone, _ = _fig16_group("astar")
    assert gap <= 0.0 or zone <= INTIMATE, (gap, zone)


@pytest.mark.parametrize(("scene", "planner"), [("daza2021_path5", "daza2021"), ("sousa2022_fig16", "sousa2022")])
def test_same_seed_same_episode(scene, planner):
    _, info_a, modes_a, steps_a = _run(scene, planner, seed=3)
    _, info_b, modes_b, steps_b = _run(scene, planner, seed=3)
    assert modes_a == modes_b
    assert len(steps_a) == len(steps_b) > 50
    assert all(np.array_equal(a, b) for a, b in zip(steps_a, steps_b, strict=True))
    assert info_a["metrics"] == info_b["metrics"]
