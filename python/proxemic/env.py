"""The single-robot gymnasium environment."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from proxemic import _core, scenarios
from proxemic.errors import InputError
from proxemic.sim import Simulation, ensure_gl_backend

OUTCOMES = ("running", "success", "collision", "timeout")

#: The local planner's mode by code (Daza 2021 Algorithm 1; see proxemic-core control::social::Mode).
PLANNER_MODES = ("follow_path", "orca", "social_momentum", "wait")


class ProxemicEnv(gym.Env[dict[str, np.ndarray], np.ndarray]):
    """## Description.

    A Pepper-like holonomic robot crosses a building shared with scripted people (a museum, a care
    center). The physics runs in MuJoCo; every control step of the people, the built-in planner,
    the metrics, the reward and the observations is computed in the Rust core in one call.
    The robot is the scenario's first robot.

    ## Action Space

    ``Box(-1, 1, (3,), float32)``: the robot-frame command (vx, vy, wz), normalised by the robot's
    maximum speed (0.55 m/s for Pepper) and maximum angular speed (2.0 rad/s). Out-of-range actions
    are clipped to [-1, 1] (as Gymnasium's MuJoCo environments clip to ``ctrlrange``); then the
    speed norm is capped at the maximum speed and the change from the previous command is limited
    by the maximum acceleration (0.55 m/s^2 linear, 3 rad/s^2 angular). An action containing NaN or
    infinity raises :class:`proxemic.InputError`. With ``autopilot=True`` the action is ignored and
    the robot's built-in planner (plain A* by default) drives.

    ## Observation Space

    A ``Dict`` of float32 arrays:

    | key | shape | content |
    |---|---|---|
    | ``robot`` | (5,) | goal offset (x, y) in the robot frame [m], robot velocity (vx, vy) in its frame [m/s], yaw rate [rad/s] |
    | ``people`` | (k, 5) | the k nearest people within sensor range: position (x, y) and velocity (vx, vy) in the robot frame, radius; zero rows beyond the mask |
    | ``people_mask`` | (k,) | 1 for a real person row, 0 for padding |
    | ``lidar`` | (rays,) | 2D range scan over 360 degrees from the robot's heading, counter-clockwise [m], capped at the range |

    Goal offsets are bounded by the map diagonal, velocities by 5 m/s and yaw rate by 10 rad/s
    (values beyond are clipped; they do not occur unless the physics is pushed far out of its
    regime). k, rays and range come from the scenario's ``[sensors]`` (defaults 8, 72, 8 m).

    ## Rewards

    The sum of five terms, each reported in ``info`` as ``reward_<term>`` (they add up exactly to
    the reward): ``progress`` (decrease of the geodesic distance to the goal, per metre),
    ``success`` (+10 once), ``collision`` (-10 once), ``time`` (-0.01 per step) and
    ``personal_space`` (-0.1 times how deep the robot is inside the closest person's 1.2 m personal
    zone, as a fraction of it). Weights come from the scenario's ``[reward]``.

    ## Starting State

    The robot at the scenario's start pose (optionally jittered), at rest; walkers at random points
    of their routes with jittered speeds; all drawn from the seed given to ``reset``.

    ## Episode End

    Terminated on success (robot centre within ``episode.success_radius`` of the goal) or on a
    collision with a person or with walls and furniture; truncated when ``episode.max_time`` is
    reached. ``info["metrics"]`` holds the episode's metrics at the end.

    ## Arguments

    | argument | default | meaning |
    |---|---|---|
    | ``scenario`` | ``"museum"`` | bundled scenario name or path to a scenario TOML file |
    | ``render_mode`` | ``None`` | ``"rgb_array"`` (MuJoCo offscreen, EGL/OSMesa), ``"topdown"`` (fast 2D numpy view) or ``"human"`` |
    | ``autopilot`` | ``False`` | ignore actions and let the robot's built-in planner drive |
    | ``planner`` | ``None`` | replace the scenario's planner (one of ``proxemic._core.PLANNERS``) |
    | ``width``, ``height`` | 640, 480 | frame size |
    | ``camera`` | ``"top"`` | ``"top"`` or ``"follow"`` (a camera tracking the robot) |

    ## Version History

    * v0: first release: plain A* planner, route-walking people, first-cut metrics.
    """

    metadata = {"render_modes": ["rgb_array", "topdown", "human"], "render_fps": 10}  # noqa: RUF012

    def __init__(
        self,
        scenario: str | Path = "museum",
        *,
        render_mode: str | None = None,
        autopilot: bool = False,
        planner: str | None = None,
        width: int = 640,
        height: int = 480,
        camera: str = "top",
    ) -> None:
        """Builds the environment. See the class docstring for the arguments."""
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise InputError(
                f"render_mode: expected one of {self.metadata['render_modes']} or None, got {render_mode!r}",
                field="render_mode",
                expected=str(self.metadata["render_modes"]),
                found=repr(render_mode),
            )
        if camera not in ("top", "follow"):
            raise InputError(
                f"camera: expected 'top' or 'follow', got {camera!r}",
                field="camera",
                expected="'top' or 'follow'",
                found=repr(camera),
            )
        self.render_mode = render_mode
        self.autopilot = autopilot
        self.width, self.height, self.camera = width, height, camera
        self.core_scenario, self.scenario = scenarios.load(scenario, planner=planner)
        self.world = _core.World(self.core_scenario)
        self.sim = Simulation(self.scenario)
        self.metadata = {**self.metadata, "render_fps": round(self.scenario["scene"]["control_hz"])}

        sensors = self.scenario["sensors"]
        k, rays, rng = sensors["k_nearest"], sensors["lidar_rays"], float(sensors["lidar_range"])
        d = float(self.world.obs_position_bound)
        vmax, wmax = float(_core.OBS_MAX_SPEED), float(_core.OBS_MAX_ANGULAR)
        f32 = np.float32
        self.observation_space = spaces.Dict(
            {
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
        )
        self.action_space = spaces.Box(-1.0, 1.0, (3,), dtype=np.float32)

        # Output buffers written in place by the core; the views below are created once.
        self._out = np.zeros(self.world.num_robots * self.world.stride)
        self._people = np.zeros(self.world.num_people * 3)
        self._people2d = self._people.reshape(-1, 3)
        row = self._out[: self.world.stride]
        lay = self.world.layout
        self._views = {name: row[off : off + n] for name, (off, n) in lay.items()}
        self._obs_people_view = self._views["obs_people"].reshape(k, _core.PERSON_FEATURES)
        off = lay["command"][0]
        # Every robot's command (the others keep their built-in planners).
        self._commands = self._out.reshape(self.world.num_robots, self.world.stride)[:, off : off + 3]
        self._action = np.zeros(3 * self.world.num_robots)
        self._action[3:] = np.nan  # other robots (if any) keep their built-in planners
        self._terms = [f"reward_{t}" for t in _core.REWARD_TERMS]
        self._topdown: Any = None
        self._viewer: Any = None
        self._done = True

    # ------------------------------------------------------------------ gymnasium API
    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        """Starts an episode; the same seed gives the same episode, bit for bit."""
        super().reset(seed=seed)
        core_seed = int(self.np_random.integers(0, 2**63 - 1))
        self.world.reset(core_seed, self._out, self._people)
        poses = self._out.reshape(self.world.num_robots, -1)[:, self.world.layout["pose"][0] :][:, :3]
        self.sim.reset(poses, self._people2d)
        self._done = False
        if self.render_mode == "human":
            self.render()
        return self._observation(), self._info(final=False)

    def step(self, action: np.ndarray) -> tuple[dict[str, np.ndarray], float, bool, bool, dict[str, Any]]:
        """Advances one control step (``1 / control_hz`` seconds; ``frame_skip`` physics steps)."""
        if not self.autopilot:
            a = self._action
            a[:3] = action
            if not np.isfinite(a[:3]).all():
                raise InputError(
                    f"action: expected 3 finite numbers in [-1, 1], got {a[:3].tolist()}",
                    field="action",
                    expected="3 finite numbers in [-1, 1]",
                    found=str(a[:3].tolist()),
                )
            self.world.command(a, self._out)
        sim = self.sim
        sim.write_people(self._people2d)
        sim.step(self._commands)
        sim.read()
        self.world.step(sim.state, sim.contacts, self._out, self._people)
        flags = self._views["flags"]
        terminated, truncated = bool(flags[0]), bool(flags[1])
        self._done = terminated or truncated
        if self.render_mode == "human":
            self.render()
        return (
            self._observation(),
            float(self._views["reward"][0]),
            terminated,
            truncated,
            self._info(final=self._done),
        )

    def _observation(self) -> dict[str, np.ndarray]:
        v = self._views
        return {
            "robot": v["obs_robot"].astype(np.float32),
            "people": self._obs_people_view.astype(np.float32),
            "people_mask": v["obs_people_mask"].astype(np.float32),
            "lidar": v["obs_lidar"].astype(np.float32),
        }

    def _info(self, *, final: bool) -> dict[str, Any]:
        v = self._views
        terms = v["reward_terms"]
        info: dict[str, Any] = dict(zip(self._terms, terms.tolist(), strict=True))
        flags = v["flags"]
        info["is_success"] = bool(flags[2])
        info["collision"] = bool(flags[3])
        info["planner_action"] = v["planner_action"].astype(np.float32)
        info["planner_mode"] = PLANNER_MODES[int(v["mode"][0])]
        info["time_of_day"] = self.world.time_of_day
        if final:
            info["metrics"] = self.metrics()
        return info

    # ------------------------------------------------------------------ extras
    def metrics(self) -> dict[str, Any]:
        """The robot's episode metrics so far: ``outcome`` and every metric of ``design/metrics.md``.

        Undefined values are ``None`` (e.g. ``time_to_goal`` without success). ``d_min`` holds one
        value per person (scenario order) and ``psi_object`` / ``psi_object_any`` one per object
        with an interaction space (scenario order); :func:`flat_metrics` names them.
        """
        metrics: dict[str, Any] = self.world.episode_metrics()[0]
        return metrics

    def flat_metrics(self) -> dict[str, Any]:
        """:meth:`metrics` with the per-person and per-object lists as named scalar keys.

        ``d_min`` becomes ``d_min_<person>``, ``psi_object`` ``psi_object_<object>`` and
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
        return np.array(self._views["pose"])

    def people(self) -> np.ndarray:
        """The people now: (P, 6) x, y, heading, vx, vy, radius."""
        return np.asarray(self.world.people())

    def render(self) -> np.ndarray | None:
        """Renders according to ``render_mode`` (``None`` returns nothing)."""
        if self.render_mode is None:
            gym.logger.warn("render() called without a render_mode; pass render_mode= to the constructor")
            return None
        if self.render_mode == "topdown":
            return self._render_topdown()
        if self.render_mode == "human":
            return self._render_human()
        ensure_gl_backend()
        camera = "top" if self.camera == "top" else "robot_0/follow"
        return self.sim.render(self.width, self.height, camera)

    def _render_topdown(self) -> np.ndarray:
        from proxemic.viz.topdown import TopDownRenderer

        if self._topdown is None:
            self._topdown = TopDownRenderer(self.scenario, self.width, self.height)
        people = self.people()
        robots = self._out.reshape(self.world.num_robots, -1)[:, self.world.layout["pose"][0] :][:, :3]
        goals = np.array([r["goal"] for r in self.scenario["robots"]], dtype=np.float64)
        frame: np.ndarray = self._topdown.render(
            robots, people[:, [0, 1, 2, 5]], goals=goals, paths=[self.planned_path()]
        )
        return frame

    def _render_human(self) -> None:
        import mujoco.viewer

        if self._viewer is None:
            self._viewer = mujoco.viewer.launch_passive(self.sim.model, self.sim.data)
        self._viewer.sync()
        return None

    def close(self) -> None:
        """Releases rendering resources."""
        self.sim.close()
        if self._viewer is not None:
            self._viewer.close()
            self._viewer = None


def flatten_metrics(metrics: dict[str, Any], scenario: dict[str, Any]) -> dict[str, Any]:
    """Metrics with the per-person and per-object lists as ``<metric>_<name>`` scalar keys."""
    people = [p["name"] for p in scenario.get("persons", [])]
    objects = [o["name"] for o in scenario.get("objects", []) if o.get("interaction") is not None]
    names = {"d_min": people, "psi_object": objects, "psi_object_any": objects}
    out: dict[str, Any] = {}
    for key, value in metrics.items():
        if isinstance(value, list):
            labels = names.get(key) or [str(k) for k in range(len(value))]
            for label, v in zip(labels, value, strict=False):
                out[f"{key}_{label}"] = v
        else:
            out[key] = value
    return out
