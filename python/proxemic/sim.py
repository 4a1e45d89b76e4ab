"""MuJoCo side of proxemic: build the model from a scenario, step it, read it, render it.

The model is assembled with ``mujoco.MjSpec`` from the validated scenario (a dict from the Rust
core) and the MJCF assets in ``proxemic/data/models``: static geoms for walls and furniture, one
Pepper-like base per robot (``robot_<i>/``, slide-x, slide-y, hinge-yaw joints with robot-frame
velocity servos), one mocap body per person (``person_<i>/``). Mocap bodies generate contacts
only with the robots, so the contacts read back are exactly robot-person, robot-static and
robot-robot events.
"""

from __future__ import annotations

import os
from importlib import resources
from pathlib import Path
from typing import Any

# MuJoCo chooses its OpenGL backend when it is imported: pick an offscreen one first when there is
# no display (see `ensure_gl_backend`), or rendering fails with "no OpenGL platform library".
if "MUJOCO_GL" not in os.environ and not os.environ.get("DISPLAY"):
    os.environ["MUJOCO_GL"] = "egl"

import mujoco
import numpy as np

from proxemic import _core
from proxemic.furniture import add_object
from proxemic.viz.topdown import ROBOT_PALETTE

#: Colours of robots by index (RGBA), cycled: the top-down view's palette, so a robot has the same
#: colour in both views.
ROBOT_COLOURS: tuple[tuple[float, float, float, float], ...] = tuple(
    (r / 255.0, g / 255.0, b / 255.0, 1.0) for r, g, b in ROBOT_PALETTE
)

#: Owner codes of geoms in contact classification.
OWNER_STATIC = -1
OWNER_PERSON = -2
OWNER_NONE = -3


def models_dir() -> Path:
    """Folder of the MJCF assets shipped inside the package."""
    return Path(str(resources.files("proxemic") / "data" / "models"))


def _yaw_quat(yaw: float) -> list[float]:
    return [float(np.cos(yaw / 2.0)), 0.0, 0.0, float(np.sin(yaw / 2.0))]


def build_spec(scenario: dict[str, Any]) -> mujoco.MjSpec:
    """Builds the MuJoCo spec of a validated scenario dict (see ``Scenario.to_json``)."""
    scene = scenario["scene"]
    spec = mujoco.MjSpec()
    spec.modelname = scene["name"]
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
        add_object(wb, o)

    assets = models_dir()
    robot_model = mujoco.MjSpec.from_file(str(assets / "pepper.xml"))
    for i, _r in enumerate(scenario["robots"]):
        # Attached at the origin: the joints' values are the world pose (x, y, yaw).
        frame = wb.add_frame(pos=[0.0, 0.0, 0.0])
        spec.attach(robot_model, frame=frame, prefix=f"robot_{i}/")
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
    person_model = mujoco.MjSpec.from_file(str(assets / "pedestrian.xml"))
    for i, p in enumerate(scenario["persons"]):
        x, y, th = p["pose"]
        frame = wb.add_frame(pos=[x, y, 0.0], quat=_yaw_quat(th))
        spec.attach(person_model, frame=frame, prefix=f"person_{i}/")
        body = spec.geom(f"person_{i}/body")
        half = max(p["height"] / 2.0 - p["radius"] - 0.12, 0.05)
        body.size = [p["radius"], half, 0.0]
        body.pos = [0.0, 0.0, p["radius"] + half]
        if p["group"] is not None:
            hue = (p["group"] * 0.618034) % 1.0
            body.rgba = [0.35 + 0.5 * hue, 0.45, 0.85 - 0.5 * hue, 1.0]
    return spec


class Simulation:
    """Owns the MjModel and MjData of a scenario and moves arrays in and out of them."""

    def __init__(self, scenario: dict[str, Any]) -> None:
        """Compiles the model of `scenario` (a validated scenario dict)."""
        self.scenario = scenario
        self.model = build_spec(scenario).compile()
        self.data = mujoco.MjData(self.model)
        m = self.model
        self.num_robots = len(scenario["robots"])
        self.num_people = len(scenario["persons"])
        self.frame_skip = round(scenario["scene"]["physics_hz"] / scenario["scene"]["control_hz"])
        self._qpos = np.array(
            [[m.jnt_qposadr[m.joint(f"robot_{i}/{j}").id] for j in ("x", "y", "yaw")] for i in range(self.num_robots)],
            dtype=np.intp,
        )
        self._qvel = np.array(
            [[m.jnt_dofadr[m.joint(f"robot_{i}/{j}").id] for j in ("x", "y", "yaw")] for i in range(self.num_robots)],
            dtype=np.intp,
        )
        self._ctrl = np.array(
            [[m.actuator(f"robot_{i}/{a}").id for a in ("vx", "vy", "wz")] for i in range(self.num_robots)],
            dtype=np.intp,
        )
        self._mocap = np.array(
            [m.body_mocapid[m.body(f"person_{i}/root").id] for i in range(self.num_people)], dtype=np.intp
        )
        # Contiguous layouts (the usual case) use slices, which numpy handles faster than fancy indexing.
        self._qpos_slice = _as_slice(self._qpos)
        self._qvel_slice = _as_slice(self._qvel)
        self._ctrl_slice = _as_slice(self._ctrl)
        self._mocap_slice = _as_slice(self._mocap)
        owner = np.full(m.ngeom, OWNER_NONE, dtype=np.int64)
        for g in range(m.ngeom):
            name = m.geom(g).name
            if name.startswith("robot_"):
                owner[g] = int(name.split("/")[0].split("_")[1])
            elif name.startswith("person_"):
                owner[g] = OWNER_PERSON
            elif name.startswith(("wall_", "object/")):
                owner[g] = OWNER_STATIC
        self._owner = owner
        self.state = np.zeros(6 * self.num_robots)
        self.contacts = np.zeros(self.num_robots, dtype=np.uint8)
        self._quat = np.zeros((self.num_people, 4))
        self._renderers: dict[tuple[int, int], Any] = {}

    def reset(self, robot_poses: np.ndarray, people: np.ndarray) -> None:
        """Resets the physics with robots at `robot_poses` (N, 3) and people at `people` (P, 3)."""
        m, d = self.model, self.data
        mujoco.mj_resetData(m, d)
        for i in range(self.num_robots):
            d.qpos[self._qpos[i]] = robot_poses[i]
        self.write_people(people)
        mujoco.mj_forward(m, d)
        self.contacts[:] = 0
        self.read()

    def write_people(self, people: np.ndarray) -> None:
        """Writes the people's poses (P, 3: x, y, heading) into their mocap bodies."""
        if self.num_people == 0:
            return
        d = self.data
        idx = self._mocap_slice if self._mocap_slice is not None else self._mocap
        d.mocap_pos[idx, 0] = people[:, 0]
        d.mocap_pos[idx, 1] = people[:, 1]
        half = people[:, 2] * 0.5
        q = self._quat
        np.cos(half, out=q[:, 0])
        np.sin(half, out=q[:, 3])
        d.mocap_quat[idx] = q

    def step(self, command: np.ndarray) -> None:
        """Writes robot-frame commands (N, 3) to the servos and advances one control period.

        Contacts are checked after every physics step (a person's push can separate the bodies
        again within one control period), and accumulated into `contacts` as CONTACT_* bits.
        """
        m, d = self.model, self.data
        idx = self._ctrl_slice if self._ctrl_slice is not None else self._ctrl
        d.ctrl[idx] = command.reshape(-1)
        self.contacts[:] = 0
        for _ in range(self.frame_skip):
            mujoco.mj_step(m, d)
            if d.ncon:
                self._classify_contacts(d.contact.geom[: d.ncon])

    def read(self) -> None:
        """Reads the robots' world-frame poses and velocities into `state`."""
        d = self.data
        st = self.state.reshape(-1, 6)
        if self._qpos_slice is not None and self.num_robots == 1:
            st[0, :3] = d.qpos[self._qpos_slice]
            st[0, 3:] = d.qvel[self._qvel_slice]
        else:
            st[:, :3] = d.qpos[self._qpos]
            st[:, 3:] = d.qvel[self._qvel]

    def _classify_contacts(self, geoms: np.ndarray) -> None:
        owners = self._owner[geoms]
        for a, b in ((0, 1), (1, 0)):
            mine, other = owners[:, a], owners[:, b]
            for k in np.nonzero(mine >= 0)[0]:
                i, o = int(mine[k]), int(other[k])
                if o == OWNER_PERSON:
                    self.contacts[i] |= _core.CONTACT_PERSON
                elif o == OWNER_STATIC:
                    self.contacts[i] |= _core.CONTACT_STATIC
                elif o >= 0 and o != i:
                    self.contacts[i] |= _core.CONTACT_ROBOT

    def render(self, width: int, height: int, camera: str = "top") -> np.ndarray:
        """Renders an RGB frame offscreen (EGL or OSMesa; see `ensure_gl_backend`)."""
        key = (width, height)
        renderer = self._renderers.get(key)
        if renderer is None:
            renderer = mujoco.Renderer(self.model, height, width)
            self._renderers[key] = renderer
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_camlight(self.model, self.data)
        renderer.update_scene(self.data, camera=camera)
        renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = 0
        renderer.scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = 0
        return renderer.render().copy()

    def close(self) -> None:
        """Releases the renderers' GL contexts."""
        for r in self._renderers.values():
            r.close()
        self._renderers.clear()


def _as_slice(idx: np.ndarray) -> slice | None:
    flat = idx.reshape(-1)
    if flat.size == 0:
        return None
    if np.array_equal(flat, np.arange(flat[0], flat[0] + flat.size)):
        return slice(int(flat[0]), int(flat[0]) + flat.size)
    return None


def ensure_gl_backend() -> str:
    """Chooses an offscreen OpenGL backend before MuJoCo creates a context.

    Honours an existing ``MUJOCO_GL``; otherwise uses EGL when no display is available (both EGL
    and OSMesa work on CPU-only machines with Mesa's llvmpipe). Returns the backend name.
    """
    if "MUJOCO_GL" not in os.environ and not os.environ.get("DISPLAY"):
        os.environ["MUJOCO_GL"] = "egl"
    return os.environ.get("MUJOCO_GL", "glfw")
