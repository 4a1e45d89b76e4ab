"""The simulation of a scenario: the physics model stepped a control period at a time.

Contact filtering: the static geometry has contype 2 and conaffinity 0, robots contype 1 and
conaffinity 1 (other robots, people) plus 2 while the core's ``near_static`` hint says they are
within ``CONTACT_RANGE`` of a wall or object, and each person's body contype = conaffinity = 1
only while within that range of a robot (the core's person hint; 0 leaves the body out of the
broadphase). Static-static, person-static and
person-person pairs are never generated (mocap bodies are welded to the world), and the hints only
drop pairs that cannot touch during the control step: the contacts are the same.
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np

from proxemic import _core
from proxemic.sim import timer
from proxemic.sim.model import DYNAMIC_BIT, STATIC_BIT, _view, build_spec, check_crowd_fits
from proxemic.sim.reduced import _PERSON_GEOM, CROWD_MAX, FULL_MODEL_PEOPLE, ReducedModels
from proxemic.sim.render import Rendering


class Simulation(ReducedModels, Rendering):
    """The physics model and data of a scenario (and its render model), with arrays in and out.

    Attributes:
        model: The physics model (collision geoms only; see :mod:`proxemic.sim.model`).
        data: Its data.
        state: The robots' world-frame poses and velocities after :meth:`read`, ``6 * N`` values
            (x, y, theta, vx, vy, wz per robot).
        contacts: One uint8 of ``CONTACT_*`` bits per robot, accumulated over the last :meth:`step`.
        frame_skip: Physics steps per control step.
    """

    def __init__(self, scenario: dict[str, Any]) -> None:
        """Compiles the physics model of `scenario` (a validated scenario dict)."""
        self.scenario = scenario
        check_crowd_fits(scenario)
        self.num_robots = len(scenario["robots"])
        self.num_people = len(scenario["persons"])
        n, p = self.num_robots, self.num_people
        #: Whether the physics model leaves the people out (more than :data:`FULL_MODEL_PEOPLE`):
        #: every period with people in reach is then stepped on a crowd model (see `_crowd`).
        self.standins_only = p > FULL_MODEL_PEOPLE
        self.model = build_spec({**scenario, "persons": []} if self.standins_only else scenario, visual=False).compile()
        self.data = mujoco.MjData(self.model)
        m, d = self.model, self.data
        self.frame_skip = round(scenario["scene"]["physics_hz"] / scenario["scene"]["control_hz"])
        qpos = np.array([[m.jnt_qposadr[m.joint(f"robot_{i}/{j}").id] for j in ("x", "y", "yaw")] for i in range(n)])
        qvel = np.array([[m.jnt_dofadr[m.joint(f"robot_{i}/{j}").id] for j in ("x", "y", "yaw")] for i in range(n)])
        ctrl = np.array([[m.actuator(f"robot_{i}/{a}").id for a in ("vx", "vy", "wz")] for i in range(n)])
        robot_geoms = [[g for g in range(m.ngeom) if m.geom(g).name.startswith(f"robot_{i}/")] for i in range(n)]
        robot_bodies = [m.body(f"robot_{i}/base").id for i in range(n)]
        # Views of the data's arrays (the data's memory never moves), sliced once.
        self._qpos = _view(d.qpos, qpos)
        self._qvel = _view(d.qvel, qvel)
        self._ctrl = _view(d.ctrl, ctrl)
        if self.standins_only:
            # The people's poses and body flags kept here, for the crowd models' stand-ins; their
            # body geoms' values from a model with one person of each body shape.
            shapes: dict[tuple[float, float], int] = {}
            kind = [shapes.setdefault((q["radius"], q["height"]), len(shapes)) for q in scenario["persons"]]
            firsts = [kind.index(k) for k in range(len(shapes))]
            ref = build_spec({**scenario, "persons": [scenario["persons"][i] for i in firsts]}, visual=False).compile()
            ref_geoms = np.array([ref.geom(f"person_{k}/body").id for k in range(len(shapes))], dtype=np.intp)
            ref_bodies = np.array([ref.body(f"person_{k}/root").id for k in range(len(shapes))], dtype=np.intp)
            if not (ref.body_bvhnum[ref_bodies] == 1).all():  # SHOULD NOT OCCUR: one collision geom each
                raise ValueError("a person's body with more than one bounding volume")
            idx = np.array(kind, dtype=np.intp)
            self._person_ref = (ref, ref_geoms)
            self._person_geom = {f: getattr(ref, f)[ref_geoms][idx] for f in _PERSON_GEOM}
            self._person_bvh = ref.bvh_aabb[ref.body_bvhadr[ref_bodies]][idx]
            self._mocap_pos = np.zeros((p, 3))
            self._mocap_quat = np.zeros((p, 4))
            self._person_flags = [np.zeros(p, dtype=np.int32), np.zeros(p, dtype=np.int32)]
            person_geoms: list[int] = []
        else:
            mocap = np.array([m.body_mocapid[m.body(f"person_{i}/root").id] for i in range(p)], dtype=np.intp)
            person_geoms = [m.geom(f"person_{i}/body").id for i in range(p)]
            person_bodies = [m.body(f"person_{i}/root").id for i in range(p)]
            self._mocap_pos = _view(d.mocap_pos, mocap)
            self._mocap_quat = _view(d.mocap_quat, mocap)
            # A person's body flags decide whether the broadphase sees them at all (MuJoCo checks a
            # body's contype/conaffinity before pairing it), so they are the ones switched.
            pb = np.array(person_bodies, dtype=np.intp)
            self._person_flags = [_view(m.body_contype, pb), _view(m.body_conaffinity, pb)]
            # The physics model's values the stand-ins take over (each person's body geom and
            # bounding volume).
            self._person_ref = (m, np.array(person_geoms, dtype=np.intp))
            self._person_geom = {f: _view(getattr(m, f), self._person_ref[1]) for f in _PERSON_GEOM}
            self._person_bvh = m.bvh_aabb[m.body_bvhadr[pb]] if p else np.zeros((0, 6))
            if p and not (m.body_bvhnum[pb] == 1).all():  # SHOULD NOT OCCUR: one collision geom each
                raise ValueError("a person's body with more than one bounding volume")
        per_robot = {len(g) for g in robot_geoms}
        if len(per_robot) > 1:  # SHOULD NOT OCCUR: every robot is the same model
            raise ValueError("robots with different numbers of collision geoms")
        self._robot_geom_ids = np.array(robot_geoms, dtype=np.intp).reshape(n, -1)
        self._robot_body_ids = np.array(robot_bodies, dtype=np.intp)
        self._robot_geom_aff = _view(m.geom_conaffinity, self._robot_geom_ids)
        self._robot_body_aff = _view(m.body_conaffinity, self._robot_body_ids)
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
        if self.standins_only:  # a crowd model's stand-ins' body geoms follow the physics model's
            self._owner_list += [-1] * p
            self._bit_list += [int(_core.CONTACT_PERSON)] * p
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
        self._robots_only = (
            self._reduced(scenario, static=True) if scenario["persons"] and not self.standins_only else None
        )
        self._free = self._reduced(scenario, static=False) if scenario["persons"] or has_static else None
        # Periods with a few people in reach: the people in reach (indices, from the hints), the
        # physics model's values the stand-ins take over (each person's body geom and bounding
        # volume) and the crowd models (see `_crowd`) by size, compiled here (a compilation in
        # a step would cost some hundred steps).
        self._near: tuple[int, ...] = ()
        #: The model and data the last control period was stepped on (the physics model, a
        #: reduced or a crowd model; for the benches' like-with-like bare denominators).
        self.stepped: tuple[mujoco.MjModel, mujoco.MjData] = (m, self.data)
        sizes = [1 << k for k in range(min(p // 2, CROWD_MAX).bit_length())]
        self._crowds = {size: self._new_crowd(size) for size in sizes}
        # More people in reach: the physics model (without the people in it, a crowd model of
        # them, compiled when first needed).
        self._crowd_max = p if self.standins_only else (sizes[-1] if sizes else 0)
        self._render: tuple[mujoco.MjModel, mujoco.MjData] | None = None
        self._renderers: dict[tuple[int, int], Any] = {}

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
        saved = timer._timer_off()  # see proxemic.sim.timer
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
            if saved is not None:
                timer._TIMER.value = saved  # type: ignore[union-attr]

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

    def read(self) -> None:
        """Reads the robots' world-frame poses and velocities into `state`."""
        self._state_pose[...] = self._qpos
        self._state_vel[...] = self._qvel
