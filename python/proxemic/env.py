"""The single-robot gymnasium environment."""

from __future__ import annotations

import pickle
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

from proxemic import _core, scenarios
from proxemic.errors import InvariantError, NeedsResetError, input_error, invariant_in
from proxemic.records import EpisodeMetrics
from proxemic.viz.topdown import FRAME_SIZE
from proxemic.world import (
    PLANNER_MODES,
    RENDER_MODES,
    WorldSim,
    action_space,
    available_render_modes,
    check_flags,
    check_frame_size,
    check_overlays,
    check_render_mode,
    check_reset_args,
    warn_no_render_mode,
)

OUTCOMES = ("running", "success", "collision", "timeout")

__all__ = ["OUTCOMES", "PLANNER_MODES", "ProxemicEnv"]


class ProxemicEnv(gym.Env[dict[str, Any], np.ndarray]):
    """## Description.

    A Pepper-like holonomic robot crosses a building shared with scripted people (a museum, a care
    center). The physics runs in MuJoCo; every control step of the people, the built-in planner,
    the metrics, the reward and the observations is computed in the Rust core in one call.
    The robot is the scenario's first robot.

    The people follow scripted behaviours (``person.behaviour`` in the scenario, driven by a
    social force model, never through walls or furniture, aware of the robot or oblivious to
    it): walkers on routes with pauses, standing people, exhibit visitors who dwell facing each
    exhibit of a list, standing conversations (F-formations) that form and break up on a
    schedule, a tour guide (a person, or a robot of the scenario) whose followers gather on an
    arc facing it at every stop (Daza 2021 Fig. 11), people seated on benches and sofas, slow walkers (speed presets such as
    ``"elderly"``), and care-center residents and staff who follow the agenda (arriving before
    each activity, staying for it with the therapist facing the residents, leaving after). The
    museum (``proxemic/Museum-v5``) has 52 people with all of these but residents; the care center
    (``proxemic/CareCenter-v5``) runs a morning agenda whose activities end and start during the
    episode. Recorded people (a scenario's ``[[replay]]`` track files, e.g. converted ETH/UCY
    recordings) are where their files say, present from their first sample to their last (absent
    people are parked far away and left out of observations and metrics), and react to the robot
    within ``react_radius`` (``docs/recorded-crowds.md``).

    ## Action Space

    ``Box(-1, 1, (3,), float32)``: the robot-frame command (vx, vy, wz), normalised by the robot's
    maximum speed (0.55 m/s for Pepper) and maximum angular speed (2.0 rad/s). Out-of-range actions
    are clipped to [-1, 1] (as Gymnasium's MuJoCo environments clip to ``ctrlrange``); then the
    speed norm is capped at the maximum speed and the change from the previous command is limited
    by the maximum acceleration (0.55 m/s^2 linear, 3 rad/s^2 angular). An action containing NaN or
    infinity raises :class:`proxemic.InputError`. With ``autopilot=True`` the action is ignored and
    the robot's built-in planner (plain A* by default) drives.

    A differential-drive robot (``drive = "differential"`` in its ``[[robot]]``) takes (v, 0, wz):
    ``Box([-1, 0, -1], [1, 0, 1])``, the forward speed (negative: reverse) and the turn rate,
    normalised as above; a non-zero second value raises :class:`proxemic.InputError`. Its speed and
    turn rate are limited separately (``max_speed``, ``max_accel``, ``max_angular_speed``,
    ``max_angular_accel``), and the base never moves sideways. Its built-in planners' holonomic
    commands are turned into (v, wz) by one rule, except ORCA's (``astar_orca``) and Social
    Momentum's, which plan among the velocities the robot can track (``docs/scenarios.md``,
    differential drive).

    ## Observation Space

    A ``Dict`` of float32 arrays:

    | key | shape | content |
    |---|---|---|
    | ``robot`` | (5,) | goal offset (x, y) in the robot frame [m] (to the next waypoint while a tour has one), robot velocity (vx, vy) in its frame [m/s], yaw rate [rad/s] |
    | ``people`` | (k, 5) | the k nearest people within sensor range: position (x, y) and velocity (vx, vy) in the robot frame, radius; zero rows beyond the mask |
    | ``people_mask`` | (k,) | 1 for a real person row, 0 for padding |
    | ``lidar`` | (rays,) | 2D range scan over 360 degrees from the robot's heading, counter-clockwise [m], capped at the range |
    | ``subgoal`` | (2,) | only with the ``[sensors] subgoal`` look-ahead L > 0 (or ``subgoal=L``): the point L metres along the shortest path to the goal (the goal itself when nearer), in the robot frame [m], each value in [-L, L] |

    Goal offsets are bounded by the map diagonal, velocities by 5 m/s and yaw rate by 10 rad/s
    (values beyond are clipped; they do not occur unless the physics is pushed far out of its
    regime). k, rays and range come from the scenario's ``[sensors]`` (defaults 8, 72, 8 m). The
    ``subgoal`` key gives a learning policy the way round walls that the straight goal offset does
    not (the shortest path on the robot's inflated map, the plain A* planner's map; it ignores
    people); it is off by default.

    ## Rewards

    The sum of five terms, each reported in ``info`` as ``reward_<term>`` (they add up exactly to
    the reward): ``progress`` (decrease of the geodesic distance to the goal, per metre),
    ``success`` (+10 once), ``collision`` (-10 once), ``time`` (-0.01 per step) and
    ``personal_space`` (-0.1 times how deep the robot is inside the closest person's 1.2 m personal
    zone, as a fraction of it). Weights come from the scenario's ``[reward]``.

    ## Starting State

    The robot at the scenario's start pose (optionally jittered), at rest; walkers at random points
    of their routes, visitors at a random exhibit part-way through their dwell, everyone who walks
    with a jittered speed; people with a schedule where the episode's start time puts them; all
    drawn from the seed given to ``reset``.

    ## Episode End

    Terminated on success (robot centre within ``episode.success_radius`` of the goal) or on a
    collision with a person, with walls and furniture, or with another robot (scenarios with
    several robots: the others keep their built-in planners; see :mod:`proxemic.parallel` for
    all of them as agents); truncated when ``episode.max_time`` is reached. ``info["metrics"]``
    holds the episode's metrics at the end.

    ## Arguments

    | argument | default | meaning |
    |---|---|---|
    | ``scenario`` | ``"museum"`` | bundled scenario name, path to a scenario TOML file, or a ``proxemic._core.Scenario`` |
    | ``render_mode`` | ``None`` | ``"rgb_array"`` (MuJoCo offscreen, EGL/OSMesa), ``"topdown"`` (fast 2D numpy view) or ``"human"`` |
    | ``autopilot`` | ``False`` | ignore actions and let the robot's built-in planner drive |
    | ``planner_actions`` | ``True`` | run the built-in planner every step to fill ``info["planner_action"]`` even while a policy acts; ``False`` skips that work (no ``planner_action`` / ``planner_mode`` in ``info``) |
    | ``planner`` | ``None`` | replace the scenario's planner (one of ``proxemic._core.PLANNERS``: ``astar``, ``social_astar``, ``social``, the non-social baselines ``astar_orca`` and ``astar_stop``, ``social_momentum``, ``eband``, and the papers' own ``daza2021``, ``sousa2022`` (with ``sousa2022_astar``, its figures' pairing) and ``calderita``; docs: planners.md) |
    | ``eband`` | ``None`` | elastic-band gains by name (``contraction_gain``, ``repulsion_gain``, ``social_gain``) |
    | ``goal`` | ``None`` | the robot's goal (x, y) instead of the scenario's |
    | ``drive`` | ``None`` | every robot's drive, ``"holonomic"`` or ``"differential"``, instead of the scenario's (``None``: the scenario's own; it overrides a ``drive=`` key of a generated scene's name); the action space follows |
    | ``subgoal`` | ``None`` | the ``[sensors] subgoal`` look-ahead in metres (in [0, 10]; 0 leaves the key out) instead of the scenario's |
    | ``width``, ``height`` | ``FRAME_SIZE`` | frame size (``proxemic.viz.topdown.FRAME_SIZE``) |
    | ``camera`` | ``"top"`` | ``"top"`` or ``"follow"`` (a camera tracking the robot) |
    | ``overlays`` | ``("path",)`` | what the ``"topdown"`` view draws over the scene: any of ``"zones"``, ``"groups"``, ``"object_spaces"``, ``"path"`` (see :meth:`set_overlays`) |

    ## Version History

    * v0: first release: plain A* planner, route-walking people, first-cut metrics; living
      scenes (visitors, conversations, tours, seated people, agenda-driven residents and staff).
    """

    metadata = {"render_modes": list(RENDER_MODES), "render_fps": 10}  # noqa: RUF012

    def __init__(
        self,
        scenario: str | Path | _core.Scenario = "museum",
        *,
        render_mode: str | None = None,
        autopilot: bool = False,
        planner_actions: bool = True,
        planner: str | None = None,
        eband: Mapping[str, float] | None = None,
        goal: Sequence[float] | None = None,
        drive: str | None = None,
        subgoal: float | None = None,
        width: int = FRAME_SIZE[0],
        height: int = FRAME_SIZE[1],
        camera: str = "top",
        overlays: Iterable[str] = ("path",),
    ) -> None:
        """Builds the environment. See the class docstring for the arguments."""
        check_render_mode(render_mode)
        check_frame_size(width, height)
        check_flags(autopilot=autopilot, planner_actions=planner_actions)
        self._args: dict[str, Any] = {
            "scenario": scenario,
            "render_mode": render_mode,
            "autopilot": autopilot,
            "planner_actions": planner_actions,
            "planner": planner,
            "eband": eband,
            "goal": goal,
            "drive": drive,
            "subgoal": subgoal,
            "width": width,
            "height": height,
            "camera": camera,
            "overlays": tuple(overlays),
        }
        if camera not in ("top", "follow"):
            raise input_error("camera", "'top' or 'follow'", camera)
        self.render_mode = render_mode
        self.overlays: tuple[str, ...] = ()
        self.set_overlays(overlays)
        self.autopilot = autopilot
        self.width, self.height, self.camera = width, height, camera
        self.core_scenario, self.scenario = scenarios.load(
            scenario, planner=planner, eband=eband, goal=goal, drive=drive, subgoal=subgoal
        )
        self.ws = WorldSim(self.core_scenario, self.scenario)
        self.world, self.sim = self.ws.world, self.ws.sim
        self.metadata = {
            **self.metadata,
            "render_modes": available_render_modes(),  # no "human" on a headless machine
            "render_fps": round(self.scenario["scene"]["control_hz"]),
        }
        self.observation_space = self.ws.observation_space(robots=False)
        self.action_space = action_space(self.scenario["robots"][0].get("drive", "holonomic"))
        # The core's buffers (written in place; other robots, if any, keep their built-in planners).
        self._out, self._people = self.ws.out, self.ws.people
        if not (autopilot or planner_actions):
            # A policy drives and nobody reads the planner's command: skip that work.
            self.ws.set_planning([False] + [True] * (self.ws.num_robots - 1))
        self._done, self._started = True, False
        self._reset_seed: int | None = None

    def __reduce__(self) -> tuple[Any, tuple[dict[str, Any]]]:
        """Pickles as the constructor's arguments: a copy is a new env (episode state not carried).

        Vector envs and process pools move envs this way. A scenario given as a compiled
        ``proxemic._core.Scenario`` cannot be pickled; pass its name or file instead.
        """
        if isinstance(self._args["scenario"], _core.Scenario):
            raise pickle.PicklingError(
                "ProxemicEnv: a scenario given as a proxemic._core.Scenario cannot be pickled; "
                "build the env from a scenario name or file path to pickle it"
            )
        return _rebuild, (self._args,)

    # ------------------------------------------------------------------ gymnasium API
    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """Starts an episode; the same seed gives the same episode, bit for bit.

        Args:
            seed: None (continue the env's random stream) or an integer >= 0.
            options: Accepted for the gymnasium API; this env takes no options (None or ``{}``).

        Raises:
            InputError: A seed that is not None or a non-negative integer, or any option.
        """
        check_reset_args(seed, options)
        self._reset_seed = seed
        super().reset(seed=seed)
        self.ws.reset(int(self.np_random.integers(0, 2**63 - 1)))
        self._done, self._started = False, True
        if self.render_mode == "human":
            self.render()
        return self._observation(), self._info(final=False)

    def step(self, action: np.ndarray) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        """Advances one control step (``1 / control_hz`` seconds; ``frame_skip`` physics steps).

        Raises:
            InputError: An action that is not 3 finite real numbers of shape (3,).
            NeedsResetError: Before the first ``reset()``, or after the episode ended.
        """
        if self._done:
            raise NeedsResetError(
                "step() after the episode ended (terminated or truncated): call reset() first"
                if self._started
                else "step() before reset(): call reset() first"
            )
        ws = self.ws
        if self.autopilot:
            ws.step()
        else:
            ws.act(0, action, "action")
            ws.step_actions()
        reward, terminated, truncated = ws.outcome(0)
        self._done = terminated or truncated
        if self.render_mode == "human":
            self.render()
        return self._observation(), reward, terminated, truncated, self._info(final=self._done)

    def _observation(self) -> dict[str, np.ndarray]:
        return self.ws.observation(0, robots=False)

    def _info(self, *, final: bool) -> dict[str, Any]:
        info = self.ws.info(0)
        if final:
            info["metrics"] = self.metrics()
        return info

    # ------------------------------------------------------------------ extras
    def metrics(self) -> EpisodeMetrics:
        """The robot's episode metrics so far: ``outcome`` and every metric of ``docs/metrics.md``.

        Undefined values are ``None`` (e.g. ``time_to_goal`` without success). ``d_min`` holds one
        value per person (scenario order) and ``psi_object_active`` / ``psi_object_any`` one per object
        with an interaction space (scenario order); :func:`flat_metrics` names them.

        Raises:
            InvariantError: The record broke one of its invariants (a bug in proxemic): its ``file``
                names the env (its id, or the scene's name), the seed given to ``reset`` and the
                core's episode (scene, world seed, robot), its ``field`` the invariant.
        """
        try:
            return self.world.episode_metrics([0])[0]
        except InvariantError as e:
            env = self.spec.id if self.spec is not None else self.scenario["scene"]["name"]
            raise invariant_in(f"env {env}, reset(seed={self._reset_seed}), robot 0", e) from e

    def flat_metrics(self) -> dict[str, Any]:
        """:meth:`metrics` with the per-person and per-object lists as named scalar keys.

        ``d_min`` becomes ``d_min_<person>``, ``psi_object_active`` ``psi_object_active_<object>`` and
        ``psi_object_any`` ``psi_object_any_<object>``: one column per metric in eval's records.
        """
        return flatten_metrics(self.metrics(), self.scenario)

    def astar_path(self) -> np.ndarray:
        """The plain A* path from the episode's start to the goal, (K, 2) (the reference of L_ratio)."""
        return np.asarray(self.world.astar_path(0))

    def planned_path(self) -> np.ndarray:
        """The global path the robot follows, (K, 2) world-frame waypoints."""
        return np.asarray(self.world.path(0))

    def robot_pose(self) -> np.ndarray:
        """The robot's (x, y, theta) after the last step."""
        return self.ws.poses()[0]

    def people(self) -> np.ndarray:
        """The people now: (P, 6) x, y, heading, vx, vy, radius."""
        return np.asarray(self.world.people())

    def render(self) -> np.ndarray | None:
        """Renders according to ``render_mode`` (``None`` returns nothing)."""
        if self.render_mode is None:
            warn_no_render_mode()
            return None
        camera = "top" if self.camera == "top" else "robot_0/follow"
        return self.ws.render(self.render_mode, self.width, self.height, camera, self.overlays)

    def set_overlays(self, overlays: Iterable[str]) -> None:
        """Chooses what the top-down view draws over the scene.

        Args:
            overlays: Any of ``"zones"`` (Hall's intimate, personal and social rings around each
                person, radii from the scenario's ``[proxemics]``), ``"groups"`` (the groups the
                robot perceives: o-space and outline), ``"object_spaces"`` (interaction spaces
                coloured by R(t) at the current time of day) and ``"path"`` (the robot's global
                path). An empty iterable draws the bare scene.

        Raises:
            InputError: An unknown overlay name.
        """
        self.overlays = check_overlays(overlays)

    def render_topdown(self, overlays: Iterable[str] | None = None) -> np.ndarray:
        """The fast 2D top-down frame (numpy only), whatever the ``render_mode``.

        Args:
            overlays: Overlays for this frame (see :meth:`set_overlays`); default the env's.

        Returns:
            A ``(height, width, 3)`` uint8 RGB image.
        """
        chosen = self.overlays if overlays is None else check_overlays(overlays)
        return self.ws.render_topdown(self.width, self.height, chosen)

    def close(self) -> None:
        """Releases rendering resources."""
        self.ws.close()


def _rebuild(args: dict[str, Any]) -> ProxemicEnv:
    return ProxemicEnv(**args)


def flatten_metrics(metrics: Mapping[str, Any], scenario: dict[str, Any]) -> dict[str, Any]:
    """Metrics with the per-person and per-object lists as ``<metric>_<name>`` scalar keys."""
    people = [p["name"] for p in scenario.get("persons", [])]
    objects = [o["name"] for o in scenario.get("objects", []) if o.get("interaction") is not None]
    names = {"d_min": people, "psi_object_active": objects, "psi_object_any": objects}
    out: dict[str, Any] = {}
    for key, value in metrics.items():
        if isinstance(value, list):
            labels = names.get(key) or [str(k) for k in range(len(value))]
            for label, v in zip(labels, value, strict=False):
                out[f"{key}_{label}"] = v
        else:
            out[key] = value
    return out
