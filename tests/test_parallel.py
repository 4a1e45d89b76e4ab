"""The PettingZoo parallel env: API conformance, determinism, multi-robot behaviour, bad input."""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np
import pytest
from pettingzoo.test import api_test, parallel_api_test
from pettingzoo.utils.conversions import parallel_to_aec

import proxemic
from proxemic import InputError, ScenarioError
from proxemic.env import ProxemicEnv

ROOT = Path(__file__).resolve().parent.parent

TWO_ROBOTS = """
[scene]
name = "two_robots"
bounds = [0, 0, 10, 8]

[[wall]]
from = [0, 0]
to = [10, 0]

[[person]]
route = [[2, 2], [8, 2]]
speed = 1.0

[[robot]]
start = [1.5, 4, 0]
goal = [8.5, 4]

[[robot]]
start = [8.5, 4.0, 3.14159]
goal = [1.5, 4]

[episode]
max_time = 20
"""


def test_parallel_api_test_passes():
    env = proxemic.parallel_env("daza2021_fig15")
    parallel_api_test(env, num_cycles=150)


def test_aec_conversion_passes_the_api_test():
    env = parallel_to_aec(proxemic.parallel_env("daza2021_fig15", robots=3))
    api_test(env, num_cycles=40)


def test_agents_spaces_and_what_each_robot_sees_of_the_others():
    env = proxemic.parallel_env("daza2021_fig15", robots=3)
    assert env.possible_agents == ["robot_0", "robot_1", "robot_2"]
    obs, infos = env.reset(seed=3)
    space = env.observation_space("robot_0")
    assert space["robots"].shape == (2, proxemic._core.PEER_FEATURES)
    assert space["robots_mask"].shape == (2,)
    assert env.action_space("robot_1").shape == (3,)
    # robot_0 near (2, 6) facing east; robot_1 near (10, 6) facing west (about 8 m: at the sensor
    # range), robot_2 near (6, 2) facing north (each start jittered by up to 0.2 m per axis).
    # Nearest first: robot_2 (about 5.66 m), then robot_1 (about 8 m).
    start = [np.asarray(env.world.trajectory(i))[0] for i in range(3)]
    assert all(
        np.abs(s[:2] - nominal).max() <= 0.2 for s, nominal in zip(start, [(2, 6), (10, 6), (6, 2)], strict=True)
    )

    def seen(by: int, other: int) -> np.ndarray:
        """`other`'s position in `by`'s frame (x ahead, y to the left)."""
        d, yaw = start[other][:2] - start[by][:2], start[by][2]
        return np.array([np.cos(yaw) * d[0] + np.sin(yaw) * d[1], -np.sin(yaw) * d[0] + np.cos(yaw) * d[1]])

    rows = obs["robot_0"]["robots"]
    np.testing.assert_array_equal(obs["robot_0"]["robots_mask"], [1.0, 1.0])
    np.testing.assert_array_equal(rows[:, 0], [2.0, 1.0])  # identities
    np.testing.assert_allclose(rows[0, 1:3], seen(0, 2), atol=1e-5)  # robot frame of robot_0
    np.testing.assert_allclose(rows[1, 1:3], seen(0, 1), atol=1e-5)
    np.testing.assert_allclose(rows[:, 5], 0.24)
    np.testing.assert_array_equal(rows[:, 6], [1.0, 1.0])  # both running
    # robot_1 sees robot_0 about 8 m ahead in its own (westward) frame.
    r1 = obs["robot_1"]["robots"]
    assert r1[1, 0] == 0.0
    np.testing.assert_allclose(r1[1, 1:3], seen(1, 0), atol=1e-5)
    assert abs(r1[1, 1] - 8.0) < 0.6 and abs(r1[1, 2]) < 0.6
    for a in env.agents:
        assert space.contains(obs[a]), a
        assert set(infos[a]) >= {"reward_progress", "planner_action", "planner_mode", "is_success"}


def _episode(env, seed: int, policy_seed: int = 0) -> list:
    """Every output of a whole episode, with random actions from a seeded generator."""
    rng = np.random.default_rng(policy_seed)
    trace = [env.reset(seed=seed)]
    while env.agents:
        actions = {a: rng.uniform(-1, 1, 3).astype(np.float32) for a in env.agents}
        trace.append(env.step(actions))
    return trace


def _assert_same(a, b, where: str = "") -> None:
    if isinstance(a, dict):
        assert a.keys() == b.keys(), where
        for k in a:
            _assert_same(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, list | tuple):
        assert len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            _assert_same(x, y, f"{where}[{i}]")
    elif isinstance(a, np.ndarray):
        assert a.dtype == b.dtype and a.shape == b.shape, where
        assert a.tobytes() == b.tobytes(), where
    elif isinstance(a, float) and np.isnan(a):
        assert isinstance(b, float) and np.isnan(b), where
    else:
        assert a == b, where


def test_same_seed_same_episode_for_every_agent_bit_for_bit(write_scenario):
    path = write_scenario(TWO_ROBOTS)
    first = _episode(proxemic.parallel_env(path), seed=11)
    again = _episode(proxemic.parallel_env(path), seed=11)
    assert len(first) > 10
    _assert_same(first, again, "episode")
    # A different seed changes the episode (the person's phase and speed are drawn from it).
    other = _episode(proxemic.parallel_env(path), seed=12)
    with pytest.raises(AssertionError):
        _assert_same(first, other, "episode")


def test_four_robots_cross_without_robot_collision_and_all_arrive():
    for seed in (0, 1):
        env = proxemic.parallel_env("daza2021_fig15", autopilot=True, planners="social")
        env.reset(seed=seed)
        outcomes = {}
        while env.agents:
            _, _, term, trunc, infos = env.step({})
            for a in term:
                if term[a] or trunc[a]:
                    outcomes[a] = infos[a]["metrics"]["outcome"]
                    team = infos[a].get("team")
        assert outcomes == {a: "success" for a in env.possible_agents}, (seed, outcomes)
        assert team["agent_collisions"] == 0 and team["robot_collision_steps"] == 0
        assert team["min_robot_gap"] > 0.0
        assert team["success_rate"] == 1.0
        assert 0.0 < team["team_time"] <= team["total_time"]


def test_care_center_delivery_robots_meet_in_the_corridor_and_all_deliver():
    # Test-split seeds (on seed 0 the robots no longer meet since the people react to them).
    met = 0
    for seed in range(1000, 1010):
        env = proxemic.parallel_env("care_center_multi", autopilot=True)
        assert len(env.possible_agents) == 3
        env.reset(seed=seed)
        while env.agents:
            env.step({})
        team = env.episode_metrics()
        assert team["agent_collisions"] == 0 and team["person_collisions"] == 0, seed
        met += team["min_robot_gap"] < 1.0  # they did meet (and passed each other)
        assert [m["outcome"] for m in team["robots"]] == ["success"] * 3, (seed, team["robots"])
    assert met >= 1


def test_plain_astar_robots_collide_at_the_crossing_and_it_is_counted():
    # The same crossing with plain A* (no robot avoidance): the collision check can fail.
    env = proxemic.parallel_env("daza2021_fig15", autopilot=True, planners="astar")
    env.reset(seed=0)
    while env.agents:
        env.step({})
    team = env.episode_metrics()
    assert team["agent_collisions"] >= 2
    assert team["min_robot_gap"] < 0.05
    assert [m["outcome"] for m in team["robots"]].count("collision") == team["agent_collisions"]


def test_mixed_planners_and_autopilot_sets():
    env = proxemic.parallel_env(
        "daza2021_fig15", planners={"robot_1": "astar", "robot_2": "astar_orca"}, autopilot={"robot_3"}
    )
    planners = [r["planner"] for r in env.scenario["robots"]]
    assert planners[1:3] == ["astar", "astar_orca"]
    env.reset(seed=0)
    # robot_3 is on autopilot: its action may be left out; the others must act.
    zero = np.zeros(3, np.float32)
    _, _, _, _, infos = env.step({"robot_0": zero, "robot_1": zero, "robot_2": zero})
    assert infos["robot_2"]["planner_mode"] == "orca"
    with pytest.raises(InputError, match="missing"):
        env.step({"robot_0": zero})


def test_without_planner_actions_policy_agents_skip_their_planners():
    env = proxemic.parallel_env("daza2021_fig15", autopilot={"robot_3"}, planner_actions=False)
    _, infos = env.reset(seed=0)
    assert "planner_action" not in infos["robot_0"] and "planner_mode" not in infos["robot_0"]
    assert "planner_action" in infos["robot_3"]  # on autopilot: its planner drives it
    forward = np.array([1.0, 0.0, 0.0], np.float32)
    for _ in range(20):
        _, _, _, _, infos = env.step({a: forward for a in ("robot_0", "robot_1", "robot_2")})
    assert "planner_action" not in infos["robot_1"]
    # The policies drove robots 0-2 forward; robot 3 followed its own planner toward its goal.
    moved = env.state()[:, :2] - np.array([[2, 6], [10, 6], [6, 2], [6, 10]], np.float32)
    assert np.linalg.norm(moved, axis=1).min() > 0.5


def test_batched_outputs_equal_the_per_robot_reads_bit_for_bit():
    # The parallel env reads every live robot's observation, reward, flags and info in one go
    # (WorldSim.observations and results); the single-robot env reads one robot at a time
    # (observation, outcome, info): the same values, keys in the same order, for every robot
    # and any subset, with planners on and off.
    env = proxemic.parallel_env("museum_multi", robots=5, autopilot={"robot_3"}, planner_actions=False)
    ws = env.ws
    env.reset(seed=4)
    rng = np.random.default_rng(5)
    for step in range(12):
        env.step({a: rng.uniform(-1, 1, 3).astype(np.float32) for a in env.agents if a != "robot_3"})
        for rows in ([0, 1, 2, 3, 4], [1, 3, 4], [4, 0], [2]):
            where = f"step {step}, rows {rows}"
            batch = ws.observations(robots=True, rows=rows)
            rewards, terms, truncs, infos = ws.results(rows)
            for r, obs, rew, term, trunc, info in zip(rows, batch, rewards, terms, truncs, infos, strict=True):
                one = ws.observation(r, robots=True)
                assert list(obs) == list(one), where
                _assert_same(obs, one, where)
                assert (rew, term, trunc) == ws.outcome(r), where
                single = ws.info(r)
                assert list(info) == list(single), where
                _assert_same(info, single, where)
                assert [type(v) for v in info.values()] == [type(v) for v in single.values()], where
                assert ("planner_action" in info) == (r == 3), where  # robot_3's planner drives it


def test_subgoal_sensor_reaches_every_agent_and_the_batched_reads(write_scenario):
    # `[sensors] subgoal` adds the key to every agent's observation and space; the batched read
    # (WorldSim.observations) gives what the per-robot read gives.
    path = write_scenario(TWO_ROBOTS + "\n[sensors]\nsubgoal = 1.0\n")
    env = proxemic.parallel_env(str(path))
    obs, _ = env.reset(seed=0)
    for _ in range(3):
        for agent, o in obs.items():
            assert env.observation_space(agent).contains(o), agent
            assert 0.5 < float(np.linalg.norm(o["subgoal"])) <= 1.0 * np.sqrt(2), (agent, o["subgoal"])
        batch = env.ws.observations(robots=True)
        for r, o in enumerate(batch):
            one = env.ws.observation(r, robots=True)
            assert list(o) == list(one)
            _assert_same(o, one, f"robot {r}")
        obs, *_ = env.step({a: np.zeros(3, np.float32) for a in env.agents})


def test_actions_in_any_key_order_give_the_same_episode():
    # step() takes the robot indices of actions given in the live agents' order as they are,
    # and looks them up otherwise: the same actions in another order drive the same robots.
    def episode(order: int) -> list:
        env = proxemic.parallel_env("museum_multi", robots=4)
        rng = np.random.default_rng(8)
        trace = [env.reset(seed=2)]
        for _ in range(15):
            acts = {a: rng.uniform(-1, 1, 3).astype(np.float32) for a in env.agents}
            trace.append(env.step(dict(list(acts.items())[::order])))
        return trace

    _assert_same(episode(1), episode(-1), "episode")


JOIN_ROOM = """
[scene]
name = "join"
bounds = [0, 0, 10, 10]

[[wall]]
from = [0, 0]
to = [10, 0]

[[person]]
behaviour = "standing"
pose = [3, {y}, 0]
group = 1

[[person]]
behaviour = "standing"
pose = [4, {y}, 3.14159]
group = 1

[[robot]]
start = [3.5, 5.0, -1.5708]
goal = [8.5, 5.0]
planner = "social"

[[robot]]
start = [3.5, 7.5, -1.5708]
goal = [8.5, 8.5]
planner = "social"
"""


def test_a_robot_in_a_conversation_is_a_person_to_the_other_robots():
    # robot_1 stands 2.5 m from robot_0 and over 3 m (the controller's people range) from both
    # people. With the conversation at y = 4, robot_0 is inside it (1.1 m from both, at rest):
    # robot_1's social planner handles robot_0 as a person (Social Momentum). With the
    # conversation moved away (y = 1), robot_0 is just a robot: robot_1 follows its path.
    modes = {}
    for y in (4, 1):
        env = proxemic.parallel_env(proxemic._core.Scenario.from_toml(JOIN_ROOM.format(y=y), "join.toml"))
        _, infos = env.reset(seed=0)
        joins = env.world.perception()["robot_joins"]
        modes[y] = (joins[0] is not None, infos["robot_1"]["planner_mode"])
    assert modes == {4: (True, "social_momentum"), 1: (False, "follow_path")}


def _intrusions(poses: list[np.ndarray], people: list[np.ndarray], robots: list[int], zone: float) -> int:
    """Steps where a robot came within `zone` of a person by its own motion (toward that person)."""
    count = 0
    for t in range(1, len(poses)):
        for i in robots:
            p0, p1 = poses[t - 1][i, :2], poses[t][i, :2]
            q = people[t][:, :2]
            d = np.linalg.norm(q - p1, axis=1)
            toward = (q - p0) @ (p1 - p0) > 1e-9
            count += int(np.sum((d < zone) & toward))
    return count


def _museum_multi_ignoring(tmp_path) -> str:
    """``museum_multi`` with every person's reaction to robots set to ``ignore`` (a file in `tmp_path`)."""
    envs = Path(proxemic.__file__).parent / "data" / "envs"
    text = (envs / "museum_multi.toml").read_text()
    text = text.replace('extends = "museum.toml"', f'extends = "{envs / "museum.toml"}"', 1)
    text = text.replace("[scene]\n", '[scene]\nreaction = "ignore"\n', 1)
    out = tmp_path / "museum_multi_ignore.toml"
    out.write_text(text)
    return str(out)


def _museum_run(planners: str | None, seed: int, steps: int = 400, scenario: str = "museum_multi"):
    env = proxemic.parallel_env(scenario, robots=4, autopilot=True, planners=planners)
    env.reset(seed=seed)
    poses, people = [env.ws.poses()], [env.people()]
    while env.agents and len(poses) < steps:
        env.step({})
        poses.append(env.ws.poses())
        people.append(env.people())
    return env, poses, people


def test_museum_robots_keep_out_of_intimate_zones_while_they_have_room(tmp_path):
    zone = None
    for seed in (0, 1):
        env, poses, people = _museum_run(None, seed)  # the scene's planner: social, for all four
        zone = env.scenario["proxemics"]["zones"][0]  # Hall's intimate zone radius (m)
        assert {r["planner"] for r in env.scenario["robots"]} == {"social"}
        assert _intrusions(poses, people, [0, 1, 2, 3], zone) == 0, seed
        team = env.episode_metrics()
        assert team["agent_collisions"] == 0 and team["person_collisions"] == 0
        # The robots made real progress (not a test that passes by standing still).
        assert min(np.linalg.norm(poses[-1][:, :2] - poses[0][:, :2], axis=1)) > 5.0
    # The same measure catches plain A* walking into people who do not make way for it (seed 1,
    # the people set to `ignore`: it does). People who see the robot step aside for plain A* too
    # (seed 1 with the default `aware`: no intrusion), so the control needs the invisible robot.
    _, poses, people = _museum_run("astar", 1, scenario=_museum_multi_ignoring(tmp_path))
    assert _intrusions(poses, people, [0, 1, 2, 3], zone) > 0


def test_bad_input_is_a_clear_error(write_scenario):
    # A robot count outside [1, 8] is one mistake, one class, whichever side it falls (counts past
    # the file's 4 robots get sampled extra robots, up to 8).
    for bad in (0, -2, 9):
        with pytest.raises(ScenarioError) as e:
            proxemic.parallel_env("daza2021_fig15", robots=bad)
        assert e.value.field == "robots" and "[1, 8]" in e.value.expected and e.value.found == str(bad)
    with pytest.raises(InputError, match="robots") as e:
        proxemic.parallel_env("daza2021_fig15", robots="two")
    assert e.value.field == "robots"
    overlapping = TWO_ROBOTS.replace("start = [8.5, 4.0, 3.14159]", "start = [1.8, 4.1, 3.14159]")
    with pytest.raises(ScenarioError) as e:
        proxemic.parallel_env(write_scenario(overlapping))
    assert e.value.field == "robot[1].start" and "overlapping" in str(e.value)
    assert str(e.value).startswith(str(e.value.file))
    # An unknown planner is a ScenarioError, as it is in the file, from the core's one check.
    with pytest.raises(ScenarioError) as e:
        proxemic.parallel_env("daza2021_fig15", planners={"robot_1": "teleport"})
    assert e.value.field == "robot[1].planner" and "teleport" in str(e.value)
    with pytest.raises(ScenarioError, match="teleport") as e:
        proxemic.parallel_env("daza2021_fig15", planners="teleport")
    assert e.value.field == "planner"
    with pytest.raises(ScenarioError) as e:
        proxemic.parallel_env(
            write_scenario(TWO_ROBOTS.replace("goal = [8.5, 4]", 'goal = [8.5, 4]\nplanner = "teleport"'))
        )
    assert e.value.field.startswith("robot[0].planner")
    with pytest.raises(InputError, match="robot_9"):
        proxemic.parallel_env("daza2021_fig15", planners={"robot_9": "astar"})
    env = proxemic.parallel_env("daza2021_fig15", robots=2)
    env.reset(seed=0)
    with pytest.raises(InputError) as e:
        env.step({"robot_0": [np.nan, 0, 0], "robot_1": [0, 0, 0]})
    assert e.value.field == "actions['robot_0']"
    with pytest.raises(InputError, match="robot_7"):
        env.step({"robot_0": [0, 0, 0], "robot_1": [0, 0, 0], "robot_7": [0, 0, 0]})
    with pytest.raises(InputError) as e:
        env.world.set_planning([True])
    assert e.value.field == "planning" and "2 flags" in e.value.expected


def test_example_with_a_standard_multi_agent_wrapper_runs():
    ns = runpy.run_path(str(ROOT / "examples" / "parallel_vec_env.py"), run_name="example")
    result = ns["main"](steps=30)
    assert result["num_envs"] == 4 * 2  # 4 robots x 2 copies of the env
    assert result["obs_shape"][0] == 8
    assert result["steps"] == 30


class _CountingWorld:
    """Counts every attribute of the core ``World`` used (each one is a call into Rust)."""

    def __init__(self, inner: object) -> None:
        self._inner = inner
        self.used: list[str] = []

    def __getattr__(self, name: str) -> object:
        self.used.append(name)
        return getattr(self._inner, name)


def test_one_rust_call_per_control_step_for_all_robots():
    """Policies act for some robots, planners drive the others: every control step is one call
    into the core (``World.step``), apart from the metrics of the robots whose episode ends."""
    env = proxemic.parallel_env("museum_multi", robots=6, autopilot={"robot_4", "robot_5"})
    _, infos = env.reset(seed=1)
    counting = _CountingWorld(env.ws.world)
    env.ws.world = env.world = counting  # type: ignore[assignment]
    before = counting._inner.calls  # type: ignore[attr-defined]
    steps = 0
    for _ in range(40):
        counting.used.clear()
        acts = {a: infos[a]["planner_action"] for a in env.agents if a not in env.autopilot}
        _, _, terms, truncs, infos = env.step(acts)
        steps += 1
        ended = sum(terms.values()) + sum(truncs.values())
        assert counting.used == (["step"] if not ended else ["step", "episode_metrics"]), counting.used
        if not env.agents:
            break
    assert counting._inner.calls - before == steps  # type: ignore[attr-defined]
    # The single-robot env too, with a policy and on autopilot.
    for autopilot in (False, True):
        single = ProxemicEnv("museum", autopilot=autopilot)
        single.reset(seed=0)
        counting = _CountingWorld(single.ws.world)
        single.ws.world = single.world = counting  # type: ignore[assignment]
        for _ in range(5):
            single.step(np.array([0.5, 0.0, 0.1], np.float32))
        assert counting.used == ["step"] * 5


def test_museum_guide_robot_leads_its_tour_group():
    """museum_multi's robot 1 leads four visitors: when it stands at its first stop (among the Old
    Masters) they have followed it from gallery A and gather around it, and they stay with it."""
    env = proxemic.parallel_env("museum_multi", robots=2, autopilot=True)
    _, infos = env.reset(seed=0)
    names = [p["name"] for p in env.scenario["persons"]]
    group = [names.index(f"robot_tour_visitor_{k}") for k in range(1, 5)]
    start = env.state()[1, :2].copy()
    first_stop = np.asarray(env.scenario["robots"][1]["waypoints"][0])
    gathered_at = None
    for step in range(900):
        _, _, _, _, infos = env.step({})
        r = env.state()[1, :2]
        people = env.people()[group, :2]
        dist = np.linalg.norm(people - r, axis=1)
        if step > 20:
            assert dist.max() < 8.0, (step, dist)  # they keep up with it
        at_stop = np.linalg.norm(r - first_stop) < 0.35
        if at_stop and infos.get("robot_1", {}).get("planner_mode") == "wait":
            gathered_at = gathered_at if gathered_at is not None else step
            if step - gathered_at >= 120:  # 12 s into the stop
                assert np.linalg.norm(r - start) > 10.0
                assert ((dist > 0.9) & (dist < 2.5)).all(), dist
                break
    else:
        raise AssertionError("robot 1 never stood 12 s at its first stop")
