"""The social map and the social planner: zones, groups, object spaces over the day, paths."""

from __future__ import annotations

import numpy as np
import pytest

from proxemic.env import ProxemicEnv
from proxemic.errors import InputError
from proxemic.social import SocialMap, parse_time_of_day

# A 14 x 8 m room: a conversation of three people stands on the straight line from the robot's
# start to its goal, with room to go around it; a TV with an agenda on the north wall.
ROOM = """
[scene]
name = "conversation_room"
bounds = [0, 0, 14, 8]
start_time = "10:00"

[[wall]]
from = [0, 0]
to = [14, 0]
[[wall]]
from = [14, 0]
to = [14, 8]
[[wall]]
from = [14, 8]
to = [0, 8]
[[wall]]
from = [0, 8]
to = [0, 0]

[[object]]
name = "tv"
kind = "tv"
pose = [7, 7.8, -1.5707963]
size = [0.1, 1.2]
interaction = { shape = "trapezoid", length = 2.0, near_width = 1.2, far_width = 2.4 }

[[person]]
behaviour = "standing"
pose = [6.6, 3.6, 0.785]
group = 1
[[person]]
behaviour = "standing"
pose = [7.4, 3.6, 2.356]
group = 1
[[person]]
behaviour = "standing"
pose = [7.0, 4.4, -1.5708]
group = 1

[[robot]]
start = [1.5, 4, 0]
goal = [12.5, 4]

[[activity]]
object = "tv"
start = "10:00"
end = "11:00"
"""


@pytest.fixture
def room(write_scenario):
    return write_scenario(ROOM, "room.toml")


def test_social_path_stays_out_of_intimate_zones_where_plain_astar_goes_through(room):
    sm = SocialMap(room)
    plain, social = sm.plan(social=False), sm.plan(social=True)
    assert plain is not None and social is not None
    plain_f = sm.factor_along(plain)
    social_f = sm.factor_along(social)
    assert np.isinf(plain_f).any(), "the plain path must cross the conversation"
    assert not np.isinf(social_f).any(), "the social path enters an intimate zone"
    assert (sm.factor_along(social, "combined") < 253).all(), "the social path enters a lethal cell"
    # it detours, but not absurdly
    length = lambda p: float(np.sum(np.linalg.norm(np.diff(p, axis=0), axis=1)))  # noqa: E731
    assert length(plain) < length(social) < 1.6 * length(plain)


def test_the_conversation_is_detected_as_one_group(room):
    sm = SocialMap(room)
    groups = [sorted(g) for g in sm.perception["groups"] if len(g) > 1]
    assert groups == [[0, 1, 2]]
    (ind,) = [i for i in sm.perception["individuals"] if len(i["members"]) == 3]
    assert np.allclose(ind["centre"], (7.0, 3.8667), atol=1e-3)
    assert sm.perception["truth"] == [1, 1, 1]
    assert sm.perception["accuracy"]["f1"] == 1.0


def test_object_space_follows_the_agenda(room):
    during = SocialMap(room, time_of_day="10:30").layers["objects"]
    long_before = SocialMap(room, time_of_day="08:00").layers["objects"]
    ramping = SocialMap(room, time_of_day="09:37:30").layers["objects"]  # halfway up the 45 min ramp
    assert np.isclose(during.max(), 3.5)
    assert np.isclose(long_before.max(), 1.5)
    assert np.isclose(ramping.max(), 2.5)
    assert (during > 1.0).sum() == (long_before > 1.0).sum() > 100


def test_layers_have_the_grid_shape_and_static_walls_stay_lethal(room):
    sm = SocialMap(room)
    layers = sm.layers
    shape = layers["static"].shape
    assert shape == layers["people"].shape == layers["objects"].shape == layers["combined"].shape
    assert shape == (80, 140)
    static = layers["static"] >= 253
    assert (layers["combined"][static] >= 253).all()


def test_social_planner_drives_an_episode_and_replans(room):
    env = ProxemicEnv(room, autopilot=True, planner="social_astar")
    env.reset(seed=0)
    min_d = np.inf
    while True:
        _, _, terminated, truncated, info = env.step(np.zeros(3, np.float32))
        people = env.people()
        min_d = min(min_d, float(np.linalg.norm(people[:, :2] - env.robot_pose()[:2], axis=1).min()))
        if terminated or truncated:
            break
    assert info["metrics"]["outcome"] == "success"
    assert min_d > 0.45  # never in anyone's intimate zone (centre distance)
    assert env.world.replans(0) == 0  # planned once, never re-planned: nobody moved into the path
    # ...though its refreshes searched again (and kept the path they found no better).
    searches = env.world.social_searches(0)
    assert searches > 1
    env.reset(seed=0)
    assert env.world.social_searches(0) < searches  # counted per episode
    env.close()


@pytest.mark.parametrize("seed", [0, 1, 2, 5, 9])
def test_social_enters_an_elevator_car_to_the_corner_beside_the_person_in_it(seed):
    """The goal (the car's free back corner) lies in the standing person's personal or intimate
    zone: only the cost beyond the goal's own counts, so ``social`` goes in rather than brake in
    the doorway (these tuning seeds timed out before), and it never brings itself into the
    person's intimate zone."""
    from proxemic import francis2023
    from proxemic.evaluation.episodes import run_task

    record = run_task((francis2023.scenario_name("entering_elevator", seed=seed), "social", seed)).record
    assert record["outcome"] == "success", record["outcome"]
    assert record["intimate_gap_entries_robot_caused"] == 0


def test_a_person_walking_into_the_path_triggers_a_replan(write_scenario):
    walker = "[[person]]\nroute = [[10.5, 1.2], [10.5, 6.8]]\nspeed = 0.8\naware = false\n\n[[robot]]"
    path = write_scenario(ROOM.replace("[[robot]]", walker, 1), "walker.toml")
    env = ProxemicEnv(path, autopilot=True, planner="social_astar")
    env.reset(seed=1)
    while True:
        _, _, terminated, truncated, _ = env.step(np.zeros(3, np.float32))
        if terminated or truncated:
            break
    assert env.world.replans(0) >= 1
    assert env.world.social_searches(0) >= env.world.replans(0)
    env.close()


def test_plot_writes_a_picture(room, tmp_path):
    sm = SocialMap(room)
    out = sm.plot(tmp_path / "map.png", paths={"plain A*": sm.plan(social=False), "social A*": sm.plan()})
    assert out.stat().st_size > 20_000


@pytest.mark.parametrize("bad", ["25:00", "10h30", "10:61", -5.0, 90000])
def test_bad_time_of_day(bad):
    with pytest.raises(InputError):
        parse_time_of_day(bad)
    assert parse_time_of_day("10:30") == 37800.0


@pytest.mark.parametrize("planner", ["social", "astar_orca", "astar_stop", "social_momentum", "eband"])
def test_every_named_planner_drives_the_env_and_reports_its_mode(room, planner):
    env = ProxemicEnv(room, autopilot=True, planner=planner)
    env.reset(seed=0)
    modes = set()
    min_d = np.inf
    while True:
        _, _, terminated, truncated, info = env.step(np.zeros(3, np.float32))
        modes.add(info["planner_mode"])
        people = env.people()
        min_d = min(min_d, float(np.linalg.norm(people[:, :2] - env.robot_pose()[:2], axis=1).min()))
        if terminated or truncated:
            break
    # plain ORCA on the plain A* path may stall in front of the conversation (a local minimum:
    # the ablation shows why the social global path matters), and so may the stop-and-wait
    # baseline when no way round is free; neither may collide
    expected = {"timeout", "success"} if planner in ("astar_orca", "astar_stop") else {"success"}
    assert info["metrics"]["outcome"] in expected, planner
    assert modes <= {"follow_path", "orca", "social_momentum", "wait"}
    if planner in ("social", "social_momentum"):
        assert "social_momentum" in modes
        assert min_d >= 0.45
    env.close()
