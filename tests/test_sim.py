"""MuJoCo scene: the model built from the scenario, the velocity servos, contact events."""

from __future__ import annotations

from collections import Counter
from pathlib import Path
from typing import Any

import mujoco
import numpy as np
import pytest

from proxemic import _core, scenarios
from proxemic.sim import Simulation


def _sim(text: str) -> Simulation:
    import json

    core = _core.Scenario.from_toml(text, "test.toml")
    return Simulation(json.loads(core.to_json()))


def test_model_has_one_robot_and_a_mocap_body_per_person():
    _, desc = scenarios.load("museum")
    sim = Simulation(desc)
    assert sim.model.nu == 3
    assert sim.model.nmocap == len(desc["persons"])
    assert sim.frame_skip == 10
    assert abs(sim.model.opt.timestep - 0.01) < 1e-12


def test_body_frame_velocity_servo_tracks_commands(small_room):
    sim = _sim(small_room)
    sim.reset(np.array([[3.0, 4.0, np.pi / 2]]), np.array([[2.0, 2.0, 0.0]]))
    # forward in the body frame while facing +y: the robot moves along +y
    for _ in range(10):
        sim.step(np.array([0.4, 0.0, 0.0]))
    sim.read()
    x, y, _th, vx, vy, _wz = sim.state
    assert abs(x - 3.0) < 0.02 and y > 4.3
    assert abs(vy - 0.4) < 0.02 and abs(vx) < 0.02


def test_a_robot_faster_and_wider_than_pepper_gets_its_own_servo_ranges_and_footprint(small_room):
    """pepper.xml's servos are Pepper's (0.55 m/s per axis, 2 rad/s): a robot with other limits gets
    its own, so the physics executes what the core allowed, and its footprint is its radius."""
    import json

    from proxemic.sim.model import build_spec

    limits = "\nmax_speed = 1.0\nmax_angular_speed = 3.0\nradius = 0.3"
    fast = small_room.replace("goal = [8.5, 4]", "goal = [8.5, 4]" + limits)
    desc = json.loads(_core.Scenario.from_toml(fast, "test.toml").to_json())
    for visual in (False, True):
        model = build_spec(desc, visual=visual).compile()
        ranges = {model.actuator(k).name: tuple(model.actuator_ctrlrange[k]) for k in range(model.nu)}
        assert ranges == {"robot_0/vx": (-1.0, 1.0), "robot_0/vy": (-1.0, 1.0), "robot_0/wz": (-3.0, 3.0)}
        assert model.geom("robot_0/base").size[0] == 0.3
    sim = _sim(fast)
    sim.reset(np.array([[3.0, 4.0, 0.0]]), np.array([[2.0, 2.0, 0.0]]))
    for _ in range(10):
        sim.step(np.array([0.9, 0.0, 2.5]))
    sim.read()
    *_, vx, vy, wz = sim.state
    assert abs(np.hypot(vx, vy) - 0.9) < 0.03 and abs(wz - 2.5) < 0.1, sim.state
    # Pepper's own robot keeps Pepper's servos.
    pepper = _sim(small_room).model
    assert tuple(pepper.actuator_ctrlrange[0]) == (-0.55, 0.55) and pepper.geom("robot_0/base").size[0] == 0.24


def test_wall_contact_is_reported_as_static(small_room):
    sim = _sim(small_room)
    sim.reset(np.array([[9.3, 4.0, 0.0]]), np.array([[2.0, 2.0, 0.0]]))
    flags = 0
    for _ in range(20):
        sim.step(np.array([0.55, 0.0, 0.0]))
        sim.read()
        flags |= int(sim.contacts[0])
    assert flags & _core.CONTACT_STATIC
    assert not flags & _core.CONTACT_PERSON
    assert sim.state[0] < 10.0 - 0.1 - 0.23  # stopped by the wall


def test_person_contact_is_reported(small_room):
    sim = _sim(small_room)
    sim.reset(np.array([[5.0, 4.0, 0.0]]), np.array([[5.3, 4.0, 0.0]]))
    sim.step(np.zeros(3))
    sim.read()
    assert sim.contacts[0] & _core.CONTACT_PERSON


def test_people_face_their_heading(small_room):
    sim = _sim(small_room)
    sim.reset(np.array([[1.5, 4.0, 0.0]]), np.array([[4.0, 2.0, np.pi / 2]]))
    sim.sync_render()
    nose = sim.render_data.geom_xpos[sim.render_model.geom("person_0/nose").id]
    assert nose[1] > 2.05 and abs(nose[0] - 4.0) < 1e-6


def test_every_object_kind_has_a_model_and_keeps_its_collision_footprint():
    from proxemic.furniture import COLLISION_GROUP

    kinds = set()
    for name in ("museum", "care_center"):
        _, desc = scenarios.load(name)
        m = Simulation(desc).render_model
        for o in desc["objects"]:
            kinds.add(o["kind"])
            g = m.geom(f"object/{o['name']}")
            # the collision geom is the footprint the core plans with, hidden from the cameras
            assert g.group[0] == COLLISION_GROUP
            assert g.contype[0] == (1 if o["solid"] else 0)
            assert abs(g.size[2 if o["radius"] is None else 1] * 2.0 - o["height"]) < 1e-9
            parts = [k for k in range(m.ngeom) if m.geom(k).name.startswith(f"object/{o['name']}/")]
            assert parts, f"{o['kind']} {o['name']} has no visual model"
            assert all(m.geom_contype[k] == 0 and m.geom_conaffinity[k] == 0 for k in parts)
            # every part stays within the object's height (a bed's pillow may sit 7 cm on top)
            half = {int(mujoco.mjtGeom.mjGEOM_BOX): 2, int(mujoco.mjtGeom.mjGEOM_CYLINDER): 1}
            top = max(m.geom_pos[k][2] + m.geom_size[k][half.get(int(m.geom_type[k]), 0)] for k in parts)
            assert top <= o["height"] + 0.07 + 1e-9, (o["kind"], top)
    assert {"painting", "table", "round_table", "tv", "stretcher", "bench", "exhibit"} <= kinds


def test_robots_are_colour_coded_like_the_top_down_view():
    from proxemic.palette import ROBOT_PALETTE

    _, desc = scenarios.load("daza2021_fig15")
    m = Simulation(desc).render_model
    assert len(desc["robots"]) == 4
    for i in range(4):
        rgba = m.geom(f"robot_{i}/shell").rgba
        np.testing.assert_allclose(rgba[:3] * 255.0, ROBOT_PALETTE[i], atol=1e-6)
    colours = {tuple(m.geom(f"robot_{i}/shell").rgba) for i in range(4)}
    assert len(colours) == 4


def test_physics_model_is_the_render_model_without_what_cannot_collide():
    _, desc = scenarios.load("museum_multi")
    sim = Simulation(desc)
    m, rm = sim.model, sim.render_model
    # Only colliding geoms (static, robots' base and torso, people's bodies), no cameras or lights.
    assert m.ncam == 0 and m.nlight == 0
    assert all(m.geom_contype[g] or m.geom_conaffinity[g] for g in range(m.ngeom))
    assert m.ngeom == len(desc["walls"]) + sum(o["solid"] for o in desc["objects"]) + 2 * len(desc["robots"]) + len(
        desc["persons"]
    )
    assert rm.ngeom > 2 * m.ngeom
    # The same bodies with the same masses and inertia (the visual parts are massless).
    for i in range(len(desc["robots"])):
        b, rb = m.body(f"robot_{i}/base"), rm.body(f"robot_{i}/base")
        assert b.mass[0] == rb.mass[0] == 28.0
        assert np.array_equal(b.inertia, rb.inertia) and np.array_equal(b.ipos, rb.ipos)
    assert (m.nq, m.nv, m.nu, m.nmocap) == (rm.nq, rm.nv, rm.nu, rm.nmocap)


def test_physics_and_render_models_step_bit_for_bit_alike(small_room):
    """A robot pushed by a person into a wall: contacts with both, the same trajectory in the
    physics model (contact hints on) and in the full visual model."""
    sim = _sim(small_room)
    rm, rd = sim.render_model, sim.render_data
    robot = np.array([[9.0, 4.0, 0.0]])
    person = np.array([[8.4, 4.0, 0.0, 1.0]])
    sim.reset(robot, person)
    mujoco.mj_resetData(rm, rd)
    rd.qpos[:] = sim.data.qpos
    rd.mocap_pos[:] = sim.data.mocap_pos
    rd.mocap_quat[:] = sim.data.mocap_quat
    flags = 0
    for k in range(25):
        person[0, 0] += 0.06  # the person walks into the robot
        sim.write_people(person)
        rd.mocap_pos[:] = sim.data.mocap_pos
        rd.mocap_quat[:] = sim.data.mocap_quat
        cmd = np.array([0.5, 0.05, 0.2 * (k % 3 - 1)])
        sim.step(cmd)
        flags |= int(sim.contacts[0])
        rd.ctrl[:] = cmd
        for _ in range(sim.frame_skip):
            mujoco.mj_step(rm, rd)
        assert np.array_equal(sim.data.qpos, rd.qpos) and np.array_equal(sim.data.qvel, rd.qvel), k
    assert flags & _core.CONTACT_STATIC and flags & _core.CONTACT_PERSON


@pytest.mark.parametrize("robots", [11, 2])
def test_contact_hints_change_nothing_but_the_cost(robots: int):
    """Robots driven blindly into walls, people and each other: the episode with the core's
    contact hints equals the one with every pair tested, bit for bit; and the hints do leave out
    far pairs, and (with two robots) whole control periods, stepped with the collision detection
    off."""
    import proxemic

    quiet = [0]

    def run(hints: bool) -> tuple[list[np.ndarray], int]:
        env = proxemic.parallel_env("museum_multi", robots=robots, planners="astar")
        sim = env.ws.sim
        skipped = 0
        real, real_step = sim.set_hints, sim.step
        if not hints:  # every pair tested, contacts read after every physics step
            sim.set_hints = lambda s, p: real(np.ones_like(s), np.ones_like(p))  # type: ignore[method-assign]
            sim.step = lambda command, possible=True: real_step(command, True)  # type: ignore[method-assign]
        else:
            ws = env.ws

            def counted(command: np.ndarray, possible: bool = True) -> None:
                quiet[0] += int(not possible)
                # the core's contacts_possible flag: any hint set, in every row
                hinted = (
                    any(ws.sections[k].any() for k in ("near_static", "near_robot"))
                    or ws.people[3 :: _core.PERSON_OUT].any()
                )
                assert (ws.sections["contacts_possible"] == float(possible)).all() and possible == hinted
                real_step(command, possible)

            sim.step = counted  # type: ignore[method-assign]
        rng = np.random.default_rng(3)
        env.reset(seed=5)
        states = []
        for _ in range(400):
            if not env.agents:
                break
            # full speed ahead, turning a little: into walls, people and each other
            env.step({a: np.array([1.0, 0.0, rng.uniform(-0.3, 0.3)]) for a in env.agents})
            states.append(sim.data.qpos.copy())
            skipped += int((sim.model.body_contype == 0).sum())  # people out of the broadphase
        return states, skipped

    on, skipped = run(True)
    off, none = run(False)
    assert len(on) == len(off) > 20
    assert all(np.array_equal(a, b) for a, b in zip(on, off, strict=True))
    assert none == 0 and skipped > 0
    assert len(on) < 400  # every robot collided before the step limit
    if robots == 2:
        assert quiet[0] > 0


def test_steps_without_the_bindings_default_timer_and_leaves_a_users_timer(small_room):
    from proxemic.sim import timer as sim_module

    if sim_module._TIMER is None or sim_module._DEFAULT_TIMER is None:
        pytest.skip("this MuJoCo's bindings install no default timer")
    sim = _sim(small_room)
    sim.reset(np.array([[3.0, 4.0, 0.0]]), np.array([[2.0, 2.0, 0.0]]))
    # the default timer: off while stepping (MjData.timer gets no time), back on afterwards
    for possible in (True, False):
        sim.step(np.array([0.4, 0.0, 0.2]), possible)
        assert sim_module._TIMER.value == sim_module._DEFAULT_TIMER
    assert sim.data.timer[mujoco.mjtTimer.mjTIMER_STEP].number == sim.frame_skip  # the contact step
    assert sim.data.timer[mujoco.mjtTimer.mjTIMER_STEP].duration == 0.0
    d = mujoco.MjData(sim.model)
    mujoco.mj_step(sim.model, d)
    assert d.timer[mujoco.mjtTimer.mjTIMER_STEP].duration > 0.0
    # a timer the user set keeps running
    ticks: list[int] = []

    def clock() -> float:
        ticks.append(0)
        return float(len(ticks))

    mujoco.set_mjcb_time(clock)
    try:
        sim.step(np.array([0.4, 0.0, 0.2]))
        assert ticks
    finally:
        mujoco.set_mjcb_time(None)
        sim_module._TIMER.value = sim_module._DEFAULT_TIMER


@pytest.mark.parametrize("driver", ["random", "astar"])
def test_periods_without_people_in_reach_on_the_robots_only_model_end_in_the_same_states(driver: str):
    """A policy driving at random, and the plain A* autopilot, in the museum: the env stepping its
    control periods without a person in reach (contacts off, or only walls, objects and robots in
    reach) on the physics model without the people equals the one stepping every period on the
    physics model, bit for bit; every kind of period occurs."""
    from proxemic.env import ProxemicEnv

    def run(robots_only: bool) -> tuple[list[np.ndarray], list[tuple[bool, bool]], int]:
        env = ProxemicEnv("museum", planner_actions=False, autopilot=driver == "astar")
        sim = env.sim
        assert sim.contact_free_model.ngeom < sim.robots_model.ngeom < sim.model.ngeom
        if not robots_only:
            sim._robots_only = sim._free = None
        kinds: list[tuple[bool, bool]] = []
        touched = [0]
        real = sim.step

        def step(command: np.ndarray, possible: bool = True) -> None:
            # contacts on; a person in reach (the hints are set only for periods with contacts on)
            kinds.append((possible, possible and any(sim._hints[1] or [])))
            real(command, possible)
            touched[0] += int(sim.contacts.any())
            if robots_only and not kinds[-1][1]:  # Simulation.stepped names the reduced model used
                assert sim.stepped[0] is (sim.robots_model if possible else sim.contact_free_model)

        sim.step = step  # type: ignore[method-assign]
        rng = np.random.default_rng(8)
        env.reset(seed=3)
        states = []
        for _ in range(900):
            obs, _, terminated, truncated, _ = env.step(rng.uniform(-1.0, 1.0, 3).astype(np.float32))
            states.append(np.concatenate([sim.data.qpos, sim.data.qvel, obs["lidar"], sim.contacts]))
            if terminated or truncated:
                env.reset()
        return states, kinds, touched[0]

    fast, kinds, touched = run(True)
    plain, plain_kinds, plain_touched = run(False)
    assert kinds == plain_kinds and touched == plain_touched
    assert all(np.array_equal(a, b) for a, b in zip(fast, plain, strict=True))
    assert kinds.count((False, False)) > 30 and kinds.count((True, False)) > 30
    if driver == "random":
        assert touched > 0  # into walls and objects
    else:
        assert kinds.count((True, True)) > 30


def _drive_at_people(env: Any, sim: Any, rng_seed: int, reset_seed: int, steps: int) -> list[np.ndarray]:
    """Every robot of a parallel env driven at its nearest person for `steps` steps; the physics state after each."""
    rng = np.random.default_rng(rng_seed)
    env.reset(seed=reset_seed)
    states = []
    for _ in range(steps):
        if not env.agents:
            env.reset()
        obs = env.ws.observations(robots=True)
        actions = {}
        for a in env.agents:
            o = obs[int(a.split("_")[1])]
            x, y = o["people"][0][:2] if o["people_mask"][0] else (1.0, 0.0)
            scale = max(1.0, abs(float(x)), abs(float(y)))
            actions[a] = np.array([x / scale, y / scale, rng.uniform(-0.3, 0.3)], np.float32)
        env.step(actions)
        states.append(np.concatenate([sim.data.qpos, sim.data.qvel, sim.contacts]))
    return states


def test_periods_with_a_few_people_in_reach_on_the_crowd_models_end_in_the_same_states(tmp_path):
    """Eleven robots driving at the nearest person they see in the museum (whose people do not make
    way for robots, so that up to 16 are in reach at once): the env stepping its
    control periods with a few people in reach on the crowd models (stand-ins for those people
    only) equals the one stepping them on the physics model, bit for bit, with the same contacts;
    every crowd model is used, people are touched in those periods, and the people in reach
    change while a crowd model keeps its size (its stand-ins reassigned)."""
    import proxemic

    def run(crowds: bool) -> tuple[list[np.ndarray], Counter[int], int, int]:
        env = proxemic.parallel_env(scene, robots=11, planner_actions=False)
        sim = env.ws.sim
        assert sorted(sim._crowds) == [1, 2, 4, 8, 16] and sim._crowd_max == 16
        assert all(c.model.nbody == sim.robots_model.nbody + k for k, c in sim._crowds.items())
        if not crowds:
            sim._crowd_max = 0
        sizes: Counter[int] = Counter()
        touched, reassigned = [0], [0]
        real = sim.step

        def step(command: np.ndarray, possible: bool = True) -> None:
            near = sim._near
            on_crowd = possible and 0 < len(near) <= 16
            if on_crowd:
                size = 1 << (len(near) - 1).bit_length()
                sizes[size] += 1
                reassigned[0] += int(sim._crowds[size].near not in ((), near))
            real(command, possible)
            touched[0] += int(on_crowd and bool((sim.contacts & _core.CONTACT_PERSON).any()))

        sim.step = step  # type: ignore[method-assign]
        states = _drive_at_people(env, sim, rng_seed=3, reset_seed=5, steps=400)
        return states, sizes, touched[0], reassigned[0]

    envs = Path(proxemic.__file__).parent / "data" / "envs"
    text = (envs / "museum_multi.toml").read_text()
    text = text.replace('extends = "museum.toml"', f'extends = "{envs / "museum.toml"}"', 1)
    text = text.replace("[scene]\n", '[scene]\nreaction = "ignore"\n', 1)
    scene = str(tmp_path / "museum_multi_ignore.toml")
    Path(scene).write_text(text)
    fast, sizes, touched, reassigned = run(True)
    plain, _, plain_touched, _ = run(False)
    assert all(np.array_equal(a, b) for a, b in zip(fast, plain, strict=True))
    assert touched == plain_touched > 10
    assert set(sizes) == {1, 2, 4, 8, 16} and reassigned > 10


def test_a_period_stepped_in_one_call_reads_the_contacts_of_every_physics_step():
    """Eleven robots driving blindly into walls, people and each other: every control period the
    simulation steps (in one call, again a physics step at a time when a step found a contact)
    ends in the same state with the same contact bits as plain stepping, one physics step at a
    time on the physics model reading each step's contacts; and periods occur whose contacts
    were found only in physics steps before their last."""
    import proxemic

    env = proxemic.parallel_env("museum_multi", robots=11, planner_actions=False)
    sim = env.ws.sim
    m = sim.model
    ref = mujoco.MjData(m)
    real = sim.step
    owner, bit = sim._owner_list, sim._bit_list
    periods, early_only = [0], [0]

    def step(command: np.ndarray, possible: bool = True) -> None:
        # the reference: the physics model from the same state, the same contact bits set
        for name in ("qpos", "qvel", "act", "ctrl", "qacc_warmstart", "mocap_pos", "mocap_quat"):
            getattr(ref, name)[:] = getattr(sim.data, name)
        ref.time = sim.data.time
        sim._ctrl[...] = command
        ref.ctrl[:] = sim.data.ctrl
        acc = [0] * sim.num_robots
        last = 0
        for _ in range(sim.frame_skip):
            mujoco.mj_step(m, ref)
            last = ref.ncon
            for g1, g2 in ref.contact.geom[: ref.ncon].tolist():
                if owner[g1] >= 0:
                    acc[owner[g1]] |= bit[g2]
                if owner[g2] >= 0:
                    acc[owner[g2]] |= bit[g1]
        real(command, possible)
        assert sim.contacts.tolist() == acc
        assert np.array_equal(sim.data.qpos, ref.qpos) and np.array_equal(sim.data.qvel, ref.qvel)
        periods[0] += 1
        early_only[0] += int(any(acc) and last == 0)

    sim.step = step  # type: ignore[method-assign]
    rng = np.random.default_rng(4)
    env.reset(seed=2)
    for _ in range(300):
        if not env.agents:
            env.reset()
        env.step({a: np.array([1.0, rng.uniform(-0.5, 0.5), rng.uniform(-0.3, 0.3)]) for a in env.agents})
    assert periods[0] == 300 and early_only[0] > 0


@pytest.mark.parametrize("standins_only", [False, True])
def test_a_crowd_beyond_the_default_arena_builds_and_steps(tmp_path, monkeypatch, standins_only: bool):
    # 2500 people: MuJoCo's collision pass needs about 4 bytes per pair of bodies, 25 MB, more than
    # its default 16 MB arena (a bare mujoco.FatalError before the arena was sized from the scene);
    # in the physics model (a limit above them) and left out of it (the default).
    from proxemic.env import ProxemicEnv
    from proxemic.sim import simulation

    if not standins_only:
        monkeypatch.setattr(simulation, "FULL_MODEL_PEOPLE", 10**6)

    people = "".join(
        f'[[person]]\nbehaviour = "standing"\npose = [{2 + (k % 50) * 1.2:.1f}, {2 + (k // 50) * 1.2:.1f}, 0]\n'
        for k in range(2500)
    )
    text = f'[scene]\nname = "big"\nbounds = [0, -3, 64, 64]\n[[robot]]\nstart = [1, -2, 0]\ngoal = [60, -2]\n{people}'
    path = tmp_path / "big.toml"
    path.write_text(text)
    env = ProxemicEnv(path, autopilot=True, planner="astar")
    try:
        assert env.sim.standins_only == standins_only
        assert env.sim.model.nmocap == (0 if standins_only else 2500)
        env.reset(seed=0)
        for _ in range(3):
            env.step(np.zeros(3))
    finally:
        env.close()


def test_a_crowd_left_out_of_the_physics_model_steps_like_the_physics_model_with_it(tmp_path, monkeypatch):
    """Eleven robots driving at the nearest person they see in the museum (people not making way):
    with the people left out of the physics model (every period with people in reach on a crowd
    model of stand-ins, the larger ones compiled when first needed) the states and contacts equal
    the physics model's with every person in it, bit for bit, with people touched and more people
    in reach at once than the crowd models compiled up front."""
    import proxemic
    from proxemic.sim import simulation

    envs = Path(proxemic.__file__).parent / "data" / "envs"
    text = (envs / "museum_multi.toml").read_text()
    text = text.replace('extends = "museum.toml"', f'extends = "{envs / "museum.toml"}"', 1)
    text = text.replace("[scene]\n", '[scene]\nreaction = "ignore"\n', 1)
    scene = str(tmp_path / "museum_multi_ignore.toml")
    Path(scene).write_text(text)

    def run(standins_only: bool) -> tuple[list[np.ndarray], int, int]:
        monkeypatch.setattr(simulation, "FULL_MODEL_PEOPLE", 0 if standins_only else 10**6)
        env = proxemic.parallel_env(scene, robots=11, planner_actions=False)
        sim = env.ws.sim
        assert sim.standins_only == standins_only
        if not standins_only:
            sim._crowd_max = 0  # every period with people in reach on the physics model
        most, touched = [0], [0]
        real = sim.step

        def step(command: np.ndarray, possible: bool = True) -> None:
            real(command, possible)
            if possible:
                most[0] = max(most[0], len(sim._near))
                touched[0] += int(bool((sim.contacts & _core.CONTACT_PERSON).any()))

        sim.step = step  # type: ignore[method-assign]
        states = _drive_at_people(env, sim, rng_seed=4, reset_seed=6, steps=300)
        if standins_only:
            assert sim.model.nmocap == 0 and max(sim._crowds) >= most[0] > 0
        return states, touched[0], most[0]

    monkeypatch.setattr(simulation, "CROWD_MAX", 4)  # so that larger crowd models are compiled in steps
    fast, touched, most = run(True)
    plain, plain_touched, _ = run(False)
    assert all(np.array_equal(a, b) for a, b in zip(fast, plain, strict=True))
    assert touched == plain_touched > 10 and most > 4


def test_a_crowd_too_large_for_mujoco_is_an_input_error_naming_the_people_and_the_limit():
    from proxemic.errors import InputError
    from proxemic.sim.model import check_crowd_fits, max_people

    limit = max_people(1)
    check_crowd_fits({"persons": [{}] * limit, "robots": [{}]})
    with pytest.raises(InputError, match=rf"persons: expected at most {limit} people .* got {limit + 1} people"):
        check_crowd_fits({"persons": [{}] * (limit + 1), "robots": [{}]})
