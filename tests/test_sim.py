"""MuJoCo scene: the model built from the scenario, the velocity servos, contact events."""

from __future__ import annotations

import mujoco
import numpy as np

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
    mujoco.mj_forward(sim.model, sim.data)
    nose = sim.data.geom_xpos[sim.model.geom("person_0/nose").id]
    assert nose[1] > 2.05 and abs(nose[0] - 4.0) < 1e-6


def test_every_object_kind_has_a_model_and_keeps_its_collision_footprint():
    from proxemic.furniture import COLLISION_GROUP

    kinds = set()
    for name in ("museum", "care_center"):
        _, desc = scenarios.load(name)
        m = Simulation(desc).model
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
    from proxemic.viz.topdown import ROBOT_PALETTE

    _, desc = scenarios.load("daza2021_fig15")
    m = Simulation(desc).model
    assert len(desc["robots"]) == 4
    for i in range(4):
        rgba = m.geom(f"robot_{i}/shell").rgba
        np.testing.assert_allclose(rgba[:3] * 255.0, ROBOT_PALETTE[i], atol=1e-6)
    colours = {tuple(m.geom(f"robot_{i}/shell").rgba) for i in range(4)}
    assert len(colours) == 4
