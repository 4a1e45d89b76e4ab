"""The reduced models a control period is stepped on when few or no people can touch a robot.

Two reduced models step the control periods in which the core's hints put no person in reach of a robot: the physics
model without the people (``Simulation.robots_model``) while contacts with walls, objects or
robots are possible, the robots alone (``Simulation.contact_free_model``) while no contact is.
The people's mocap bodies then act on nothing (nor the static geometry without contacts), so the
robots end each such period in the same state with the same contacts bit for bit, at a third of
the cost with 50 people (their bodies' kinematics are most of a contact-free step), a fifth
without the static geometry. Periods with a few people in reach are stepped on a crowd model
(``ReducedModels._crowd``): the physics model with 1, 2, 4, ... stand-in people taking over the
bodies and poses of just those people, in the same order, so the contacts are the same and come
in the same order. A crowd of more than ``FULL_MODEL_PEOPLE`` people is left out of the physics
model altogether (``Simulation.standins_only``): every period with people in reach is then
stepped on a crowd model, the larger ones compiled when first needed.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import mujoco
import numpy as np

from proxemic.sim.model import _view, build_spec

#: Most people in reach of a robot in a control period stepped on a crowd model (see
#: ``ReducedModels._crowd``; also at most half the scene's people): the crowd models are compiled
#: with 1, 2, 4, ... stand-ins up to it (beyond it, without :attr:`Simulation.standins_only`, the
#: physics model steps the period).
CROWD_MAX = 64
#: The most people a physics model holds (:attr:`Simulation.standins_only` above): MuJoCo's
#: model building grows with the square of the bodies (MjSpec's add_body and XML parsing: 38 s
#: for 10,000 people, 0.45 s for 1000), so a larger crowd is left out of the physics model and
#: every period with people in reach is stepped on a crowd model of stand-ins, the larger ones
#: compiled when first needed. Every scene up to it keeps the physics model with all the people.
FULL_MODEL_PEOPLE = 1000

#: The model values of a person's body geom that differ between people (its capsule's size and
#: placement, and what the broadphase derives from them): what a stand-in takes over.
_PERSON_GEOM = ("geom_size", "geom_pos", "geom_quat", "geom_rbound", "geom_aabb")
#: Geom values that may differ between people without changing a contact (colour, owner body).
_GEOM_ANY = ("geom_rgba", "geom_bodyid")


@dataclass(eq=False)
class _Crowd:
    """A crowd model (see :meth:`ReducedModels._crowd`): the model and data, and views of its stand-ins."""

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


class ReducedModels:
    """The reduced and crowd models of :class:`proxemic.sim.Simulation` (a base class of it)."""

    scenario: dict[str, Any]
    model: mujoco.MjModel
    num_people: int
    _sig: int
    _state: np.ndarray
    _robot_geom_ids: np.ndarray
    _robot_body_ids: np.ndarray
    _robot_geom_aff: np.ndarray
    _robot_body_aff: np.ndarray
    _solo_affs: list[tuple[np.ndarray, np.ndarray]]
    _robots_only: tuple[mujoco.MjModel, mujoco.MjData] | None
    _free: tuple[mujoco.MjModel, mujoco.MjData] | None
    _crowds: dict[int, _Crowd]
    _person_geom: dict[str, np.ndarray]
    _person_ref: tuple[mujoco.MjModel, np.ndarray]
    standins_only: bool
    _person_bvh: np.ndarray
    _mocap_pos: np.ndarray
    _mocap_quat: np.ndarray
    _flags_no_contact: int

    @property
    def robots_model(self) -> mujoco.MjModel:
        """The model stepped while contacts are on but no person is in reach.

        The physics model without the people (the physics model itself in a scene without people
        or with :attr:`Simulation.standins_only`).
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
            # The people come last in both models: the bodies and geoms the two have in common
            # (the physics model without people has fewer than a crowd model).
            bodies, geoms = min(m.nbody, full.nbody), min(m.ngeom, full.ngeom)
            names += [(mujoco.mjtObj.mjOBJ_BODY, bodies, bodies), (mujoco.mjtObj.mjOBJ_GEOM, geoms, geoms)]
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
        size = min(1 << (n - 1).bit_length(), self.num_people)
        crowd = self._crowds.get(size)
        if crowd is None:  # more people in reach than ever before, without them in the physics model
            crowd = self._crowds[size] = self._new_crowd(size)
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
        full, person_geoms = self._person_ref
        geoms = np.array([m.geom(f"person_{i}/body").id for i in range(size)], dtype=np.intp)
        bodies = np.array([m.body(f"person_{i}/root").id for i in range(size)], dtype=np.intp)
        mocap = np.array([m.body_mocapid[b] for b in bodies], dtype=np.intp)
        if self.standins_only and not np.array_equal(geoms, self.model.ngeom + np.arange(size)):
            # SHOULD NOT OCCUR: the contact classification takes the geoms after the physics
            # model's for people
            raise ValueError("a crowd model's stand-ins do not follow the physics model's geoms")
        # Everything else about a person's body geom is the asset's, the same for every person
        # and stand-in (checked: a difference would make the contacts differ).
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
