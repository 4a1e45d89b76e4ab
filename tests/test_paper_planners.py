"""The papers' own planners, ``daza2021`` and ``sousa2022``, against their papers' claims.

Daza et al. 2021 (Micromachines 12, 193): Algorithm 1 (plain A*, ORCA among robots, Social
Momentum near people and groups); Fig. 15 (four robots cross with ORCA) and Paths 1-5 (Table 2).
Sousa et al. 2022 (Sensors 22, 4602) §4.5, Figs. 16-17: Delaunay groups (triangles 3 + 4 form one
group) and a path (planned on the Gaussians' cost map, §3.1, then Social Momentum) that respects
the personal space of the groups' and people's asymmetric Gaussians.
"""

from __future__ import annotations

import math
import re
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

import proxemic
from proxemic import ScenarioError, _core
from proxemic.cli import main
from proxemic.env import ProxemicEnv
from proxemic.records import Individual, Perception
from proxemic.reproduce import SOUSA_PERSONAL_RADIUS
from proxemic.splits import TEST_EPISODE_SEEDS

PAPER_PLANNERS = ("daza2021", "sousa2022")

#: Sousa 2022 Fig. 16: the people of triangles 3 + 4 (``g3_1`` ... ``g3_4`` in the scene file,
#: the 7th to 10th people).
FIG16_GROUP_3_4 = [6, 7, 8, 9]
#: Daza 2021's intimate radius (m): the keep-out level of Daza's Social Momentum.
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


@pytest.mark.parametrize(
    "path",
    [
        1,
        2,
        3,
        4,
        5,
    ],
)
def test_daza_paths_reach_the_goal_with_social_momentum_near_people(path):
    _, info, modes, _ = _run(f"daza2021_path{path}", "daza2021", seed=0)
    assert info["metrics"]["outcome"] == "success", (path, info["metrics"]["outcome"])
    assert modes["social_momentum"] > 0, modes


@pytest.mark.parametrize(
    "path",
    [
        pytest.param(
            4,
            marks=pytest.mark.xfail(
                strict=True,
                reason="measured with the groups on the A* line (seed 0): success, Social "
                "Momentum 238 of 240 steps, psi_intimate, group_psi_intimate and ospace_pct 0, but at the "
                "end robot_1 is perceived with one person only (the members shifted aside as robot_0 "
                "passed through) and robot_0's track passes 0.27 m from a person's final position",
            ),
        ),
        pytest.param(
            5,
            marks=pytest.mark.xfail(
                strict=True,
                reason="measured with the groups on the A* line (seed 0): success, Social "
                "Momentum 239 of 258 steps (wait 18), but at the end robot_1 is perceived with one person "
                "only (the members shifted aside as robot_0 passed) and robot_0's track passes 0.13 m "
                "from a person's final position",
            ),
        ),
    ],
)
def test_daza_paths_4_and_5_give_the_robot_in_a_group_a_zone_and_keep_out_of_it(path):
    # Daza 2021 Figs. 20-21 (Paths 4, 5): groups of people and robots. "A proxemic zone is
    # associated to the robot in the group, which together with the proxemic zones of people form
    # a space 'O' ... a trajectory is defined by the Social Momentum algorithm" (Sect. 5, lines
    # 17-19 of Algorithm 1: "treat it as a person"); "when the planning agent has to pass through
    # this group of humans and robots, it should not go too close or in the middle of them"
    # (Sect. 4) and "the intimate zones of people will never be invaded by robots" (Sect. 5).
    # The paper claims no ORCA here: people are detected at every step, so lines 12-22 run.
    env, info, modes, _ = _run(f"daza2021_path{path}", "daza2021", seed=0)
    assert info["metrics"]["outcome"] == "success"
    assert modes["social_momentum"] > 0, modes
    # robot_1 stands in a human group and is perceived as one of its members.
    per = env.world.perception()
    assert any(1 in ind["robots"] and len(ind["members"]) >= 2 for ind in per["individuals"]), per["individuals"]
    # robot_0 keeps out of every person's intimate zone, of robot_1's (treated as a person) and
    # of the groups' O spaces.
    traj = np.asarray(env.world.trajectory(0))[:, :2]
    other = np.asarray(env.world.trajectory(1))[:, :2]
    n = min(len(traj), len(other))
    people = np.asarray(env.world.people())[:, :2]
    assert np.linalg.norm(traj[:, None] - people[None], axis=2).min() > INTIMATE
    assert np.linalg.norm(traj[:n] - other[:n], axis=1).min() > INTIMATE
    assert info["metrics"]["psi_intimate"] == 0.0 and info["metrics"]["group_psi_intimate"] == 0.0
    assert info["metrics"]["ospace_pct"] == 0.0


def _core_zone_distance(ind: Individual, points: np.ndarray) -> np.ndarray:
    """The zone distances of ``points`` in ``ind``'s Gaussian, by the core's definition (the one
    the planners use), not a copy of it."""
    pts = np.ascontiguousarray(points[:, :2], dtype=np.float64)
    (x, y), (front, rear, right, left) = ind["centre"], ind["sides"]
    return _core.zone_distances((x, y), ind["heading"], (front, rear, right, left), ind["zone_scale"], pts)


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
    zone = float(_core_zone_distance(ind, traj).min())
    return groups, gap, zone, info["metrics"]["outcome"]


def test_sousa_fig16_triangles_3_and_4_form_one_group_and_the_sousa_path_avoids_it():
    groups, gap, zone, outcome = _fig16_group("sousa2022")
    assert FIG16_GROUP_3_4 in groups, groups
    assert outcome == "success"
    assert gap > 0.0, f"the robot entered the o-space of triangles 3 + 4 ({gap:.2f} m)"
    assert zone > INTIMATE, f"the robot entered the group's Gaussian intimate level (zone distance {zone:.2f} m)"


#: Daza 2021's personal radius (m): the outer edge of the personal zone (0.5-1 m, Sect. 2).
PERSONAL = SOUSA_PERSONAL_RADIUS


def _least_zones(scene: str, planner: str) -> tuple[float, float, Perception]:
    """``planner``'s least zone distance (Sousa eq. 5, m) over the perceived groups and over the
    people standing alone of ``scene`` (seed 0), and the perception at the end."""
    env, info, _, _ = _run(scene, planner, seed=0)
    assert info["metrics"]["outcome"] == "success"
    traj = np.asarray(env.world.trajectory(0))[:, :2]
    least = {True: math.inf, False: math.inf}
    for ind in env.world.perception()["individuals"]:
        zone = float(_core_zone_distance(ind, traj).min())
        least[len(ind["members"]) > 1] = min(least[len(ind["members"]) > 1], zone)
    return least[True], least[False], env.world.perception()


def test_sousa_figs_16_17_plain_astar_crosses_a_groups_and_a_persons_personal_space():
    # Sousa 2022 Sect. 4.5: "in both results (Figures 16 and 17), the resulting path planning
    # achieved by the A* algorithm does not respect the personal space, crossing the proxemics
    # space for groups and for a single person". Measured (seed 0): least zone distance 0.95 m
    # (group 1) / 0.89 m (the angry individual) on Fig. 16, 0.81 m (group 3 + 4) / 0.90 m (the
    # angry individual) on Fig. 17.
    for scene in ("sousa2022_fig16", "sousa2022_fig17"):
        groups, alone, _ = _least_zones(scene, "astar")
        assert groups < PERSONAL and alone < PERSONAL, (scene, groups, alone)


def test_sousa_figs_16_17_the_sousa_path_respects_every_personal_space():
    # Sousa 2022 Sect. 4.5: "by combining the proposed approach with social momentum (red line)
    # ... the robot respects groups and individual space imposed by Gaussian functions"; Daza's
    # method is used "for avoiding the personal space of persons". The path is planned on the
    # Gaussians' cost map (Sect. 3.1, Fig. 3) and Social Momentum keeps out of their personal
    # level. Measured (seed 0): least zone distance 1.10 m (group 1) / 1.67 m (individuals) on
    # Fig. 16, 1.14 m (group 3 + 4) / 1.31 m on Fig. 17.
    for scene in ("sousa2022_fig16", "sousa2022_fig17"):
        groups, alone, _ = _least_zones(scene, "sousa2022")
        assert groups >= PERSONAL and alone >= PERSONAL, (scene, groups, alone)


#: Test-split seeds of the perturbed Sousa figures (none was looked at when the scenes were laid out).
SOUSA_VARIANT_SEEDS = TEST_EPISODE_SEEDS[:8]


def _shifted_figure(figure: str, seed: int, out: Path) -> Path:
    """``sousa2022_<figure>`` with every group moved rigidly and every person alone moved by up to
    0.1 m in x and y (uniform, ``seed``): the figures' people positions are our invention, so the
    claim on Sousa's path must not hinge on them."""
    text = (Path(proxemic.__file__).parent / "data" / "envs" / f"sousa2022_{figure}.toml").read_text()
    rng = np.random.default_rng(seed)
    shifts: dict[str, np.ndarray] = {}
    blocks = text.split("[[person]]")
    for k, block in enumerate(blocks[1:], start=1):
        group = re.search(r"^group = (\d+)", block, re.MULTILINE)
        key = f"group {group.group(1)}" if group else f"person {k}"
        dx, dy = shifts.setdefault(key, rng.uniform(-0.1, 0.1, 2))
        pose = re.search(r"pose = \[([-\d.]+), ([-\d.]+), ", block)
        assert pose is not None, block
        moved = f"pose = [{float(pose.group(1)) + dx:.4f}, {float(pose.group(2)) + dy:.4f}, "
        blocks[k] = block[: pose.start()] + moved + block[pose.end() :]
    path = out / f"sousa2022_{figure}_{seed}.toml"
    path.write_text("[[person]]".join(blocks))
    return path


@pytest.mark.parametrize("figure", ["fig16", "fig17"])
def test_sousa_path_respects_every_personal_space_with_the_people_moved(figure, tmp_path):
    # The claim of test_sousa_figs_16_17_the_sousa_path_respects_every_personal_space on 8
    # variants of each figure (people moved by up to 0.1 m, test-split seeds), with the groups
    # still the scene's. Measured: least zone distance 1.10-1.14 m (groups), 1.23 m or more
    # (people alone); plain A* entered both kinds in 18 of 20 variants of tuning seeds 0-9.
    for seed in SOUSA_VARIANT_SEEDS:
        scene = str(_shifted_figure(figure, seed, tmp_path))
        groups, alone, per = _least_zones(scene, "sousa2022")
        assert per["accuracy"]["f1"] == 1.0, (seed, per["groups"])
        assert groups >= PERSONAL and alone >= PERSONAL, (seed, groups, alone)


@pytest.mark.xfail(
    strict=True,
    reason=(
        "measured with the people standing still (reaction ignore, as in the paper's static "
        "figures): plain A* enters a group's and a single person's personal space in 11 of the 16 "
        "variants; on Fig. 16 seeds 1005, 1006 and 1007 it passes the groups at zone distance 1.07, "
        "1.01 and 1.06 m, on Fig. 17 seeds 1003 and 1005 the people alone at 1.06 and 1.01 m. The "
        "figures' positions were moved (0.15 m) on the figures themselves, not on a tuning split, and "
        "the A* statement does not hold on every held-out variant"
    ),
)
def test_sousa_plain_astar_crosses_both_kinds_with_the_people_moved(tmp_path):
    # Sect. 4.5's statement about the A* path, on the held-out variants of the figures (people
    # moved by up to 0.1 m, SOUSA_VARIANT_SEEDS); on tuning seeds 0-9 it holds in 14 of 20.
    missed = []
    for figure in ("fig16", "fig17"):
        for seed in SOUSA_VARIANT_SEEDS:
            groups, alone, _ = _least_zones(str(_shifted_figure(figure, seed, tmp_path)), "astar")
            if not (groups < PERSONAL and alone < PERSONAL):
                missed.append((figure, seed, round(groups, 2), round(alone, 2)))
    assert not missed, missed


@pytest.mark.parametrize(("scene", "planner"), [("daza2021_path5", "daza2021"), ("sousa2022_fig16", "sousa2022")])
def test_same_seed_same_episode(scene, planner):
    _, info_a, modes_a, steps_a = _run(scene, planner, seed=3)
    _, info_b, modes_b, steps_b = _run(scene, planner, seed=3)
    assert modes_a == modes_b
    assert len(steps_a) == len(steps_b) > 50
    assert all(np.array_equal(a, b) for a, b in zip(steps_a, steps_b, strict=True))
    assert info_a["metrics"] == info_b["metrics"]
