"""MuJoCo side of proxemic: build the model from a scenario, step it, read it, render it.

The model is assembled with ``mujoco.MjSpec`` from the validated scenario (a dict from the Rust
core) and the MJCF assets in ``proxemic/data/models``: static geoms for walls and furniture, one
Pepper-like base per robot (``robot_<i>/``, slide-x, slide-y, hinge-yaw joints with robot-frame
velocity servos), one mocap body per person (``person_<i>/``). Mocap bodies generate contacts
only with the robots, so the contacts read back are exactly robot-person, robot-static and
robot-robot events.

Two models are compiled from the same spec. The physics model (:attr:`Simulation.model`) holds
only what collides: the walls' and objects' collision footprints, each robot's base and torso,
each person's body capsule, with the same masses; no cameras, lights, floor or visual parts. The
render model (:attr:`Simulation.render_model`, compiled on first use) adds the furniture models,
the people's heads and the robots' heads, tablets and coloured shells, and is posed from the
physics model's state before each frame. The visual parts are massless and never collide, so both
models step bit for bit alike; the physics model is just cheaper to step. Two reduced models step
the control periods in which the core's hints put no person in reach of a robot: the physics
model without the people (``Simulation.robots_model``) while contacts with walls, objects or
robots are possible, the robots alone (``Simulation.contact_free_model``) while no contact is.
The people's mocap bodies then act on nothing (nor the static geometry without contacts), so the
robots end each such period in the same state with the same contacts bit for bit, at a third of
the cost with 50 people (their bodies' kinematics are most of a contact-free step), a fifth
without the static geometry. Periods with a few people in reach are stepped on a crowd model
(``Simulation._crowd``): the physics model with 1, 2, 4, ... stand-in people taking over the
bodies and poses of just those people, in the same order, so the contacts are the same and come
in the same order.

Contact filtering: the static geometry has contype 2 and conaffinity 0, robots contype 1 and
conaffinity 1 (other robots, people) plus 2 while the core's ``near_static`` hint says they are
within ``CONTACT_RANGE`` of a wall or object, and each person's body contype = conaffinity = 1
only while within that range of a robot (the core's person hint; 0 leaves the body out of the
broadphase). Static-static, person-static and
person-person pairs are never generated (mocap bodies are welded to the world), and the hints only
drop pairs that cannot touch during the control step: the contacts are the same.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
from collections.abc import Iterator
from dataclasses import dataclass, field
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

#: Contact bits of the physics model: the static geometry's contype, and the robots' and
#: people's contype (see the module docstring).
STATIC_BIT = 2
DYNAMIC_BIT = 1


def _timer_slot() -> ctypes.c_void_p | None:
    """MuJoCo's global timer callback ``mjcb_time`` (the C pointer), or None if not found."""
    folder = Path(mujoco.__file__).parent
    for lib in sorted(folder.glob("libmujoco.so*")) + sorted(folder.glob("libmujoco*.dylib")) + [folder / "mujoco.dll"]:
        try:
            return ctypes.c_void_p.in_dll(ctypes.CDLL(str(lib)), "mjcb_time")
        except (OSError, ValueError):
            continue
    return None


# MuJoCo's Python bindings (4.x) install a timer callback at import: every step then reads the
# clock some 30 times to fill ``MjData.timer`` (a tenth of a control step's physics here). The
# simulation steps with it switched off (``data.timer`` stays empty; nothing else uses the
# callback, so the physics is the same bit for bit) and puts it back after each step. Only that
# default is switched off: a timer a user set (``mujoco.set_mjcb_time``) is left running.
_TIMER = _timer_slot()
_DEFAULT_TIMER: int | None = _TIMER.value if _TIMER is not None else None


def _timer_off() -> int | None:
    """Switches the bindings' default timer off; returns it (to restore) or None if it was not on."""
    if _TIMER is None or _DEFAULT_TIMER is None or _TIMER.value != _DEFAULT_TIMER:
        return None
    _TIMER.value = None
    return _DEFAULT_TIMER


@contextlib.contextmanager
def timer_off() -> Iterator[None]:
    """MuJoCo stepped as :meth:`Simulation.step` steps it: without the bindings' default timer.

    For benches timing bare ``mj_step`` calls against the env's own (like with like).
    """
    saved = _timer_off()
    try:
        yield
    finally:
        if saved is not None:
            assert _TIMER is not None
            _TIMER.value = saved


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
    for i, _r in enumerate(scenario["robots"]):
        # Attached at the origin: the joints' values are the world pose (x, y, yaw).
        frame = wb.add_frame(pos=[0.0, 0.0, 0.0])
        spec.attach(robot_model, frame=frame, prefix=f"robot_{i}/")
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


#: Most people in reach of a robot in a control period stepped on a crowd model (see
#: ``Simulation._crowd``; also at most half the scene's people): the crowd models are compiled
#: with 1, 2, 4, ... stand-ins up to it.
CROWD_MAX = 64

#: The model values of a person's body geom that differ between people (its capsule's size and
#: placement, and what the broadphase derives from them): what a stand-in takes over.
_PERSON_GEOM = ("geom_size", "geom_pos", "geom_quat", "geom_rbound", "geom_aabb")
#: Geom values that may differ between people without changing a contact (colour, owner body).
_GEOM_ANY = ("geom_rgba", "geom_bodyid")


@dataclass(eq=False)
class _Crowd:
    """A crowd model (see :meth:`Simulation._crowd`): the model and data, and views of its stand-ins."""

    model: mujoco.MjModel
    data: mujoco.MjData
    #: The stand-ins' values of each ``_PERSON_GEOM`` field, their bounding volumes and body flags.
    geom: dict[str, np.ndarray]
    bvh: np.ndarray
    flags: list[np.ndarray]
    mocap_pos: np.ndarray
    mocap_quat: np.ndarray
    #: The people the stand-ins stand in for, and the views of the used stand-ins' mocap poses.
    near: tuple[int, ...] = ()
    idx: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.intp))
    pos: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    quat: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))


class Simulation:
    """The physics model and data of a scenario (and its render model), with arrays in and out.

    Attributes:
        model: The physics model (collision geoms only; see the module docstring).
        data: Its data.
        state: The robots' world-frame poses and velocities after :meth:`read`, ``6 * N`` values
            (x, y, theta, vx, vy, wz per robot).
        contacts: One uint8 of ``CONTACT_*`` bits per robot, accumulated over the last :meth:`step`.
        frame_skip: Physics steps per control step.
    """

    def __init__(self, scenario: dict[str, Any]) -> None:
        """Compiles the physics model of `scenario` (a validated scenario dict)."""
        self.scenario = scenario
        self.model = build_spec(scenario, visual=False).compile()
        self.data = mujoco.MjData(self.model)
        m, d = self.model, self.data
        self.num_robots = len(scenario["robots"])
        self.num_people = len(scenario["persons"])
        self.frame_skip = round(scenario["scene"]["physics_hz"] / scenario["scene"]["control_hz"])
        n, p = self.num_robots, self.num_people
        qpos = np.array([[m.jnt_qposadr[m.joint(f"robot_{i}/{j}").id] for j in ("x", "y", "yaw")] for i in range(n)])
        qvel = np.array([[m.jnt_dofadr[m.joint(f"robot_{i}/{j}").id] for j in ("x", "y", "yaw")] for i in range(n)])
        ctrl = np.array([[m.actuator(f"robot_{i}/{a}").id for a in ("vx", "vy", "wz")] for i in range(n)])
        mocap = np.array([m.body_mocapid[m.body(f"person_{i}/root").id] for i in range(p)], dtype=np.intp)
        robot_geoms = [[g for g in range(m.ngeom) if m.geom(g).name.startswith(f"robot_{i}/")] for i in range(n)]
        robot_bodies = [m.body(f"robot_{i}/base").id for i in range(n)]
        person_geoms = [m.geom(f"person_{i}/body").id for i in range(p)]
        person_bodies = [m.body(f"person_{i}/root").id for i in range(p)]
        # Views of the data's arrays (the data's memory never moves), sliced once.
        self._qpos = _view(d.qpos, qpos)
        self._qvel = _view(d.qvel, qvel)
        self._ctrl = _view(d.ctrl, ctrl)
        self._mocap_pos = _view(d.mocap_pos, mocap)
        self._mocap_quat = _view(d.mocap_quat, mocap)
        per_robot = {len(g) for g in robot_geoms}
        if len(per_robot) > 1:  # SHOULD NOT OCCUR: every robot is the same model
            raise ValueError("robots with different numbers of collision geoms")
        self._robot_geom_ids = np.array(robot_geoms, dtype=np.intp).reshape(n, -1)
        self._robot_body_ids = np.array(robot_bodies, dtype=np.intp)
        self._robot_geom_aff = _view(m.geom_conaffinity, self._robot_geom_ids)
        self._robot_body_aff = _view(m.body_conaffinity, self._robot_body_ids)
        # A person's body flags decide whether the broadphase sees them at all (MuJoCo checks a
        # body's contype/conaffinity before pairing it), so they are the ones switched.
        pb = np.array(person_bodies, dtype=np.intp)
        self._person_flags = [_view(m.body_contype, pb), _view(m.body_conaffinity, pb)]
        # Contact classification: per geom, the robot owning it (-1 for none) and the CONTACT_*
        # bit another robot touching it gets.
        owner = np.full(m.ngeom, -1, dtype=np.intp)
        bit = np.zeros(m.ngeom, dtype=np.uint8)
        for i, geoms in enumerate(robot_geoms):
            owner[geoms] = i
            bit[geoms] = _core.CONTACT_ROBOT
        bit[person_geoms] = _core.CONTACT_PERSON
        for g in range(m.ngeom):
            if m.geom(g).name.startswith(("wall_", "object/")):
                bit[g] = _core.CONTACT_STATIC
        self._owner_list: list[int] = owner.tolist()
        self._bit_list: list[int] = bit.tolist()
        self.state = np.zeros(6 * n)
        self._state2d = self.state.reshape(n, 6)
        # `state`'s pose and velocity columns, sliced once (read() runs every control step).
        self._state_pose = self._state2d[:, :3]
        self._state_vel = self._state2d[:, 3:]
        self.contacts = np.zeros(n, dtype=np.uint8)
        # The people's buffer write_people() last copied from and its column views with the
        # matching mocap views, (destination, source) pairs (see `_people_copies`).
        self._people_src: np.ndarray | None = None
        self._people_pairs: list[tuple[np.ndarray, np.ndarray]] = []
        self._mocap_xy = self._mocap_pos[:, :2]
        # The robots' affinities while set_hints() computes them (one buffer, no temporaries),
        # and the hints last set (none yet: reset() sets them all).
        self._aff = np.zeros(n)
        self._hints: tuple[list[float] | None, list[float] | None] = (None, None)
        # A control period the hints rule every contact out for is stepped with contacts
        # disabled: the collision detection (half of an mj_step here) finds nothing anyway, and
        # with no contact the solver's input is the same, so the states are bit-identical.
        self._opt = m.opt  # the model's options (the wrapper looked up once)
        self._flags = int(m.opt.disableflags)
        self._flags_no_contact = self._flags | int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
        # The integration state without the people's poses and the forces applied to bodies
        # (mocap and body arrays differ in size between the models; nothing applies forces here),
        # what step() copies between the physics model and the reduced ones.
        self._sig = int(mujoco.mjtState.mjSTATE_INTEGRATION) & ~int(
            mujoco.mjtState.mjSTATE_MOCAP_POS
            | mujoco.mjtState.mjSTATE_MOCAP_QUAT
            | mujoco.mjtState.mjSTATE_XFRC_APPLIED
        )
        self._state = np.zeros(mujoco.mj_stateSize(m, self._sig))
        has_static = bool(scenario["walls"] or scenario["objects"])
        # The robots' affinity views of every reduced model with the static geometry (set_hints
        # writes them all).
        self._solo_affs: list[tuple[np.ndarray, np.ndarray]] = []
        self._robots_only = self._reduced(scenario, static=True) if scenario["persons"] else None
        self._free = self._reduced(scenario, static=False) if scenario["persons"] or has_static else None
        # Periods with a few people in reach: the people in reach (indices, from the hints), the
        # physics model's values the stand-ins take over (each person's body geom and bounding
        # volume) and the crowd models (see `_crowd`) by size, compiled here (a compilation in
        # a step would cost some hundred steps).
        self._near: tuple[int, ...] = ()
        #: The model and data the last control period was stepped on (the physics model, a
        #: reduced or a crowd model; for the benches' like-with-like bare denominators).
        self.stepped: tuple[mujoco.MjModel, mujoco.MjData] = (m, self.data)
        self._person_geom = {f: _view(getattr(m, f), np.array(person_geoms, dtype=np.intp)) for f in _PERSON_GEOM}
        self._person_bvh = m.bvh_aabb[m.body_bvhadr[pb]] if p else np.zeros((0, 6))
        if p and not (m.body_bvhnum[pb] == 1).all():  # SHOULD NOT OCCUR: one collision geom each
            raise ValueError("a person's body with more than one bounding volume")
        sizes = [1 << k for k in range(min(p // 2, CROWD_MAX).bit_length())]
        self._crowds = {size: self._new_crowd(size) for size in sizes}
        self._crowd_max = sizes[-1] if sizes else 0  # more people in reach: the physics model
        self._render: tuple[mujoco.MjModel, mujoco.MjData] | None = None
        self._renderers: dict[tuple[int, int], Any] = {}

    @property
    def robots_model(self) -> mujoco.MjModel:
        """The model stepped while contacts are on but no person is in reach.

        The physics model without the people (the physics model itself in a scene without people).
        """
        return self.model if self._robots_only is None else self._robots_only[0]

    @property
    def contact_free_model(self) -> mujoco.MjModel:
        """The model stepped while no contact is possible.

        The robots alone (no people, walls or objects), collision detection off (the physics model
        itself in an empty scene).
        """
        return self.model if self._free is None else self._free[0]

    def _reduced(self, scenario: dict[str, Any], static: bool, people: int = 0) -> tuple[mujoco.MjModel, mujoco.MjData]:
        """A reduced physics model for :meth:`step`, and its data.

        The physics model of `scenario` without the people (and with `static` False, without
        the walls and objects); with `people`, with the first `people` people (the crowd models'
        stand-ins, see :meth:`_crowd`).

        While no person's body is in the broadphase (no contact possible at all, or only the
        robots' with the static geometry and each other) the people's mocap bodies act on
        nothing, and without contacts the static geometry neither: the robots' joints and
        actuators are the same in every model, in the same order (and with `static` the static
        geometry's and robots' bodies and geoms too, with the same contact bits: :meth:`set_hints`
        writes both), so a control period stepped from the same integration state (time, joints,
        velocities, actuator states, warm start, controls) ends in the same state with the same
        contacts, bit for bit, for a third of the cost with 50 people (a fifth without the
        static geometry).
        """
        persons = scenario["persons"][:people]
        reduced = (
            {**scenario, "persons": persons} if static else {**scenario, "persons": [], "walls": [], "objects": []}
        )
        m = build_spec(reduced, visual=False).compile()
        full = self.model
        names = [(mujoco.mjtObj.mjOBJ_JOINT, full.njnt, m.njnt), (mujoco.mjtObj.mjOBJ_ACTUATOR, full.nu, m.nu)]
        if static:
            names += [(mujoco.mjtObj.mjOBJ_BODY, m.nbody, m.nbody), (mujoco.mjtObj.mjOBJ_GEOM, m.ngeom, m.ngeom)]
        same = (full.nq, full.nv, full.na, full.nu) == (m.nq, m.nv, m.na, m.nu) and all(
            n1 == n2 and all(mujoco.mj_id2name(full, t, i) == mujoco.mj_id2name(m, t, i) for i in range(n1))
            for t, n1, n2 in names
        )
        if not same or mujoco.mj_stateSize(m, self._sig) != len(self._state):  # SHOULD NOT OCCUR: built alike
            raise ValueError("a reduced physics model differs from the physics model in joints, bodies or geoms")
        if static:
            affs = (_view(m.geom_conaffinity, self._robot_geom_ids), _view(m.body_conaffinity, self._robot_body_ids))
            affs[0][...] = self._robot_geom_aff  # the hints set so far
            affs[1][...] = self._robot_body_aff
            self._solo_affs.append(affs)
        else:
            m.opt.disableflags = self._flags_no_contact
        return m, mujoco.MjData(m)

    def reset(self, robot_poses: np.ndarray, people: np.ndarray) -> None:
        """Resets the physics: robots at `robot_poses` (N, 3), people at `people`.

        `people` has P rows of at least 3 columns (x, y, heading; then the core's contact hints,
        unused here: every contact pair is enabled until the next :meth:`set_hints`).
        """
        m, d = self.model, self.data
        mujoco.mj_resetData(m, d)
        self._qpos[:] = robot_poses
        self.write_people(people)
        self.set_hints(np.ones(self.num_robots), np.ones(self.num_people))
        mujoco.mj_forward(m, d)
        self.contacts[:] = 0
        self.read()

    def write_people(self, people: np.ndarray) -> None:
        """Writes the people's poses into their mocap bodies.

        `people` has P rows: x, y, heading, and (the core's buffer, ``PERSON_OUT`` columns) the
        contact hint and the heading's yaw quaternion w and z; with 3 columns the quaternion is
        computed here.
        """
        if self.num_people == 0:
            return
        if people.shape[1] >= 6:
            if people is not self._people_src:
                self._people_pairs = self._people_copies(people)
                self._people_src = people
            for dst, src in self._people_pairs:
                dst[...] = src
            return
        self._mocap_xy[...] = people[:, :2]
        q = self._mocap_quat
        half = people[:, 2] * 0.5
        q[:, 0] = np.cos(half)
        q[:, 3] = np.sin(half)

    def _people_copies(self, people: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
        """The (destination, source) views write_people() copies from the core's `people` buffer.

        Sliced once per buffer: the core writes into the same buffer every control step.
        """
        q = self._mocap_quat
        return [(self._mocap_xy, people[:, :2]), (q[:, 0], people[:, 4]), (q[:, 3], people[:, 5])]

    def set_hints(self, near_static: np.ndarray, near_people: np.ndarray) -> None:
        """Sets which contact pairs the physics tests (the core's hints, 1.0 or 0.0 each).

        The model's contact bits are written only where the hints differ from the last ones set
        (the bits are set here and nowhere else).

        Args:
            near_static: Per robot: test it against the static geometry.
            near_people: Per person: test them against the robots.
        """
        # The model keeps the bits: hints equal to the last ones set are not written again
        # (as Python lists, compared in one go, cheaper than numpy's writes on arrays this small).
        static, people = near_static.tolist(), near_people.tolist()
        if static != self._hints[0]:
            aff = self._aff
            np.multiply(near_static, STATIC_BIT, out=aff)
            aff += DYNAMIC_BIT
            self._robot_geom_aff[...] = aff[:, None]
            self._robot_body_aff[...] = aff
            for geom_aff, body_aff in self._solo_affs:
                geom_aff[...] = aff[:, None]
                body_aff[...] = aff
        if people != self._hints[1]:
            for arr in self._person_flags:
                arr[...] = near_people
            self._near = tuple(np.flatnonzero(near_people).tolist())
        self._hints = (static, people)

    def step(self, command: np.ndarray, contacts_possible: bool = True) -> None:
        """Writes robot-frame commands (N, 3) to the servos and advances one control period.

        Contacts are checked after every physics step (a person's push can separate the bodies
        again within one control period), and accumulated into `contacts` as CONTACT_* bits.
        With `contacts_possible` False (the core's hints rule every contact out for this
        period), the physics steps are made in one call with the collision detection off and no
        contact is read. Periods with no person in the broadphase are stepped on a reduced model
        (contacts off: :attr:`contact_free_model`; the hints set for no person:
        :attr:`robots_model`), the state copied in and back (the data's other quantities, e.g.
        body poses, keep their values of the last period stepped on the physics model).
        """
        m, d = self.model, self.data
        self._ctrl[...] = command
        timer = _timer_off()  # see _TIMER
        try:
            # A reduced model when no person is in reach (and the state back below).
            target = self._free
            if contacts_possible:
                near = self._near
                if self._hints[1] is None:  # every pair enabled (reset)
                    target = None
                elif not near:
                    target = self._robots_only
                else:
                    target = self._crowd(near) if len(near) <= self._crowd_max else None
            state, sig = self._state, self._sig
            if target is not None:
                mujoco.mj_getState(m, d, state, sig)
                m, d = target
                mujoco.mj_setState(m, d, state, sig)
            elif contacts_possible:
                mujoco.mj_getState(m, d, state, sig)  # the period's start, should it be stepped again
            self.stepped = (m, d)
            if not contacts_possible:
                if target is None:
                    opt = self._opt
                    opt.disableflags = self._flags_no_contact
                    try:
                        mujoco.mj_step(m, d, self.frame_skip)
                    finally:
                        opt.disableflags = self._flags
                else:
                    mujoco.mj_step(m, d, self.frame_skip)
                self.contacts.fill(0)
            elif not self._contact_in_period(m, d):
                self.contacts.fill(0)
            else:  # the period again from its start, a physics step at a time
                mujoco.mj_setState(m, d, state, sig)
                owner, bit = self._owner_list, self._bit_list
                acc = [0] * self.num_robots
                step = mujoco.mj_step
                for _ in range(self.frame_skip):
                    step(m, d)
                    if d.ncon:
                        # A handful of pairs at most: plain Python beats numpy on arrays this small.
                        for g1, g2 in d.contact.geom[: d.ncon].tolist():
                            o1, o2 = owner[g1], owner[g2]
                            if o1 >= 0:
                                acc[o1] |= bit[g2]
                            if o2 >= 0:
                                acc[o2] |= bit[g1]
                self.contacts[:] = acc
            if target is not None:
                mujoco.mj_getState(m, d, state, sig)
                mujoco.mj_setState(self.model, self.data, state, sig)
        finally:
            if timer is not None:
                _TIMER.value = timer  # type: ignore[union-attr]

    def _contact_in_period(self, m: mujoco.MjModel, d: mujoco.MjData) -> bool:
        """Steps the control period in one call; whether any of its physics steps found a contact.

        MuJoCo's high-water mark of contacts (``maxuse_con``, raised by every physics step's
        constraint stage to the contacts it found) is cleared first: still 0 afterwards, no step
        found one, and the period is done. Otherwise :meth:`step` steps it again from its start a
        physics step at a time to read each step's contacts (the same steps from the same
        integration state, so the same states bit for bit); most periods with contacts possible
        have none, and save the calls of stepping one physics step at a time.
        """
        d.maxuse_con = 0
        mujoco.mj_step(m, d, self.frame_skip)
        return bool(d.maxuse_con)

    def _crowd(self, near: tuple[int, ...]) -> tuple[mujoco.MjModel, mujoco.MjData]:
        """The crowd model for the people `near` (indices, ascending), their stand-ins posed.

        A crowd model is the physics model with K people (K a power of two, the smallest not below
        ``len(near)``): stand-ins that take over the body geoms, bounding volumes and poses of the
        people in reach, in the same order (so the broadphase pairs, and the contacts, come in the
        same order), the others left out of the broadphase. The people out of reach act on
        nothing in such a period, so the robots end it in the same state with the same contacts
        bit for bit, without the cost of every person's body kinematics.
        """
        n = len(near)
        crowd = self._crowds[1 << (n - 1).bit_length()]
        if crowd.near != near:
            idx = np.array(near, dtype=np.intp)
            for f, dst in crowd.geom.items():
                dst[:n] = self._person_geom[f][idx]
            crowd.bvh[:n] = self._person_bvh[idx]
            for arr in crowd.flags:
                arr[:n] = 1
                arr[n:] = 0
            crowd.near, crowd.idx = near, idx
            crowd.pos, crowd.quat = crowd.mocap_pos[:n], crowd.mocap_quat[:n]
        # (the arrays' own take: numpy's function adds a wrapper's cost as large as the copy's)
        self._mocap_pos.take(crowd.idx, axis=0, out=crowd.pos)
        self._mocap_quat.take(crowd.idx, axis=0, out=crowd.quat)
        return crowd.model, crowd.data

    def _new_crowd(self, size: int) -> _Crowd:
        """A crowd model of `size` stand-ins (see :meth:`_crowd`), nobody in reach yet."""
        m, d = self._reduced(self.scenario, static=True, people=size)
        full = self.model
        geoms = np.array([m.geom(f"person_{i}/body").id for i in range(size)], dtype=np.intp)
        bodies = np.array([m.body(f"person_{i}/root").id for i in range(size)], dtype=np.intp)
        mocap = np.array([m.body_mocapid[b] for b in bodies], dtype=np.intp)
        # Everything else about a person's body geom is the asset's, the same for every person
        # and stand-in (checked: a difference would make the contacts differ).
        person_geoms = np.array([full.geom(f"person_{i}/body").id for i in range(self.num_people)], dtype=np.intp)
        for f in dir(full):
            a = getattr(full, f)
            if f.startswith("geom_") and f not in _PERSON_GEOM and f not in _GEOM_ANY and isinstance(a, np.ndarray):
                if a.shape[:1] == (full.ngeom,) and not (a[person_geoms] == getattr(m, f)[geoms[0]]).all():
                    raise ValueError(f"people's body geoms differ in {f}")  # SHOULD NOT OCCUR
        start = int(m.body_bvhadr[bodies[0]])
        if not (m.body_bvhnum[bodies] == 1).all() or not np.array_equal(m.body_bvhadr[bodies], start + np.arange(size)):
            # SHOULD NOT OCCUR: built alike
            raise ValueError("a stand-in's body with more than one bounding volume")
        flags = [_view(m.body_contype, bodies), _view(m.body_conaffinity, bodies)]
        for arr in flags:
            arr[...] = 0
        return _Crowd(
            model=m,
            data=d,
            geom={f: _view(getattr(m, f), geoms) for f in _PERSON_GEOM},
            bvh=m.bvh_aabb[start : start + size],
            flags=flags,
            mocap_pos=_view(d.mocap_pos, mocap),
            mocap_quat=_view(d.mocap_quat, mocap),
        )

    def read(self) -> None:
        """Reads the robots' world-frame poses and velocities into `state`."""
        self._state_pose[...] = self._qpos
        self._state_vel[...] = self._qvel

    @property
    def render_model(self) -> mujoco.MjModel:
        """The render model (compiled on first use): the physics model plus the visual parts."""
        return self._render_pair()[0]

    @property
    def render_data(self) -> mujoco.MjData:
        """The render model's data, posed by :meth:`sync_render`."""
        return self._render_pair()[1]

    def _render_pair(self) -> tuple[mujoco.MjModel, mujoco.MjData]:
        if self._render is None:
            rm = build_spec(self.scenario, visual=True).compile()
            if (rm.nq, rm.nv, rm.nmocap, rm.nu) != (self.model.nq, self.model.nv, self.model.nmocap, self.model.nu):
                raise ValueError("render and physics models differ in joints or bodies")  # SHOULD NOT OCCUR
            self._render = (rm, mujoco.MjData(rm))
        return self._render

    def sync_render(self) -> None:
        """Poses the render model like the physics: joints, velocities, people, time."""
        rm, rd = self._render_pair()
        d = self.data
        rd.qpos[:] = d.qpos
        rd.qvel[:] = d.qvel
        rd.mocap_pos[:] = d.mocap_pos
        rd.mocap_quat[:] = d.mocap_quat
        rd.time = d.time
        mujoco.mj_kinematics(rm, rd)
        mujoco.mj_camlight(rm, rd)

    def render(self, width: int, height: int, camera: str = "top") -> np.ndarray:
        """Renders an RGB frame offscreen (EGL or OSMesa; see `ensure_gl_backend`)."""
        key = (width, height)
        self.sync_render()
        rm, rd = self._render_pair()
        renderer = self._renderers.get(key)
        if renderer is None:
            renderer = mujoco.Renderer(rm, height, width)
            self._renderers[key] = renderer
        renderer.update_scene(rd, camera=camera)
        renderer.scene.flags[mujoco.mjtRndFlag.mjRND_SHADOW] = 0
        renderer.scene.flags[mujoco.mjtRndFlag.mjRND_REFLECTION] = 0
        return renderer.render().copy()

    def close(self) -> None:
        """Releases the renderers' GL contexts."""
        for r in self._renderers.values():
            r.close()
        self._renderers.clear()


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


def ensure_gl_backend() -> str:
    """Chooses an offscreen OpenGL backend before MuJoCo creates a context.

    Honours an existing ``MUJOCO_GL``; otherwise uses EGL when no display is available (both EGL
    and OSMesa work on CPU-only machines with Mesa's llvmpipe). Returns the backend name.
    """
    if "MUJOCO_GL" not in os.environ and not os.environ.get("DISPLAY"):
        os.environ["MUJOCO_GL"] = "egl"
    return os.environ.get("MUJOCO_GL", "glfw")
