"""The Rust world and the MuJoCo simulation of one scenario, stepped together.

Both front ends drive a :class:`WorldSim`: the gymnasium env (:mod:`proxemic.env`, one robot
acting) and the PettingZoo parallel env (:mod:`proxemic.parallel`, every robot an agent). A
control step is one Rust call for all robots, ``World.step``: it turns the policies' actions into
commands, calls back :meth:`WorldSim._physics` (MuJoCo, the only part with the GIL held), and
computes the people, metrics, rewards, observations and planners; every output lands in one
float64 buffer of ``num_robots`` rows sliced by the core's layout. The observation and action spaces
and the rendering live here too, so both front ends describe a robot the same way.
"""

from __future__ import annotations

import functools
import operator
import os
import re
import warnings
from collections.abc import Callable, Iterable
from math import isfinite
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from proxemic import _core
from proxemic.errors import ACTION_EXPECTED, REAL_KINDS, InputError, check_action, input_error, typed_repr
from proxemic.sim import Simulation, ensure_gl_backend

#: The local planner's mode by code (Daza 2021 Algorithm 1; see proxemic-core control::social::Mode).
PLANNER_MODES = ("follow_path", "orca", "social_momentum", "wait")

#: Reward term names in ``info`` (``reward_<term>``), in the order the core sums them.
REWARD_KEYS = tuple(f"reward_{t}" for t in _core.REWARD_TERMS)

#: Render modes both front ends support.
RENDER_MODES = ("rgb_array", "topdown", "human")


def action_space(drive: str = "holonomic") -> spaces.Box:
    """A robot's action space: the normalised robot-frame command (vx, vy, wz) in [-1, 1].

    For a differential-drive robot (``drive = "differential"``) the action is (v, 0, wz): the
    forward speed (negative: reverse) and the turn rate; its ``vy`` bound is [0, 0] and a
    non-zero ``vy`` is refused with an :class:`~proxemic.InputError`.
    """
    if drive == "differential":
        return spaces.Box(np.array([-1, 0, -1], np.float32), np.array([1, 0, 1], np.float32), dtype=np.float32)
    return spaces.Box(-1.0, 1.0, (3,), dtype=np.float32)


@functools.cache
def missing_display() -> str | None:
    """Why the ``"human"`` render mode cannot open a window here, or None when it can.

    The viewer needs GLFW and a display; without one, MuJoCo's viewer would print "could not
    initialize GLFW" and end the process, so the display is probed once (GLFW's own init, which
    fails without ending anything) before any viewer is started.
    """
    try:
        import glfw
    except ImportError as e:  # pragma: no cover - glfw is a dependency of mujoco
        return f"the glfw package is missing ({e})"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ok = glfw.init()
    if ok:
        glfw.terminate()
        return None
    # GLFW's messages read "(65550) b'X11: The DISPLAY environment variable is missing'".
    messages = [re.sub(r"^\(\d+\) b?['\"]?(.*?)['\"]?$", r"\1", str(w.message)) for w in caught]
    reason = "; ".join(messages) or "GLFW could not be initialised"
    display = os.environ.get("DISPLAY")
    where = "DISPLAY is unset" if not display else f"DISPLAY={display!r} cannot be opened"
    return f"{where} ({reason})"


def available_render_modes() -> list[str]:
    """The render modes this machine supports: :data:`RENDER_MODES` without ``"human"`` when headless."""
    return [m for m in RENDER_MODES if m != "human" or missing_display() is None]


def check_render_mode(render_mode: str | None) -> None:
    """Raises :class:`InputError` unless `render_mode` is None or a mode this machine can render.

    ``"human"`` needs a display (see :func:`missing_display`); the message names the alternatives.
    """
    if render_mode is not None and render_mode not in RENDER_MODES:
        raise input_error("render_mode", f"one of {list(RENDER_MODES)} or None", render_mode)
    if render_mode == "human" and (why := missing_display()) is not None:
        raise input_error(
            "render_mode",
            "a display for 'human' (a window), or 'rgb_array' (MuJoCo offscreen) or 'topdown' (2D view)",
            why,
            note="'human' opens a window; use 'rgb_array' or 'topdown' on a headless machine",
        )


#: Largest frame side (pixels) of the renderers.
MAX_FRAME = 4096


def check_frame_size(width: Any, height: Any) -> None:
    """Raises :class:`InputError` unless `width` and `height` are integers in [1, :data:`MAX_FRAME`]."""
    for name, value in (("width", width), ("height", height)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 1 <= value <= MAX_FRAME:
            integer = isinstance(value, (int, np.integer)) and not isinstance(value, bool)
            found = repr(value) if integer else typed_repr(value)
            raise input_error(name, f"a frame size in pixels, an integer from 1 to {MAX_FRAME}", found)


def check_flags(**flags: Any) -> None:
    """Raises :class:`InputError` naming the first of `flags` (name = value) that is not a bool."""
    for name, value in flags.items():
        if not isinstance(value, (bool, np.bool_)):
            raise input_error(name, "True or False", typed_repr(value))


def check_reset_args(seed: Any, options: Any, *, warn_options: bool = False) -> None:
    """Raises :class:`InputError` unless `seed` is None or an integer >= 0 and `options` is empty.

    With `warn_options`, options are ignored with a warning instead (PettingZoo's API test passes
    arbitrary options to ``reset`` and expects them accepted).
    """
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0):
        raise input_error("seed", "None or an integer >= 0", seed)
    if options and warn_options:
        warnings.warn(f"reset(options={options!r}) ignored: this env takes no reset options", stacklevel=3)
    elif options:
        raise input_error("options", "None or {} (this env takes no reset options)", options)


class WorldSim:
    """The core ``World`` and the MuJoCo ``Simulation`` of a scenario with their shared buffers.

    Attributes:
        world: The Rust world (people, planners, metrics, observations, rewards).
        sim: The MuJoCo simulation (robots' bodies, contacts, rendering).
        scenario: The validated scenario dict.
        out: The core's output buffer, ``num_robots * stride`` float64 values.
        rows: ``out`` as (num_robots, stride).
        sections: ``{name: (num_robots, len) view of rows}`` for every layout section.
        people: The people's buffer (P * PERSON_OUT: x, y, heading, contact hint).
        topdown: The 2D renderer, once a ``"topdown"`` frame was drawn.
    """

    def __init__(
        self,
        core_scenario: _core.Scenario,
        scenario: dict[str, Any],
        buffers: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> None:
        """Builds the world and compiles the MuJoCo model of `scenario`.

        `buffers` are the ``out`` and ``people`` buffers to write into (zeroed float64 arrays of
        the right sizes, e.g. one world's row of a vector env's batch buffers); default new ones.
        """
        self.scenario = scenario
        self.world = _core.World(core_scenario)
        self.sim = Simulation(scenario)
        w = self.world
        self.num_robots: int = w.num_robots
        if buffers is None:
            buffers = (np.zeros(w.num_robots * w.stride), np.zeros(w.num_people * _core.PERSON_OUT))
        self.out: np.ndarray = buffers[0]
        self.people: np.ndarray = buffers[1]
        self.rows = self.out.reshape(w.num_robots, w.stride)
        self._people2d = self.people.reshape(-1, _core.PERSON_OUT)
        self.layout: dict[str, tuple[int, int]] = dict(w.layout)
        self.sections = {name: self.rows[:, off : off + n] for name, (off, n) in self.layout.items()}
        self._actions = np.full(3 * w.num_robots, np.nan)
        self._action_rows = list(self._actions.reshape(-1, 3))  # each robot's slot, a view
        self._all_rows = list(range(w.num_robots))
        # The columns step_outcome() reads: reward, terminated, truncated.
        self._outcome_cols = np.array([self.layout["reward"][0], self.layout["flags"][0], self.layout["flags"][0] + 1])
        # The columns infos() reads: the reward terms, success and collision, mode, time of day.
        terms, flags = self.layout["reward_terms"], self.layout["flags"]
        self._info_cols = np.array(
            [
                *range(terms[0], terms[0] + terms[1]),
                flags[0] + 2,
                flags[0] + 3,
                self.layout["mode"][0],
                self.layout["time_of_day"][0],
            ]
        )
        # results() reads one span of every row holding these columns: the outcome's (reward,
        # terminated, truncated), then the info's; and their places in the span.
        cols = [*self._outcome_cols.tolist(), *self._info_cols.tolist()]
        self._result_span = (min(cols), max(cols) + 1)
        # (reward, terminated, truncated, the reward terms, success, collision, mode, time of day)
        # of a row's span, in one call.
        self._result_get = operator.itemgetter(*[c - min(cols) for c in cols])
        sensors = scenario["sensors"]
        self.k_nearest: int = sensors["k_nearest"]
        self.lidar_rays: int = sensors["lidar_rays"]
        self.lidar_range = float(sensors["lidar_range"])
        self.subgoal = float(sensors["subgoal"])
        # Per robot, the flat indices in `out` of its info values (``_info_cols`` of its row), and
        # its planner_action row.
        self._info_index = [r * w.stride + self._info_cols for r in range(w.num_robots)]
        self._planner_rows = list(self.sections["planner_action"])
        self._command = self.sections["command"]
        self._near_static = self.sections["near_static"][:, 0]
        self._near_people = self._people2d[:, 3]
        # Where in `out` the core says whether any contact is possible (the first row's copy).
        self._possible_index = self.layout["contacts_possible"][0]
        # Per robot, the flat indices in `out` of its reward, terminated and truncated flags
        # (the single-robot env reads them as Python floats with `out.item`).
        self._reward_index = [r * w.stride + self.layout["reward"][0] for r in range(w.num_robots)]
        self._flag_index = [r * w.stride + self.layout["flags"][0] for r in range(w.num_robots)]
        # The observation sections of a row, for robots=False and robots=True: the span of
        # columns copied (lo, hi) and each key's (offset in the span, length, shape of one row).
        self._obs_parts = {with_robots: self._obs_spec(with_robots) for with_robots in (False, True)}
        self.planning = [True] * w.num_robots
        self.topdown: Any = None
        self._viewer: Any = None

    # ------------------------------------------------------------------ spaces
    def observation_space(self, *, robots: bool) -> spaces.Dict:
        """A robot's observation space; with `robots`, also the other robots it perceives.

        Keys ``robot`` (5), ``people`` (k, 5), ``people_mask`` (k), ``lidar`` (rays), with the
        ``[sensors] subgoal`` look-ahead set ``subgoal`` (2) and, with `robots`, ``robots``
        (n - 1, 7: id, x, y, vx, vy, radius, running) and ``robots_mask`` (n - 1). Bounds as
        documented in :class:`proxemic.env.ProxemicEnv`.
        """
        k, rays, rng = self.k_nearest, self.lidar_rays, self.lidar_range
        d = float(self.world.obs_position_bound)
        vmax, wmax = float(_core.OBS_MAX_SPEED), float(_core.OBS_MAX_ANGULAR)
        f32 = np.float32
        entries: dict[str, spaces.Space[Any]] = {
            "robot": spaces.Box(
                np.array([-d, -d, -vmax, -vmax, -wmax], f32), np.array([d, d, vmax, vmax, wmax], f32), dtype=f32
            ),
            "people": spaces.Box(
                np.tile(np.array([-rng, -rng, -vmax, -vmax, 0.0], f32), (k, 1)),
                np.tile(np.array([rng, rng, vmax, vmax, 0.5], f32), (k, 1)),
                dtype=f32,
            ),
            "people_mask": spaces.Box(0.0, 1.0, (k,), dtype=f32),
            "lidar": spaces.Box(0.0, rng, (rays,), dtype=f32),
        }
        if self.subgoal > 0.0:
            entries["subgoal"] = spaces.Box(-self.subgoal, self.subgoal, (2,), dtype=f32)
        if robots:
            m = self.num_robots - 1
            rmax = max((float(r["radius"]) for r in self.scenario["robots"]), default=1.0)
            lo = np.array([0.0, -rng, -rng, -vmax, -vmax, 0.0, 0.0], f32)
            hi = np.array([max(m, 0), rng, rng, vmax, vmax, rmax, 1.0], f32)
            entries["robots"] = spaces.Box(np.tile(lo, (m, 1)), np.tile(hi, (m, 1)), dtype=f32)
            entries["robots_mask"] = spaces.Box(0.0, 1.0, (m,), dtype=f32)
        return spaces.Dict(entries)

    def _obs_spec(self, robots: bool) -> tuple[int, int, list[tuple[str, int, int, tuple[int, ...]]]]:
        """The observation keys' columns (see ``_obs_parts``); with `robots`, the peers' too."""
        # Each key's section and the shape of its rows (None: flat).
        keys: list[tuple[str, str, tuple[int, ...] | None]] = [
            ("robot", "obs_robot", None),
            ("people", "obs_people", (self.k_nearest, _core.PERSON_FEATURES)),
            ("people_mask", "obs_people_mask", None),
            ("lidar", "obs_lidar", None),
        ]
        if self.subgoal > 0.0:
            keys.append(("subgoal", "obs_subgoal", None))
        if robots:
            keys.append(("robots", "obs_robots", (self.num_robots - 1, _core.PEER_FEATURES)))
            keys.append(("robots_mask", "obs_robots_mask", None))
        lo = min(self.layout[section][0] for _, section, _ in keys)
        hi = max(sum(self.layout[section]) for _, section, _ in keys)
        parts = []
        for key, section, shape in keys:
            off, length = self.layout[section]
            parts.append((key, off - lo, length, (length,) if shape is None else shape))
        return lo, hi, parts

    def set_planning(self, planning: list[bool]) -> None:
        """Which robots' built-in planners run (see ``World.set_planning``).

        Infos of the robots whose planner is off have no ``planner_action`` and ``planner_mode``.
        """
        self.world.set_planning(planning)
        self.planning = list(planning)

    # ------------------------------------------------------------------ stepping
    def reset(self, seed: int) -> None:
        """Starts an episode from the core seed `seed` and places the bodies."""
        self.world.reset(seed, self.out, self.people)
        self.sim.reset(self.sections["pose"], self._people2d)

    def step(self, actions: np.ndarray | None = None) -> None:
        """One control step, one Rust call: the actions, the physics, then everything else.

        `actions` holds 3 normalised values per robot; NaN rows (and no `actions` at all) keep the
        built-in planners.
        """
        sim = self.sim
        acts = self._actions if actions is None else actions
        self.world.step(acts, self._physics, sim.state, sim.contacts, self.out, self.people)

    def _physics(self) -> None:
        """The physics of a control step, called back by ``World.step`` between its two halves.

        The people's poses and the contact hints in, the commands executed, the robots read.
        """
        sim = self.sim
        sim.write_people(self._people2d)
        # Nothing near anything (no robot near a wall, a person or another robot; the core's
        # flag): no contact, and the contact bits need not be set (the physics steps with the
        # collision detection off; set_hints() writes them when contacts are possible again).
        if self.out.item(self._possible_index):
            sim.set_hints(self._near_static, self._near_people)
            sim.step(self._command, True)
        else:
            sim.step(self._command, False)
        sim.read()

    def act(self, robot: int, action: Any, field: str) -> None:
        """Stores `action` for `robot` in the actions of the next :meth:`step_actions` call.

        Raises:
            InputError: not 3 finite real numbers of shape (3,) (`field` names the argument in
                the message); booleans and complex numbers are refused, not converted.
        """
        # Fast path, a real ndarray of shape (3,) (what policies return): checked as Python
        # numbers and cast into the slot; anything else goes through check_action's conversion.
        if type(action) is np.ndarray and action.shape == (3,) and action.dtype.kind in REAL_KINDS:
            a, b, c = action.tolist()
            if not (isfinite(a) and isfinite(b) and isfinite(c)):
                raise input_error(field, ACTION_EXPECTED, str([float(a), float(b), float(c)]))
            self._action_rows[robot][...] = action
            return
        self._action_rows[robot][...] = check_action(action, field)

    def act_many(self, robots: list[int], actions: list[Any], fields: Callable[[int], str]) -> None:
        """:meth:`act` for several robots at once (one array conversion).

        `fields(k)` names the k-th action in an error message; on an error no action is kept.
        """
        if not robots:
            return
        # Fast path: real-valued ndarrays of shape (3,) only (a list would let numpy turn booleans
        # into numbers; subclasses take the slow path, to the same result).
        nd = np.ndarray
        real = all([type(x) is nd and x.shape == (3,) and x.dtype.kind in REAL_KINDS for x in actions])
        if real and len(robots) == self.num_robots and robots == self._all_rows:
            # Every robot, in order: cast straight into the buffer. A finite sum means every value
            # is finite (an infinity or a NaN makes it infinite or NaN); else the checks below.
            np.concatenate(actions, out=self._actions, casting="unsafe")
            if isfinite(self._actions.sum()):
                return
            self._actions.fill(np.nan)
        a = np.asarray(actions, dtype=np.float64) if real else np.empty(0)
        if a.shape != (len(robots), 3) or not np.isfinite(a).all():
            try:
                for k, (r, action) in enumerate(zip(robots, actions, strict=True)):
                    self.act(r, action, fields(k))
            except InputError:
                self._actions.fill(np.nan)  # nothing of a rejected step is kept
                raise
            return
        acts = self._actions.reshape(-1, 3)
        if len(robots) == self.num_robots and robots == self._all_rows:
            acts[:] = a  # every robot, in order: a plain copy
        else:
            acts[robots] = a

    def step_actions(self) -> None:
        """Steps with the actions stored by :meth:`act` (others keep their planners), then clears them."""
        self.step(self._actions)
        self._actions.fill(np.nan)

    # ------------------------------------------------------------------ outputs
    def observations(self, robots: bool, rows: list[int] | None = None) -> list[dict[str, np.ndarray]]:
        """The observations of the robots `rows` (default all), float32 views of one fresh copy."""
        lo, hi, parts = self._obs_parts[robots]
        if rows is None or rows == self._all_rows:
            src = self.rows[:, lo:hi]
        elif len(rows) == 1:
            return [self.observation(rows[0], robots)]
        else:
            src = self.rows[rows, lo:hi]
        data = src.astype(np.float32)
        n = len(data)
        (k0, a0), (k1, a1), (k2, a2), (k3, a3), *peers = [
            (key, data[:, off : off + length] if len(shape) == 1 else data[:, off : off + length].reshape(n, *shape))
            for key, off, length, shape in parts
        ]
        # Dict displays, not a comprehension per robot (a function call each): this runs for every
        # agent at every step. The keys are the spec's, four, and with `robots` the peers' two;
        # the `subgoal` sensor's key (or any other) takes the general way.
        if not peers:
            return [{k0: a0[i], k1: a1[i], k2: a2[i], k3: a3[i]} for i in range(n)]
        if len(peers) == 2:
            (k4, a4), (k5, a5) = peers
            return [{k0: a0[i], k1: a1[i], k2: a2[i], k3: a3[i], k4: a4[i], k5: a5[i]} for i in range(n)]
        return [{k0: a0[i], k1: a1[i], k2: a2[i], k3: a3[i], **{k: a[i] for k, a in peers}} for i in range(n)]

    def observation(self, row: int, robots: bool) -> dict[str, np.ndarray]:
        """Robot `row`'s observation (see :meth:`observations`), float32 views of one fresh copy."""
        lo, hi, parts = self._obs_parts[robots]
        base = row * self.rows.shape[1]
        data = self.out[base + lo : base + hi].astype(np.float32)
        return {
            key: data[off : off + length] if len(shape) == 1 else data[off : off + length].reshape(shape)
            for key, off, length, shape in parts
        }

    def results(self, rows: list[int]) -> tuple[list[float], list[bool], list[bool], list[dict[str, Any]]]:
        """The rewards, terminated and truncated flags and :meth:`info` of the robots `rows`.

        After the last step; the buffer is read once (one span of every row).
        """
        lo, hi = self._result_span
        vals = self.rows[:, lo:hi].tolist()
        planning = self.planning
        actions = list(self.sections["planner_action"].astype(np.float32)) if any(planning) else []
        t0, t1, t2, t3, t4 = REWARD_KEYS  # the core's five terms (an error here if that changes)
        rewards, terms, truncs, infos = [], [], [], []
        # info() inlined, with dict displays: this runs for every agent at every step.
        for r, (rew, term, trunc, v0, v1, v2, v3, v4, success, collision, mode, tod) in zip(
            rows, map(self._result_get, map(vals.__getitem__, rows)), strict=True
        ):
            rewards.append(rew)
            terms.append(term != 0.0)
            truncs.append(trunc != 0.0)
            info: dict[str, Any] = {
                t0: v0,
                t1: v1,
                t2: v2,
                t3: v3,
                t4: v4,
                "is_success": success != 0.0,
                "collision": collision != 0.0,
            }
            if planning[r]:
                info["planner_action"] = actions[r]
                info["planner_mode"] = PLANNER_MODES[int(mode)]
            info["time_of_day"] = tod
            infos.append(info)
        return rewards, terms, truncs, infos

    def step_outcome(self) -> list[tuple[float, bool, bool]]:
        """Every robot's (reward, terminated, truncated) after the last step (one read)."""
        return [(r, t != 0.0, u != 0.0) for r, t, u in self.rows[:, self._outcome_cols].tolist()]

    def outcome(self, robot: int) -> tuple[float, bool, bool]:
        """Robot `robot`'s (reward, terminated, truncated) after the last step (see :meth:`step_outcome`)."""
        item, flags = self.out.item, self._flag_index[robot]
        return item(self._reward_index[robot]), item(flags) != 0.0, item(flags + 1) != 0.0

    def info(self, robot: int) -> dict[str, Any]:
        """Robot `robot`'s step info: reward terms, success and collision flags, planner command and mode."""
        return self._info(robot, self.out[self._info_index[robot]].tolist())

    def infos(self, robots: list[int]) -> list[dict[str, Any]]:
        """:meth:`info` of several robots (the buffer is read once; see :meth:`results`)."""
        return self.results(robots)[3]

    def _info(self, r: int, v: list[float]) -> dict[str, Any]:
        """Robot `r`'s info from its values `v` at ``_info_cols`` (what :meth:`infos` builds)."""
        nterms = len(REWARD_KEYS)
        info: dict[str, Any] = dict(zip(REWARD_KEYS, v, strict=False))  # the first nterms values
        info["is_success"] = v[nterms] != 0.0
        info["collision"] = v[nterms + 1] != 0.0
        if self.planning[r]:
            info["planner_action"] = self._planner_rows[r].astype(np.float32)
            info["planner_mode"] = PLANNER_MODES[int(v[nterms + 2])]
        info["time_of_day"] = v[nterms + 3]
        return info

    def poses(self) -> np.ndarray:
        """The robots' (x, y, theta) after the last step, (N, 3) (a copy)."""
        return np.array(self.sections["pose"])

    # ------------------------------------------------------------------ rendering
    def render(
        self, mode: str, width: int, height: int, camera: str = "top", overlays: tuple[str, ...] = ("path",)
    ) -> np.ndarray | None:
        """A frame in `mode` (``"rgb_array"``, ``"topdown"``; ``"human"`` opens a viewer, returns None).

        `overlays` (see :func:`check_overlays`) only apply to the ``"topdown"`` view.
        """
        if mode == "topdown":
            return self.render_topdown(width, height, overlays)
        if mode == "human":
            import mujoco.viewer

            self.sim.sync_render()
            if self._viewer is None:
                self._viewer = mujoco.viewer.launch_passive(self.sim.render_model, self.sim.render_data)
            self._viewer.sync()
            return None
        ensure_gl_backend()
        return self.sim.render(width, height, camera)

    def render_topdown(self, width: int, height: int, overlays: tuple[str, ...] = ("path",)) -> np.ndarray:
        """The fast 2D top-down frame (numpy only) with the chosen overlays, (height, width, 3) uint8."""
        from proxemic.viz.topdown import TopDownRenderer

        if self.topdown is None or (self.topdown.width, self.topdown.height) != (width, height):
            self.topdown = TopDownRenderer(self.scenario, width, height)
        people = np.asarray(self.world.people())
        goals = np.array([r["goal"] for r in self.scenario["robots"]], dtype=np.float64)
        extra: dict[str, Any] = {}
        if "path" in overlays:
            extra["paths"] = [np.asarray(self.world.path(i)) for i in range(self.num_robots)]
        if "zones" in overlays:
            extra["zones"] = self.scenario["proxemics"]["zones"]
        if "groups" in overlays and len(people):
            extra["groups"] = self.world.perception()["groups"]
        if "object_spaces" in overlays:
            extra["object_costs"] = self.world.object_costs()
        frame: np.ndarray = self.topdown.render(self.poses(), people[:, [0, 1, 2, 5]], goals=goals, **extra)
        return frame

    def close(self) -> None:
        """Releases rendering resources."""
        self.sim.close()
        if self._viewer is not None:
            self._viewer.close()
            self._viewer = None


def check_overlays(overlays: Iterable[str] | str) -> tuple[str, ...]:
    """The overlay names as a tuple; raises :class:`InputError` on an unknown one.

    Names: ``"zones"`` (Hall's intimate, personal and social rings around each person, radii from
    the scenario's ``[proxemics]``), ``"groups"`` (the groups the robot perceives: o-space and
    outline), ``"object_spaces"`` (interaction spaces coloured by R(t) at the current time of day)
    and ``"path"`` (the robots' global paths). An empty iterable draws the bare scene.
    """
    from proxemic.viz.topdown import OVERLAYS

    chosen = (overlays,) if isinstance(overlays, str) else tuple(overlays)
    bad = [o for o in chosen if o not in OVERLAYS]
    if bad:
        raise input_error("overlays", f"names among {list(OVERLAYS)}", bad[0])
    return chosen


def warn_no_render_mode() -> None:
    """The gymnasium warning for ``render()`` without a render mode."""
    gym.logger.warn("render() called without a render_mode; pass render_mode= to the constructor")
