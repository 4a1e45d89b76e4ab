"""The non-social baselines: plain A* (avoids walls and furniture, not people), and plain A* that
avoids collisions (``astar_orca``, ``astar_stop``), which must arrive about as often as ``social``."""

from __future__ import annotations

import re

import numpy as np
import pytest

from proxemic import splits
from proxemic.env import ProxemicEnv
from proxemic.evaluation import EvalConfig, iter_results
from proxemic.registration import ENV_IDS
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
    """The baseline does not see people: over seeds it runs into some (which is why it is a baseline;
    the museum's people avoid robots, so it is rare: once in seeds 0-59, on seed 15)."""
    env = ProxemicEnv("museum", autopilot=True)
    outcomes = [run_episode("museum", s, env=env).metrics["outcome"] for s in range(20)]
    env.close()
    assert "collision" in outcomes
    assert set(outcomes) <= {"success", "collision", "timeout"}


# --- the non-social baselines that avoid collisions ------------------------------------------------

#: The baselines that avoid collisions: plain A* followed with ORCA, and plain A* that stops.
AVOIDING_BASELINES = ("astar_orca", "astar_stop")
#: Every bundled scene (the registered env ids).
BUNDLED_SCENES = tuple(ENV_IDS.values())
#: Episode seeds of the success comparison in ``make test`` (a fixed prefix of the test split; no
#: constant of the baselines was chosen on it).
CI_SEEDS = splits.TEST_EPISODE_SEEDS[:20]
#: (scene, baseline) -> the measured figure, where the baseline succeeds more than 5 points less often
#: than ``social`` on the test split (strict xfails).
KNOWN_SHORTFALLS: dict[tuple[str, str], str] = {
    ("daza2021_path3", "astar_stop"): "astar_stop succeeds in 60% (24/40) vs social 100% (40/40) since the "
    "Daza scenes put the groups on the A* line: it waits for a standing group on its path to move",
    ("daza2021_path4", "astar_stop"): "astar_stop succeeds in 85% (34/40) vs social 100% (40/40) since the "
    "Daza scenes put the groups on the A* line",
    ("sousa2022_fig16", "astar_stop"): "astar_stop succeeds in 60% (12/20) vs social 100% (20/20): it times "
    "out in 8, stopped for people who stand by its path and never move (the Sousa figures' people do not "
    "react); which seeds' paths come that near depends on the robot's jittered start",
}


def _outcomes(scene: str, seed: int) -> dict[str, list[bool]]:
    """Success of every robot of one episode of `scene` from `seed`, per planner."""
    cfg = EvalConfig(scenario=scene, planners=["social", *AVOIDING_BASELINES], episodes=1, seed=seed, workers=1)
    out: dict[str, list[bool]] = {}
    for res in iter_results(cfg):
        out.setdefault(res.record["planner"], []).append(bool(res.record["success"]))
    return out


_SUCCESS: dict[str, dict[str, list[bool]]] = {}


def success_records(scene: str) -> dict[str, list[bool]]:
    """Per planner, the success of every robot and episode of `scene` on ``CI_SEEDS`` (run once, 2 processes)."""
    if scene not in _SUCCESS:
        import multiprocessing as mp

        with mp.get_context("fork").Pool(2) as pool:
            parts = pool.starmap(_outcomes, [(scene, s) for s in CI_SEEDS])
        _SUCCESS[scene] = {p: [x for part in parts for x in part.get(p, [])] for p in ("social", *AVOIDING_BASELINES)}
    return _SUCCESS[scene]


def _shortfall_cases() -> list[object]:
    out = []
    for scene in BUNDLED_SCENES:
        for planner in AVOIDING_BASELINES:
            reason = KNOWN_SHORTFALLS.get((scene, planner))
            marks = [pytest.mark.xfail(strict=True, reason=reason)] if reason else []
            out.append(pytest.param(scene, planner, marks=marks, id=f"{scene}-{planner}"))
    return out


@pytest.mark.parametrize(("scene", "planner"), _shortfall_cases())
def test_avoiding_baselines_succeed_about_as_often_as_social(scene: str, planner: str) -> None:
    """astar_orca and astar_stop reach the goal on every bundled scene at least as often as
    social minus 5 points (same test-split seeds, every robot of a multi-robot scene scored)."""
    rec = success_records(scene)
    n = len(rec["social"])
    assert n == len(rec[planner]) and n >= len(CI_SEEDS)
    social, base = sum(rec["social"]) / n, sum(rec[planner]) / n
    print(f"{scene}: success social {social:.0%}, {planner} {base:.0%} over {n} robot-episodes")
    assert base >= social - 0.05, (
        f"{scene}: {planner} succeeds in {base:.0%} ({sum(rec[planner])}/{n}) vs social {social:.0%} "
        f"({sum(rec['social'])}/{n}) (claim: at most 5 points below)"
    )


@pytest.mark.parametrize("planner", AVOIDING_BASELINES)
def test_avoiding_baselines_reach_the_goal_in_an_empty_museum(empty_museum, planner):
    """With nobody in the way both baselines drive the plain A* path: success, near the geodesic."""
    env = ProxemicEnv(empty_museum, autopilot=True, planner=planner)
    rec = run_episode(empty_museum, 0, env=env)
    geodesic = env.world.geodesic_start_distance(0)
    env.close()
    assert rec.metrics["outcome"] == "success", rec.metrics
    assert rec.metrics["path_length"] < 1.1 * geodesic + 0.6


def test_astar_stop_stops_for_people_where_astar_runs_into_them():
    """On the museum seeds where plain A* hits a person, astar_stop does not: it stands instead
    (the mode ``wait`` shows in its episode), and so it hits no one on those seeds."""
    hit: list[int] = []
    env = ProxemicEnv("museum", autopilot=True)
    for s in range(20):
        if run_episode("museum", s, env=env).metrics["hc"]:
            hit.append(s)
    env.close()
    assert hit, "plain A* hit nobody on seeds 0-19"
    env = ProxemicEnv("museum", autopilot=True, planner="astar_stop")
    for s in hit:
        env.reset(seed=s)
        modes = set()
        while True:
            _, _, terminated, truncated, info = env.step(np.zeros(3, np.float32))
            modes.add(info["planner_mode"])
            if terminated or truncated:
                break
        assert not info["metrics"]["hc"], f"astar_stop hit a person on seed {s}"
        assert "wait" in modes, s
    env.close()
