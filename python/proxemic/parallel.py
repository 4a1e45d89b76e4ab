"""The PettingZoo parallel environment: several robots, each an agent, among scripted people."""

from __future__ import annotations

import json
from collections.abc import Collection, Mapping
from pathlib import Path
from typing import Any

import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding
from pettingzoo import ParallelEnv

from proxemic import _core, scenarios
from proxemic.errors import InvariantError, NeedsResetError, input_error, invariant_in, typed_repr
from proxemic.records import EpisodeMetrics
from proxemic.viz.topdown import FRAME_SIZE
from proxemic.world import (
    RENDER_MODES,
    WorldSim,
    action_space,
    available_render_modes,
    check_frame_size,
    check_render_mode,
    check_reset_args,
    warn_no_render_mode,
)

AgentID = str
ObsDict = dict[str, np.ndarray]


class ProxemicParallelEnv(ParallelEnv[AgentID, ObsDict, np.ndarray]):
    """Several Pepper-like robots, agents ``robot_0 ... robot_{N-1}``, in a scene shared with people.

    Every agent is one of the scenario's ``[[robot]]`` entries, in file order. An agent sees what
    the single-robot :class:`proxemic.env.ProxemicEnv` sees (``robot``, ``people``,
    ``people_mask``, ``lidar``) plus the other robots within sensor range, nearest first, with
    their identities: ``robots`` (N - 1, 7) rows of id (the robot's index), position (x, y) and
    velocity (vx, vy) in the agent's frame, radius, and 1 while that robot's episode runs; and
    ``robots_mask`` (N - 1). Actions are the single env's ``Box(-1, 1, (3,))``.

    Robots whose names are in ``autopilot`` are driven by their built-in planner (their actions
    may be omitted and are ignored); every robot's built-in planner is the scenario's unless
    ``planners`` names another (one name for all, or ``{"robot_1": "astar", ...}``), so planners
    mix freely. The ``social`` planner (proxemic's own, with Daza 2021's mode switch) avoids other
    robots reciprocally with ORCA. ``daza2021`` (Daza 2021 Algorithm 1 as published) runs ORCA
    among the robots only when nothing but robots is detected and one is on a collision course
    (lines 5-11); with people around and the nearest object neither a person nor a group, it
    follows its path and avoids no one (line 21), as the paper writes it: a collision risk with
    a robot outside the collision cone. Both treat a robot that joined a human group as a person.

    An agent terminates on success or on a collision (with a person, the static geometry or
    another robot: Francis et al.'s HC, WC and AC), and is truncated at ``episode.max_time``; it
    is then removed from ``agents`` (its body stays, braking to a stop). Each info holds the
    reward terms (``reward_*``, summing to the reward), ``is_success``, ``collision``,
    ``planner_action``, ``planner_mode``, and, at the agent's last step, its ``metrics``; once the
    last agent is done every final info also has ``team`` (see :meth:`episode_metrics`).

    One control step is one Rust call for all robots (``World.step``: actions in, the MuJoCo
    physics called back, everything else out), the GIL released but for the physics, whole
    arrays; the same seed gives the same episode bit for bit.
    """

    metadata = {  # noqa: RUF012
        "render_modes": list(RENDER_MODES),
        "name": "proxemic_parallel_v0",
        "is_parallelizable": True,
        "render_fps": 10,
    }

    def __init__(
        self,
        scenario: str | Path | _core.Scenario = "museum",
        *,
        robots: int | None = None,
        planners: str | Mapping[str, str] | None = None,
        autopilot: bool | Collection[str] = False,
        planner_actions: bool = True,
        render_mode: str | None = None,
        drive: str | None = None,
        width: int = FRAME_SIZE[0],
        height: int = FRAME_SIZE[1],
    ) -> None:
        """Builds the environment.

        Args:
            scenario: Bundled scenario name, path of a scenario file, or a ``proxemic._core.Scenario``.
            robots: The number of robots, from 1 to the larger of the scenario's robots and
                ``MAX_ROBOTS`` (8; default: the scenario's). The first `robots` robot definitions of
                the scenario; beyond those, extra robots shaped like robot 0 with starts and goals
                sampled free and reachable (``Scenario.with_robots``).
            planners: Built-in planner of every robot (a name of ``proxemic._core.PLANNERS``, for
                example ``"daza2021"``, Daza et al. 2021 Algorithm 1: ORCA among the robots only
                when only robots are detected, no robot avoided otherwise) or per agent
                (``{"robot_1": "astar_orca"}``; the others keep the scenario's).
            autopilot: True, False, or a collection (list, set) of the agents driven by their
                built-in planner (actions ignored); a single name is given as ``["robot_0"]``.
            planner_actions: Run the built-in planners of the agents not on autopilot too, for
                ``info["planner_action"]`` and ``info["planner_mode"]``. False skips their cost
                (their infos then lack both keys).
            render_mode: ``"rgb_array"``, ``"topdown"``, ``"human"`` or None.
            drive: Every robot's drive, ``"holonomic"`` or ``"differential"``, instead of the
                scenario's (None: the scenario's own; it overrides a ``drive=`` key of a generated
                scene's name); the action spaces follow. Another value raises an ``InputError``
                naming ``drive``.
            width: Frame width (pixels).
            height: Frame height (pixels).

        Raises:
            InputError: `robots` not an integer, an unknown agent in `planners` or `autopilot`, a bad
                render mode.
            ScenarioError: `robots` outside [1, max(the scenario's robots, 8)], or no room for the
                extra robots; an unknown planner name; robots starting overlapping.
            UnknownNameError: an unknown scenario name.
        """
        check_render_mode(render_mode)
        check_frame_size(width, height)
        self._args: dict[str, Any] = {
            "scenario": scenario,
            "robots": robots,
            "planners": planners,
            "autopilot": autopilot,
            "planner_actions": planner_actions,
            "render_mode": render_mode,
            "drive": drive,
            "width": width,
            "height": height,
        }
        self.render_mode = render_mode
        self.width, self.height = width, height
        core, _ = scenarios.load(scenario, drive=drive)
        if robots is not None:
            if isinstance(robots, bool) or not isinstance(robots, (int, np.integer)):
                most = max(core.num_robots, _core.MAX_ROBOTS)
                raise input_error("robots", f"an integer number of robots in [1, {most}]", typed_repr(robots))
            core = core.with_robots(int(robots))
        names = [f"robot_{i}" for i in range(core.num_robots)]
        if isinstance(planners, str):
            core = core.with_planner(planners)
        elif planners is not None:
            for agent, name in planners.items():
                index = _agent_index(agent, names, "planners")
                core = core.with_robot_planner(index, name)
        self.core_scenario = core
        self.scenario: dict[str, Any] = json.loads(core.to_json())
        self.ws = WorldSim(core, self.scenario)
        self.world, self.sim = self.ws.world, self.ws.sim
        self.metadata = {
            **self.metadata,
            "render_modes": available_render_modes(),  # no "human" on a headless machine
            "render_fps": round(self.scenario["scene"]["control_hz"]),
        }

        self.possible_agents: list[AgentID] = names
        self.agents: list[AgentID] = []
        self._index = {a: i for i, a in enumerate(names)}
        if autopilot is True:
            self.autopilot: frozenset[str] = frozenset(names)
        elif autopilot is False:
            self.autopilot = frozenset()
        elif isinstance(autopilot, (str, bytes)) or not isinstance(autopilot, Collection):
            raise input_error(
                "autopilot",
                f"True, False or a list of agent names among {names}",
                typed_repr(autopilot),
                note=f"for one agent write autopilot=[{autopilot!r}]" if isinstance(autopilot, str) else None,
            )
        else:
            self.autopilot = frozenset(names[_agent_index(a, names, "autopilot")] for a in autopilot)
        if not planner_actions:
            self.ws.set_planning([a in self.autopilot for a in names])
        obs_space = self.ws.observation_space(robots=True)
        self.observation_spaces: dict[AgentID, spaces.Space[Any]] = {a: obs_space for a in names}
        drives = [r.get("drive", "holonomic") for r in self.ws.scenario["robots"]]
        self.action_spaces: dict[AgentID, spaces.Space[Any]] = {
            a: action_space(d) for a, d in zip(names, drives, strict=True)
        }
        self._np_random: np.random.Generator | None = None
        self._reset_seed: int | None = None  # the seed given to the last reset(), for error messages
        self._live: frozenset[str] = frozenset()
        self._rows: list[int] = []  # the live agents' robot indices
        # Final metrics of the robots whose episode ended, by robot index.
        self._final: dict[int, EpisodeMetrics] = {}

    def __reduce__(self) -> tuple[Any, tuple[dict[str, Any]]]:
        """Pickles as the constructor's arguments: a copy is a new env (episode state not carried)."""
        return _rebuild, (self._args,)

    def observation_space(self, agent: AgentID) -> spaces.Space[Any]:
        """The observation space of `agent` (the same for every agent)."""
        return self.observation_spaces[agent]

    def action_space(self, agent: AgentID) -> spaces.Space[Any]:
        """The action space of `agent`: ``Box(-1, 1, (3,), float32)``."""
        return self.action_spaces[agent]

    # ------------------------------------------------------------------ PettingZoo API
    def reset(
        self, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[AgentID, ObsDict], dict[AgentID, dict[str, Any]]]:
        """Starts an episode; the same seed gives the same episode, bit for bit.

        Args:
            seed: None (continue the env's random stream) or an integer >= 0.
            options: This env takes no options; any given are ignored with a warning.

        Raises:
            InputError: A seed that is not None or a non-negative integer.
        """
        check_reset_args(seed, options, warn_options=True)
        if seed is not None or self._np_random is None:
            self._np_random, _ = seeding.np_random(seed)
        self._reset_seed = seed
        self.ws.reset(int(self._np_random.integers(0, 2**63 - 1)))
        self._set_agents(list(self.possible_agents))
        self._final = {}
        obs = self.ws.observations(robots=True)
        infos = dict(zip(self.agents, self.ws.infos(self._rows), strict=True))
        if self.render_mode == "human":
            self.render()
        return {a: obs[i] for i, a in enumerate(self.agents)}, infos

    def step(
        self, actions: Mapping[AgentID, Any]
    ) -> tuple[
        dict[AgentID, ObsDict],
        dict[AgentID, float],
        dict[AgentID, bool],
        dict[AgentID, bool],
        dict[AgentID, dict[str, Any]],
    ]:
        """Advances one control step for every live agent.

        Raises:
            InputError: `actions` not a dict, an action for an agent that is not live, a missing
                action for a live agent not on autopilot, or an action that is not 3 finite numbers.
            NeedsResetError: before ``reset()``, or after every agent finished.
        """
        ws, index, live = self.ws, self._index, self.agents
        if not isinstance(actions, Mapping):
            raise input_error(
                "actions",
                f"a dict agent -> action with one entry per live agent {live} ({{}} when all are on autopilot)",
                typed_repr(actions),
            )
        if not live:
            raise NeedsResetError(
                "step() after every agent finished (env.agents is empty): call reset() first"
                if self._np_random is not None
                else "step() before reset(): call reset() first"
            )
        if not self._live.issuperset(actions):
            extra = next(a for a in actions if a not in self._live)
            raise input_error("actions", f"actions for live agents {live}", f"one for {extra!r}")
        autopilot = self.autopilot
        # Every key is a live agent: as many actions as agents means one for each.
        if len(actions) != len(live):
            missing = [a for a in live if a not in actions and a not in autopilot]
            if missing:
                wanted = [a for a in self.agents if a not in autopilot]
                raise input_error(
                    "actions",
                    f"an action for every live agent not on autopilot {wanted}",
                    f"keys {list(actions)}, missing {missing}",
                )
        if autopilot:
            acting = [a for a in actions if a not in autopilot]
            acts = list(map(actions.__getitem__, acting))
        else:
            acting, acts = list(actions), list(actions.values())
        # Actions in the live agents' order (what policies return): their robot indices are known.
        robots = self._rows if acting == live else list(map(index.__getitem__, acting))
        ws.act_many(robots, acts, lambda k: f"actions[{acting[k]!r}]")
        ws.step_actions()
        rows = self._rows
        obs = dict(zip(live, ws.observations(robots=True, rows=rows), strict=True))
        reward, term, trunc, info = ws.results(rows)
        rewards = dict(zip(live, reward, strict=True))
        terms, truncs = dict(zip(live, term, strict=True)), dict(zip(live, trunc, strict=True))
        infos = dict(zip(live, info, strict=True))
        if any(term) or any(trunc):
            finished = [a for a, t, u in zip(live, term, trunc, strict=True) if t or u]
            self._set_agents([a for a in live if not (terms[a] or truncs[a])])
            # A robot's metrics are final once its episode ended: evaluated once, kept.
            done = [index[a] for a in finished]
            for i, m in zip(done, self._episode_metrics(done), strict=True):
                self._final[i] = m
            for a in finished:
                infos[a]["metrics"] = self._final[index[a]]
            if not self.agents:
                team = self.episode_metrics()
                for a in finished:
                    infos[a]["team"] = team
        if self.render_mode == "human":
            self.render()
        return obs, rewards, terms, truncs, infos

    def _set_agents(self, agents: list[AgentID]) -> None:
        """Sets the live agents, with their set and robot indices (kept until they change)."""
        self.agents = agents
        self._live = frozenset(agents)
        self._rows = [self._index[a] for a in agents]

    def render(self) -> np.ndarray | None:
        """Renders according to ``render_mode`` (``None`` returns nothing)."""
        if self.render_mode is None:
            warn_no_render_mode()
            return None
        return self.ws.render(self.render_mode, self.width, self.height)

    def close(self) -> None:
        """Releases rendering resources."""
        self.ws.close()

    def state(self) -> np.ndarray:
        """The global state: every robot's (x, y, theta), (N, 3) float32."""
        return self.ws.poses().astype(np.float32)

    # ------------------------------------------------------------------ extras
    def metrics(self) -> list[EpisodeMetrics]:
        """Every robot's episode metrics so far, by robot index (see ``docs/metrics.md``)."""
        return self._episode_metrics(None)

    def _episode_metrics(self, robots: list[int] | None) -> list[EpisodeMetrics]:
        """The core's metrics of `robots` (None: all); a broken record's error names this env and its reset seed.

        Raises:
            InvariantError: A record broke one of its invariants (a bug in proxemic): its ``file``
                names the scene, the seed given to ``reset`` and the core's episode.
        """
        try:
            return self.world.episode_metrics() if robots is None else self.world.episode_metrics(robots)
        except InvariantError as e:
            episode = f"parallel env {self.scenario['scene']['name']}, reset(seed={self._reset_seed})"
            raise invariant_in(episode, e) from e

    def episode_metrics(self) -> dict[str, Any]:
        """The team's metrics so far.

        ``robots`` (per-robot metrics), ``success_rate`` (fraction of robots at their goal),
        ``agent_collisions`` (robots that touched another robot: Francis et al.'s AC),
        ``robot_collision_steps`` (control steps with a robot-robot contact, summed over robots),
        ``person_collisions`` and ``static_collisions`` (robots that touched a person or the
        static geometry), ``min_robot_gap`` (smallest surface gap between two robots, m),
        ``team_time`` (s until the last robot's episode ended: the team's makespan) and
        ``total_time`` (s, the robots' episode durations summed).
        """
        n_robots = len(self.possible_agents)
        if len(self._final) == n_robots:
            ms = [self._final[i] for i in range(n_robots)]
        else:
            ms = self.metrics()
        n = max(len(ms), 1)
        return {
            "robots": ms,
            "success_rate": sum(bool(m["success"]) for m in ms) / n,
            "agent_collisions": sum(bool(m["ac"]) for m in ms),
            "robot_collision_steps": sum(int(m["ac_count"]) for m in ms),
            "person_collisions": sum(bool(m["hc"]) for m in ms),
            "static_collisions": sum(bool(m["wc"]) for m in ms),
            "min_robot_gap": min((m["min_robot_gap"] for m in ms if m["min_robot_gap"] is not None), default=None),
            "team_time": max((float(m["duration"]) for m in ms), default=0.0),
            "total_time": sum(float(m["duration"]) for m in ms),
        }

    def people(self) -> np.ndarray:
        """The people now: (P, 6) x, y, heading, vx, vy, radius."""
        return np.asarray(self.world.people())


def parallel_env(
    scenario: str | Path | _core.Scenario = "museum",
    *,
    robots: int | None = None,
    planners: str | Mapping[str, str] | None = None,
    autopilot: bool | Collection[str] = False,
    planner_actions: bool = True,
    render_mode: str | None = None,
    **kwargs: Any,
) -> ProxemicParallelEnv:
    """A PettingZoo ``ParallelEnv`` of the scenario's robots (see :class:`ProxemicParallelEnv`)."""
    return ProxemicParallelEnv(
        scenario,
        robots=robots,
        planners=planners,
        autopilot=autopilot,
        planner_actions=planner_actions,
        render_mode=render_mode,
        **kwargs,
    )


def _rebuild(args: dict[str, Any]) -> ProxemicParallelEnv:
    return ProxemicParallelEnv(**args)


def _agent_index(agent: str, names: list[str], field: str) -> int:
    if agent not in names:
        raise input_error(field, f"one of {names}", agent)
    return names.index(agent)
