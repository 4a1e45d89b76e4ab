"""The MuJoCo models of a scenario, assembled with ``mujoco.MjSpec``.

The model is assembled with ``mujoco.MjSpec`` from the validated scenario (a dict from the Rust
core) and the MJCF assets in ``proxemic/data/models``: static geoms for walls and furniture, one
Pepper-like base per robot (``robot_<i>/``, slide-x, slide-y, hinge-yaw joints with robot-frame
velocity servos), one mocap body per person (``person_<i>/``). Mocap bodies generate contacts
only with the robots, so the contacts read back are exactly robot-person, robot-static and
robot-robot events.

Two models are compiled from the same spec. The physics model (:attr:`proxemic.sim.Simulation.model`) holds
only what collides: the walls' and objects' collision footprints, each robot's base and torso,
each person's body capsule, with the same masses; no cameras, lights, floor or visual parts. The
render model (:attr:`proxemic.sim.Simulation.render_model`, compiled on first use) adds the furniture models,
the people's heads and the robots' heads, tablets and coloured shells, and is posed from the
physics model's state before each frame. The visual parts are massless and never collide, so both
models step bit for bit alike; the physics model is just cheaper to step.

Contact filtering: the static geometry has contype 2 and conaffinity 0, robots contype 1 and
conaffinity 1 (other robots, people) plus 2 while the core's ``near_static`` hint says they are
within ``CONTACT_RANGE`` of a wall or object, and each person's body contype = conaffinity = 1
only while within that range of a robot (the core's person hint; 0 leaves the body out of the
broadphase). Static-static, person-static and
person-person pairs are never generated (mocap bodies are welded to the world), and the hints only
drop pairs that cannot touch during the control step: the contacts are the same.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from proxemic.furniture import add_object
from proxemic.palette import ROBOT_PALETTE, rgba

#: Colours of robots by index (RGBA), cycled: the palette's, so a robot has the same colour in
#: every view.
ROBOT_COLOURS: tuple[tuple[float, float, float, float], ...] = tuple(rgba(c) for c in ROBOT_PALETTE)

#: Contact bits of the physics model: the static geometry's contype, and the robots' and
#: people's contype (see the module docstring).
STATIC_BIT = 2
DYNAMIC_BIT = 1

#: MuJoCo's default arena (``<size memory>``), enough for the bundled scenes.
BASE_MEMORY = 16 << 20
#: The most arena one model may ask for (bytes): MuJoCo's collision pass takes two buffers of
#: about 2 bytes per pair of bodies each from it (measured with 10,003 bodies: mj_collision asked
#: for 200,060,004 bytes, then mj_broadphase for 200,020,000), so the arena grows with the square
#: of the crowd. Only the touched part of the arena becomes resident memory.
MAX_MEMORY = 2 << 30
#: Bytes of arena per pair of bodies in the collision pass, with a margin over the 4 measured.
PAIR_BYTES = 5


def model_memory(bodies: int) -> int:
    """The arena (``<size memory>``, bytes) of a model with `bodies` bodies (people, robots, world).

    MuJoCo's default plus :data:`PAIR_BYTES` per pair of bodies.
    """
    return BASE_MEMORY + PAIR_BYTES * bodies * bodies


def max_people(robots: int) -> int:
    """The most people a scene with `robots` robots can hold in its MuJoCo model (:data:`MAX_MEMORY`)."""
    bodies = int(((MAX_MEMORY - BASE_MEMORY) / PAIR_BYTES) ** 0.5)
    return bodies - robots - 1


def check_crowd_fits(scenario: dict[str, Any]) -> None:
    """Raises :class:`proxemic.InputError` naming the people and the limit when the crowd does not fit.

    The limit is the MuJoCo model's (:func:`max_people`); without it MuJoCo stops with a fatal
    stack overflow.
    """
    from proxemic.errors import input_error

    people, robots = len(scenario["persons"]), len(scenario["robots"])
    limit = max_people(robots)
    if people > limit:
        raise input_error(
            "persons",
            f"at most {limit} people with {robots} robot(s) (the MuJoCo model's collision arena, "
            f"{MAX_MEMORY >> 20} MB, grows with the square of the bodies)",
            f"{people} people",
        )


def models_dir() -> Path:
    """Folder of the MJCF assets shipped inside the package."""
    return Path(str(resources.files("proxemic") / "data" / "models"))


def _yaw_quat(yaw: float) -> list[float]:
    return [float(np.cos(yaw / 2.0)), 0.0, 0.0, float(np.sin(yaw / 2.0))]


def build_spec(scenario: dict[str, Any], *, visual: bool = True) -> mujoco.MjSpec:
    """Builds the MuJoCo spec of a validated scenario dict (see ``Scenario.to_json``).

    Args:
        scenario: The validated scenario.
        visual: True for the render model (everything the cameras see); False for the physics
            model: the same bodies, joints, actuators and collision geoms, without the massless
            visual parts, floor, cameras and lights, and with the contact bits described in the
            module docstring.
    """
    scene = scenario["scene"]
    check_crowd_fits(scenario)
    spec = mujoco.MjSpec()
    spec.modelname = scene["name"]
    spec.memory = model_memory(len(scenario["persons"]) + len(scenario["robots"]) + 1)
    spec.copy_during_attach = True  # the robot and person models are attached many times
    spec.compiler.degree = False
    spec.option.timestep = 1.0 / scene["physics_hz"]
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.visual.global_.offwidth = 1280
    spec.visual.global_.offheight = 960
    spec.visual.quality.offsamples = 0
    spec.visual.headlight.ambient = [0.45, 0.45, 0.45]
    spec.stat.extent = 10.0
    xmin, ymin, xmax, ymax = scene["bounds"]
    cx, cy = (xmin + xmax) / 2.0, (ymin + ymax) / 2.0
    wb = spec.worldbody

    if visual:  # the floor, light and top camera only matter to the render model
        floor_tex = spec.add_texture(
            name="floor",
            type=mujoco.mjtTexture.mjTEXTURE_2D,
            builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER,
            width=256,
            height=256,
            rgb1=[0.82, 0.8, 0.76],
            rgb2=[0.78, 0.76, 0.72],
        )
        floor_mat = spec.add_material(name="floor", texrepeat=[(xmax - xmin) / 2.0, (ymax - ymin) / 2.0])
        floor_mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = floor_tex.name
        wb.add_geom(
            name="floor",
            type=mujoco.mjtGeom.mjGEOM_PLANE,
            size=[(xmax - xmin) / 2.0, (ymax - ymin) / 2.0, 0.1],
            pos=[cx, cy, 0.0],
            material="floor",
            contype=0,
            conaffinity=0,
        )
        wb.add_light(
            name="sun",
            pos=[cx, cy, 20.0],
            dir=[0.0, 0.0, -1.0],
            type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL,
            diffuse=[0.6, 0.6, 0.6],
            castshadow=False,
        )
        # A top camera that sees the whole floor (fovy 45 degrees; aspect handled by the renderer).
        half = max((xmax - xmin) / 2.0 * 0.75, (ymax - ymin) / 2.0) + 1.0
        height = half / np.tan(np.radians(22.5))
        wb.add_camera(name="top", pos=[cx, cy, height], quat=[1.0, 0.0, 0.0, 0.0], fovy=45.0)

    for i, w in enumerate(scenario["walls"]):
        (x0, y0), (x1, y1) = w["from"], w["to"]
        length = float(np.hypot(x1 - x0, y1 - y0)) + w["thickness"]
        yaw = float(np.arctan2(y1 - y0, x1 - x0))
        wb.add_geom(
            name=f"wall_{i}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[length / 2.0, w["thickness"] / 2.0, w["height"] / 2.0],
            pos=[(x0 + x1) / 2.0, (y0 + y1) / 2.0, w["height"] / 2.0],
            quat=_yaw_quat(yaw),
            rgba=[0.72, 0.72, 0.7, 1.0],
        )
    for o in scenario["objects"]:
        add_object(wb, o, visual=visual)

    assets = models_dir()
    # The physics model attaches models already stripped of their visual parts: deleting them
    # from the assembled spec costs a pass over the whole spec per deletion (minutes at 500 people).
    robot_model = _asset(assets / "pepper.xml", visual)
    for i, r in enumerate(scenario["robots"]):
        # Attached at the origin: the joints' values are the world pose (x, y, yaw).
        frame = wb.add_frame(pos=[0.0, 0.0, 0.0])
        spec.attach(robot_model, frame=frame, prefix=f"robot_{i}/")
        _fit_robot(spec, f"robot_{i}/", r, visual)
        if not visual:
            continue
        colour = list(ROBOT_COLOURS[i % len(ROBOT_COLOURS)])
        for name in ("shell", "eyes"):
            spec.geom(f"robot_{i}/{name}").rgba = colour
        base = spec.body(f"robot_{i}/base")
        base.add_camera(
            name=f"robot_{i}/follow",
            pos=[-1.2, 0.0, 5.0],
            xyaxes=[0.0, -1.0, 0.0, 0.972, 0.0, 0.233],
            mode=mujoco.mjtCamLight.mjCAMLIGHT_TRACK,
            fovy=60.0,
        )
    # People are added geom by geom from the asset rather than attached: `MjSpec.attach` costs a
    # pass over the whole spec per call, quadratic in the crowd (a 1000-person scene took minutes).
    person_geoms = list(_asset(assets / "pedestrian.xml", visual).geoms)
    for i, p in enumerate(scenario["persons"]):
        x, y, th = p["pose"]
        root = wb.add_body(name=f"person_{i}/root", mocap=True, pos=[x, y, 0.0], quat=_yaw_quat(th))
        for g in person_geoms:
            geom = root.add_geom(
                name=f"person_{i}/{g.name}",
                type=g.type,
                size=list(g.size),
                pos=list(g.pos),
                quat=list(g.quat),
                rgba=list(g.rgba),
                contype=g.contype,
                conaffinity=g.conaffinity,
            )
            if g.name != "body":
                continue
            half = max(p["height"] / 2.0 - p["radius"] - 0.12, 0.05)
            geom.size = [p["radius"], half, 0.0]
            geom.pos = [0.0, 0.0, p["radius"] + half]
            if p["group"] is not None:
                hue = (p["group"] * 0.618034) % 1.0
                geom.rgba = [0.35 + 0.5 * hue, 0.45, 0.85 - 0.5 * hue, 1.0]
    if not visual:
        _strip_to_physics(spec)
    return spec


def _fit_robot(spec: mujoco.MjSpec, prefix: str, robot: dict[str, Any], visual: bool) -> None:
    """Fits an attached base to its scenario robot: the servos' ranges and the footprint.

    ``pepper.xml`` is Pepper (0.55 m/s per axis, 2 rad/s, radius 0.24 m); a robot with other limits
    or another radius gets its own, so the physics neither caps a faster robot's commands (the core
    has already limited them to the robot's limits) nor gives it Pepper's footprint. The base
    cylinder keeps its mass; the coloured shell follows the footprint.
    """
    speed, turn, radius = float(robot["max_speed"]), float(robot["max_angular_speed"]), float(robot["radius"])
    for axis in ("vx", "vy"):
        spec.actuator(prefix + axis).ctrlrange = [-speed, speed]
    spec.actuator(prefix + "wz").ctrlrange = [-turn, turn]
    base = spec.geom(prefix + "base")
    base.size = [radius, base.size[1], 0.0]
    if visual:
        shell = spec.geom(prefix + "shell")
        shell.size = [radius + 0.005, shell.size[1], 0.0]


def _asset(path: Path, visual: bool) -> mujoco.MjSpec:
    """An MJCF asset as a spec; for the physics model without its non-colliding geoms.

    Robots' visual parts are massless, and people are mocap bodies (their mass is unused), so
    removing them changes no dynamics.
    """
    spec = mujoco.MjSpec.from_file(str(path))
    if not visual:
        for g in list(spec.geoms):
            if g.contype == 0 and g.conaffinity == 0:
                spec.delete(g)
    return spec


def _strip_to_physics(spec: mujoco.MjSpec) -> None:
    """Sets the contact bits of the physics model (built without visual parts, cameras or lights).

    Static contype 2, robots and people contype = conaffinity = 1 (robots add 2 while near the
    static geometry, see :meth:`Simulation.set_hints`).
    """
    for g in spec.geoms:
        if g.name.startswith(("wall_", "object/")):
            g.contype, g.conaffinity = STATIC_BIT, 0
        else:
            g.contype, g.conaffinity = DYNAMIC_BIT, DYNAMIC_BIT | STATIC_BIT


def _view(arr: np.ndarray, idx: np.ndarray) -> np.ndarray:
    """``arr[idx]`` as a writable view, shaped like `idx` (plus `arr`'s trailing axes).

    The scene is built robot by robot and person by person, so every index set used here is a
    contiguous run; anything else is a bug in :func:`build_spec`.
    """
    flat = idx.reshape(-1)
    start = int(flat[0]) if flat.size else 0
    if not np.array_equal(flat, np.arange(start, start + flat.size)):
        raise ValueError(f"expected contiguous indices, got {flat.tolist()}")  # SHOULD NOT OCCUR
    return arr[start : start + flat.size].reshape(*idx.shape, *arr.shape[1:])
