"""Bad input gets a typed exception that names the file, the field, expected and found."""

from __future__ import annotations

import numpy as np
import pytest

import proxemic
from proxemic import _core, scenarios
from proxemic.env import ProxemicEnv
from proxemic.errors import InputError, PlanningError, ProxemicError, ScenarioError, UnknownNameError


def _scenario_error(text, write_scenario) -> ScenarioError:
    path = write_scenario(text)
    with pytest.raises(ScenarioError) as info:
        ProxemicEnv(str(path))
    err = info.value
    assert err.file == str(path)
    assert str(path) in str(err)
    return err


def test_hierarchy():
    assert issubclass(ScenarioError, ProxemicError) and issubclass(ScenarioError, ValueError)
    assert issubclass(InputError, ProxemicError) and issubclass(InputError, ValueError)
    assert issubclass(PlanningError, ProxemicError)
    assert proxemic.ProxemicError is ProxemicError


def test_malformed_toml(write_scenario, small_room):
    err = _scenario_error(small_room.replace("[scene]", "[scene"), write_scenario)
    assert "line" in err.field and err.expected == "valid TOML"


def test_unknown_field(write_scenario, small_room):
    err = _scenario_error(small_room.replace("speed = 1.0", "speed = 1.0\nspeeed = 2"), write_scenario)
    assert err.field.startswith("person[0]")
    assert "speeed" in err.found and "speed" in err.expected


def test_missing_field(write_scenario, small_room):
    err = _scenario_error(small_room.replace("goal = [8.5, 4]", ""), write_scenario)
    assert err.field.startswith("robot[0]") and "goal" in err.expected


def test_nan_value(write_scenario, small_room):
    err = _scenario_error(small_room.replace("speed = 1.0", "speed = nan"), write_scenario)
    assert err.field == "person[0].speed" and err.found == "NaN"


def test_robot_inside_a_wall(write_scenario, small_room):
    err = _scenario_error(small_room.replace("start = [1.5, 4, 0]", "start = [0.05, 4, 0]"), write_scenario)
    assert err.field == "robot[0].start" and "inside a wall" in err.found


def test_goal_inside_furniture(write_scenario, small_room):
    err = _scenario_error(small_room.replace("goal = [8.5, 4]", "goal = [5, 6]"), write_scenario)
    assert err.field == "robot[0].goal" and "inside" in err.found


def test_goal_too_close_to_a_wall(write_scenario, small_room):
    err = _scenario_error(small_room.replace("goal = [8.5, 4]", "goal = [9.8, 4]"), write_scenario)
    assert err.field == "robot[0].goal" and "from a wall" in err.found


def test_unreachable_goal(write_scenario, small_room):
    # a wall across the room cuts the goal off
    text = small_room.replace("[[2, 2], [8, 2]]", "[[2, 2], [4, 2]]") + "\n[[wall]]\nfrom = [6, 0]\nto = [6, 8]\n"
    path = write_scenario(text)
    with pytest.raises(PlanningError) as info:
        ProxemicEnv(str(path))
    assert info.value.field == "robot[0].goal" and "no collision-free path" in str(info.value)


def test_person_route_through_a_wall(write_scenario, small_room):
    text = small_room + "\n[[wall]]\nfrom = [5, 0]\nto = [5, 3]\n"
    err = _scenario_error(text, write_scenario)
    assert err.field == "person[0].route[0]" and "through static geometry" in err.found


def test_unknown_scenario_name():
    with pytest.raises(UnknownNameError) as info:
        ProxemicEnv("no_such_museum")
    assert "museum" in str(info.value)


@pytest.mark.parametrize("bad", [[np.nan, 0.0, 0.0], [0.0, np.inf, 0.0], [np.nan, np.nan, np.nan]])
def test_non_finite_action(bad):
    env = ProxemicEnv("museum")
    env.reset(seed=0)
    with pytest.raises(InputError) as info:
        env.step(np.array(bad, dtype=np.float32))
    assert info.value.field == "action"
    env.close()


def test_core_checks_buffer_sizes_and_state():
    scenario, _ = proxemic.scenarios.load("museum")
    world = _core.World(scenario)
    out = np.zeros(world.stride * world.num_robots)
    people = np.zeros(world.num_people * _core.PERSON_OUT)
    state, contacts = np.zeros(6), np.zeros(1, np.uint8)
    nan = np.full(3, np.nan)
    calls = []

    def physics() -> None:
        calls.append(1)

    with pytest.raises(InputError) as info:
        world.reset(0, np.zeros(3), people)
    assert info.value.field == "out"
    with pytest.raises(InputError) as info:
        world.reset(0, out, np.zeros(world.num_people * 3))
    assert info.value.field == "people_out"
    with pytest.raises(InputError):
        world.step(nan, physics, state, contacts, out, people)  # before reset
    world.reset(0, out, people)
    # Bad actions are refused before the physics runs.
    with pytest.raises(InputError) as info:
        world.step(np.array([0.0, np.nan, 1.0]), physics, state, contacts, out, people)
    assert info.value.field == "action[0]"
    with pytest.raises(InputError) as info:
        world.step(np.zeros(6), physics, state, contacts, out, people)
    assert info.value.field == "actions"
    assert not calls
    state[2] = np.nan
    with pytest.raises(InputError) as info:
        world.step(nan, physics, state, contacts, out, people)
    assert info.value.field == "state[0][2]"
    assert calls == [1]

    # An exception raised by the physics reaches the caller unchanged.
    def broken() -> None:
        raise RuntimeError("physics exploded")

    state[2] = 0.0
    with pytest.raises(RuntimeError, match="physics exploded"):
        world.step(nan, broken, state, contacts, out, people)


def test_bad_render_mode():
    with pytest.raises(InputError):
        ProxemicEnv("museum", render_mode="holographic")


def test_bad_people_name_the_field(write_scenario, small_room):
    """The people's bad input of the living scenes: a route through a wall, a group of one, an
    activity on a missing object, a person inside furniture."""
    walled = small_room.replace("[[object]]", "[[wall]]\nfrom = [5, 0]\nto = [5, 3]\n\n[[object]]", 1)
    err = _scenario_error(walled.replace("route = [[2, 2], [8, 2]]", "route = [[2, 1], [8, 1]]"), write_scenario)
    assert err.field == "person[0].route[0]" and "through static geometry" in err.found
    err = _scenario_error(small_room.replace("speed = 1.0", "speed = 1.0\ngroup = 3"), write_scenario)
    assert err.field == "person[0].group" and err.found == "group 3 with 1 member"
    activity = '[[activity]]\nobject = "stretcher"\nstart = "09:00"\nend = "10:00"\n\n[[robot]]'
    err = _scenario_error(small_room.replace("[[robot]]", activity), write_scenario)
    assert err.field == "activity[0].object" and err.found == '"stretcher"'
    inside = small_room.replace("route = [[2, 2], [8, 2]]", 'behaviour = "standing"\npose = [5, 6, 0]')
    err = _scenario_error(inside, write_scenario)
    assert err.field == "person[0].pose" and "furniture" in err.expected


def test_a_follower_of_an_unknown_robot_names_the_field(write_scenario, small_room):
    """`guide = "robot:<name>"` must name a [[robot]] of the file (error: file, field, the robots'
    names expected, the name given)."""
    follower = 'behaviour = "follower"\nguide = "robot:pepper"\ngroup = 4'
    text = small_room.replace("route = [[2, 2], [8, 2]]\nspeed = 1.0", follower)
    text += '\n[[person]]\nname = "second"\nbehaviour = "follower"\nguide = "robot:pepper"\ngroup = 4\n'
    err = _scenario_error(text, write_scenario)
    assert err.field == "person[0].guide"
    assert err.found == '"robot:pepper"'
    assert "robot:<name>" in err.expected and "robot_0" in err.expected
    assert err.file.endswith(".toml")
    # Naming the robot works (it is called robot_0 when the file gives no name).
    ok = text.replace("robot:pepper", "robot:robot_0").replace("[[robot]]", "[[robot]]\nwaypoints = [[5, 4]]")
    path = write_scenario(ok)
    _, desc = proxemic.scenarios.load(path)
    assert desc["persons"][0]["guide_robot"] == 0 and len(desc["persons"][0]["tour"]) == 3


def test_every_robot_index_is_checked_once_with_one_error():
    core, _ = scenarios.load("museum")
    world = _core.World(core)
    out = np.zeros(world.num_robots * world.stride)
    people = np.zeros(world.num_people * _core.PERSON_OUT)
    world.reset(0, out, people)
    bad = world.num_robots
    calls = {
        "plan": lambda: world.plan(bad, (1.0, 1.0), (2.0, 2.0)),
        "plan(social)": lambda: world.plan(bad, (1.0, 1.0), (2.0, 2.0), social=True),
        "social_layers": lambda: world.social_layers(bad),
        "cost_grid": lambda: world.cost_grid(bad),
        "geodesic_start_distance": lambda: world.geodesic_start_distance(bad),
        "path": lambda: world.path(bad),
        "astar_path": lambda: world.astar_path(bad),
        "trajectory": lambda: world.trajectory(bad),
        "replans": lambda: world.replans(bad),
        "social_searches": lambda: world.social_searches(bad),
    }
    for name, call in calls.items():
        with pytest.raises(InputError) as e:
            call()
        assert e.value.field == "robot" and e.value.found == str(bad), name
        assert e.value.expected == f"a robot index below {world.num_robots}", name
    assert world.trajectory(0).shape == (1, 3)  # the start, before any step


def test_start_time_and_time_of_day_through_the_core():
    core, _ = scenarios.load("calderita_exp1")
    assert core.with_start_time("09:05").to_json() == core.with_start_time(9 * 3600 + 5 * 60).to_json()
    assert proxemic.parse_time_of_day("09:05:30") == 9 * 3600 + 5 * 60 + 30
    for bad in ("24:00", "9h05", -1.0, 86400):
        with pytest.raises(InputError) as e:
            core.with_start_time(bad)
        assert e.value.field == "time_of_day"
        with pytest.raises(InputError):
            proxemic.parse_time_of_day(bad)


def test_public_names_of_the_docs_are_exported():
    from proxemic.env import ProxemicEnv as Env
    from proxemic.errors import EpisodeError

    assert proxemic.Scenario is _core.Scenario and proxemic.PLANNERS == _core.PLANNERS
    assert proxemic.ProxemicEnv is Env and proxemic.EpisodeError is EpisodeError
    assert set(proxemic.__all__) <= set(dir(proxemic)) | {"ProxemicEnv", "ProxemicParallelEnv"}
    for name in proxemic.__all__:
        assert getattr(proxemic, name) is not None, name
